// A drawing's layouts and the queue that waits for them: which layouts a new tree is asked
// with (the one it opens in, and those "fit", a turn and a zoom into a compact drawing
// want next), the `POST /api/layout` requests, and what was asked of the drawing while its
// tree was being laid out, done in order once it is drawn. Apart from tree.js because
// this is the drawing's only conversation with the server and its only asynchrony: the
// rest of the drawing reads the layouts these give as if they were always there.

import { url } from "./api.js";
import { M } from "./node_box.js";

// A tree of more nodes than this opens folded to the depth that fits the view.
export const FOLD_OVER = 200;
export const ORIENTATIONS = ["TB", "LR"];
// The most layouts the server gives in one answer (crates/neurotree-studio/src/layout.rs).
const MOST_LAYOUTS = 128;

/** TreeDrawing's methods that ask for layouts and keep what waits for them. */
export const layoutMethods = {
  /**
   * The layouts a new tree of `nodes` is drawn with, and those "fit", a turn and a zoom
   * into a compact drawing ask for next: asked in the same request.
   */
  wantedWith(nodes, { keepView, collapsed, key, previous }) {
    const k = key ?? `tree:${nodes[0].path}`;
    const { orientation, chosen } = k === this.key
      ? { orientation: this.orientation, chosen: this.orientationChosen }
      : this.storedOrientation(k);
    const detail = keepView ? this.detail : "full";
    let folded = new Set();
    if (collapsed) folded = new Set(collapsed);
    else if (previous) nodes.forEach((n, i) => previous.has(n.path) && n.children.length && folded.add(i));
    const none = new Set();
    const other = orientation === "LR" ? "TB" : "LR";
    const wanted = [[orientation, detail, folded], [other, detail, folded]];
    if (nodes.length > FOLD_OVER) {
      if (!keepView && !collapsed) wanted.push(...this.foldCandidates(chosen ? [orientation] : ORIENTATIONS, nodes, "full"));
    } else {
      for (const o of ORIENTATIONS) wanted.push([o, "full", none], [o, "compact", none]);
    }
    const seen = new Set();
    return wanted.filter(([o, d, f]) => {
      const at = this.layoutKey(o, d, f);
      return !seen.has(at) && seen.add(at);
    });
  },

  /** A promise that settles when what was asked of the drawing so far is done. */
  settled() {
    return this.drawn.then(() => this.busy);
  },

  /** Draws the tree that was laid out, then does what was asked of it meanwhile. */
  landed(draw) {
    this.pending = false;
    draw();
    const later = this.later;
    this.later = nothingLater();
    for (const [i, status] of later.statuses) this.setStatus(i, status);
    for (const [i, score] of later.scores) this.setScore(i, score);
    for (const [i, name, value] of later.marks.values()) this.mark(i, name, value);
    if (later.hot) this.drawHot(...later.hot);
    if (later.select) this.select(later.select.i, { reveal: later.select.reveal });
    for (const act of later.acts) act();
  },

  /**
   * Whether the drawing's tree is still being laid out: then `act` is kept for when it is
   * drawn (and true returned).
   */
  deferred(act) {
    if (!this.pending) return false;
    this.later.acts.push(act);
    return true;
  },

  /**
   * Asks the server for `wanted` (each `[orientation, detail, folded]`) of the nodes
   * `wire`, and their boxes with `boxes`; resolves to `{boxes, layouts}` (the layouts in the
   * order asked), rejects with why the layout was refused.
   */
  async request(wire, wanted, boxes = false) {
    const ask = async (part, withBoxes) => {
      const layouts = part.map(([orientation, detail, folded]) => ({ orientation, detail, folded: [...folded] }));
      const res = await fetch(url("/api/layout"), {
        method: "POST",
        headers: { "content-type": "application/json" },
        body: `{"nodes":${wire},"boxes":${withBoxes},"layouts":${JSON.stringify(layouts)}}`,
      });
      const answer = await res.json().catch(() => null);
      if (!res.ok || !answer) throw new Error(`the layout was refused: ${answer?.error || res.status}`);
      return answer;
    };
    // The server answers at most MOST_LAYOUTS a request (a very deep tree tries more folds).
    const parts = [];
    for (let at = 0; at < wanted.length || (boxes && !parts.length); at += MOST_LAYOUTS) {
      parts.push(wanted.slice(at, at + MOST_LAYOUTS));
    }
    const answers = await Promise.all(parts.map((part, k) => ask(part, boxes && k === 0)));
    return { boxes: answers[0]?.boxes, layouts: answers.flatMap((a) => a.layouts) };
  },

  layoutKey(orientation, detail, folded) {
    return `${orientation}|${detail}|${[...folded].sort((a, b) => a - b).join(",")}`;
  },

  /**
   * Runs `apply` once the layouts it reads (`wanted`, each `[orientation, detail, folded]`)
   * are known and what was asked before it is done: at once if they are; else after asking
   * the server for those not known. Dropped if another tree is drawn meanwhile. Returns a
   * promise that settles when it ran (or was dropped).
   */
  whenLaid(wanted, apply) {
    const missing = () => wanted.filter(([o, d, f]) => !this.layouts.has(this.layoutKey(o, d, f)));
    if (!this.busy && !missing().length) {
      apply();
      return Promise.resolve();
    }
    const generation = this.generation;
    const run = (this.busy ?? Promise.resolve()).then(async () => {
      const need = missing();
      if (generation !== this.generation) return;
      if (need.length) {
        try {
          const answer = await this.request(this.wire, need);
          if (generation !== this.generation) return;
          need.forEach(([o, d, f], k) => this.layouts.set(this.layoutKey(o, d, f), answer.layouts[k]));
        } catch (e) {
          if (generation !== this.generation) return;
          // The studio is gone: the drawing stays as it was laid out last.
          this.container.dataset.layoutError = e.message;
        }
      }
      apply();
    });
    const settled = run.catch(() => {});
    this.busy = settled;
    settled.then(() => {
      if (this.busy === settled) this.busy = null;
    });
    return run;
  },

  /** The layout in `orientation` at `detail` with `folded` folded (asked for before). */
  layoutFor(orientation, detail, folded) {
    return this.layouts.get(this.layoutKey(orientation, detail, folded))
      ?? this.lastLayout ?? { nodes: [], width: 0, height: 0, level: M.level };
  },
};

/**
 * What was asked of a drawing whose tree is still being laid out, done once it is drawn:
 * each node's last status, score and marks, the last lines drawn hot and selection (kept
 * one each, however many ticks come meanwhile), and the other requests in order.
 */
export function nothingLater() {
  return { statuses: new Map(), scores: new Map(), marks: new Map(), hot: null, select: null, acts: [] };
}

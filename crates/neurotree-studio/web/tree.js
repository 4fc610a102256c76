// The tree drawing every view shares: nodes drawn as `neurotree show --format svg` draws
// them (node_box.js: → ? ⇉ marks for the well-known controls, hexagons for decorators,
// pills for conditions, rounded boxes for actions, double boxes for subtrees, the type and
// the ports under the name, a colour and a badge per status), laid out top-down or left to
// right (remembered per file) by the same renderer: the boxes and the layout come from
// `POST /api/layout` (crates/neurotree-toolkit/src/render/plan.rs), so that the page draws a
// tree where `neurotree show --format svg` does. With zoom around the pointer or the
// selection, pan, an overview (minimap.js), collapse and expand, search, selection, and
// drag and drop for the editor. A tree opens at full detail, at a legible zoom; "fit"
// shows it whole, choosing the orientation that fits best and, when full detail does not
// fit, the compact detail (names only; the rest on hover, on selection and zoomed in). A
// tree of more than FOLD_OVER nodes opens folded to the depth that fits the view.
//
// The layouts come asynchronously (`fetch`): `setTree` returns a promise of the drawing,
// and whatever is asked of the drawing before its tree is drawn (select, mark, statuses,
// fit, fold...) is done, in order, once it is; the answer to a tree a later `setTree`
// replaced is dropped. A fold, a turn or a fit whose layout is not known yet waits for it,
// the others after it in order; the layouts "fit" and a turn need are asked with the tree.
//
// A drawing is given its nodes in pre-order, each `{name, type, category, path, id, ports,
// directions, children: [index]}`; index 0 is the root. A node's element is an SVG group carrying
// `data-node-path` and, for nodes of a TreeView, `data-node-id`; statuses are set as
// `data-status` on that group alone, so a tick touches only the nodes that changed and
// never lays the tree out again.

import { url } from "./api.js";
import { Minimap } from "./minimap.js";
import { M, NODE_HEIGHT, bodyMarkup, nodeMarkup, r, sizeAt, togglePlace } from "./node_box.js";

export { escapeXml } from "./node_box.js";
export { drawingToolbar } from "./toolbar.js";

const SVG = "http://www.w3.org/2000/svg";

// Below this scale a 12 px label is under 4 px high: not drawn.
const FAR = 0.3;
// The least zoom "fit" picks: a name drawn 12 px high, the type and ports 10 px.
export const LEGIBLE = 1;
// A fit never enlarges past this.
const MOST_FIT = 1.2;
// The least zoom "fit" shows a whole tree at: a name drawn 11 px high.
export const LEAST_FIT = 11 / 12;
// Where less room is left (the watch view beside its scene panel), "fit" shows a whole
// tree down to this zoom, as large as fits, rather than a part of it.
const SMALLEST_FIT = 0.6;
// Zoomed in past this, a compact drawing shows its nodes at full detail again.
const FULL_AT = 1.6;
const MARGIN = 20;
// A tree of more nodes than this opens folded to the depth that fits the view.
export const FOLD_OVER = 200;
const ORIENTATIONS = ["TB", "LR"];
// The most layouts the server gives in one answer (crates/neurotree-studio/src/layout.rs).
const MOST_LAYOUTS = 128;

/** The statuses a node can show, as the protocol spells them. */
export const STATUSES = ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"];
const BADGE = { SUCCESS: "✓", FAILURE: "✗", RUNNING: "▶", SKIPPED: "–" };

/**
 * A tree drawn into `container` (an element the drawing fills).
 * Options: `onSelect(index)`, `onOpen(index)` (double click), `onDrop(from, to, where)`
 * where is "before", "after" or "into" (only when `draggable`), `onDropType(type, to, where)`
 * for palette items dragged in with HTML drag and drop.
 */
export class TreeDrawing {
  constructor(container, options = {}) {
    this.options = options;
    this.container = container;
    this.nodes = [];
    this.collapsed = new Set();
    this.selected = null;
    this.matches = [];
    this.matchAt = -1;
    this.view = { x: 0, y: 0, k: 1 };
    this.size = { width: 0, height: 0 };
    this.statusOf = [];
    this.orientation = "TB";
    this.key = null;
    this.folded = false;
    // "full" or "compact" (names only).
    this.detail = "full";
    // What the last fit did: "legible" (open, at a legible zoom) or "whole" (the tree whole).
    this.fitMode = "legible";
    // Layouts asked of the server, by orientation, detail and what is folded.
    this.layouts = new Map();
    this.wire = "[]";
    // Whether the overview may be shown (the toolbar's toggle).
    this.overview = true;
    // Whether the view is still as the last fit left it.
    this.untouched = true;
    // Which `setTree` is the latest (answers to earlier ones are dropped), whether its tree
    // is still being laid out (`pending`, and its number of nodes), what was asked of the
    // drawing meanwhile (`later`), the layout asked for last (`busy`, a promise, or null)
    // and the promise of the latest tree drawn (`drawn`).
    this.generation = 0;
    this.pending = false;
    this.pendingSize = 0;
    this.later = nothingLater();
    this.busy = null;
    this.drawn = Promise.resolve();
    container.classList.add("tree-drawing");
    container.innerHTML = "";
    // For scripts and tests, which reach a drawing from its element.
    container.treeDrawing = this;
    this.svg = document.createElementNS(SVG, "svg");
    this.svg.setAttribute("class", "tree-svg");
    this.viewport = document.createElementNS(SVG, "g");
    this.viewport.setAttribute("class", "viewport");
    this.edgePath = document.createElementNS(SVG, "path");
    this.edgePath.setAttribute("class", "edges");
    this.hotPath = document.createElementNS(SVG, "path");
    this.hotPath.setAttribute("class", "edges hot");
    this.failPath = document.createElementNS(SVG, "path");
    this.failPath.setAttribute("class", "edges failed");
    this.nodeLayer = document.createElementNS(SVG, "g");
    this.nodeLayer.setAttribute("class", "nodes");
    // A compact node's full drawing, over it on hover and selection.
    this.card = document.createElementNS(SVG, "g");
    this.card.setAttribute("class", "detail-card");
    this.viewport.append(this.edgePath, this.nodeLayer, this.card);
    this.svg.append(this.viewport);
    // The running path and the failure chain change at every tick: drawn in a layer of
    // their own over the tree, so that redrawing them does not repaint the nodes.
    this.overlay = document.createElementNS(SVG, "svg");
    this.overlay.setAttribute("class", "tree-overlay");
    this.overlayViewport = document.createElementNS(SVG, "g");
    this.overlayViewport.append(this.hotPath, this.failPath);
    this.overlay.append(this.overlayViewport);
    this.minimap = new Minimap(this);
    container.append(this.svg, this.overlay, this.minimap.element);
    this.elements = [];
    this.badges = [];
    this.bindPointer();
    // The panels beside a drawing fill in after it is first drawn, and the window can be
    // resized: a view the user has not moved yet is fitted (and a big tree folded) again.
    new ResizeObserver(() => {
      const box = this.svg.getBoundingClientRect();
      const changed = box.width !== this.size.width || box.height !== this.size.height;
      this.size = { width: box.width, height: box.height };
      // A tree being laid out is fitted to the size it finds when it is drawn.
      if (this.pending) return;
      if (changed && this.untouched && box.width && this.fitMode === "whole") {
        this.fitWhole(box);
      } else if (changed && this.untouched && box.width) {
        this.whenLaid(this.folded ? this.foldCandidates() : [], () => {
          if (this.folded) {
            const before = [this.orientation, ...this.collapsed].join();
            this.foldToFit();
            if ([this.orientation, ...this.collapsed].join() !== before) {
              this.placeToggles();
              this.layout();
            } else {
              this.place();
            }
          }
          this.fit(box);
        });
      } else {
        this.minimap.frame();
      }
    }).observe(this.svg);
  }

  /**
   * Draws `nodes` (see the class comment), once the server has laid them out; returns a
   * promise that settles then (or when a later `setTree` replaced this one). `keepView`
   * keeps the zoom and what is folded (by path); `collapsed` gives the folded nodes; `key`
   * names the file, under which the orientation is remembered (default: the root's name).
   */
  setTree(nodes, { keepView = false, collapsed = null, key = null } = {}) {
    const generation = ++this.generation;
    // What was asked of the tree this one replaces is moot: it is drawn no more.
    this.later = nothingLater();
    this.busy = null;
    const wire = JSON.stringify(nodes.map((n) => ({
      name: n.name, type: n.type, category: n.category, ports: Object.entries(n.ports || {}),
      directions: n.directions || {}, children: n.children,
    })));
    const previous = keepView ? new Set([...this.collapsed].map((i) => this.nodes[i]?.path)) : null;
    const options = { keepView, collapsed, key, previous };
    if (!nodes.length) {
      this.pending = false;
      delete this.container.dataset.layoutError;
      this.draw([], "[]", [], new Map(), options);
      this.drawn = Promise.resolve();
      return this.drawn;
    }
    this.pending = true;
    this.pendingSize = nodes.length;
    const wanted = this.wantedWith(nodes, options);
    this.drawn = this.request(wire, wanted, true).then(
      (answer) => {
        if (generation !== this.generation) return;
        const layouts = new Map();
        wanted.forEach(([o, d, f], k) => layouts.set(this.layoutKey(o, d, f), answer.layouts[k]));
        delete this.container.dataset.layoutError;
        this.landed(() => this.draw(nodes, wire, answer.boxes, layouts, options));
      },
      (e) => {
        if (generation !== this.generation) return;
        // The studio is gone or refused: nothing drawn, and why on the container.
        this.container.dataset.layoutError = e.message;
        this.landed(() => this.draw([], "[]", [], new Map(), options));
      },
    );
    return this.drawn;
  }

  /** A promise that settles when what was asked of the drawing so far is done. */
  settled() {
    return this.drawn.then(() => this.busy);
  }

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
  }

  /**
   * Whether the drawing's tree is still being laid out: then `act` is kept for when it is
   * drawn (and true returned).
   */
  deferred(act) {
    if (!this.pending) return false;
    this.later.acts.push(act);
    return true;
  }

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
  }

  /** Draws `nodes` laid out: `boxes` by index, `layouts` by `layoutKey`. */
  draw(nodes, wire, boxes, layouts, { keepView, collapsed, key, previous }) {
    this.layouts = layouts;
    this.lastLayout = null;
    this.wire = wire;
    this.nodes = nodes;
    this.parent = new Array(nodes.length).fill(-1);
    nodes.forEach((n, i) => n.children.forEach((c) => (this.parent[c] = i)));
    this.useKey(key ?? (nodes.length ? `tree:${nodes[0].path}` : null));
    this.collapsed = new Set();
    if (collapsed) collapsed.forEach((i) => this.collapsed.add(i));
    else if (previous) nodes.forEach((n, i) => previous.has(n.path) && n.children.length && this.collapsed.add(i));
    this.statusOf = new Array(nodes.length).fill(null);
    if (!keepView) {
      this.detail = "full";
      this.fitMode = "legible";
      this.container.dataset.detail = "full";
      delete this.container.dataset.fit;
    }
    nodes.forEach((n, i) => {
      n.box = boxes[i];
      n.shape = n.box.shape;
    });
    this.applySizes();
    // Measured before the new nodes are in the document, so that it forces no layout of
    // them; the nodes are then written placed, in one string: a big tree is drawn in
    // one pass of the parser and one layout of the page.
    const box = this.svg.getBoundingClientRect();
    if (box.width) this.size = { width: box.width, height: box.height };
    if (!keepView && !collapsed) this.folded = nodes.length > FOLD_OVER && this.foldToFit();
    const visible = this.place();
    let html = "";
    let edges = "";
    nodes.forEach((n, i) => {
      const folded = this.collapsed.has(i);
      html += nodeMarkup(n, i, visible[i] ? this.pos[i] : null, folded, this.orientation, this.detail);
      if (visible[i] && !folded) edges += this.edgesOf(i);
    });
    this.nodeLayer.innerHTML = html;
    this.elements = Array.from(this.nodeLayer.children);
    this.badges = new Array(this.elements.length).fill(null);
    this.edgePath.setAttribute("d", edges);
    this.hotPath.setAttribute("d", "");
    this.failPath.setAttribute("d", "");
    this.minimap.draw(edges);
    this.card.innerHTML = "";
    if (!keepView) this.fit(box);
    else this.applyView();
    if (this.selected != null && this.selected >= nodes.length) this.selected = null;
    if (this.selected != null) this.elements[this.selected].classList.add("selected");
  }

  /** Reads the orientation remembered for `key` when the file shown changes. */
  useKey(key) {
    if (key === this.key) return;
    this.key = key;
    const { orientation, chosen } = this.storedOrientation(key);
    this.orientationChosen = chosen;
    this.orientation = orientation;
    this.container.dataset.orientation = this.orientation;
  }

  /** The orientation remembered for `key` (top-down if none), and whether one was. */
  storedOrientation(key) {
    let stored = null;
    try {
      stored = key && localStorage.getItem(`neurotree.orientation:${key}`);
    } catch {
      // Storage refused (a private window): the default orientation.
    }
    const chosen = ORIENTATIONS.includes(stored);
    return { orientation: chosen ? stored : "TB", chosen };
  }

  /** Switches between top-down and left-to-right, remembered for the file. */
  setOrientation(orientation) {
    if (!ORIENTATIONS.includes(orientation)) return Promise.resolve();
    if (this.deferred(() => this.setOrientation(orientation))) return this.drawn;
    return this.whenLaid([[orientation, this.detail, this.collapsed]], () => this.turn(orientation));
  }

  turn(orientation) {
    this.orientation = orientation;
    this.orientationChosen = true;
    try {
      if (this.key) localStorage.setItem(`neurotree.orientation:${this.key}`, orientation);
    } catch {
      // Not remembered; the drawing still turns.
    }
    this.placeToggles();
    this.layout();
    this.fit();
    if (this.fitMode === "whole") this.announce(false);
  }

  /** Puts the fold toggles where the orientation wants them. */
  placeToggles() {
    this.container.dataset.orientation = this.orientation;
    this.nodes.forEach((n, i) => {
      if (n.children.length) this.elements[i]?.querySelector(".toggle")?.setAttribute("transform", togglePlace(n, this.orientation));
    });
  }

  /**
   * The layouts `foldToFit` tries: `nodes` folded at each depth, in `orientations`, at
   * `detail`.
   */
  foldCandidates(orientations = this.orientationChosen ? [this.orientation] : ORIENTATIONS, nodes = this.nodes, detail = this.detail) {
    const depth = new Array(nodes.length).fill(0);
    nodes.forEach((n, i) => n.children.forEach((c) => (depth[c] = depth[i] + 1)));
    const deepest = Math.max(0, ...depth);
    const foldedAt = (d) => new Set(nodes.flatMap((n, i) => (depth[i] === d && n.children.length ? [i] : [])));
    return orientations.flatMap((o) => Array.from({ length: Math.max(0, deepest - 1) }, (_, k) => [o, detail, foldedAt(k + 1)]));
  }

  /**
   * Folds the tree at the deepest depth whose drawing is no wider (left to right: no
   * taller) than the view at a legible zoom, in the file's orientation, or, for a file
   * with none remembered, in whichever fits deeper (top-down when both do as well);
   * returns whether any node was folded.
   */
  foldToFit() {
    const nodes = this.nodes;
    const depth = new Array(nodes.length).fill(0);
    nodes.forEach((n, i) => n.children.forEach((c) => (depth[c] = depth[i] + 1)));
    const deepest = Math.max(...depth);
    const foldAt = (d) => {
      this.collapsed = new Set();
      nodes.forEach((n, i) => depth[i] === d && n.children.length && this.collapsed.add(i));
    };
    let best = { orientation: this.orientation, depth: 1 };
    for (const orientation of this.orientationChosen ? [this.orientation] : ORIENTATIONS) {
      this.orientation = orientation;
      const room = (orientation === "LR" ? this.size.height : this.size.width) / LEGIBLE || 1500;
      for (let d = deepest - 1; d >= 1; d--) {
        if (best.fits && d <= best.depth) break;
        foldAt(d);
        this.place();
        const b = this.bounds;
        const breadth = orientation === "LR" ? b.maxY - b.minY : b.maxX - b.minX;
        if (breadth + 2 * MARGIN <= room) {
          best = { orientation, depth: d, fits: true };
          break;
        }
      }
    }
    this.orientation = best.orientation;
    this.container.dataset.orientation = best.orientation;
    foldAt(best.depth);
    return this.collapsed.size > 0;
  }

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
  }

  layoutKey(orientation, detail, folded) {
    return `${orientation}|${detail}|${[...folded].sort((a, b) => a - b).join(",")}`;
  }

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
  }

  /** The layout in `orientation` at `detail` with `folded` folded (asked for before). */
  layoutFor(orientation, detail, folded) {
    return this.layouts.get(this.layoutKey(orientation, detail, folded))
      ?? this.lastLayout ?? { nodes: [], width: 0, height: 0, level: M.level };
  }

  /** Gives each node its size at the drawing's detail. */
  applySizes() {
    for (const n of this.nodes) Object.assign(n, sizeAt(n.box, this.detail));
  }

  /** Draws every node at `detail` ("full" or "compact"), placed again. */
  setDetail(detail) {
    if (detail === this.detail) return;
    this.detail = detail;
    this.container.dataset.detail = detail;
    this.applySizes();
    this.nodes.forEach((n, i) => {
      const el = this.elements[i];
      const body = el?.querySelector(":scope > .body");
      if (body) body.innerHTML = bodyMarkup(n, detail, this.collapsed.has(i), this.orientation);
      const badge = this.badges[i];
      if (badge) badge.setAttribute("transform", `translate(${r(n.w / 2 - this.badgeInset(n))},0)`);
      el?.querySelector(":scope > text.score")?.setAttribute("x", r(-n.w / 2));
    });
    this.layout();
    this.showCard(this.selected);
  }

  badgeInset(n) {
    return n.shape === "condition" ? Math.min(n.h, NODE_HEIGHT) / 2 : n.shape === "decorator" ? M.slant + 4 : 12;
  }

  /**
   * Over a compact node (`i`; null: none), its drawing at full detail: type and ports,
   * centred on it. Nothing at full detail.
   */
  showCard(i) {
    const n = i == null ? null : this.nodes[i];
    const p = i == null ? null : this.pos[i];
    if (!n || !p || this.detail !== "compact" || this.hidden(i)) {
      if (this.card.firstChild) this.card.innerHTML = "";
      this.cardOf = null;
      return;
    }
    if (this.cardOf === i) return;
    this.cardOf = i;
    const full = sizeAt(n.box, "full");
    const y = p.y + n.h / 2 - full.h / 2;
    const status = this.statusOf[i] ? ` data-status="${this.statusOf[i]}"` : "";
    this.card.innerHTML = `<g class="card ${n.box.family}" data-card-of="${i}"${status} transform="translate(${r(p.x)},${r(y)})">`
      + `${bodyMarkup(n, "full", this.collapsed.has(i), this.orientation)}</g>`;
  }

  /** Computes where the visible nodes go (`this.pos`, `this.bounds`); returns which are. */
  place() {
    const nodes = this.nodes;
    const visible = new Uint8Array(nodes.length);
    this.pos = new Array(nodes.length);
    if (!nodes.length) {
      this.bounds = null;
      return visible;
    }
    const layout = this.layoutFor(this.orientation, this.detail, this.collapsed);
    this.lastLayout = layout;
    layout.nodes.forEach((p, i) => {
      if (!p) return;
      visible[i] = 1;
      this.pos[i] = p;
    });
    this.level = layout.level;
    this.bounds = { minX: 0, maxX: layout.width, minY: 0, maxY: layout.height };
    return visible;
  }

  /** Places the drawn nodes again; called when what is collapsed changes. */
  layout() {
    const nodes = this.nodes;
    const visible = this.place();
    let d = "";
    nodes.forEach((n, i) => {
      const el = this.elements[i];
      // Only what changes is written: a big folded tree has a thousand hidden nodes.
      if (!visible[i]) {
        if (!el.hasAttribute("display")) el.setAttribute("display", "none");
        return;
      }
      if (el.hasAttribute("display")) el.removeAttribute("display");
      const p = this.pos[i];
      el.setAttribute("transform", `translate(${r(p.x)},${r(p.y)})`);
      const folded = this.collapsed.has(i);
      if (n.children.length) {
        el.toggleAttribute("data-collapsed", folded);
        el.querySelector(".toggle text").textContent = folded ? "+" : "−";
      }
      if (!folded) d += this.edgesOf(i);
    });
    this.edgePath.setAttribute("d", d);
    this.minimap.draw(d);
    this.drawHot();
    const card = this.cardOf;
    this.cardOf = null;
    this.showCard(card);
  }

  edgesOf(i) {
    let d = "";
    for (const c of this.nodes[i].children) d += this.edge(i, c);
    return d;
  }

  /** The right-angled line from parent `i` to its child `c`, bending halfway between
   * their rows (columns), as svg.rs draws it. */
  edge(i, c) {
    const p = this.pos[i];
    const q = this.pos[c];
    const first = this.pos[this.nodes[i].children[0]];
    const a = this.nodes[i];
    const b = this.nodes[c];
    if (this.orientation === "LR") {
      const right = p.x + a.w / 2;
      const bend = p.end + this.level / 2;
      return `M${r(right)} ${r(p.y + a.h / 2)}H${r(bend)}V${r(q.y + b.h / 2)}H${r(q.x - b.w / 2)}`;
    }
    const bottom = p.y + a.h;
    const bend = (bottom + first.y) / 2;
    return `M${r(p.x)} ${r(bottom)}V${r(bend)}H${r(q.x)}V${r(q.y)}`;
  }

  edgeTo(c) {
    const i = this.parent[c];
    if (!this.pos[i] || !this.pos[c] || this.hidden(c)) return "";
    return this.edge(i, c);
  }

  hidden(i) {
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) if (this.collapsed.has(p)) return true;
    return false;
  }

  /** Sets one node's status (null clears it); cheap: one attribute and the badge. */
  setStatus(i, status) {
    if (this.pending) {
      this.later.statuses.set(i, status);
      return;
    }
    if (this.statusOf[i] === status) return;
    const el = this.elements[i];
    if (!el) return;
    this.statusOf[i] = status;
    if (status == null) el.removeAttribute("data-status");
    else el.setAttribute("data-status", status);
    // A node's badge is made once and then only hidden or relabelled: a run that changes
    // hundreds of statuses a tick then costs attributes, not elements made and removed.
    const mark = BADGE[status];
    let badge = this.badges[i];
    if (mark) {
      if (!badge) {
        badge = document.createElementNS(SVG, "g");
        badge.setAttribute("class", "badge");
        const n = this.nodes[i];
        badge.setAttribute("transform", `translate(${r(n.w / 2 - this.badgeInset(n))},0)`);
        badge.innerHTML = '<circle r="7"/><text y="3.2"></text>';
        el.append(badge);
        this.badges[i] = badge;
      } else {
        badge.removeAttribute("display");
      }
      const text = badge.lastChild;
      if (text.textContent !== mark) text.textContent = mark;
    } else if (badge) badge.setAttribute("display", "none");
  }

  /**
   * Shows the last score node `i` was given (a Utility's, by its UtilitySelector) above
   * its top left corner, as `data-score` on the node and a label made once per node;
   * `null` takes it away.
   */
  setScore(i, score) {
    if (this.pending) {
      this.later.scores.set(i, score);
      return;
    }
    const el = this.elements[i];
    if (!el) return;
    if (score == null) {
      el.removeAttribute("data-score");
      el.querySelector(":scope > text.score")?.remove();
      return;
    }
    const text = Number.isInteger(score) ? String(score) : String(Math.round(score * 1000) / 1000);
    el.setAttribute("data-score", text);
    let label = el.querySelector(":scope > text.score");
    if (!label) {
      label = document.createElementNS(SVG, "text");
      label.setAttribute("class", "score");
      const n = this.nodes[i];
      label.setAttribute("x", r(-n.w / 2));
      label.setAttribute("y", -4);
      el.append(label);
    }
    label.textContent = `score ${text}`;
  }

  /** Every node's status from an array by index (null: no statuses). */
  setStatuses(statuses) {
    if (this.pending) {
      this.later.statuses = new Map();
      for (let i = 0; i < this.pendingSize; i++) this.later.statuses.set(i, statuses ? statuses[i] ?? "IDLE" : null);
      this.later.hot = [null, null];
      return;
    }
    for (let i = 0; i < this.nodes.length; i++) this.setStatus(i, statuses ? statuses[i] ?? "IDLE" : null);
    this.drawHot();
  }

  /**
   * The lines between running nodes, and between nodes on the failure chain, drawn over
   * the others. `running` and `failed` are sets of node indices; without them every node
   * is looked at.
   */
  drawHot(running = null, failed = null) {
    if (this.pending) {
      this.later.hot = [running, failed];
      return;
    }
    const hot = running ?? this.nodes.keys();
    const chain = failed ?? this.nodes.keys();
    let d = "";
    let f = "";
    for (const i of hot) {
      const p = this.parent[i];
      if (p >= 0 && this.statusOf[i] === "RUNNING" && this.statusOf[p] === "RUNNING") d += this.edgeTo(i);
    }
    for (const i of chain) {
      const p = this.parent[i];
      if (p >= 0 && this.elements[i]?.hasAttribute("data-failed") && this.elements[p].hasAttribute("data-failed")) f += this.edgeTo(i);
    }
    this.hotPath.setAttribute("d", d);
    this.failPath.setAttribute("d", f);
  }

  /** Sets or clears (value null/false) a data attribute on a node. */
  mark(i, name, value) {
    if (this.pending) {
      this.later.marks.set(`${i} ${name}`, [i, name, value]);
      return;
    }
    const el = this.elements[i];
    if (!el) return;
    if (value == null || value === false) el.removeAttribute(name);
    else el.setAttribute(name, value === true ? "" : value);
  }

  clearMarks(name) {
    if (this.pending) {
      // The tree drawn will have no marks: those asked for meanwhile go.
      for (const [at, [, n]] of this.later.marks) if (n === name) this.later.marks.delete(at);
      return;
    }
    for (const el of this.nodeLayer.querySelectorAll(`[${name}]`)) el.removeAttribute(name);
  }

  select(i, { reveal = false } = {}) {
    if (this.pending) {
      this.later.select = { i, reveal };
      return;
    }
    if (this.selected != null) this.elements[this.selected]?.classList.remove("selected");
    this.selected = i;
    if (i != null && this.elements[i]) {
      this.elements[i].classList.add("selected");
      if (reveal) this.reveal(i);
    }
    this.showCard(i);
  }

  toggle(i, fold = !this.collapsed.has(i)) {
    if (this.deferred(() => this.toggle(i, fold))) return this.drawn;
    if (!this.nodes[i]?.children.length) return Promise.resolve();
    const next = new Set(this.collapsed);
    if (fold) next.add(i);
    else next.delete(i);
    return this.whenLaid([[this.orientation, this.detail, next]], () => this.fold(i, fold));
  }

  fold(i, fold) {
    if (fold) this.collapsed.add(i);
    else this.collapsed.delete(i);
    this.untouched = false;
    const before = this.pos[i];
    this.layout();
    // Keep the node that was clicked where it was on the screen.
    const after = this.pos[i];
    if (before && after) {
      this.view.x += (before.x - after.x) * this.view.k;
      this.view.y += (before.y - after.y) * this.view.k;
      this.applyView();
    }
  }

  collapseAll(fold) {
    if (this.deferred(() => this.collapseAll(fold))) return this.drawn;
    const next = new Set();
    if (fold) this.nodes.forEach((n, i) => i !== 0 && n.children.length && next.add(i));
    return this.whenLaid([[this.orientation, this.detail, next]], () => {
      this.folded = false;
      this.collapsed = next;
      this.layout();
      this.fit();
    });
  }

  /** The centre of node `i` in the drawing's coordinates. */
  centreOf(i) {
    const p = this.pos[i];
    return p && { x: p.x, y: p.y + this.nodes[i].h / 2 };
  }

  /** Expands the ancestors of `i` and centres the view on it, at a legible zoom. */
  reveal(i) {
    if (this.deferred(() => this.reveal(i))) return this.drawn;
    const next = new Set(this.collapsed);
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) next.delete(p);
    return this.whenLaid([[this.orientation, this.detail, next]], () => this.centreOnNode(i));
  }

  centreOnNode(i) {
    let changed = false;
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) {
      if (this.collapsed.delete(p)) changed = true;
    }
    if (changed) this.layout();
    this.untouched = false;
    const c = this.centreOf(i);
    const box = this.svg.getBoundingClientRect();
    if (!c || !box.width) return;
    this.view.k = Math.max(this.view.k, LEGIBLE);
    this.view.x = box.width / 2 - c.x * this.view.k;
    this.view.y = box.height / 2 - c.y * this.view.k;
    this.applyView();
  }

  /** Marks the nodes whose name or type contains `query`; returns how many. */
  search(query) {
    if (this.deferred(() => this.search(query))) return 0;
    this.clearMarks("data-match");
    this.matches = [];
    this.matchAt = -1;
    const q = query.trim().toLowerCase();
    if (!q) return 0;
    this.nodes.forEach((n, i) => {
      if (n.name.toLowerCase().includes(q) || (n.type || "").toLowerCase().includes(q)) {
        this.matches.push(i);
        this.mark(i, "data-match", true);
      }
    });
    return this.matches.length;
  }

  /** Jumps to the next match (or the previous, with `step` -1); returns its index. */
  nextMatch(step = 1) {
    if (this.pending) return null;
    if (!this.matches.length) return null;
    this.matchAt = (this.matchAt + step + this.matches.length) % this.matches.length;
    const i = this.matches[this.matchAt];
    this.reveal(i);
    return i;
  }

  /**
   * The whole tree in the view if it fits at a legible zoom; else a legible zoom with the
   * root in view (top-down: at the top, centred; left to right: at the left, centred),
   * the rest reached by scrolling, dragging or the overview.
   */
  fit(box = this.svg.getBoundingClientRect()) {
    if (this.deferred(() => this.fit())) return;
    if (box.width) this.size = { width: box.width, height: box.height };
    this.untouched = true;
    if (!this.bounds || !box.width || !box.height) {
      this.view = { x: MARGIN, y: MARGIN, k: 1 };
      this.applyView();
      return;
    }
    const b = this.bounds;
    const w = b.maxX - b.minX + 2 * MARGIN;
    const h = b.maxY - b.minY + 2 * MARGIN;
    const k = Math.min(MOST_FIT, box.width / w, box.height / h);
    if (k >= LEGIBLE) {
      this.view = {
        k,
        x: box.width / 2 - ((b.minX + b.maxX) / 2) * k,
        y: box.height / 2 - ((b.minY + b.maxY) / 2) * k,
      };
    } else {
      const kk = LEGIBLE;
      const root = this.centreOf(0);
      // Centred on the root across, unless that leaves an empty margin on one side.
      const across = (size, centre, min, max) => {
        const v = size / 2 - centre * kk;
        if ((max - min) * kk + 2 * MARGIN <= size) return size / 2 - ((min + max) / 2) * kk;
        return Math.min(MARGIN - min * kk, Math.max(size - MARGIN - max * kk, v));
      };
      this.view = this.orientation === "LR"
        ? { k: kk, x: MARGIN - b.minX * kk, y: across(box.height, root.y, b.minY, b.maxY) }
        : { k: kk, x: across(box.width, root.x, b.minX, b.maxX), y: MARGIN - b.minY * kk };
    }
    this.applyView();
  }

  /**
   * The whole tree in the view ("fit" on the toolbar): at full detail if it fits there at a
   * legible zoom, else at the compact detail in whichever orientation shows it larger (at
   * 1500×950 Nav2's trees at LEAST_FIT or more; where less room is left, as large as fits,
   * down to SMALLEST_FIT); a tree of more than FOLD_OVER nodes its first levels, folded, as it
   * opens. What it chose is on the container (`data-detail`, `data-orientation`,
   * `data-fit`: "whole", or "partial" when even that is too large to show whole).
   */
  fitWhole(box = this.svg.getBoundingClientRect()) {
    if (this.deferred(() => this.fitWhole())) return this.drawn;
    if (box.width) this.size = { width: box.width, height: box.height };
    if (!this.nodes.length || !box.width || !box.height) return Promise.resolve();
    const none = new Set();
    const wanted = this.nodes.length > FOLD_OVER
      ? this.foldCandidates(undefined, this.nodes, "full")
      : ORIENTATIONS.flatMap((o) => [[o, "full", none], [o, "compact", none]]);
    return this.whenLaid(wanted, () => this.fitWholeNow(box));
  }

  fitWholeNow(box) {
    this.fitMode = "whole";
    if (this.nodes.length > FOLD_OVER) {
      this.setDetail("full");
      this.folded = this.foldToFit();
      this.placeToggles();
      this.layout();
      this.fit(box);
      this.fitMode = "whole";
      this.fitScale = this.view.k;
      this.announce(false);
      return;
    }
    const none = new Set();
    const room = (l) => Math.min(MOST_FIT, (box.width - 2 * MARGIN) / l.width, (box.height - 2 * MARGIN) / l.height);
    let choice = [this.orientation, "full"];
    if (room(this.layoutFor(this.orientation, "full", none)) < LEGIBLE) {
      const tb = room(this.layoutFor("TB", "compact", none));
      const lr = room(this.layoutFor("LR", "compact", none));
      choice = lr > tb ? ["LR", "compact"] : ["TB", "compact"];
    }
    this.collapsed = none;
    this.folded = false;
    const turned = choice[0] !== this.orientation;
    this.orientation = choice[0];
    this.container.dataset.orientation = this.orientation;
    if (choice[1] !== this.detail) this.setDetail(choice[1]);
    else this.layout();
    if (turned) this.placeToggles();
    const b = this.bounds;
    const k = room(this.layoutFor(this.orientation, this.detail, none));
    const least = this.detail === "compact" ? SMALLEST_FIT : LEGIBLE;
    this.untouched = true;
    if (k >= least) {
      this.view = {
        k,
        x: box.width / 2 - ((b.minX + b.maxX) / 2) * k,
        y: box.height / 2 - ((b.minY + b.maxY) / 2) * k,
      };
    } else {
      // Too large even so: the root in view with names 11 px tall, the rest reached by
      // panning.
      const kk = this.detail === "compact" ? LEAST_FIT : LEGIBLE;
      this.view = this.orientation === "LR"
        ? { k: kk, x: MARGIN, y: MARGIN }
        : { k: kk, x: Math.max(MARGIN, box.width / 2 - (this.pos[0]?.x ?? 0) * kk), y: MARGIN };
    }
    this.fitScale = this.view.k;
    this.applyView();
    this.announce(k < least);
  }

  /** Says on the container what the last whole fit chose. */
  announce(partial) {
    this.container.dataset.fit = partial || this.folded ? "partial" : "whole";
  }

  /** Zooms by `factor` keeping the point (cx, cy) of the view still (default: its centre). */
  zoom(factor, cx, cy) {
    const box = this.svg.getBoundingClientRect();
    if (cx == null) {
      cx = box.width / 2;
      cy = box.height / 2;
    }
    this.untouched = false;
    const k = Math.min(4, Math.max(0.05, this.view.k * factor));
    this.view.x = cx - ((cx - this.view.x) * k) / this.view.k;
    this.view.y = cy - ((cy - this.view.y) * k) / this.view.k;
    this.view.k = k;
    this.applyView();
    if (this.detail === "compact" && k >= FULL_AT && !this.pending) {
      this.whenLaid([[this.orientation, "full", this.collapsed]], () => {
        if (this.detail !== "compact") return;
        this.detailKeeping("full", cx, cy);
        this.applyView();
      });
    }
  }

  /** Turns to `detail`, the node nearest the point (cx, cy) of the view kept where it is. */
  detailKeeping(detail, cx, cy) {
    const { x, y, k } = this.view;
    let near = null;
    let best = Infinity;
    this.pos.forEach((p, i) => {
      if (!p) return;
      const d = Math.hypot(p.x * k + x - cx, (p.y + this.nodes[i].h / 2) * k + y - cy);
      if (d < best) {
        best = d;
        near = i;
      }
    });
    const before = near == null ? null : this.centreOf(near);
    // No longer as "fit" left it.
    this.fitMode = "legible";
    delete this.container.dataset.fit;
    this.setDetail(detail);
    const after = near == null ? null : this.centreOf(near);
    if (before && after) {
      this.view.x += (before.x - after.x) * k;
      this.view.y += (before.y - after.y) * k;
    }
  }

  /** Zooms around the selected node (brought into view first), else the view's centre. */
  zoomAtSelection(factor) {
    if (this.deferred(() => this.zoomAtSelection(factor))) return;
    const i = this.selected;
    const c = i != null && !this.hidden(i) ? this.centreOf(i) : null;
    if (!c) {
      this.zoom(factor);
      return;
    }
    const box = this.svg.getBoundingClientRect();
    let sx = c.x * this.view.k + this.view.x;
    let sy = c.y * this.view.k + this.view.y;
    if (sx < 0 || sy < 0 || sx > box.width || sy > box.height) {
      this.view.x += box.width / 2 - sx;
      this.view.y += box.height / 2 - sy;
      sx = box.width / 2;
      sy = box.height / 2;
    }
    this.zoom(factor, sx, sy);
  }

  /** Moves the view so that the drawing's point (x, y) is at its centre. */
  centreOn(x, y) {
    this.untouched = false;
    const { width, height } = this.size;
    this.view.x = width / 2 - x * this.view.k;
    this.view.y = height / 2 - y * this.view.k;
    this.applyView();
  }

  /** Lets the overview show (when the tree is larger than the view) or hides it. */
  setOverview(on) {
    this.overview = on;
    this.minimap.frame();
  }

  applyView() {
    const { x, y, k } = this.view;
    const transform = `translate(${r(x)},${r(y)}) scale(${Math.round(k * 1000) / 1000})`;
    this.viewport.setAttribute("transform", transform);
    this.overlayViewport.setAttribute("transform", transform);
    // Zoomed out past reading, labels are not drawn: less to paint at every tick.
    this.svg.classList.toggle("far", k < FAR);
    this.minimap.frame();
  }

  indexOf(target) {
    const g = target.closest && target.closest("g.node");
    return g ? Number(g.dataset.index) : null;
  }

  /** Where a drop at (clientX, clientY) lands on node `i`: before it, after it (along the
   * row of its siblings), or into it. */
  dropPlace(i, clientX, clientY) {
    const box = this.elements[i].getBoundingClientRect();
    const f = this.orientation === "LR" && clientY != null
      ? (clientY - box.top) / Math.max(1, box.height)
      : (clientX - box.left) / Math.max(1, box.width);
    if (f < 0.3) return "before";
    if (f > 0.7) return "after";
    return "into";
  }

  bindPointer() {
    const svg = this.svg;
    svg.addEventListener("wheel", (e) => {
      e.preventDefault();
      const box = svg.getBoundingClientRect();
      // A pinch on a touchpad comes as a wheel with ctrlKey and small steps.
      const lines = e.deltaMode === 1 ? 16 : 1;
      const rate = e.ctrlKey ? 0.01 : 0.0015;
      this.zoom(Math.exp(-e.deltaY * lines * rate), e.clientX - box.left, e.clientY - box.top);
    }, { passive: false });
    // A compact node shows its type and ports while the pointer is over it.
    svg.addEventListener("pointerover", (e) => {
      const i = this.indexOf(e.target);
      this.showCard(i ?? this.selected);
    });
    svg.addEventListener("pointerleave", () => this.showCard(this.selected));
    let drag = null;
    svg.addEventListener("pointerdown", (e) => {
      if (e.button !== 0) return;
      const toggle = e.target.closest(".toggle");
      const i = this.indexOf(e.target);
      if (toggle && i != null) {
        this.toggle(i);
        e.stopPropagation();
        return;
      }
      drag = { x: e.clientX, y: e.clientY, vx: this.view.x, vy: this.view.y, node: i, moved: false };
    });
    svg.addEventListener("pointermove", (e) => {
      if (!drag) return;
      const dx = e.clientX - drag.x;
      const dy = e.clientY - drag.y;
      if (!drag.moved && Math.hypot(dx, dy) < 5) return;
      if (!drag.moved) svg.setPointerCapture(e.pointerId);
      drag.moved = true;
      if (drag.node != null && this.options.draggable && drag.node !== 0) {
        this.dragOver(e, drag.node);
      } else {
        this.untouched = false;
        this.view.x = drag.vx + dx;
        this.view.y = drag.vy + dy;
        this.applyView();
      }
    });
    svg.addEventListener("pointerup", (e) => {
      if (!drag) return;
      const d = drag;
      drag = null;
      if (d.moved) svg.releasePointerCapture(e.pointerId);
      this.clearDropMarks();
      if (!d.moved) {
        const now = performance.now();
        const again = this.lastClick && this.lastClick.node === d.node && now - this.lastClick.at < 400;
        this.lastClick = { node: d.node, at: now };
        this.select(d.node);
        this.options.onSelect?.(d.node);
        if (again && d.node != null) this.options.onOpen?.(d.node);
        return;
      }
      if (d.node != null && this.options.draggable && d.node !== 0) {
        const under = document.elementFromPoint(e.clientX, e.clientY);
        const to = under ? this.indexOf(under) : null;
        if (to != null && to !== d.node) this.options.onDrop?.(d.node, to, this.dropPlace(to, e.clientX, e.clientY));
      }
    });
    // Palette entries dragged in (HTML drag and drop).
    svg.addEventListener("dragover", (e) => {
      if (!this.options.onDropType) return;
      const i = this.indexOf(e.target);
      this.clearDropMarks();
      if (i == null) return;
      e.preventDefault();
      this.mark(i, "data-drop", this.dropPlace(i, e.clientX, e.clientY));
    });
    svg.addEventListener("dragleave", () => this.clearDropMarks());
    svg.addEventListener("drop", (e) => {
      this.clearDropMarks();
      const i = this.indexOf(e.target);
      const type = e.dataTransfer.getData("application/x-neurotree-type") || e.dataTransfer.getData("text/plain");
      if (i == null || !type) return;
      e.preventDefault();
      this.options.onDropType?.(type, i, this.dropPlace(i, e.clientX, e.clientY));
    });
  }

  dragOver(e, from) {
    this.clearDropMarks();
    this.mark(from, "data-dragging", true);
    const under = document.elementFromPoint(e.clientX, e.clientY);
    const to = under ? this.indexOf(under) : null;
    if (to != null && to !== from) this.mark(to, "data-drop", this.dropPlace(to, e.clientX, e.clientY));
  }

  clearDropMarks() {
    this.clearMarks("data-drop");
    this.clearMarks("data-dragging");
  }
}

/**
 * What was asked of a drawing whose tree is still being laid out, done once it is drawn:
 * each node's last status, score and marks, the last lines drawn hot and selection (kept
 * one each, however many ticks come meanwhile), and the other requests in order.
 */
function nothingLater() {
  return { statuses: new Map(), scores: new Map(), marks: new Map(), hot: null, select: null, acts: [] };
}

/** The nodes of a protocol TreeView, ready for a drawing (same order, same indices). */
export function nodesOfTreeView(view) {
  return view.nodes.map((n) => ({
    id: n.id,
    name: n.name,
    type: n.type,
    category: n.category,
    path: n.path,
    subtree: n.subtree,
    ports: n.ports || {},
    directions: n.directions || {},
    children: n.children.slice(),
  }));
}

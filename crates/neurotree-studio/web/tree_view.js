// A drawing's view of its tree: the zoom and pan, "fit" (legible, or the whole tree in the
// orientation and detail that show it largest), zoom around the pointer or the selection
// (a compact drawing turns to full detail zoomed in), centring on a node, and the
// overview's frame. Apart from tree.js because it is the part a person drives: the scales
// a tree is shown at are chosen here and nowhere else.

import { r } from "./node_box.js";
import { FOLD_OVER, ORIENTATIONS } from "./tree_layouts.js";

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
export const MARGIN = 20;

/** TreeDrawing's methods that zoom, pan and fit its view. */
export const viewMethods = {
  /** The centre of node `i` in the drawing's coordinates. */
  centreOf(i) {
    const p = this.pos[i];
    return p && { x: p.x, y: p.y + this.nodes[i].h / 2 };
  },

  /** Expands the ancestors of `i` and centres the view on it, at a legible zoom. */
  reveal(i) {
    if (this.deferred(() => this.reveal(i))) return this.drawn;
    const next = new Set(this.collapsed);
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) next.delete(p);
    return this.whenLaid([[this.orientation, this.detail, next]], () => this.centreOnNode(i));
  },

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
  },

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
  },

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
  },

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
  },

  /** Says on the container what the last whole fit chose. */
  announce(partial) {
    this.container.dataset.fit = partial || this.folded ? "partial" : "whole";
  },

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
  },

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
  },

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
  },

  /** Moves the view so that the drawing's point (x, y) is at its centre. */
  centreOn(x, y) {
    this.untouched = false;
    const { width, height } = this.size;
    this.view.x = width / 2 - x * this.view.k;
    this.view.y = height / 2 - y * this.view.k;
    this.applyView();
  },

  /** Lets the overview show (when the tree is larger than the view) or hides it. */
  setOverview(on) {
    this.overview = on;
    this.minimap.frame();
  },

  applyView() {
    const { x, y, k } = this.view;
    const transform = `translate(${r(x)},${r(y)}) scale(${Math.round(k * 1000) / 1000})`;
    this.viewport.setAttribute("transform", transform);
    this.overlayViewport.setAttribute("transform", transform);
    // Zoomed out past reading, labels are not drawn: less to paint at every tick.
    this.svg.classList.toggle("far", k < FAR);
    this.minimap.frame();
  },
};

// Folding a drawing's tree: a node folded or opened by its toggle, all folded or opened
// at once, and a big tree folded as it opens, at the deepest depth that fits the view at
// a legible zoom (in whichever orientation fits deeper, for a file with none remembered).
// Apart from tree.js because what is folded decides which layout is asked and drawn: each
// fold waits for its layout, then keeps the clicked node where it was.

import { ORIENTATIONS } from "./tree_layouts.js";
import { LEGIBLE, MARGIN } from "./tree_view.js";

/** TreeDrawing's methods that fold and open its nodes. */
export const foldingMethods = {
  toggle(i, fold = !this.collapsed.has(i)) {
    if (this.deferred(() => this.toggle(i, fold))) return this.drawn;
    if (!this.nodes[i]?.children.length) return Promise.resolve();
    const next = new Set(this.collapsed);
    if (fold) next.add(i);
    else next.delete(i);
    return this.whenLaid([[this.orientation, this.detail, next]], () => this.fold(i, fold));
  },

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
  },

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
  },

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
  },

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
  },
};

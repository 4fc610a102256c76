// The overview of a tree drawing: the laid-out tree small, and where the view is. It never
// covers a node: it takes the first corner of the drawing where it hides none, and steps
// aside (hidden) when every corner would.

import { r } from "./node_box.js";

const MARGIN = 20;
// The overview's largest size on the screen.
const MINI_WIDTH = 240;
const MINI_HEIGHT = 160;
// Its distance from the drawing's edges, and its frame (padding and border).
const INSET = 10;
const FRAME = 10;

/**
 * The overview of a drawing (`[data-minimap]`): the laid-out tree small, one path for the
 * boxes and one for the lines (a picture only: nothing in it carries `data-node-path`),
 * and a frame where the view is; a click or a drag in it moves the view there. Shown
 * while the drawing is larger than its view, or folded to fit it, unless turned off
 * (`drawing.overview`) or no corner is free of nodes.
 */
export class Minimap {
  constructor(drawing) {
    this.drawing = drawing;
    const el = document.createElement("div");
    el.className = "minimap";
    el.dataset.minimap = "";
    el.hidden = true;
    el.title = "overview: click or drag to move the view";
    el.innerHTML = `<svg><path class="mini-edges"/><path class="mini-nodes"/><rect class="mini-frame"/></svg>`;
    this.element = el;
    this.svg = el.firstChild;
    [this.edges, this.boxes, this.frameRect] = this.svg.children;
    let dragging = false;
    // Where it sits is kept while the pointer works in it.
    this.held = () => dragging;
    const move = (e) => {
      const ctm = this.svg.getScreenCTM();
      if (!ctm) return;
      const p = new DOMPoint(e.clientX, e.clientY).matrixTransform(ctm.inverse());
      drawing.centreOn(p.x, p.y);
    };
    el.addEventListener("pointerdown", (e) => {
      if (e.button !== 0) return;
      dragging = true;
      el.setPointerCapture(e.pointerId);
      move(e);
      e.preventDefault();
    });
    el.addEventListener("pointermove", (e) => dragging && move(e));
    el.addEventListener("pointerup", (e) => {
      dragging = false;
      if (el.hasPointerCapture(e.pointerId)) el.releasePointerCapture(e.pointerId);
    });
    el.addEventListener("wheel", (e) => e.preventDefault(), { passive: false });
  }

  /** Draws the laid-out tree (`edges`: its lines' path). */
  draw(edges) {
    const { nodes, pos, bounds } = this.drawing;
    if (!bounds) {
      this.element.hidden = true;
      this.bounds = null;
      return;
    }
    let d = "";
    nodes.forEach((n, i) => {
      const p = pos[i];
      if (p) d += `M${r(p.x - n.w / 2)} ${r(p.y)}h${n.w}v${r(n.h)}h${-n.w}z`;
    });
    this.boxes.setAttribute("d", d);
    this.edges.setAttribute("d", edges);
    const pad = MARGIN;
    const w = bounds.maxX - bounds.minX + 2 * pad;
    const h = bounds.maxY - bounds.minY + 2 * pad;
    const s = Math.min(MINI_WIDTH / w, MINI_HEIGHT / h);
    this.svg.setAttribute("viewBox", `${r(bounds.minX - pad)} ${r(bounds.minY - pad)} ${r(w)} ${r(h)}`);
    this.svg.setAttribute("width", String(Math.max(40, Math.round(w * s))));
    this.svg.setAttribute("height", String(Math.max(30, Math.round(h * s))));
    this.bounds = bounds;
    this.frame();
  }

  /** Frames the part of the tree the view shows; shows the overview only when needed. */
  frame() {
    const { view, size, bounds, folded } = this.drawing;
    if (!bounds || !size.width) {
      this.element.hidden = true;
      return;
    }
    const x = -view.x / view.k;
    const y = -view.y / view.k;
    const w = size.width / view.k;
    const h = size.height / view.k;
    const larger = bounds.minX < x || bounds.minY < y || bounds.maxX > x + w || bounds.maxY > y + h;
    const shown = (larger || folded) && this.drawing.overview;
    const corner = shown && this.held?.() && !this.element.hidden ? this.corner : shown ? this.freeCorner() : null;
    this.corner = corner;
    this.element.hidden = !corner;
    if (corner) {
      this.element.style.left = `${corner.left}px`;
      this.element.style.top = `${corner.top}px`;
      this.element.dataset.corner = corner.name;
    }
    this.frameRect.setAttribute("x", r(x));
    this.frameRect.setAttribute("y", r(y));
    this.frameRect.setAttribute("width", r(w));
    this.frameRect.setAttribute("height", r(h));
  }

  /**
   * The first corner of the view (bottom right, bottom left, top right, top left) where the
   * overview covers no node as the view now shows them: `{name, left, top}`, or null.
   */
  freeCorner() {
    const { nodes, pos, view, size } = this.drawing;
    const mw = Number(this.svg.getAttribute("width")) + FRAME;
    const mh = Number(this.svg.getAttribute("height")) + FRAME;
    const corners = [
      ["bottom-right", size.width - INSET - mw, size.height - INSET - mh],
      ["bottom-left", INSET, size.height - INSET - mh],
      ["top-right", size.width - INSET - mw, INSET],
      ["top-left", INSET, INSET],
    ];
    // A node's drawing reaches past its box: its fold toggle, its badge, its score.
    const reach = 16 * view.k;
    for (const [name, left, top] of corners) {
      const covers = nodes.some((n, i) => {
        const p = pos[i];
        if (!p) return false;
        const x0 = (p.x - n.w / 2) * view.k + view.x - reach;
        const y0 = p.y * view.k + view.y - reach;
        const x1 = (p.x + n.w / 2) * view.k + view.x + reach;
        const y1 = (p.y + n.h) * view.k + view.y + reach;
        return x0 < left + mw && x1 > left && y0 < top + mh && y1 > top;
      });
      if (!covers) return { name, left, top };
    }
    return null;
  }
}


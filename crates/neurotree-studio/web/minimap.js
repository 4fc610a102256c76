// The overview of a tree drawing: the laid-out tree small, and where the view is.

import { r } from "./node_box.js";

const MARGIN = 20;
// The overview's largest size on the screen.
const MINI_WIDTH = 240;
const MINI_HEIGHT = 160;

/**
 * The overview of a drawing (`[data-minimap]`): the laid-out tree small, one path for the
 * boxes and one for the lines (a picture only: nothing in it carries `data-node-path`),
 * and a frame where the view is; a click or a drag in it moves the view there. Shown
 * while the drawing is larger than its view, or folded to fit it.
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
    this.element.hidden = !(larger || folded);
    this.frameRect.setAttribute("x", r(x));
    this.frameRect.setAttribute("y", r(y));
    this.frameRect.setAttribute("width", r(w));
    this.frameRect.setAttribute("height", r(h));
  }
}


// A drawing under the pointer: the wheel and pinch zoom, panning by dragging, a click that
// selects (twice: opens), the fold toggles, the compact node's card on hover, and the
// editor's drag and drop (a node moved before, after or into another; a palette type
// dropped in). Apart from tree.js because the events are bound once, when the drawing is
// made, and only call the drawing's other methods.

/** TreeDrawing's methods that answer the pointer. */
export const pointerMethods = {
  indexOf(target) {
    const g = target.closest && target.closest("g.node");
    return g ? Number(g.dataset.index) : null;
  },

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
  },

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
  },

  dragOver(e, from) {
    this.clearDropMarks();
    this.mark(from, "data-dragging", true);
    const under = document.elementFromPoint(e.clientX, e.clientY);
    const to = under ? this.indexOf(under) : null;
    if (to != null && to !== from) this.mark(to, "data-drop", this.dropPlace(to, e.clientX, e.clientY));
  },

  clearDropMarks() {
    this.clearMarks("data-drop");
    this.clearMarks("data-dragging");
  },
};

// Where a drawing's nodes go and how they are drawn there: each node's size at the
// drawing's detail (full or compact), the positions a layout gives, the lines between
// parents and children as svg.rs draws them, and the full drawing shown over a compact
// node. Apart from tree.js because it is the geometry every other part reads (folding,
// the view, the marks), and changes only with the renderer it follows.

import { M, NODE_HEIGHT, bodyMarkup, r, sizeAt } from "./node_box.js";

/** TreeDrawing's methods that place the nodes and draw the lines between them. */
export const placingMethods = {
  /** Gives each node its size at the drawing's detail. */
  applySizes() {
    for (const n of this.nodes) Object.assign(n, sizeAt(n.box, this.detail));
  },

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
  },

  badgeInset(n) {
    return n.shape === "condition" ? Math.min(n.h, NODE_HEIGHT) / 2 : n.shape === "decorator" ? M.slant + 4 : 12;
  },

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
  },

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
  },

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
  },

  edgesOf(i) {
    let d = "";
    for (const c of this.nodes[i].children) d += this.edge(i, c);
    return d;
  },

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
  },

  edgeTo(c) {
    const i = this.parent[c];
    if (!this.pos[i] || !this.pos[c] || this.hidden(c)) return "";
    return this.edge(i, c);
  },

  hidden(i) {
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) if (this.collapsed.has(p)) return true;
    return false;
  },
};

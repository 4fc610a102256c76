// The tree drawing every view shares: nodes drawn as `neurotree show --format svg` draws
// them (→ ? ⇉ marks for the well-known controls, hexagons for decorators, pills for
// conditions, rounded boxes for actions, double boxes for subtrees, the type under the
// name, a colour and a badge per status), laid out by d3-hierarchy's tidy tree, with zoom
// and pan, collapse and expand, search, selection, and drag and drop for the editor.
//
// A drawing is given its nodes in pre-order, each `{name, type, category, path, id,
// children: [index]}`; index 0 is the root. A node's element is an SVG group carrying
// `data-node-path` and, for nodes of a TreeView, `data-node-id`; statuses are set as
// `data-status` on that group alone, so a tick touches only the nodes that changed and
// never lays the tree out again.

import { tree as tidyTree, hierarchy } from "./vendor/d3-hierarchy/d3-hierarchy.mjs";

const SVG = "http://www.w3.org/2000/svg";

// The sizes of the SVG renderer (crates/neurotree-toolkit/src/render/svg.rs).
const NODE_HEIGHT = 40;
const NAME_SIZE = 12;
const TYPE_SIZE = 10;
const GLYPH_WIDTH = 22;
const PADDING = 10;
const SLANT = 10;
const MIN_WIDTH = 44;
const LINE_STEP = 14;
const SIBLING = 14;
const COUSIN = 24;
const LEVEL = 36;
// Below this scale a 12 px label is under 4 px high: not drawn.
const FAR = 0.3;

/** The statuses a node can show, as the protocol spells them. */
export const STATUSES = ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"];
const BADGE = { SUCCESS: "✓", FAILURE: "✗", RUNNING: "▶", SKIPPED: "–" };

// Advance widths of printable ASCII in thousandths of the font size: DejaVu Sans Book and
// Bold, the table text_width.rs measures with, so boxes match the command's pictures.
const REGULAR = [
  318, 401, 460, 838, 636, 950, 780, 275, 390, 390, 500, 838, 318, 361, 318, 337, 636, 636, 636,
  636, 636, 636, 636, 636, 636, 636, 337, 337, 838, 838, 838, 531, 1000, 684, 686, 698, 770, 632,
  575, 775, 752, 295, 295, 656, 557, 863, 748, 787, 603, 787, 695, 635, 611, 732, 684, 989, 685,
  611, 685, 390, 337, 390, 838, 500, 500, 613, 635, 550, 635, 615, 352, 635, 634, 278, 278, 579,
  278, 974, 634, 612, 635, 635, 411, 521, 392, 634, 592, 818, 592, 592, 525, 636, 337, 636, 838,
];
const BOLD = [
  348, 456, 521, 838, 696, 1002, 872, 306, 457, 457, 523, 838, 380, 415, 380, 365, 696, 696, 696,
  696, 696, 696, 696, 696, 696, 696, 400, 400, 838, 838, 838, 580, 1000, 774, 762, 734, 830, 683,
  683, 821, 837, 372, 372, 775, 637, 995, 837, 850, 733, 850, 770, 720, 682, 812, 774, 1103, 771,
  724, 725, 457, 365, 457, 838, 500, 500, 675, 716, 593, 716, 678, 435, 716, 712, 343, 343, 665,
  343, 1042, 712, 687, 716, 716, 493, 595, 478, 712, 652, 924, 645, 652, 582, 712, 365, 712, 838,
];

function textWidth(text, size, bold) {
  const table = bold ? BOLD : REGULAR;
  let total = 0;
  for (const ch of text) {
    const c = ch.codePointAt(0);
    if (c >= 32 && c <= 126) total += table[c - 32];
    else if ((c >= 0x1100 && c <= 0x115f) || (c >= 0x2e80 && c <= 0xa4cf) || (c >= 0xac00 && c <= 0xd7a3)
      || (c >= 0xf900 && c <= 0xfaff) || (c >= 0xff00 && c <= 0xff60) || (c >= 0x1f300 && c <= 0x1faff)) total += 1000;
    else total += 760;
  }
  return (total * size) / 1000;
}

// The built-in controls with a mark, by family (neurotree-core's `Family`).
const FAMILY = {
  Sequence: "sequential", ReactiveSequence: "sequential", SequenceWithMemory: "sequential",
  AsyncSequence: "sequential", SequenceStar: "sequential",
  Fallback: "alternative", ReactiveFallback: "alternative", AsyncFallback: "alternative",
  Parallel: "concurrent", ParallelAll: "concurrent",
};
const GLYPH = { sequential: "→", alternative: "?", concurrent: "⇉" };

/** The drawn shape of a node: one of the families above, or its category. */
export function shapeOf(type, category) {
  return FAMILY[type] || category || "action";
}

export function escapeXml(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&apos;" })[c]);
}

function printable(text) {
  // eslint-disable-next-line no-control-regex
  return String(text).replace(/[\n\r\t]/g, " ").replace(/[\u0000-\u001f\u007f]/g, "\ufffd");
}

function r(v) {
  return Math.round(v * 10) / 10;
}

/** The box a node needs, as svg.rs's `box_size` computes it. */
function boxWidth(node, shape) {
  const name = textWidth(node.label, NAME_SIZE, true);
  const type = node.typeLabel ? textWidth(node.typeLabel, TYPE_SIZE, false) : 0;
  let width = Math.max(name, type) + 2 * PADDING;
  if (GLYPH[shape]) width += GLYPH_WIDTH;
  else if (shape === "decorator") width += 2 * SLANT;
  else if (shape === "condition") width += NODE_HEIGHT / 2;
  else if (shape === "subtree") width += 6;
  return Math.ceil(Math.max(width, MIN_WIDTH));
}

/** The markup of one node at `at` (its top centre; null: hidden), drawn centred on
 * (0, 0) horizontally with its top at y = 0. */
function nodeMarkup(node, index, at, folded) {
  const shape = node.shape;
  const w = node.w;
  const h = NODE_HEIGHT;
  const l = -w / 2;
  let out = "";
  if (shape === "decorator") {
    const pts = [[l, h / 2], [l + SLANT, 0], [l + w - SLANT, 0], [l + w, h / 2], [l + w - SLANT, h], [l + SLANT, h]]
      .map(([x, y]) => `${r(x)},${r(y)}`).join(" ");
    out += `<polygon class="shape" points="${pts}"/>`;
  } else {
    const rx = shape === "condition" ? h / 2 : shape === "action" ? 8 : 2;
    out += `<rect class="shape" x="${r(l)}" y="0" width="${w}" height="${h}" rx="${rx}"/>`;
    if (shape === "subtree") out += `<rect class="inner" x="${r(l + 3)}" y="3" width="${w - 6}" height="${h - 6}" rx="1"/>`;
  }
  let left = l;
  let right = l + w;
  const glyph = GLYPH[shape];
  if (glyph) {
    out += `<line class="inner" x1="${r(l + GLYPH_WIDTH)}" y1="0" x2="${r(l + GLYPH_WIDTH)}" y2="${h}"/>`
      + `<text class="glyph" x="${r(l + GLYPH_WIDTH / 2)}" y="${r(h / 2 + 15 * 0.35)}">${glyph}</text>`;
    left = l + GLYPH_WIDTH;
  } else if (shape === "condition") {
    left = l + h / 4;
    right = l + w - h / 4;
  }
  const centre = r((left + right) / 2);
  const nameY = node.typeLabel ? 17 : r(h / 2 + NAME_SIZE * 0.35);
  out += `<text class="name" x="${centre}" y="${nameY}">${escapeXml(node.label)}</text>`;
  if (node.typeLabel) out += `<text class="type" x="${centre}" y="${17 + LINE_STEP}">${escapeXml(node.typeLabel)}</text>`;
  if (node.children.length) {
    out += `<g class="toggle" transform="translate(0,${h + 7})"><circle r="6"/><text y="3.5">${folded ? "+" : "−"}</text></g>`;
  }
  const id = node.id == null ? "" : ` data-node-id="${node.id}"`;
  const place = at ? ` transform="translate(${r(at.x)},${r(at.y)})"` : ' display="none"';
  const fold = folded ? " data-collapsed" : "";
  const title = `${node.path} (${node.type})`;
  const family = shape === "sequential" || shape === "alternative" || shape === "concurrent" ? "control" : shape;
  return `<g class="node ${family}" data-index="${index}" data-node-path="${escapeXml(node.path)}"${id}${place}${fold}><title>${escapeXml(title)}</title>${out}</g>`;
}

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
    this.statusOf = [];
    container.classList.add("tree-drawing");
    container.innerHTML = "";
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
    this.viewport.append(this.edgePath, this.nodeLayer);
    this.svg.append(this.viewport);
    // The running path and the failure chain change at every tick: drawn in a layer of
    // their own over the tree, so that redrawing them does not repaint the nodes.
    this.overlay = document.createElementNS(SVG, "svg");
    this.overlay.setAttribute("class", "tree-overlay");
    this.overlayViewport = document.createElementNS(SVG, "g");
    this.overlayViewport.append(this.hotPath, this.failPath);
    this.overlay.append(this.overlayViewport);
    container.append(this.svg, this.overlay);
    this.elements = [];
    this.badges = [];
    this.bindPointer();
  }

  /** Draws `nodes` (see the class comment); keeps collapsed nodes by path when asked. */
  setTree(nodes, { keepView = false, collapsed = null } = {}) {
    const previous = keepView ? new Set([...this.collapsed].map((i) => this.nodes[i]?.path)) : null;
    this.nodes = nodes;
    this.parent = new Array(nodes.length).fill(-1);
    nodes.forEach((n, i) => n.children.forEach((c) => (this.parent[c] = i)));
    this.collapsed = new Set();
    if (collapsed) collapsed.forEach((i) => this.collapsed.add(i));
    else if (previous) nodes.forEach((n, i) => previous.has(n.path) && n.children.length && this.collapsed.add(i));
    this.statusOf = new Array(nodes.length).fill(null);
    for (const n of nodes) {
      n.label = printable(n.name);
      n.typeLabel = n.type && n.type !== n.name ? printable(n.type) : null;
      n.shape = shapeOf(n.type, n.category);
      n.w = boxWidth(n, n.shape);
    }
    // Measured before the new nodes are in the document, so that it forces no layout of
    // them; the nodes are then written placed, in one string: a big tree is drawn in
    // one pass of the parser and one layout of the page.
    const box = this.svg.getBoundingClientRect();
    const visible = this.place();
    let html = "";
    let edges = "";
    nodes.forEach((n, i) => {
      const folded = this.collapsed.has(i);
      html += nodeMarkup(n, i, visible[i] ? this.pos[i] : null, folded);
      if (visible[i] && !folded) edges += this.edgesOf(i);
    });
    this.nodeLayer.innerHTML = html;
    this.elements = Array.from(this.nodeLayer.children);
    this.badges = new Array(this.elements.length).fill(null);
    this.edgePath.setAttribute("d", edges);
    this.hotPath.setAttribute("d", "");
    this.failPath.setAttribute("d", "");
    if (!keepView) this.fit(box);
    if (this.selected != null && this.selected >= nodes.length) this.selected = null;
    if (this.selected != null) this.elements[this.selected].classList.add("selected");
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
    const root = hierarchy(0, (i) => (this.collapsed.has(i) ? null : nodes[i].children));
    tidyTree()
      .nodeSize([1, NODE_HEIGHT + LEVEL])
      .separation((a, b) => (nodes[a.data].w + nodes[b.data].w) / 2 + (a.parent === b.parent ? SIBLING : COUSIN))(root);
    let minX = Infinity;
    let maxX = -Infinity;
    let maxY = 0;
    root.each((d) => {
      visible[d.data] = 1;
      this.pos[d.data] = { x: d.x, y: d.y };
      minX = Math.min(minX, d.x - nodes[d.data].w / 2);
      maxX = Math.max(maxX, d.x + nodes[d.data].w / 2);
      maxY = Math.max(maxY, d.y + NODE_HEIGHT);
    });
    this.bounds = { minX, maxX, minY: 0, maxY };
    return visible;
  }

  /** Places the drawn nodes again; called when what is collapsed changes. */
  layout() {
    const nodes = this.nodes;
    const visible = this.place();
    let d = "";
    nodes.forEach((n, i) => {
      const el = this.elements[i];
      if (!visible[i]) {
        el.setAttribute("display", "none");
        return;
      }
      el.removeAttribute("display");
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
    this.drawHot();
  }

  edgesOf(i) {
    const kids = this.nodes[i].children;
    if (!kids.length) return "";
    const p = this.pos[i];
    const bottom = p.y + NODE_HEIGHT;
    const bend = bottom + LEVEL / 2;
    let d = "";
    for (const c of kids) {
      const q = this.pos[c];
      d += `M${r(p.x)} ${r(bottom)}V${r(bend)}H${r(q.x)}V${r(q.y)}`;
    }
    return d;
  }

  edgeTo(c) {
    const i = this.parent[c];
    const p = this.pos[i];
    const q = this.pos[c];
    if (!p || !q || this.hidden(c)) return "";
    const bottom = p.y + NODE_HEIGHT;
    return `M${r(p.x)} ${r(bottom)}V${r(bottom + LEVEL / 2)}H${r(q.x)}V${r(q.y)}`;
  }

  hidden(i) {
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) if (this.collapsed.has(p)) return true;
    return false;
  }

  /** Sets one node's status (null clears it); cheap: one attribute and the badge. */
  setStatus(i, status) {
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
        const inset = n.shape === "condition" ? NODE_HEIGHT / 2 : n.shape === "decorator" ? SLANT + 4 : 12;
        badge.setAttribute("transform", `translate(${r(n.w / 2 - inset)},0)`);
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

  /** Every node's status from an array by index (null: no statuses). */
  setStatuses(statuses) {
    for (let i = 0; i < this.nodes.length; i++) this.setStatus(i, statuses ? statuses[i] ?? "IDLE" : null);
    this.drawHot();
  }

  /**
   * The lines between running nodes, and between nodes on the failure chain, drawn over
   * the others. `running` and `failed` are sets of node indices; without them every node
   * is looked at.
   */
  drawHot(running = null, failed = null) {
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
    const el = this.elements[i];
    if (!el) return;
    if (value == null || value === false) el.removeAttribute(name);
    else el.setAttribute(name, value === true ? "" : value);
  }

  clearMarks(name) {
    for (const el of this.nodeLayer.querySelectorAll(`[${name}]`)) el.removeAttribute(name);
  }

  select(i, { reveal = false } = {}) {
    if (this.selected != null) this.elements[this.selected]?.classList.remove("selected");
    this.selected = i;
    if (i != null && this.elements[i]) {
      this.elements[i].classList.add("selected");
      if (reveal) this.reveal(i);
    }
  }

  toggle(i, fold = !this.collapsed.has(i)) {
    if (!this.nodes[i]?.children.length) return;
    if (fold) this.collapsed.add(i);
    else this.collapsed.delete(i);
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
    this.collapsed.clear();
    if (fold) this.nodes.forEach((n, i) => i !== 0 && n.children.length && this.collapsed.add(i));
    this.layout();
    this.fit();
  }

  /** Expands the ancestors of `i` and centres the view on it. */
  reveal(i) {
    let changed = false;
    for (let p = this.parent[i]; p >= 0; p = this.parent[p]) {
      if (this.collapsed.delete(p)) changed = true;
    }
    if (changed) this.layout();
    const p = this.pos[i];
    const box = this.svg.getBoundingClientRect();
    if (!p || !box.width) return;
    if (this.view.k < 0.6) this.view.k = 0.9;
    this.view.x = box.width / 2 - p.x * this.view.k;
    this.view.y = box.height / 2 - (p.y + NODE_HEIGHT / 2) * this.view.k;
    this.applyView();
  }

  /** Marks the nodes whose name or type contains `query`; returns how many. */
  search(query) {
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
    if (!this.matches.length) return null;
    this.matchAt = (this.matchAt + step + this.matches.length) % this.matches.length;
    const i = this.matches[this.matchAt];
    this.reveal(i);
    return i;
  }

  fit(box = this.svg.getBoundingClientRect()) {
    if (!this.bounds || !box.width || !box.height) {
      this.view = { x: 20, y: 20, k: 1 };
      this.applyView();
      return;
    }
    const w = this.bounds.maxX - this.bounds.minX + 40;
    const h = this.bounds.maxY - this.bounds.minY + 40;
    const k = Math.min(1.2, box.width / w, box.height / h);
    // Very wide trees would shrink to dots; keep them readable and show the top.
    const kk = Math.max(k, 0.15);
    this.view = {
      k: kk,
      x: box.width / 2 - ((this.bounds.minX + this.bounds.maxX) / 2) * kk,
      y: 20 * kk,
    };
    this.applyView();
  }

  zoom(factor, cx, cy) {
    const box = this.svg.getBoundingClientRect();
    if (cx == null) {
      cx = box.width / 2;
      cy = box.height / 2;
    }
    const k = Math.min(4, Math.max(0.05, this.view.k * factor));
    this.view.x = cx - ((cx - this.view.x) * k) / this.view.k;
    this.view.y = cy - ((cy - this.view.y) * k) / this.view.k;
    this.view.k = k;
    this.applyView();
  }

  applyView() {
    const { x, y, k } = this.view;
    const transform = `translate(${r(x)},${r(y)}) scale(${Math.round(k * 1000) / 1000})`;
    this.viewport.setAttribute("transform", transform);
    this.overlayViewport.setAttribute("transform", transform);
    // Zoomed out past reading, labels are not drawn: less to paint at every tick.
    this.svg.classList.toggle("far", k < FAR);
  }

  indexOf(target) {
    const g = target.closest && target.closest("g.node");
    return g ? Number(g.dataset.index) : null;
  }

  /** Where a drop at client x lands on node `i`: before it, after it, or into it. */
  dropPlace(i, clientX) {
    const box = this.elements[i].getBoundingClientRect();
    const f = (clientX - box.left) / Math.max(1, box.width);
    if (f < 0.3) return "before";
    if (f > 0.7) return "after";
    return "into";
  }

  bindPointer() {
    const svg = this.svg;
    svg.addEventListener("wheel", (e) => {
      e.preventDefault();
      const box = svg.getBoundingClientRect();
      this.zoom(Math.exp(-e.deltaY * 0.0015), e.clientX - box.left, e.clientY - box.top);
    }, { passive: false });
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
        if (to != null && to !== d.node) this.options.onDrop?.(d.node, to, this.dropPlace(to, e.clientX));
      }
    });
    // Palette entries dragged in (HTML drag and drop).
    svg.addEventListener("dragover", (e) => {
      if (!this.options.onDropType) return;
      const i = this.indexOf(e.target);
      this.clearDropMarks();
      if (i == null) return;
      e.preventDefault();
      this.mark(i, "data-drop", this.dropPlace(i, e.clientX));
    });
    svg.addEventListener("dragleave", () => this.clearDropMarks());
    svg.addEventListener("drop", (e) => {
      this.clearDropMarks();
      const i = this.indexOf(e.target);
      const type = e.dataTransfer.getData("application/x-neurotree-type") || e.dataTransfer.getData("text/plain");
      if (i == null || !type) return;
      e.preventDefault();
      this.options.onDropType?.(type, i, this.dropPlace(i, e.clientX));
    });
  }

  dragOver(e, from) {
    this.clearDropMarks();
    this.mark(from, "data-dragging", true);
    const under = document.elementFromPoint(e.clientX, e.clientY);
    const to = under ? this.indexOf(under) : null;
    if (to != null && to !== from) this.mark(to, "data-drop", this.dropPlace(to, e.clientX));
  }

  clearDropMarks() {
    this.clearMarks("data-drop");
    this.clearMarks("data-dragging");
  }
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
    children: n.children.slice(),
  }));
}

/** A toolbar for a drawing: search, fit, zoom, collapse all / expand all. */
export function drawingToolbar(drawing, { onJump } = {}) {
  const bar = document.createElement("div");
  bar.className = "drawing-tools";
  bar.innerHTML = `<input type="search" class="node-search" placeholder="search name or type" aria-label="search nodes">
    <span class="match-count"></span>
    <button data-action="search-prev" title="previous match">▲</button><button data-action="search-next" title="next match (Enter)">▼</button>
    <button data-action="fit" title="fit the tree to the view">fit</button>
    <button data-action="zoom-in" title="zoom in">+</button><button data-action="zoom-out" title="zoom out">−</button>
    <button data-action="collapse-all" title="collapse every control">collapse</button><button data-action="expand-all" title="expand everything">expand</button>`;
  const input = bar.querySelector("input");
  const count = bar.querySelector(".match-count");
  const jump = (step) => {
    const i = drawing.nextMatch(step);
    if (i != null) {
      count.textContent = `${drawing.matchAt + 1}/${drawing.matches.length}`;
      onJump?.(i);
    }
  };
  input.addEventListener("input", () => {
    const n = drawing.search(input.value);
    count.textContent = input.value ? `${n} found` : "";
    if (n) jump(1);
  });
  input.addEventListener("keydown", (e) => {
    if (e.key === "Enter") jump(e.shiftKey ? -1 : 1);
    e.stopPropagation();
  });
  bar.addEventListener("click", (e) => {
    const a = e.target.closest("[data-action]")?.dataset.action;
    if (a === "search-next") jump(1);
    else if (a === "search-prev") jump(-1);
    else if (a === "fit") drawing.fit();
    else if (a === "zoom-in") drawing.zoom(1.25);
    else if (a === "zoom-out") drawing.zoom(0.8);
    else if (a === "collapse-all") drawing.collapseAll(true);
    else if (a === "expand-all") drawing.collapseAll(false);
  });
  return bar;
}

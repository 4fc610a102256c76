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
//
// This file holds the class, its making and the drawing of a new tree; its other methods
// are in a module per concept, put on the class below: tree_layouts.js (the layouts asked
// and what waits for them), tree_placing.js (where nodes go, the lines between them),
// tree_marks.js (statuses, marks, selection, search), tree_folding.js, tree_view.js
// (zoom, pan, fit) and tree_pointer.js (clicks, drags, the wheel).

import { Minimap } from "./minimap.js";
import { nodeMarkup, togglePlace } from "./node_box.js";
import { foldingMethods } from "./tree_folding.js";
import { FOLD_OVER, ORIENTATIONS, layoutMethods, nothingLater } from "./tree_layouts.js";
import { markMethods } from "./tree_marks.js";
import { placingMethods } from "./tree_placing.js";
import { pointerMethods } from "./tree_pointer.js";
import { viewMethods } from "./tree_view.js";

export { escapeXml } from "./node_box.js";
export { drawingToolbar } from "./toolbar.js";
export { FOLD_OVER } from "./tree_layouts.js";
export { STATUSES } from "./tree_marks.js";
export { LEAST_FIT, LEGIBLE } from "./tree_view.js";

const SVG = "http://www.w3.org/2000/svg";

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
}

// The drawing's other methods, one module per concept (each says what it holds): the
// class as callers know it, its methods defined as class methods are (not enumerable).
for (const methods of [layoutMethods, placingMethods, markMethods, foldingMethods, viewMethods, pointerMethods]) {
  for (const [name, method] of Object.entries(Object.getOwnPropertyDescriptors(methods))) {
    Object.defineProperty(TreeDrawing.prototype, name, { ...method, enumerable: false });
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
    directions: n.directions || {},
    children: n.children.slice(),
  }));
}

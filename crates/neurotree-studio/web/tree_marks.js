// What a drawing shows on its nodes without laying them out again: statuses and their
// badges, Utility scores, the running path and the failure chain drawn hot, data
// attributes (errors, breakpoints, search matches...), the selection and search. Apart
// from tree.js because these change at every tick and must stay cheap: an attribute or
// a badge per node that changed, and each is kept for later while a tree is laid out.

import { r } from "./node_box.js";

const SVG = "http://www.w3.org/2000/svg";

/** The statuses a node can show, as the protocol spells them. */
export const STATUSES = ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"];
const BADGE = { SUCCESS: "✓", FAILURE: "✗", RUNNING: "▶", SKIPPED: "–" };

/** TreeDrawing's methods that mark its nodes, select and search them. */
export const markMethods = {
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
  },

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
  },

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
  },

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
  },

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
  },

  clearMarks(name) {
    if (this.pending) {
      // The tree drawn will have no marks: those asked for meanwhile go.
      for (const [at, [, n]] of this.later.marks) if (n === name) this.later.marks.delete(at);
      return;
    }
    for (const el of this.nodeLayer.querySelectorAll(`[${name}]`)) el.removeAttribute(name);
  },

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
  },

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
  },

  /** Jumps to the next match (or the previous, with `step` -1); returns its index. */
  nextMatch(step = 1) {
    if (this.pending) return null;
    if (!this.matches.length) return null;
    this.matchAt = (this.matchAt + step + this.matches.length) % this.matches.length;
    const i = this.matches[this.matchAt];
    this.reveal(i);
    return i;
  },
};

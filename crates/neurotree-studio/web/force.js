// Results forced by hand in the watch view (PROTOCOL.md, "Forced results"): the selected
// node's menu forces its next result, SUCCESS, FAILURE or RUNNING, once or until cleared
// (`[data-action="force"]`); the forces are listed in the side panel, each with a button
// that clears it (`[data-action="unforce"]`), and drawn on their nodes (`data-forced` on
// the node's group: the status, and `once` or `cleared`). A once-force that applied shows
// the tick it applied at; going back before that tick and stepping applies it again.

const STATUSES = ["SUCCESS", "FAILURE", "RUNNING"];

const CSS = `
.node[data-forced] .shape { stroke: #e8590c; stroke-width: 3px; stroke-dasharray: 6 3; }
.force-menu { display: flex; flex-wrap: wrap; gap: 4px; align-items: center; margin: 6px 0; }
.force-menu .force-label { width: 100%; font-size: 12px; color: #666; }
.force-list li { display: flex; gap: 6px; align-items: center; }
.force-list li[data-applied] .force-what { color: #888; }
`;

export class ForcePanel {
  // `send` sends a message to the server; `nodes()` is the tree's nodes (id order);
  // `changed()` draws the selected node's panel again.
  constructor(section, { drawing, send, nodes, changed }) {
    this.drawing = drawing;
    this.send = send;
    this.nodes = nodes;
    this.changed = changed;
    this.forces = [];
    // Whether the run's tree was built so that its results can be forced.
    this.forcing = true;
    if (!document.querySelector("style[data-force-style]")) {
      const style = document.createElement("style");
      style.dataset.forceStyle = "";
      style.textContent = CSS;
      document.head.append(style);
    }
    const box = document.createElement("section");
    box.className = "forces";
    box.innerHTML = `<h3>Forced results</h3><ul class="force-list" data-force-list></ul>`;
    section.querySelector(".selected-node")?.after(box);
    this.list = box.querySelector("[data-force-list]");
    section.addEventListener("click", (e) => {
      const button = e.target.closest("[data-action='force'], [data-action='unforce']");
      if (!button) return;
      const node = Number(button.dataset.node);
      if (button.dataset.action === "unforce") this.send({ type: "force", node, status: "off" });
      else this.send({ type: "force", node, status: button.dataset.status, until: button.dataset.until });
    });
    this.render();
  }

  // The server's list: [{node, status, until, applied}]; `forcing` (from `hello`) whether
  // the run can be forced at all.
  set(list, forcing = this.forcing) {
    this.forcing = forcing;
    this.forces = list || [];
    this.drawing.clearMarks("data-forced");
    for (const f of this.forces) {
      if (f.until === "cleared" || f.applied == null) this.drawing.mark(f.node, "data-forced", `${f.status} ${f.until}`);
    }
    this.render();
    this.changed();
  }

  render() {
    const nodes = this.nodes();
    this.list.innerHTML = "";
    if (!this.forcing) {
      this.list.innerHTML = '<li class="hint" data-force-off>this run\'s tree was built without the hooks that force results</li>';
      return;
    }
    if (!this.forces.length) {
      this.list.innerHTML = '<li class="hint">none: a node\'s menu forces its next result</li>';
      return;
    }
    for (const f of this.forces) {
      const li = document.createElement("li");
      li.dataset.forceNode = String(f.node);
      li.dataset.status = f.status;
      li.dataset.until = f.until;
      if (f.applied != null) li.dataset.applied = String(f.applied);
      const what = document.createElement("span");
      what.className = "force-what";
      const when = f.until === "cleared" ? "until cleared" : f.applied != null ? `once, applied at tick ${f.applied}` : "once, at its next tick";
      what.textContent = `${nodes[f.node]?.path ?? f.node} → ${f.status} (${when})`;
      li.append(what, this.button("unforce", f.node, "clear", "clear this force"));
      this.list.append(li);
    }
  }

  // The force controls of `node`, added to its panel `box`.
  menu(box, node) {
    if (!this.forcing) return;
    const menu = document.createElement("div");
    menu.className = "force-menu";
    menu.dataset.forceMenu = "";
    const current = this.forces.find((f) => f.node === node.id);
    for (const until of ["once", "cleared"]) {
      const label = document.createElement("span");
      label.className = "force-label";
      label.textContent = until === "once" ? "force its next result:" : "force every result until cleared:";
      menu.append(label);
      for (const status of STATUSES) {
        const b = this.button("force", node.id, status, `return ${status} in place of its tick, ${until === "once" ? "once" : "until cleared"}`);
        b.dataset.status = status;
        b.dataset.until = until;
        menu.append(b);
      }
    }
    if (current) menu.append(this.button("unforce", node.id, "clear force", "clear this node's force"));
    box.append(menu);
  }

  button(action, node, text, title) {
    const b = document.createElement("button");
    b.dataset.action = action;
    b.dataset.node = String(node);
    b.textContent = text;
    b.title = title;
    return b;
  }
}

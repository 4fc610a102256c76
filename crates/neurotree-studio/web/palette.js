// The editor's palette: every node type the server's loader knows (`/api/palette`: the
// built-ins, registered types, `--model` files and the file's own TreeNodesModel) and the
// trees of the file, grouped by category and searchable by name or description; the
// chosen type's ports (type, default, description) below. A type is added by "+ add",
// by a double click, by Enter in the search field, or dragged onto a node.

const ORDER = ["control", "decorator", "condition", "action", "subtree"];

/**
 * The palette drawn into `root` (an element it fills). `onChoose(type)` when a type is
 * picked, `onAdd(type)` when it is to be added to the selected node. Returns `{render,
 * focus}`: `render(types, chosen)` draws the list (the editor owns which type is chosen).
 */
export function mountPalette(root, { onChoose, onAdd }) {
  root.innerHTML = `
    <h2>Palette</h2>
    <input type="search" class="palette-search" placeholder="search node types" aria-label="search node types">
    <ul class="palette-list"></ul>
    <div class="palette-detail"></div>`;
  const search = root.querySelector(".palette-search");
  const list = root.querySelector(".palette-list");
  const detail = root.querySelector(".palette-detail");
  let shown = { types: [], chosen: null };

  function render(types, chosen) {
    shown = { types, chosen };
    const q = search.value.trim().toLowerCase();
    const sorted = [...types].sort((a, b) => ORDER.indexOf(a.category) - ORDER.indexOf(b.category) || a.type.localeCompare(b.type));
    let html = "";
    let group = null;
    for (const t of sorted) {
      if (q && !t.type.toLowerCase().includes(q) && !(t.description || "").toLowerCase().includes(q)) continue;
      if (t.category !== group) {
        group = t.category;
        html += `<li class="group">${esc(group)}</li>`;
      }
      const sel = t.type === chosen ? ' aria-selected="true"' : "";
      html += `<li class="palette-item cat-${esc(t.category)}" draggable="true" data-type="${esc(t.type)}"${sel} title="${esc(t.description || "")}">${esc(t.type)}</li>`;
    }
    list.innerHTML = html;
    const t = chosen && types.find((x) => x.type === chosen);
    detail.innerHTML = t ? typeDetail(t) : '<p class="hint">Pick a type, then “+ add” (or drag it onto a node).</p>';
  }

  search.addEventListener("input", () => render(shown.types, shown.chosen));
  search.addEventListener("keydown", (e) => {
    if (e.key === "Enter") {
      // The type named exactly, else the first one shown.
      const q = search.value.trim().toLowerCase();
      const items = [...list.querySelectorAll(".palette-item")];
      const pick = items.find((i) => i.dataset.type.toLowerCase() === q) || items[0];
      if (pick) {
        onChoose(pick.dataset.type);
        onAdd(pick.dataset.type);
      }
    } else if (e.key === "Escape") search.blur();
    // The editor's shortcuts (Delete, arrows) are not for this field.
    e.stopPropagation();
  });
  list.addEventListener("click", (e) => {
    const item = e.target.closest(".palette-item");
    if (item) onChoose(item.dataset.type);
  });
  list.addEventListener("dblclick", (e) => {
    const item = e.target.closest(".palette-item");
    if (item) onAdd(item.dataset.type);
  });
  list.addEventListener("dragstart", (e) => {
    const item = e.target.closest(".palette-item");
    if (!item) return;
    e.dataTransfer.setData("application/x-neurotree-type", item.dataset.type);
    e.dataTransfer.setData("text/plain", item.dataset.type);
    e.dataTransfer.effectAllowed = "copy";
  });

  return { render, focus: () => search.focus() };
}

function typeDetail(t) {
  const ports = (t.ports || [])
    .map((p) => `<li><b>${esc(p.name)}</b> <i>${esc(p.direction)}</i> ${esc(p.type || "")}${p.default != null ? ` = ${esc(p.default)}` : ""}${p.description ? `<br><small>${esc(p.description)}</small>` : ""}</li>`)
    .join("");
  return `<h3>${esc(t.type)} <small>${esc(t.category)}${t.builtin ? ", built-in" : ""}</small></h3>${t.description ? `<p>${esc(t.description)}</p>` : ""}${ports ? `<ul class="ports">${ports}</ul>` : "<p><small>no ports</small></p>"}`;
}

function esc(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" })[c]);
}

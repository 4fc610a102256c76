// The editor's side panel: the selected node's name, type and path, its problems, a field
// per port its type declares (and per other attribute), adding an attribute, and the
// move buttons; the field being typed in keeps its focus and caret when it is drawn again.
// Apart from editor.js because it is markup drawn from the state, changing nothing: its
// fields are read by the editor's events, which call the actions.

import * as xml from "./xmldoc.js";

/** Draws the side panel for the selected node (a hint when none is). */
export function renderSidePanel(view) {
  const { section, state, selectedElement, subtreeEntry, indexOfElement, drawn } = view;
  const panel = section.querySelector(".side-panel");
  const el = selectedElement();
  if (!el) {
    panel.innerHTML = '<p class="hint">Click a node to see its name and ports. Drag nodes to move them; Alt+←/→ reorders, Alt+↑ moves out, Delete deletes, Insert adds the palette\'s type, Ctrl+C / Ctrl+X / Ctrl+V / Ctrl+D copy, cut, paste and duplicate.</p>';
    return;
  }
  const type = xml.typeOf(el);
  const entry = state.palette.get(type) || subtreeEntry(type);
  const i = indexOfElement(state.selected);
  const node = drawn[i];
  const errors = [...(state.check?.errors || []), ...(state.check?.warnings || []), ...(state.check?.lint || [])]
    .filter((p) => p.tree === state.treeId && p.element && p.element.join() === state.selected.join());
  const ports = entry?.ports || [];
  const known = new Set(["name", "ID", ...ports.map((p) => p.name)]);
  const extra = Array.from(el.attributes).map((a) => a.name).filter((n) => !known.has(n));
  let html = `<h2>${esc(xml.nameOf(el))}</h2><p class="node-type">${esc(type)} <small>${esc(entry?.category || "unknown type")}</small></p>`;
  html += `<p class="node-path">${esc(node?.path || "")}</p>`;
  if (errors.length) html += `<ul class="node-problems">${errors.map((p) => `<li>${esc(p.message)}</li>`).join("")}</ul>`;
  html += `<label class="field">name<input data-attr="name" value="${esc(el.getAttribute("name") || "")}" placeholder="${esc(type)}"></label>`;
  if (el.tagName === "SubTree") {
    html += `<button data-action="open-subtree">open tree ${esc(el.getAttribute("ID") || "")}</button>`;
  }
  if (ports.length) html += "<h3>Ports</h3>";
  for (const p of ports) {
    const value = el.getAttribute(p.name);
    html += `<label class="field" title="${esc(p.description || "")}"><span>${esc(p.name)} <small>${esc(p.direction)} ${esc(p.type || "")}</small></span>
      <input data-port="${esc(p.name)}" value="${esc(value ?? "")}" placeholder="${esc(p.default ?? "")}"></label>`;
    if (p.description) html += `<small class="port-doc">${esc(p.description)}</small>`;
  }
  if (extra.length) html += "<h3>Other attributes</h3>";
  for (const name of extra) {
    html += `<label class="field"><span>${esc(name)}</span><input data-port="${esc(name)}" value="${esc(el.getAttribute(name))}"></label>`;
  }
  html += `<h3>Add an attribute</h3><div class="add-attr"><input class="new-attr-name" placeholder="name"><input class="new-attr-value" placeholder="value"><button data-action="add-attribute">set</button></div>`;
  html += `<h3>Move</h3><div class="moves"><button data-action="move-earlier" title="Alt+←">← earlier</button><button data-action="move-later" title="Alt+→">later →</button><button data-action="move-out" title="Alt+↑">out ↑</button></div>`;
  const focused = document.activeElement && panel.contains(document.activeElement) ? document.activeElement : null;
  const focusKey = focused && (focused.dataset.port ? `[data-port="${CSS.escape(focused.dataset.port)}"]` : focused.dataset.attr ? `[data-attr="${focused.dataset.attr}"]` : null);
  const caret = focused?.selectionStart;
  panel.innerHTML = html;
  if (focusKey) {
    const again = panel.querySelector(focusKey);
    if (again) {
      again.focus();
      if (caret != null) again.setSelectionRange(caret, caret);
    }
  }
}

function esc(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" })[c]);
}

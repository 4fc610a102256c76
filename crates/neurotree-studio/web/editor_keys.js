// The editor's keyboard: save, undo and redo everywhere in the view; outside its fields,
// copy, cut, paste, duplicate, delete, add, reorder and move out, the arrow keys walking the
// tree, Enter opening a subtree. Apart from editor.js because it is one table of keys to
// the editor's actions, read in one place.

/** Answers the keys while the editor is the view shown. */
export function bindKeys(view) {
  document.addEventListener("keydown", (e) => onKey(view, e));
}

function onKey(view, e) {
  const { app, state, actions, palette, selectedElement, indexOfElement, drawn } = view;
  if (!app.isShown("edit")) return;
  const inField = /^(INPUT|TEXTAREA|SELECT)$/.test(document.activeElement?.tagName || "");
  const ctrl = e.ctrlKey || e.metaKey;
  const key = e.key.toLowerCase();
  if (ctrl && key === "s") {
    e.preventDefault();
    actions.save();
  } else if (ctrl && key === "z" && !inField) {
    e.preventDefault();
    e.shiftKey ? actions.redo() : actions.undo();
  } else if (ctrl && key === "y" && !inField) {
    e.preventDefault();
    actions.redo();
  } else if (inField) {
    return;
  } else if (ctrl && (key === "c" || key === "x")) {
    e.preventDefault();
    actions.copy(state.selected);
    if (key === "x") actions.remove(state.selected);
  } else if (ctrl && key === "v") {
    e.preventDefault();
    actions.paste(state.selected);
  } else if (ctrl && key === "d") {
    e.preventDefault();
    actions.duplicate(state.selected);
  } else if (e.key === "Delete" || e.key === "Backspace") {
    e.preventDefault();
    actions.remove(state.selected);
  } else if (e.key === "Insert" || (key === "a" && !ctrl)) {
    e.preventDefault();
    if (state.paletteType && e.key === "Insert") actions.add(state.paletteType, state.selected, "into");
    else palette.focus();
  } else if (e.altKey && (e.key === "ArrowLeft" || e.key === "ArrowDown")) {
    e.preventDefault();
    actions.shift(e.key === "ArrowLeft" ? -1 : 1);
  } else if (e.altKey && e.key === "ArrowRight") {
    e.preventDefault();
    actions.shift(1);
  } else if (e.altKey && e.key === "ArrowUp") {
    e.preventDefault();
    actions.shift(0);
  } else if (e.key.startsWith("Arrow") && state.selected) {
    e.preventDefault();
    navigate(view, e.key);
  } else if (e.key === "Enter" && state.selected) {
    const el = selectedElement();
    if (el?.tagName === "SubTree") actions.openTab(el.getAttribute("ID"), drawn[indexOfElement(state.selected)]?.path || "");
  }
}

// Arrow keys walk the tree: up to the parent, down to the first child, sideways to siblings.
function navigate(view, key) {
  const { state, actions, indexOfElement } = view;
  const p = state.selected;
  let next = null;
  if (key === "ArrowUp" && p.length > 1) next = p.slice(0, -1);
  else if (key === "ArrowDown") next = [...p, 0];
  else if (key === "ArrowLeft" && p[p.length - 1] > 0) next = [...p.slice(0, -1), p[p.length - 1] - 1];
  else if (key === "ArrowRight") next = [...p.slice(0, -1), p[p.length - 1] + 1];
  if (next && indexOfElement(next) >= 0) actions.select(next, true);
}

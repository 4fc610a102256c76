// The editor view: one file's trees drawn from its XML DOM, a palette of node types, a
// side panel with the selected node's name and ports, add / delete / move by drag and
// drop or keyboard, checks by the server's loader shown at the nodes, undo and redo,
// save (with the changed-on-disk conflict), a watch on the file's mtime, and SVG export.
//
// The view's state is one object, `state`, changed only by the functions of `actions`.
// Every edit is a named action that records the file's text before it: undo and redo swap
// those texts, so every edit, however made, undoes the same way.
//
// This file holds the state, the actions and the drawing of the view; the side panel
// (editor_panel.js), the problem list (editor_problems.js) and the keyboard
// (editor_keys.js) are modules of their own, given the view's parts as `view`.

import * as api from "./api.js";
import { bindKeys } from "./editor_keys.js";
import { renderSidePanel } from "./editor_panel.js";
import * as problems from "./editor_problems.js";
import { mountPalette } from "./palette.js";
import { TreeDrawing, drawingToolbar } from "./tree.js";
import * as xml from "./xmldoc.js";

const CHECK_DELAY_MS = 300;
const STAT_EVERY_MS = 2000;
// Typing into one field within this long is one undo step.
const COALESCE_MS = 1500;

export function mountEditor(section, app) {
  const state = {
    path: null,
    file: null, // {doc, prolog, epilog, separators, error}
    rawText: null, // the text when it is not well-formed XML
    savedText: "",
    mtime: null,
    diskMtime: null, // a newer mtime seen on disk and not acted on yet
    check: null,
    checking: false,
    palette: new Map(),
    treeId: null,
    tabs: [], // [{id, prefix}]
    selected: null, // element index path in the shown tree
    paletteType: null,
    clipboard: null, // a copied node, as XML text
    undo: [],
    redo: [],
    saving: false,
  };

  section.innerHTML = `
    <aside class="palette"></aside>
    <div class="edit-main">
      <div class="toolbar">
        <select class="file-select" aria-label="file"></select>
        <button data-action="open">open</button>
        <span class="sep"></span>
        <button data-action="undo" title="undo (Ctrl+Z)">↶ undo</button>
        <button data-action="redo" title="redo (Ctrl+Shift+Z)">↷ redo</button>
        <button data-action="add" title="add the palette's type to the selected node (Insert)">+ add</button>
        <button data-action="delete" title="delete the selected node (Delete)">delete</button>
        <button data-action="save" title="save (Ctrl+S)">save</button>
        <button data-action="reload" title="read the file from disk again">reload</button>
        <button data-action="export-svg" title="download the tree as SVG">export SVG</button>
        <span class="edit-status" data-edit-status></span>
      </div>
      <div class="banner" hidden></div>
      <div class="tree-tabs" role="tablist"></div>
      <div class="canvas-wrap"><div class="canvas"></div><textarea class="raw-text" hidden spellcheck="false"></textarea></div>
      <div class="problems"><h3>Problems <span class="problem-count"></span></h3><ul class="problem-list"></ul></div>
    </div>
    <aside class="side-panel"><p class="hint">Click a node to see its ports.</p></aside>`;

  const $ = (sel) => section.querySelector(sel);
  const canvas = $(".canvas");
  const drawing = new TreeDrawing(canvas, {
    draggable: true,
    onSelect: (i) => actions.select(i == null ? null : drawn[i].element),
    onOpen: (i) => drawn[i].subtree && actions.openTab(drawn[i].subtree, drawn[i].path),
    onDrop: (from, to, where) => actions.move(drawn[from].element, drawn[to].element, where),
    onDropType: (type, to, where) => actions.add(type, drawn[to].element, where),
  });
  $(".canvas-wrap").before(drawingToolbar(drawing, { onJump: (i) => actions.select(drawn[i].element, false) }));
  const palette = mountPalette($(".palette"), {
    onChoose: (type) => actions.choosePaletteType(type),
    onAdd: (type) => actions.add(type, state.selected, "into"),
  });
  let drawn = []; // the nodes of the shown tree, as drawn
  let checkTimer = null;
  let lastEdit = null; // {key, at} of the last attribute edit, to coalesce typing

  const text = () => (state.file && !state.file.error ? xml.serializeXml(state.file) : state.rawText ?? "");
  const shownTree = () => (state.file && !state.file.error ? xml.treeElement(state.file.doc, state.treeId) : null);
  const selectedElement = () => (state.selected && shownTree() ? xml.elementAt(shownTree(), state.selected) : null);
  const indexOfElement = (elPath) => drawn.findIndex((n) => n.element.join() === elPath.join());

  function setStatus(msg, kind = "") {
    const s = $(".edit-status");
    s.textContent = msg;
    s.dataset.kind = kind;
  }

  const isDirty = () => (state.file ? text() !== state.savedText : false);

  function flagState() {
    const dirty = isDirty();
    section.dataset.dirty = String(dirty);
    $('[data-action="undo"]').disabled = !state.undo.length;
    $('[data-action="redo"]').disabled = !state.redo.length;
    app.setTitle(state.path ? `${dirty ? "● " : ""}${state.path}` : "");
  }

  // What the side panel, the problem list and the keyboard read and call; `drawn` and
  // `actions` read when they are used (the one is replaced at every drawing, the other
  // defined below).
  const view = {
    section, app, state, drawing, palette, $, selectedElement, indexOfElement, subtreeEntry, setStatus, renderPanel,
    get drawn() {
      return drawn;
    },
    get actions() {
      return actions;
    },
  };

  // --- the actions: the only functions that change `state` -----------------------------
  const actions = {
    async open(path, { discard = false } = {}) {
      if (!path) return;
      if (!discard && isDirty() && !window.confirm(`${state.path} has edits not saved. Open ${path} and drop them?`)) return;
      setStatus(`opening ${path}…`);
      // The palette is asked for with the file, not after it.
      const asked = api.get("/api/palette", { path }).catch((e) => e);
      let answer;
      try {
        answer = await api.get("/api/file", { path });
      } catch (e) {
        setStatus(e.message, "error");
        return;
      }
      state.path = path;
      state.undo = [];
      state.redo = [];
      state.selected = null;
      state.diskMtime = null;
      state.mtime = answer.mtime;
      loadText(answer.text);
      // What an unedited file saves as: the DOM's serialization, not the bytes read.
      state.savedText = text();
      state.treeId = state.file.error ? null : xml.mainTreeId(state.file.doc, answer.check);
      state.tabs = state.treeId ? [{ id: state.treeId, prefix: "" }] : [];
      const pal = await asked;
      if (pal instanceof Error) setStatus(`palette: ${pal.message}`, "error");
      else {
        state.palette = new Map(pal.types.map((t) => [t.type, t]));
        // A name a file may write for a type (`<inverter>`) is drawn as that type; the
        // palette does not offer it.
        for (const a of pal.aliases || []) {
          const target = state.palette.get(a.type);
          if (target && !state.palette.has(a.name)) state.palette.set(a.name, { ...target, type: a.name, alias: a.type });
        }
      }
      app.remember({ view: "edit", file: path });
      $(".file-select").value = path;
      render({ fit: true });
      showCheck(answer.check);
      setStatus(answer.check?.ok === false ? "opened, with errors" : "opened");
      // Loaded once drawn (the layout comes from the server); for the time-to-drawn
      // measurement, the frame after the tree is in the DOM.
      drawing.drawn.then(() => {
        section.dataset.loaded = path;
        requestAnimationFrame(() => setTimeout(() => performance.mark(`studio:edit-drawn:${path}`), 0));
      });
    },

    openTab(id, prefix = "") {
      if (!xml.treeElement(state.file.doc, id)) {
        setStatus(`${id} is not a tree of this file: open the file that has it (an include, or a --model)`, "error");
        return;
      }
      if (!state.tabs.some((t) => t.id === id)) state.tabs.push({ id, prefix });
      else if (prefix) state.tabs.find((t) => t.id === id).prefix = prefix;
      state.treeId = id;
      state.selected = null;
      render({ fit: true });
      markProblems();
    },

    closeTab(id) {
      if (state.tabs.length < 2) return;
      state.tabs = state.tabs.filter((t) => t.id !== id);
      if (state.treeId === id) actions.openTab(state.tabs[0].id);
      else renderTabs();
    },

    select(elPath, reveal = false) {
      state.selected = elPath;
      const i = elPath ? indexOfElement(elPath) : -1;
      drawing.select(i >= 0 ? i : null, { reveal });
      renderPanel();
    },

    choosePaletteType(type) {
      state.paletteType = type;
      renderPalette();
    },

    setAttribute(elPath, name, value) {
      edit(`set ${name}`, `${state.treeId}:${elPath.join()}:${name}`, () => {
        const el = xml.elementAt(shownTree(), elPath);
        if (value === "" || value == null) el.removeAttribute(name);
        else el.setAttribute(name, value);
        return elPath;
      }, { redraw: name === "name" || name === "ID" });
    },

    add(type, target, where = "into") {
      const tree = shownTree();
      if (!tree || !type) return;
      const entry = state.palette.get(type) || subtreeEntry(type);
      edit(`add ${type}`, null, () => {
        const doc = state.file.doc;
        const unit = xml.indentUnit(doc);
        const el = xml.newElement(doc, type, entry);
        const at = target ? xml.elementAt(tree, target) : null;
        if (!at) {
          if (tree.firstElementChild) throw new Error("select a node to add to");
          xml.insertElement(tree, el, null, unit);
          return xml.pathOf(tree, el);
        }
        const isRoot = at.parentElement === tree;
        const category = xml.categoryOf(at, state.palette);
        let place = where;
        if (place === "into" && !xml.acceptsChild(at, category)) place = "after";
        if (isRoot && place !== "into") throw new Error(`the tree's root takes no siblings; add into a control`);
        if (place === "into") xml.insertElement(at, el, null, unit);
        else xml.insertElement(at.parentElement, el, place === "before" ? at : at.nextElementSibling, unit);
        return xml.pathOf(tree, el);
      });
    },

    // Copies the selected node and what is under it (as XML text, so that it can be
    // pasted into another tree or file).
    copy(elPath) {
      const el = elPath && xml.elementAt(shownTree(), elPath);
      if (!el) return;
      state.clipboard = new XMLSerializer().serializeToString(el);
      setStatus(`copied ${xml.nameOf(el)}`);
    },

    // Pastes the copied node into the selected one (after it, when it takes no child).
    paste(target) {
      const tree = shownTree();
      const at = target && xml.elementAt(tree, target);
      if (!state.clipboard || !at) return;
      const parsed = new DOMParser().parseFromString(state.clipboard, "application/xml").documentElement;
      if (!parsed || parsed.getElementsByTagName("parsererror").length) return;
      edit(`paste ${xml.nameOf(parsed)}`, null, () => {
        const doc = state.file.doc;
        const el = doc.importNode(parsed, true);
        const unit = xml.indentUnit(doc);
        const isRoot = at.parentElement === tree;
        const place = xml.acceptsChild(at, xml.categoryOf(at, state.palette)) ? "into" : "after";
        if (isRoot && place !== "into") throw new Error("the tree's root takes no siblings; paste into a control");
        if (place === "into") xml.insertElement(at, el, null, unit);
        else xml.insertElement(at.parentElement, el, at.nextElementSibling, unit);
        return xml.pathOf(tree, el);
      });
    },

    // A copy of the node and what is under it, right after it.
    duplicate(elPath) {
      const tree = shownTree();
      const el = elPath && xml.elementAt(tree, elPath);
      if (!el || el.parentElement === tree) return;
      edit(`duplicate ${xml.nameOf(el)}`, null, () => {
        const copy = el.cloneNode(true);
        xml.insertElement(el.parentElement, copy, el.nextElementSibling, xml.indentUnit(state.file.doc));
        return xml.pathOf(tree, copy);
      });
    },

    remove(elPath) {
      const tree = shownTree();
      const el = elPath && xml.elementAt(tree, elPath);
      if (!el) return;
      if (el.parentElement === tree) {
        setStatus("the tree's root cannot be deleted: add another root first, or delete the tree", "error");
        return;
      }
      edit(`delete ${xml.nameOf(el)}`, null, () => {
        const parent = el.parentElement;
        const next = el.nextElementSibling;
        const prev = el.previousElementSibling;
        xml.removeElement(el);
        return xml.pathOf(tree, next || prev || parent);
      });
    },

    move(from, to, where) {
      const tree = shownTree();
      const el = xml.elementAt(tree, from);
      const at = xml.elementAt(tree, to);
      if (!el || !at || el === at || el.contains(at)) return;
      if (el.parentElement === tree) return;
      const category = xml.categoryOf(at, state.palette);
      let place = where;
      if (place === "into" && !xml.acceptsChild(at, category)) place = "after";
      if (at.parentElement === tree && place !== "into") return;
      // Dropped where it already is: nothing to undo.
      if ((place === "after" && at.nextElementSibling === el) || (place === "before" && at.previousElementSibling === el)) return;
      if (place === "into" && at.lastElementChild === el) return;
      edit(`move ${xml.nameOf(el)}`, null, () => {
        const unit = xml.indentUnit(state.file.doc);
        xml.removeElement(el);
        if (place === "into") xml.insertElement(at, el, null, unit);
        else xml.insertElement(at.parentElement, el, place === "before" ? at : at.nextElementSibling, unit);
        return xml.pathOf(tree, el);
      });
    },

    // Moves the selected node one place earlier (-1) or later (+1) among its siblings, or
    // out of its parent (0), after it.
    shift(step) {
      const tree = shownTree();
      const el = selectedElement();
      if (!el || el.parentElement === tree) return;
      const parent = el.parentElement;
      if (step === 0) {
        if (parent.parentElement === tree) return;
        actions.move(xml.pathOf(tree, el), xml.pathOf(tree, parent), "after");
        return;
      }
      const sibling = step < 0 ? el.previousElementSibling : el.nextElementSibling;
      if (!sibling) return;
      actions.move(xml.pathOf(tree, el), xml.pathOf(tree, sibling), step < 0 ? "before" : "after");
    },

    undo() {
      const entry = state.undo.pop();
      if (!entry) return;
      state.redo.push({ name: entry.name, text: text(), selected: state.selected, treeId: state.treeId });
      restore(entry);
      setStatus(`undid ${entry.name}`);
    },

    redo() {
      const entry = state.redo.pop();
      if (!entry) return;
      state.undo.push({ name: entry.name, text: text(), selected: state.selected, treeId: state.treeId });
      restore(entry);
      setStatus(`redid ${entry.name}`);
    },

    applyRawText(newText) {
      edit("edit text", null, () => {
        loadText(newText);
        if (!state.file.error) {
          state.treeId = xml.mainTreeId(state.file.doc, state.check);
          state.tabs = state.treeId ? [{ id: state.treeId, prefix: "" }] : [];
        }
        return null;
      });
    },

    async save(overwrite = false) {
      if (!state.path || state.saving) return;
      const body = text();
      state.saving = true;
      setStatus("saving…");
      try {
        const answer = await api.post("/api/save", { path: state.path, text: body, mtime: overwrite ? null : state.mtime });
        state.mtime = answer.mtime;
        state.diskMtime = null;
        state.savedText = body;
        hideBanner();
        showCheck(answer.check);
        setStatus(`saved ${state.path}`, "ok");
        section.dataset.saved = String(answer.mtime);
      } catch (e) {
        if (e.status === 409) {
          showBanner("The file changed on disk since it was opened.", [
            ["Reload from disk (drop my edits)", () => actions.reload()],
            ["Overwrite with mine", () => actions.save(true)],
          ]);
          setStatus("not saved: changed on disk", "error");
        } else setStatus(`not saved: ${e.message}`, "error");
      } finally {
        state.saving = false;
        flagState();
      }
    },

    async reload() {
      hideBanner();
      const keep = { tabs: state.tabs, treeId: state.treeId };
      await actions.open(state.path, { discard: true });
      if (state.file && !state.file.error && xml.treeElement(state.file.doc, keep.treeId)) {
        state.tabs = keep.tabs.filter((t) => xml.treeElement(state.file.doc, t.id));
        actions.openTab(keep.treeId);
      }
    },

    async exportSvg() {
      if (!state.path) return;
      try {
        const blob = await api.postBlob("/api/svg", { path: state.path, text: text(), tree: state.treeId });
        const base = state.path.split("/").pop().replace(/\.xml$/i, "");
        api.download(blob, `${base}${state.treeId ? `-${state.treeId}` : ""}.svg`);
        setStatus("SVG exported", "ok");
      } catch (e) {
        setStatus(`export: ${e.message}`, "error");
      }
    },
  };

  // An edit: record the text before it, run it, draw again, check. `key` coalesces
  // repeated edits of one field into one undo step.
  function edit(name, key, change, { redraw = true } = {}) {
    const before = { name, text: text(), selected: state.selected, treeId: state.treeId };
    const now = performance.now();
    const coalesce = key && lastEdit && lastEdit.key === key && now - lastEdit.at < COALESCE_MS;
    let selected;
    try {
      selected = change();
    } catch (e) {
      setStatus(e.message, "error");
      return;
    }
    if (!coalesce) state.undo.push(before);
    lastEdit = key ? { key, at: now } : null;
    state.redo = [];
    if (selected !== undefined) state.selected = selected;
    if (redraw) render();
    else flagState();
    setStatus(name);
    scheduleCheck();
  }

  function restore(entry) {
    lastEdit = null;
    loadText(entry.text);
    state.treeId = entry.treeId;
    state.selected = entry.selected;
    if (state.file && !state.file.error && !xml.treeElement(state.file.doc, state.treeId)) {
      state.treeId = xml.mainTreeId(state.file.doc, state.check);
    }
    render();
    scheduleCheck();
  }

  function loadText(t) {
    const file = xml.parseXml(t);
    state.file = file;
    state.rawText = file.error ? t : null;
  }

  function subtreeEntry(type) {
    return state.file && xml.treeElement(state.file.doc, type) ? { type, category: "subtree", builtin: false } : null;
  }

  // --- checks --------------------------------------------------------------------------
  function scheduleCheck() {
    clearTimeout(checkTimer);
    section.dataset.check = "pending";
    checkTimer = setTimeout(runCheck, CHECK_DELAY_MS);
  }

  async function runCheck() {
    const body = text();
    try {
      const check = await api.post("/api/check", { path: state.path, text: body });
      if (body === text()) showCheck(check);
    } catch (e) {
      setStatus(`check: ${e.message}`, "error");
    }
  }

  function showCheck(check) {
    problems.showCheck(view, check);
  }

  function markProblems() {
    problems.markProblems(view);
  }

  // --- drawing -------------------------------------------------------------------------
  function render({ fit = false } = {}) {
    const raw = $(".raw-text");
    if (state.file?.error) {
      raw.hidden = false;
      canvas.hidden = true;
      if (raw.value !== state.rawText) raw.value = state.rawText;
      drawn = [];
      drawing.setTree([]);
    } else {
      raw.hidden = true;
      canvas.hidden = false;
      const tree = shownTree();
      const tab = state.tabs.find((t) => t.id === state.treeId);
      drawn = tree ? xml.nodesOfTree(tree, state.palette, tab?.prefix || "") : [];
      // The orientation is remembered per file (its main tree), and per tree for the
      // subtrees opened in tabs of their own.
      drawing.setTree(drawn, { keepView: !fit, key: tab?.prefix ? `${state.path}#${state.treeId}` : state.path });
      const i = state.selected ? indexOfElement(state.selected) : -1;
      if (state.selected && i < 0) state.selected = null;
      drawing.select(i >= 0 ? i : null);
      markProblems();
    }
    renderTabs();
    renderPalette();
    renderPanel();
    flagState();
  }

  function renderTabs() {
    const bar = $(".tree-tabs");
    bar.innerHTML = "";
    if (!state.file || state.file.error) return;
    for (const t of state.tabs) {
      const b = document.createElement("button");
      b.className = "tab";
      b.dataset.tree = t.id;
      b.setAttribute("role", "tab");
      b.setAttribute("aria-selected", String(t.id === state.treeId));
      b.innerHTML = `<span></span>${state.tabs.length > 1 ? '<span class="close" title="close">×</span>' : ""}`;
      b.firstChild.textContent = t.id;
      b.addEventListener("click", (e) => (e.target.classList.contains("close") ? actions.closeTab(t.id) : actions.openTab(t.id)));
      bar.append(b);
    }
    const others = xml.trees(state.file.doc).map((t) => t.getAttribute("ID")).filter((id) => !state.tabs.some((t) => t.id === id));
    if (others.length) {
      const sel = document.createElement("select");
      sel.className = "open-tree";
      sel.innerHTML = `<option value="">open tree…</option>`;
      for (const id of others) sel.add(new Option(id, id));
      sel.addEventListener("change", () => sel.value && actions.openTab(sel.value));
      bar.append(sel);
    }
  }

  function renderPalette() {
    const types = [...state.palette.values()].filter((t) => !t.alias);
    if (state.file && !state.file.error) {
      for (const t of xml.trees(state.file.doc)) {
        const id = t.getAttribute("ID");
        if (!state.palette.has(id)) types.push({ type: id, category: "subtree", builtin: false, description: "a tree of this file", ports: [] });
      }
    }
    palette.render(types, state.paletteType);
  }

  function renderPanel() {
    renderSidePanel(view);
  }

  function showBanner(message, buttons) {
    const b = $(".banner");
    b.hidden = false;
    b.innerHTML = "";
    const p = document.createElement("span");
    p.textContent = message;
    b.append(p);
    for (const [label, fn] of buttons) {
      const btn = document.createElement("button");
      btn.textContent = label;
      btn.addEventListener("click", fn);
      b.append(btn);
    }
  }

  function hideBanner() {
    $(".banner").hidden = true;
  }

  // --- events --------------------------------------------------------------------------
  section.addEventListener("click", (e) => {
    const a = e.target.closest("[data-action]")?.dataset.action;
    if (!a) return;
    const sel = state.selected;
    if (a === "open") actions.open($(".file-select").value);
    else if (a === "undo") actions.undo();
    else if (a === "redo") actions.redo();
    else if (a === "save") actions.save();
    else if (a === "reload") actions.reload();
    else if (a === "export-svg") actions.exportSvg();
    else if (a === "add") state.paletteType ? actions.add(state.paletteType, sel, "into") : setStatus("pick a type in the palette first", "error");
    else if (a === "delete") actions.remove(sel);
    else if (a === "open-subtree") {
      const el = selectedElement();
      actions.openTab(el.getAttribute("ID"), drawn[indexOfElement(sel)]?.path || "");
    } else if (a === "move-earlier") actions.shift(-1);
    else if (a === "move-later") actions.shift(1);
    else if (a === "move-out") actions.shift(0);
    else if (a === "add-attribute") {
      const name = $(".new-attr-name").value.trim();
      if (name && sel) actions.setAttribute(sel, name, $(".new-attr-value").value);
      renderPanel();
    }
  });

  section.addEventListener("input", (e) => {
    const t = e.target;
    if (!state.selected) return;
    if (t.dataset.port) actions.setAttribute(state.selected, t.dataset.port, t.value);
    else if (t.dataset.attr === "name") actions.setAttribute(state.selected, "name", t.value);
  });
  // A renamed node is drawn again once the field is left, not at every key.
  section.addEventListener("change", (e) => {
    if (e.target.dataset.attr === "name") render();
  });

  $(".raw-text").addEventListener("change", (e) => actions.applyRawText(e.target.value));

  bindKeys(view);
  // Leaving the page with edits not saved asks first.
  window.addEventListener("beforeunload", (e) => {
    if (isDirty()) e.preventDefault();
  });

  // The file on disk: noticed when it changes, offered for reload.
  setInterval(async () => {
    if (!state.path || state.saving || !app.isShown("edit")) return;
    try {
      const { mtime } = await api.get("/api/stat", { path: state.path });
      if (mtime !== state.mtime && mtime !== state.diskMtime) {
        state.diskMtime = mtime;
        showBanner(`${state.path} changed on disk.`, [
          ["Reload", () => actions.reload()],
          ["Keep mine", () => hideBanner()],
        ]);
      }
    } catch {
      /* the server may be restarting; the next poll tries again */
    }
  }, STAT_EVERY_MS);

  async function listFiles() {
    try {
      const { files } = await api.get("/api/files");
      const sel = $(".file-select");
      sel.innerHTML = "";
      for (const f of files.filter((f) => f.kind === "tree")) sel.add(new Option(f.path, f.path));
      if (state.path) sel.value = state.path;
    } catch (e) {
      setStatus(`files: ${e.message}`, "error");
    }
  }
  listFiles();

  return { actions, state, drawing, show: () => drawing.fit() };
}

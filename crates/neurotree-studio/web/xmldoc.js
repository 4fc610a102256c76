// A BehaviorTree.CPP file kept as an XML DOM, so that what the editor does not touch
// (comments, other trees, TreeNodesModel, attributes it does not know, the XML
// declaration) is written back as it was read. Nodes are addressed as the server's Check
// addresses them: a `<BehaviorTree ID=…>` and the indices of element children from it
// down (`[0]` is the tree's root node, `[0, 2]` its third child).

const CATEGORY_TAGS = { Action: "action", Condition: "condition", Control: "control", Decorator: "decorator", SubTree: "subtree" };

/** A parsed file: `{doc, prolog, epilog, separators, error}`; `error` is the parser's message, if any. */
export function parseXml(text) {
  const first = parseStrict(text);
  if (!first.error) return first;
  // BehaviorTree.CPP (tinyxml2) and NeuroTree's loader read a bare `&` or `<` inside an
  // attribute (`if="A>-B && ok"`), which XML forbids; such a file is read with them
  // escaped, and saved so (it loads the same).
  const repaired = escapeLoose(text);
  if (repaired === text) return first;
  const second = parseStrict(repaired);
  return second.error ? first : { ...second, repaired: true };
}

function parseStrict(text) {
  const doc = new DOMParser().parseFromString(text, "application/xml");
  const bad = doc.getElementsByTagName("parsererror")[0];
  // What the DOM cannot hold: the declaration and the line breaks around the top level.
  const prolog = /^\s*(<\?xml[^]*?\?>\s*)?/.exec(text)[0];
  const epilog = /\s*$/.exec(text)[0];
  const separators = bad ? [] : topLevelSeparators(text.slice(prolog.length), doc);
  // Chrome wraps the parser's message in a page of its own: keep the message.
  const error = bad ? (bad.querySelector("div")?.textContent || bad.textContent).trim() : null;
  return { doc, prolog, epilog, separators, error };
}

// `text` with every `&` that starts no entity escaped, and every `<` inside a quoted
// attribute value; comments, CDATA and processing instructions are left as they are.
function escapeLoose(text) {
  let out = "";
  let i = 0;
  const bareAmp = /&(?!(?:amp|lt|gt|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);)/g;
  const startsBare = /^&(?!(?:amp|lt|gt|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);)/;
  while (i < text.length) {
    const lt = text.indexOf("<", i);
    if (lt < 0) {
      out += text.slice(i).replace(bareAmp, "&amp;");
      break;
    }
    out += text.slice(i, lt).replace(bareAmp, "&amp;");
    const skip = [["<!--", "-->"], ["<![CDATA[", "]]>"], ["<?", "?>"], ["<!", ">"]].find(([a]) => text.startsWith(a, lt));
    if (skip) {
      const end = text.indexOf(skip[1], lt + skip[0].length);
      const stop = end < 0 ? text.length : end + skip[1].length;
      out += text.slice(lt, stop);
      i = stop;
      continue;
    }
    // A tag: copy up to its closing `>`, escaping inside quoted values.
    let j = lt + 1;
    let quote = null;
    let tag = "<";
    for (; j < text.length; j++) {
      const c = text[j];
      if (quote) {
        if (c === quote) quote = null;
        tag += c === "<" ? "&lt;" : c === "&" && startsBare.test(text.slice(j, j + 12)) ? "&amp;" : c;
      } else {
        tag += c;
        if (c === '"' || c === "'") quote = c;
        else if (c === ">") break;
      }
    }
    out += tag;
    i = j + 1;
  }
  return out;
}

// The whitespace between the top-level nodes of `body` (comments and the root element),
// so that an unedited file keeps its line breaks.
function topLevelSeparators(body, doc) {
  const seps = [];
  const rootTag = doc.documentElement?.tagName;
  let pos = 0;
  let first = true;
  while (pos < body.length) {
    const ws = /^\s*/.exec(body.slice(pos))[0];
    pos += ws.length;
    if (pos >= body.length) break;
    if (!first) seps.push(ws);
    first = false;
    const m = /^(<!--[^]*?-->|<!DOCTYPE[^>]*>|<\?[^]*?\?>)/.exec(body.slice(pos));
    if (m) {
      pos += m[0].length;
      continue;
    }
    const close = rootTag ? body.lastIndexOf(`</${rootTag}`) : -1;
    if (close >= pos) pos = body.indexOf(">", close) + 1;
    else pos = body.indexOf("/>", pos) + 2;
    if (pos <= 1) break;
  }
  return seps;
}

/** The text of a parsed file. */
export function serializeXml(file) {
  const ser = new XMLSerializer();
  const parts = Array.from(file.doc.childNodes).map((n) => ser.serializeToString(n));
  let out = file.prolog;
  parts.forEach((p, i) => {
    if (i > 0) out += file.separators[i - 1] ?? "\n";
    out += p;
  });
  return out + file.epilog;
}

export function trees(doc) {
  return Array.from(doc.documentElement?.children || []).filter((e) => e.tagName === "BehaviorTree");
}

export function treeElement(doc, id) {
  return trees(doc).find((t) => t.getAttribute("ID") === id) || null;
}

/** The tree to show first: main_tree_to_execute, else the Check's main, else the first. */
export function mainTreeId(doc, check) {
  const ids = trees(doc).map((t) => t.getAttribute("ID"));
  const named = doc.documentElement?.getAttribute("main_tree_to_execute");
  if (named && ids.includes(named)) return named;
  if (check?.main && ids.includes(check.main)) return check.main;
  return ids[0] ?? null;
}

export function elementAt(tree, path) {
  let el = tree;
  for (const i of path) {
    el = el?.children[i];
    if (!el) return null;
  }
  return el;
}

export function pathOf(tree, el) {
  const path = [];
  while (el && el !== tree) {
    const parent = el.parentElement;
    if (!parent) return null;
    path.unshift(Array.prototype.indexOf.call(parent.children, el));
    el = parent;
  }
  return el === tree ? path : null;
}

/** A node element's type: the ID of `<Action ID=…>` and its kin, else its tag. */
export function typeOf(el) {
  return CATEGORY_TAGS[el.tagName] && el.hasAttribute("ID") ? el.getAttribute("ID") : el.tagName;
}

/** A node's name: its `name` attribute, else its type (PROTOCOL.md "Node path"). */
export function nameOf(el) {
  return el.getAttribute("name") || typeOf(el);
}

/** The category of a node element, by the palette's types, else its tag. */
export function categoryOf(el, palette) {
  if (el.tagName === "SubTree") return "subtree";
  return palette.get(typeOf(el))?.category || CATEGORY_TAGS[el.tagName] || "action";
}

/**
 * The nodes of one tree for a drawing, in pre-order: `{name, type, category, path,
 * element: [indices], ports, children}`; `prefix` goes before every path.
 */
export function nodesOfTree(tree, palette, prefix = "") {
  const nodes = [];
  const walk = (el, elPath, parentPath) => {
    const index = nodes.length;
    const name = nameOf(el);
    const path = parentPath ? `${parentPath}/${name}` : name;
    const node = {
      id: null,
      name,
      type: typeOf(el),
      category: categoryOf(el, palette),
      path,
      element: elPath,
      subtree: el.tagName === "SubTree" ? el.getAttribute("ID") : null,
      ports: portsOf(el, palette),
      directions: directionsOf(el, palette),
      children: [],
    };
    nodes.push(node);
    Array.from(el.children).forEach((c, i) => {
      node.children.push(nodes.length);
      walk(c, [...elPath, i], path);
    });
    return index;
  };
  Array.from(tree.children).forEach((el, i) => walk(el, [i], prefix));
  return nodes;
}

/**
 * A node element's ports as `neurotree show` draws them (render::node_ports): its
 * attributes but `name`, `ID` and the `_`-prefixed ones (pre- and post-conditions,
 * `_autoremap`), which are not ports; and the ports its type declares with a default that
 * the file leaves out, which the loader gives the node.
 */
export function portsOf(el, palette) {
  const ports = {};
  for (const a of el.attributes) {
    if (a.name !== "name" && a.name !== "ID" && !a.name.startsWith("_")) ports[a.name] = a.value;
  }
  const type = el.tagName === "SubTree" ? null : palette?.get(typeOf(el));
  if (type) {
    for (const p of type.ports || []) if (!(p.name in ports) && p.default != null) ports[p.name] = p.default;
  }
  return ports;
}

/** Which way each port the element's type declares carries data, from the palette (as
 * `Blueprint::port_direction` gives the page's TreeViews): `{name: "input" | …}`. */
export function directionsOf(el, palette) {
  const type = el.tagName === "SubTree" ? null : palette?.get(typeOf(el));
  return Object.fromEntries((type?.ports || []).map((p) => [p.name, p.direction]));
}

/** The indentation one level adds in this file (two spaces when it cannot tell). */
export function indentUnit(doc) {
  for (const t of trees(doc)) {
    const a = indentOf(t);
    const child = t.firstElementChild;
    const b = child && indentOf(child);
    if (a != null && b != null && b.length > a.length) return b.slice(a.length);
  }
  return "  ";
}

function isBlank(node) {
  return node && node.nodeType === Node.TEXT_NODE && /^\s*$/.test(node.data);
}

function indentOf(el) {
  const prev = el.previousSibling;
  if (!isBlank(prev) || !prev.data.includes("\n")) return null;
  return prev.data.slice(prev.data.lastIndexOf("\n") + 1);
}

/** Inserts `el` into `parent` before `before` (null: last), on a line of its own. */
export function insertElement(parent, el, before, unit) {
  const doc = parent.ownerDocument;
  const outer = indentOf(parent) ?? "";
  const inner = outer + unit;
  if (!parent.firstElementChild) {
    for (const n of Array.from(parent.childNodes)) if (isBlank(n)) n.remove();
    parent.append(doc.createTextNode(`\n${inner}`), el, doc.createTextNode(`\n${outer}`));
  } else if (before) {
    parent.insertBefore(el, before);
    parent.insertBefore(doc.createTextNode(`\n${inner}`), before);
  } else {
    const last = parent.lastElementChild;
    const gap = doc.createTextNode(`\n${inner}`);
    parent.insertBefore(gap, last.nextSibling);
    parent.insertBefore(el, gap.nextSibling);
  }
  reindent(el, inner, unit);
}

/** Takes `el` out of the document with the line break before it. */
export function removeElement(el) {
  const parent = el.parentNode;
  if (isBlank(el.previousSibling)) el.previousSibling.remove();
  el.remove();
  if (parent && !parent.firstElementChild && parent.nodeType === Node.ELEMENT_NODE) {
    for (const n of Array.from(parent.childNodes)) if (isBlank(n)) n.remove();
  }
}

// Line breaks inside a moved element follow its new depth.
function reindent(el, indent, unit) {
  for (const n of Array.from(el.childNodes)) {
    if (isBlank(n) && n.data.includes("\n")) {
      const closing = !n.nextSibling;
      n.data = `\n${closing ? indent : indent + unit}`;
    } else if (n.nodeType === Node.ELEMENT_NODE) {
      reindent(n, indent + unit, unit);
    }
  }
}

/** Whether node `el` may hold another child: controls always, decorators when empty. */
export function acceptsChild(el, category) {
  if (category === "control") return true;
  if (category === "decorator") return el.children.length === 0;
  return false;
}

/** A new element for a node of `type` (its palette entry, if any). */
export function newElement(doc, type, entry) {
  if (entry?.category === "subtree" && !entry.builtin) {
    const el = doc.createElement("SubTree");
    el.setAttribute("ID", type);
    return el;
  }
  return doc.createElement(type);
}

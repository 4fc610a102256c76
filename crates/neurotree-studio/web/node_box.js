// A node's box as the page draws it, the same as `neurotree show --format svg` draws it
// (crates/neurotree-toolkit/src/render/node_box.rs and svg.rs): its shape, its lines (name,
// type, one per port, long ones shortened with … and whole in the title) and its size,
// measured with the renderer's own sizes and font-width tables, which the studio serves.
// A port line starts with its direction's mark (`in `, `out `, `inout `) when the node's
// type declares the port.

import METRICS from "./drawing-metrics.js";

// The sizes and font widths of the SVG renderer (crates/neurotree-toolkit/src/render/
// node_box.rs), served by the studio as a module: the page's boxes are the command's,
// from one table.
export const M = METRICS;
export const NODE_HEIGHT = M.node_height;

/** How wide `text` is drawn at `size` px, by the renderer's DejaVu Sans tables. */
export function textWidth(text, size, bold) {
  const table = bold ? M.bold : M.regular;
  let total = 0;
  for (const ch of text) {
    const c = ch.codePointAt(0);
    if (c >= 32 && c <= 126) total += table[c - 32];
    else if (M.wide_ranges.some(([from, to]) => c >= from && c <= to)) total += M.wide;
    else total += M.other;
  }
  return (total * size) / 1000;
}

// The mark a port line starts with, by direction (`input`, `output`, `inout`).
const MARKS = Object.fromEntries(M.direction_marks);

/** `{mark}name: value` cut to the renderer's port width, value first (node_box.rs's
 * `shorten`). */
function shorten(mark, name, value) {
  const fits = (n, v) => textWidth(`${mark}${n}: ${v}`, M.port_size, false) <= M.port_width;
  if (fits(name, value)) return [name, value];
  const v = Array.from(value);
  while (v.length) {
    v.pop();
    if (fits(name, `${v.join("")}…`)) return [name, `${v.join("")}…`];
  }
  const n = Array.from(name);
  for (;;) {
    const cut = `${n.join("")}…`;
    if (!n.length || fits(cut, "")) return [cut, ""];
    n.pop();
  }
}

/** A node's ports (`{name: text}` as written) as the lines drawn under its name, each
 * marked with its direction from `directions` (`{name: "input" | "output" | "inout"}`). */
export function portLines(ports, directions) {
  return Object.entries(ports || {}).map(([rawName, rawValue]) => {
    const name = printable(rawName);
    const value = printable(rawValue);
    const direction = MARKS[directions?.[rawName]] != null ? directions[rawName] : null;
    const mark = direction ? MARKS[direction] : "";
    const [shownName, shownValue] = shorten(mark, name, value);
    return {
      name: shownName, value: shownValue, direction, mark,
      binding: /^\{.*\}$/s.test(value), whole: `${mark}${name}: ${value}`,
    };
  });
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

export function printable(text) {
  // eslint-disable-next-line no-control-regex
  return String(text).replace(/[\n\r\t]/g, " ").replace(/[\u0000-\u001f\u007f]/g, "\ufffd");
}

export function r(v) {
  return Math.round(v * 10) / 10;
}

/** The box a node needs, as node_box.rs's `box_size` computes it: `{w, h}`. */
export function boxSize(node, shape) {
  const name = textWidth(node.label, M.name_size, true);
  const type = node.typeLabel ? textWidth(node.typeLabel, M.type_size, false) : 0;
  const ports = node.portLines.reduce((most, p) => Math.max(most, textWidth(`${p.mark}${p.name}: ${p.value}`, M.port_size, false)), 0);
  let width = Math.max(name, type, ports) + 2 * M.padding;
  if (GLYPH[shape]) width += M.glyph_width;
  else if (shape === "decorator") width += 2 * M.slant;
  else if (shape === "condition") width += NODE_HEIGHT / 2;
  else if (shape === "subtree") width += 6;
  const lines = 1 + (node.typeLabel ? 1 : 0) + node.portLines.length;
  return { w: Math.ceil(Math.max(width, M.min_width)), h: NODE_HEIGHT + M.line_step * Math.max(0, lines - 2) };
}

/** Where a node's fold toggle sits: under it top-down, at its right end left to right. */
export function togglePlace(node, orientation) {
  return orientation === "LR" ? `translate(${r(node.w / 2 + 8)},${r(node.h / 2)})` : `translate(0,${r(node.h + 7)})`;
}

/** The markup of one node at `at` (its top centre; null: hidden), drawn centred on
 * (0, 0) horizontally with its top at y = 0. */
export function nodeMarkup(node, index, at, folded, orientation) {
  const shape = node.shape;
  const w = node.w;
  const h = node.h;
  const l = -w / 2;
  let out = "";
  if (shape === "decorator") {
    const s = M.slant;
    const pts = [[l, h / 2], [l + s, 0], [l + w - s, 0], [l + w, h / 2], [l + w - s, h], [l + s, h]]
      .map(([x, y]) => `${r(x)},${r(y)}`).join(" ");
    out += `<polygon class="shape" points="${pts}"/>`;
  } else {
    const rx = shape === "condition" ? Math.min(h, NODE_HEIGHT) / 2 : shape === "action" ? 8 : 2;
    out += `<rect class="shape" x="${r(l)}" y="0" width="${w}" height="${h}" rx="${rx}"/>`;
    if (shape === "subtree") out += `<rect class="inner" x="${r(l + 3)}" y="3" width="${w - 6}" height="${h - 6}" rx="1"/>`;
  }
  let left = l;
  let right = l + w;
  const glyph = GLYPH[shape];
  if (glyph) {
    const g = M.glyph_width;
    out += `<line class="inner" x1="${r(l + g)}" y1="0" x2="${r(l + g)}" y2="${h}"/>`
      + `<text class="glyph" x="${r(l + g / 2)}" y="${r(h / 2 + 15 * 0.35)}">${glyph}</text>`;
    left = l + g;
  } else if (shape === "condition") {
    left = l + NODE_HEIGHT / 4;
    right = l + w - NODE_HEIGHT / 4;
  }
  const centre = r((left + right) / 2);
  const alone = !node.typeLabel && !node.portLines.length;
  let y = M.first_baseline;
  out += `<text class="name" x="${centre}" y="${alone ? r(h / 2 + M.name_size * 0.35) : y}">${escapeXml(node.label)}</text>`;
  if (node.typeLabel) {
    y += M.line_step;
    out += `<text class="type" x="${centre}" y="${y}">${escapeXml(node.typeLabel)}</text>`;
  }
  for (const p of node.portLines) {
    y += M.line_step;
    const direction = p.direction ? ` data-direction="${p.direction}"` : "";
    const mark = p.direction ? `<tspan class="direction">${escapeXml(p.mark)}</tspan>` : "";
    out += `<text class="port"${direction} x="${centre}" y="${y}">${mark}<tspan class="port-name">${escapeXml(p.name)}: </tspan>`
      + `<tspan class="${p.binding ? "binding" : "literal"}">${escapeXml(p.value)}</tspan></text>`;
  }
  if (node.children.length) {
    out += `<g class="toggle" transform="${togglePlace(node, orientation)}"><circle r="6"/><text y="3.5">${folded ? "+" : "−"}</text></g>`;
  }
  const id = node.id == null ? "" : ` data-node-id="${node.id}"`;
  const place = at ? ` transform="translate(${r(at.x)},${r(at.y)})"` : ' display="none"';
  const fold = folded ? " data-collapsed" : "";
  const title = `${node.path} (${node.type})${node.portLines.map((p) => `\n${p.whole}`).join("")}`;
  const family = shape === "sequential" || shape === "alternative" || shape === "concurrent" ? "control" : shape;
  return `<g class="node ${family}" data-index="${index}" data-node-path="${escapeXml(node.path)}"${id}${place}${fold}><title>${escapeXml(title)}</title>${out}</g>`;
}


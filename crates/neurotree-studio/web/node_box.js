// A node's box as the page draws it, the same as `neurotree show --format svg` draws it.
// Everything about the box comes from the renderer (crates/neurotree-toolkit/src/render/
// plan.rs, served as `POST /api/layout`): its shape and family, its glyph, its lines made
// printable (name, type, one per port, long ones shortened with … and whole in the title),
// its size at full detail and at the compact detail (the name alone, wrapped onto two lines
// when long). This module only writes the markup.

import METRICS from "./drawing-metrics.js";

// The sizes of the SVG renderer (node_box.rs), served by the studio as a module.
export const M = METRICS;
export const NODE_HEIGHT = M.node_height;

export function escapeXml(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&apos;" })[c]);
}

export function r(v) {
  return Math.round(v * 10) / 10;
}

/** Where a node's fold toggle sits: under it top-down, at its right end left to right. */
export function togglePlace(node, orientation) {
  return orientation === "LR" ? `translate(${r(node.w / 2 + 8)},${r(node.h / 2)})` : `translate(0,${r(node.h + 7)})`;
}

/** A node's size at `detail` ("full" or "compact"): `{w, h}`. */
export function sizeAt(box, detail) {
  return detail === "compact" ? { w: box.compact.width, h: box.compact.height } : { w: box.width, h: box.height };
}

/** The title viewers show on hover: path, type, every port whole. */
export function titleOf(node) {
  return `${node.path} (${node.type})${node.box.ports.map((p) => `\n${p.whole}`).join("")}`;
}

/** The shape and lines of one node at `detail`, drawn centred on x = 0, its top at y = 0
 * (the inside of its `.body` group). */
export function bodyMarkup(node, detail, folded, orientation) {
  const box = node.box;
  const shape = box.shape;
  const { w, h } = sizeAt(box, detail);
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
  if (box.glyph) {
    const g = M.glyph_width;
    out += `<line class="inner" x1="${r(l + g)}" y1="0" x2="${r(l + g)}" y2="${h}"/>`
      + `<text class="glyph" x="${r(l + g / 2)}" y="${r(h / 2 + 15 * 0.35)}">${box.glyph}</text>`;
    left = l + g;
  } else if (shape === "condition") {
    left = l + Math.min(h, NODE_HEIGHT) / 4;
    right = l + w - Math.min(h, NODE_HEIGHT) / 4;
  }
  const centre = r((left + right) / 2);
  if (detail === "compact") {
    const lines = box.compact.lines;
    const first = h / 2 + M.name_size * 0.35 - ((lines.length - 1) * M.line_step) / 2;
    lines.forEach((line, k) => {
      out += `<text class="name" x="${centre}" y="${r(first + k * M.line_step)}">${escapeXml(line)}</text>`;
    });
  } else {
    const alone = !box.type_label && !box.ports.length;
    let y = M.first_baseline;
    out += `<text class="name" x="${centre}" y="${alone ? r(h / 2 + M.name_size * 0.35) : y}">${escapeXml(box.label)}</text>`;
    if (box.type_label) {
      y += M.line_step;
      out += `<text class="type" x="${centre}" y="${y}">${escapeXml(box.type_label)}</text>`;
    }
    for (const p of box.ports) {
      y += M.line_step;
      const direction = p.direction ? ` data-direction="${p.direction}"` : "";
      const mark = p.direction ? `<tspan class="direction">${escapeXml(p.mark)}</tspan>` : "";
      const text = `<text class="port"${direction} x="${centre}" y="${y}">${mark}<tspan class="port-name">${escapeXml(p.name)}: </tspan>`
        + `<tspan class="${p.binding ? "binding" : "literal"}">${escapeXml(p.value)}</tspan></text>`;
      // A line cut on the node is whole in a title of its own, shown on hover over it.
      out += p.cut ? `<g class="cut" data-whole="${escapeXml(p.whole)}"><title>${escapeXml(p.whole)}</title>${text}</g>` : text;
    }
  }
  if (node.children.length) {
    out += `<g class="toggle" transform="${togglePlace({ w, h }, orientation)}"><circle r="6"/><text y="3.5">${folded ? "+" : "−"}</text></g>`;
  }
  return out;
}

/** The markup of one node at `at` (its top centre; null: hidden). */
export function nodeMarkup(node, index, at, folded, orientation, detail) {
  const id = node.id == null ? "" : ` data-node-id="${node.id}"`;
  const place = at ? ` transform="translate(${r(at.x)},${r(at.y)})"` : ' display="none"';
  const fold = folded ? " data-collapsed" : "";
  return `<g class="node ${node.box.family}" data-index="${index}" data-node-path="${escapeXml(node.path)}"${id}${place}${fold}>`
    + `<title>${escapeXml(titleOf(node))}</title><g class="body">${bodyMarkup(node, detail, folded, orientation)}</g></g>`;
}

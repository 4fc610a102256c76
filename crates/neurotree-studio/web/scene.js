// The scene panel: the world a watched tree acts on, as the run draws it each tick
// (PROTOCOL.md, "Scene"): polygons, polylines, circles and texts in world coordinates (y
// up), drawn as SVG scaled to the scene's bounds. Each item's element carries
// `data-scene-item` with the item's id, for tests and scripts.

const SVG = "http://www.w3.org/2000/svg";

export class SceneView {
  // `box` is the panel: hidden while the run draws no scene.
  constructor(box) {
    this.box = box;
    // Its own look, kept here with its only user: a band under the tree, a third of the
    // view's height (the `hidden` attribute still hides it: no display is set).
    box.style.cssText = "flex: 0 0 36%; min-height: 120px; position: relative; border-top: 1px solid #ccc; background: #fbfbf8;";
    this.svg = document.createElementNS(SVG, "svg");
    this.svg.style.cssText = "width: 100%; height: 100%; display: block;";
    this.svg.setAttribute("preserveAspectRatio", "xMidYMid meet");
    this.note = document.createElement("p");
    this.note.className = "hint";
    this.note.style.cssText = "position: absolute; left: 8px; top: 4px; margin: 0;";
    box.append(this.svg, this.note);
    this.shown = null;
  }

  // Shows `scene` (null: none), or says `why` it is not drawn.
  set(scene, why) {
    if (!scene) {
      this.shown = null;
      this.svg.replaceChildren();
      this.note.textContent = why ? `the scene is not drawn: ${why}` : "";
      this.box.hidden = !why;
      this.box.dataset.items = "0";
      return;
    }
    this.box.hidden = false;
    this.note.textContent = "";
    this.shown = scene;
    const [[x0, y0], [x1, y1]] = scene.bounds;
    // World y points up, SVG y down: every y is negated, so the view starts at -y1.
    this.svg.setAttribute("viewBox", `${x0} ${-y1} ${Math.max(x1 - x0, 1e-9)} ${Math.max(y1 - y0, 1e-9)}`);
    const elements = scene.items.map(drawItem);
    this.svg.replaceChildren(...elements);
    this.box.dataset.items = String(elements.length);
  }
}

function drawItem(item) {
  let el;
  const pts = (points) => points.map(([x, y]) => `${x},${-y}`).join(" ");
  switch (item.shape) {
    case "polygon":
      el = document.createElementNS(SVG, "polygon");
      el.setAttribute("points", pts(item.points));
      break;
    case "polyline":
      el = document.createElementNS(SVG, "polyline");
      el.setAttribute("points", pts(item.points));
      el.setAttribute("fill", "none");
      el.setAttribute("stroke-linejoin", "round");
      el.setAttribute("stroke-linecap", "round");
      break;
    case "circle":
      el = document.createElementNS(SVG, "circle");
      el.setAttribute("cx", item.center[0]);
      el.setAttribute("cy", -item.center[1]);
      el.setAttribute("r", item.radius);
      break;
    case "text":
      el = document.createElementNS(SVG, "text");
      el.setAttribute("x", item.at[0]);
      el.setAttribute("y", -item.at[1]);
      el.setAttribute("font-size", item.size);
      el.textContent = item.text;
      break;
    default:
      el = document.createElementNS(SVG, "g");
  }
  // Filled shapes without an outline meet their neighbours edge to edge (a row of wall
  // cells): drawn crisp, no seam shows between them.
  if (item.fill && !item.stroke && item.shape === "polygon") el.setAttribute("shape-rendering", "crispEdges");
  if (item.fill) el.setAttribute("fill", item.fill);
  else if (item.shape !== "polyline") el.setAttribute("fill", "none");
  if (item.stroke) {
    el.setAttribute("stroke", item.stroke);
    el.setAttribute("stroke-width", item.width || 0.05);
  }
  el.dataset.sceneItem = item.id;
  return el;
}

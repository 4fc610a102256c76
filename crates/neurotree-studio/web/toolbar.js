// A drawing's toolbar: search, orientation, fit (and what it chose), zoom, collapse and
// expand, the panels beside the tree, the overview.

/**
 * Hides the panels of the view `bar` sits in (the palette, the side panel), giving the tree
 * the window, or shows them again. The drawing's resize observer refits a view the user has
 * not moved.
 */
function togglePanels(bar) {
  const view = bar.closest(".view");
  const hide = view.dataset.panels !== "hidden";
  if (hide) view.dataset.panels = "hidden";
  else delete view.dataset.panels;
  bar.querySelector('[data-action="panels"]').setAttribute("aria-pressed", String(hide));
}

/** A toolbar for a drawing: search, orientation, fit, zoom, collapse all / expand all, panels. */
export function drawingToolbar(drawing, { onJump } = {}) {
  const bar = document.createElement("div");
  bar.className = "drawing-tools";
  bar.innerHTML = `<input type="search" class="node-search" placeholder="search name or type" aria-label="search nodes">
    <span class="match-count"></span>
    <button data-action="search-prev" title="previous match">▲</button><button data-action="search-next" title="next match (Enter)">▼</button>
    <button data-action="orientation" title="lay the tree out left to right or top down"></button>
    <button data-action="fit" title="show the whole tree: the orientation that fits best, names only when the whole nodes do not fit">fit</button>
    <span class="fit-choice" data-fit-choice title="what the drawing shows: the whole nodes, or their names (the rest on hover, on selection and zoomed in)"></span>
    <button data-action="zoom-in" title="zoom in around the selected node">+</button><button data-action="zoom-out" title="zoom out around the selected node">−</button>
    <button data-action="collapse-all" title="collapse every control">collapse</button><button data-action="expand-all" title="expand everything">expand</button>
    <button data-action="panels" title="hide the panels beside the tree, or show them again" aria-pressed="false">panels</button>
    <button data-action="overview" title="show or hide the overview of a tree larger than the view" aria-pressed="true">overview</button>`;
  const input = bar.querySelector("input");
  const count = bar.querySelector(".match-count");
  const turn = bar.querySelector('[data-action="orientation"]');
  const choice = bar.querySelector("[data-fit-choice]");
  const showOrientation = () => {
    turn.textContent = drawing.orientation === "LR" ? "⇥ left to right" : "⤓ top down";
    turn.dataset.orientation = drawing.orientation;
    const fit = drawing.container.dataset.fit;
    const detail = drawing.detail === "compact" ? "names only" : "full detail";
    choice.textContent = fit
      ? `fit: ${detail}, ${drawing.orientation === "LR" ? "left to right" : "top down"}, ${Math.round((drawing.fitScale || 1) * 100)}%${fit === "partial" ? ", not whole" : ""}`
      : detail;
    choice.dataset.detail = drawing.detail;
  };
  new MutationObserver(showOrientation).observe(drawing.container, {
    attributes: true,
    attributeFilter: ["data-orientation", "data-detail", "data-fit"],
  });
  showOrientation();
  const jump = (step) => {
    const i = drawing.nextMatch(step);
    if (i == null) return;
    // Counted once the match is shown (its branch unfolded may wait for its layout).
    const text = `${drawing.matchAt + 1}/${drawing.matches.length}`;
    drawing.settled().then(() => {
      count.textContent = text;
      onJump?.(i);
    });
  };
  input.addEventListener("input", () => {
    const n = drawing.search(input.value);
    count.textContent = input.value ? `${n} found` : "";
    if (n) jump(1);
  });
  input.addEventListener("keydown", (e) => {
    if (e.key === "Enter") jump(e.shiftKey ? -1 : 1);
    e.stopPropagation();
  });
  bar.addEventListener("click", (e) => {
    const a = e.target.closest("[data-action]")?.dataset.action;
    if (a === "search-next") jump(1);
    else if (a === "search-prev") jump(-1);
    else if (a === "orientation") drawing.setOrientation(drawing.orientation === "LR" ? "TB" : "LR");
    else if (a === "fit") drawing.fitWhole();
    else if (a === "zoom-in") drawing.zoomAtSelection(1.25);
    else if (a === "zoom-out") drawing.zoomAtSelection(0.8);
    else if (a === "collapse-all") drawing.collapseAll(true);
    else if (a === "expand-all") drawing.collapseAll(false);
    else if (a === "panels") togglePanels(bar);
    else if (a === "overview") {
      drawing.setOverview(!drawing.overview);
      e.target.setAttribute("aria-pressed", String(drawing.overview));
    }
  });
  return bar;
}

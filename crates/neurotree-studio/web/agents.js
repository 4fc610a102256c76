// The agents of a watched crowd (PROTOCOL.md, "Agents"): a page of them at a time, found by
// id or label with the search box, each a `[data-agent]` button that watches it; the agent
// watched (`[data-watched-agent]`, its id as value and text), why it is awake
// (`[data-why-awake]`), and whether a pause or a breakpoint stands the whole crowd still
// with it (`[data-agent-together]`) or that agent alone.
//
// The list is asked for (`GET /api/agents`) at each `hello`, then twice a second while a
// crowd is watched and the view is open, and at once after a search or a choice; the server
// sends one page of it, never the whole crowd. Hidden when the run watched is not a crowd.

import * as api from "./api.js";

const PAGE = 50;
const POLL_MS = 500;

export function mountAgents(side) {
  const panel = document.createElement("section");
  panel.className = "agents-panel";
  panel.hidden = true;
  panel.innerHTML = `
    <h3>Agents <span class="agent-count" data-agent-count></span></h3>
    <p class="agent-watched">watching <data data-watched-agent value=""></data>
      <span class="agent-label" data-watched-label></span></p>
    <p class="why-awake" data-why-awake></p>
    <label class="agent-together" title="a pause or a breakpoint of the agent watched stands the whole crowd still">
      <input type="checkbox" data-agent-together> pause the whole crowd with it</label>
    <input type="search" class="agent-search" data-agent-search placeholder="find an agent by id or name" aria-label="find an agent">
    <ul class="agent-list" data-agent-list></ul>
    <div class="agent-pager">
      <button data-agent-page="-1" title="the agents before">◂</button>
      <span data-agent-range></span>
      <button data-agent-page="1" title="the agents after">▸</button>
    </div>`;
  side.prepend(panel);
  const $ = (sel) => panel.querySelector(sel);
  const state = { query: "", offset: 0, shownList: "", watched: null, asking: false, again: false };

  async function refresh() {
    if (state.asking) {
      state.again = true;
      return;
    }
    state.asking = true;
    try {
      const page = await api.get("/api/agents", { q: state.query, offset: state.offset, limit: PAGE });
      render(page);
    } catch {
      // The run may be gone; the next poll asks again.
    } finally {
      state.asking = false;
      if (state.again) {
        state.again = false;
        refresh();
      }
    }
  }

  function render(page) {
    panel.hidden = !page.crowd;
    if (!page.crowd) return;
    $("[data-agent-count]").textContent = `${page.total}`;
    const watched = page.watched?.id ?? "";
    state.watched = watched;
    const w = $("[data-watched-agent]");
    if (w.value !== watched) {
      w.value = watched;
      w.textContent = watched;
    }
    $("[data-watched-label]").textContent = page.watched?.label ?? "";
    $("[data-why-awake]").textContent = page.awake ?? "";
    const together = $("[data-agent-together]");
    if (document.activeElement !== together) together.checked = !!page.together;
    const list = JSON.stringify(page.agents);
    if (list !== state.shownList) {
      state.shownList = list;
      const ul = $("[data-agent-list]");
      ul.replaceChildren(
        ...page.agents.map((a) => {
          const li = document.createElement("li");
          const b = document.createElement("button");
          b.dataset.agent = a.id;
          b.textContent = a.label ? `${a.id} · ${a.label}` : a.id;
          li.append(b);
          return li;
        }),
      );
    }
    for (const b of panel.querySelectorAll("[data-agent]")) {
      b.setAttribute("aria-current", String(b.dataset.agent === watched));
    }
    const last = Math.min(page.offset + page.agents.length, page.matches);
    $("[data-agent-range]").textContent = page.matches
      ? `${page.offset + 1}–${last} of ${page.matches}`
      : "no agent found";
    $("[data-agent-page='-1']").disabled = page.offset === 0;
    $("[data-agent-page='1']").disabled = last >= page.matches;
  }

  panel.addEventListener("click", async (e) => {
    const agent = e.target.closest("[data-agent]");
    if (agent) {
      try {
        await api.post("/api/agents/watch", { id: agent.dataset.agent });
      } catch (err) {
        $("[data-why-awake]").textContent = err.message;
      }
      refresh();
      return;
    }
    const pager = e.target.closest("[data-agent-page]");
    if (pager) {
      state.offset = Math.max(0, state.offset + Number(pager.dataset.agentPage) * PAGE);
      refresh();
    }
  });
  let typing = 0;
  $("[data-agent-search]").addEventListener("input", (e) => {
    state.query = e.target.value;
    state.offset = 0;
    clearTimeout(typing);
    typing = setTimeout(refresh, 120);
  });
  $("[data-agent-together]").addEventListener("change", (e) => {
    api.post("/api/agents/together", { together: e.target.checked }).then(refresh, () => refresh());
  });

  // Only while a crowd is watched and the view shown; a run that is not a crowd is asked
  // again at its next `hello` (watch.js), which a crowd's first agent sends.
  setInterval(() => {
    if (!panel.hidden && !panel.closest("[hidden]")) refresh();
  }, POLL_MS);
  refresh();
  return { refresh };
}

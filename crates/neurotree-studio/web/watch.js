// The watch view: a running tree as the server's studio observer reports it over `/ws`
// (PROTOCOL.md): every node's status live, the running path and the list of nodes running
// now, each scope's blackboard (editable between ticks), the failure reason chain,
// breakpoints, pause / step / continue, each Utility's last score on its node, back / forward through the ticks the run kept
// (a step or continue from a past tick forks the run there), the tick counter
// (`[data-tick]`), and the scene the run draws of its world (`[data-scene]`).
//
// `state` changes only through `actions` (what the user does; most are sent to the
// server) and `receive` (what the server says, one function per message). A tick message
// touches only the nodes it names, one attribute each, no layout; the panels follow at
// most once a frame. The socket reconnects by itself; the server's `hello` carries
// everything, so nothing is kept across connections but what the user chose (collapsed
// nodes, selection).

import * as api from "./api.js";
import { TreeDrawing, drawingToolbar, nodesOfTreeView } from "./tree.js";
import { SceneView } from "./scene.js";
import { ForcePanel } from "./force.js";
import { mountAgents } from "./agents.js";

export function mountWatch(section, app) {
  const state = {
    connected: false,
    run: null,
    tree: null,
    tick: 0,
    statuses: [],
    running: new Set(),
    failedNodes: new Set(), // the nodes on the failure chain, as marked
    paused: null,
    breakpoints: new Map(), // node id -> when
    blackboards: [],
    // The blackboard edits the run refused, [{scope, key, why}], shown at their fields
    // until an edit of the entry applies.
    refusedEdits: [],
    failure: null,
    ended: null,
    // The ticks the run kept: {window, oldest, newest, at, blocked} (PROTOCOL.md, "Rewind").
    rewind: null,
    selected: null,
    // Tick messages and status changes received, for measurements.
    received: { ticks: 0, changes: 0 },
  };

  section.innerHTML = `
    <div class="watch-main">
      <div class="toolbar">
        <span class="conn" data-connection="closed">disconnected</span>
        <span class="run-name"></span>
        <span class="tick-box">tick <b data-tick="0">0</b></span>
        <button data-action="pause" title="stop before the next tick (Space)">❚❚ pause</button>
        <button data-action="back" title="show the tick before">◂ back</button>
        <button data-action="forward" title="show the tick after">▸ forward</button>
        <button data-action="step" title="tick once, then stop (S)">▸❚ step</button>
        <button data-action="continue" title="go on (Space)">▶ continue</button>
        <span class="run-state" data-run-state="none"></span>
      </div>
      <div class="canvas"></div>
      <div class="scene-panel" data-scene hidden></div>
    </div>
    <aside class="side-panel watch-side">
      <section class="selected-node"><p class="hint">Click a node to set a breakpoint on it.</p></section>
      <section><h3>Running now <span class="running-count"></span></h3><ul class="running-list" data-running-list></ul></section>
      <section><h3>Last failure</h3><div class="failure" data-failure><p class="hint">none</p></div></section>
      <section><h3>Blackboards</h3><div class="blackboards"></div></section>
    </aside>`;

  const $ = (sel) => section.querySelector(sel);
  const drawing = new TreeDrawing($(".canvas"), {
    onSelect: (i) => actions.select(i),
  });
  $(".canvas").before(drawingToolbar(drawing));
  const scene = new SceneView($("[data-scene]"));
  const forces = new ForcePanel(section, {
    drawing,
    send: (m) => socket?.send(m),
    nodes: () => state.tree?.nodes || [],
    changed: () => renderSelected(),
  });
  // A crowd's agents, when the run is one (agents.js).
  const agents = mountAgents($(".watch-side"));
  const tickEl = $("[data-tick]");
  const shown = [];
  let socket = null;

  const actions = {
    connect() {
      if (socket) return;
      socket = api.watchSocket(receive, (s) => {
        state.connected = s === "open";
        const c = $(".conn");
        c.dataset.connection = s;
        c.textContent = s === "open" ? "connected" : "reconnecting…";
      });
    },
    select(i) {
      state.selected = i;
      renderSelected();
    },
    pause: () => socket?.send({ type: "pause" }),
    step: () => socket?.send({ type: "step" }),
    continue: () => socket?.send({ type: "continue" }),
    back: () => socket?.send({ type: "back" }),
    forward: () => socket?.send({ type: "forward" }),
    breakpoint(id, when) {
      socket?.send({ type: "breakpoint", node: id, when });
    },
    setEntry(scope, key, value) {
      socket?.send({ type: "set", scope, key, value });
    },
  };

  // The tick counter and the nodes' statuses follow every message at once; the panels
  // (running list, failure chain, blackboards) and the highlighted paths are drawn again
  // at most once a frame, so a run ticking faster than the screen does not queue work.
  const dirty = new Set();
  let frame = 0;
  function later(panel) {
    dirty.add(panel);
    if (!frame) frame = requestAnimationFrame(drawPanels);
  }
  function drawPanels() {
    frame = 0;
    const panels = [...dirty];
    dirty.clear();
    for (const panel of panels) panel();
  }

  function receive(msg) {
    switch (msg.type) {
      case "hello":
        return hello(msg);
      case "tick":
        return tick(msg);
      case "blackboards":
        state.blackboards = msg.scopes || [];
        return later(renderBlackboards);
      case "edits":
        state.refusedEdits = msg.refused || [];
        return later(showRefusedEdits);
      case "failure":
        state.failure = msg.failure;
        return later(renderFailure);
      case "paused":
        state.paused = msg.paused;
        setTick(msg.tick);
        return renderRunState();
      case "resumed":
        state.paused = null;
        setTick(msg.tick);
        return renderRunState();
      case "breakpoints":
        return setBreakpoints(msg.breakpoints);
      case "forces":
        return forces.set(msg.forces);
      case "rewind":
        state.rewind = msg.rewind;
        return renderRunState();
      case "scene":
        return scene.set(msg.scene, msg.why);
      case "ended":
        state.ended = msg.status;
        state.paused = null;
        setTick(msg.tick);
        return renderRunState();
      case "refused":
        return app.toast(`the server refused a message: ${msg.why}`);
      default:
        return undefined;
    }
  }

  function hello(msg) {
    state.run = msg.run;
    if (!msg.run) {
      $(".run-name").textContent = "no run attached: start one with `neurotree run FILE --studio PORT`";
      state.tree = null;
      drawing.setTree([]);
      section.dataset.run = "none";
      return;
    }
    $(".run-name").textContent = msg.run.name || "";
    agents.refresh();
    const signature = msg.tree.nodes.map((n) => n.path).join("\n");
    const same = state.tree && state.signature === signature;
    state.tree = msg.tree;
    state.signature = signature;
    if (!same) {
      drawing.setTree(nodesOfTreeView(msg.tree), { keepView: false, key: msg.run.name || null })
        .then(() => requestAnimationFrame(() => setTimeout(() => performance.mark("studio:watch-drawn"), 0)));
    }
    state.statuses = msg.statuses.slice();
    state.running = new Set();
    state.statuses.forEach((s, i) => s === "RUNNING" && state.running.add(i));
    drawing.setStatuses(state.statuses);
    for (const [id, score] of msg.scores || []) drawing.setScore(id, score);
    if (!same) {
      state.failedNodes = new Set();
      failureShown = "";
    }
    state.paused = msg.paused;
    state.ended = msg.ended;
    state.rewind = msg.rewind;
    scene.set(msg.scene, null);
    state.blackboards = msg.blackboards || [];
    state.refusedEdits = msg.edits || [];
    state.failure = msg.failure;
    setBreakpoints(msg.breakpoints || []);
    forces.set(msg.forces || [], msg.forcing !== false);
    setTick(msg.tick);
    renderRunning();
    renderBlackboards();
    renderFailure();
    drawHot();
    renderRunState();
    renderSelected();
    section.dataset.run = "attached";
    ack(msg.tick);
  }

  // Telling the server a tick was applied lets it send the next: it never queues stale
  // ticks on the socket, so the page shows the newest however fast the run goes.
  function ack(tick) {
    socket?.send({ type: "ack", tick: tick ?? 0 });
  }

  function tick(msg) {
    if (!state.tree) return;
    state.received.ticks += 1;
    state.received.changes += msg.changes.length;
    let runningChanged = false;
    for (const [id, status] of msg.changes) {
      const i = id; // a TreeView's nodes are in id order
      if (state.statuses[i] === status) continue;
      if (state.statuses[i] === "RUNNING" || status === "RUNNING") runningChanged = true;
      state.statuses[i] = status;
      if (status === "RUNNING") state.running.add(i);
      else state.running.delete(i);
      drawing.setStatus(i, status);
      if (i === state.selected) later(showSelectedStatus);
    }
    for (const [id, score] of msg.scores || []) drawing.setScore(id, score);
    setTick(msg.tick);
    if (runningChanged) {
      later(drawHot);
      later(renderRunning);
    }
    ack(msg.tick);
  }

  function drawHot() {
    drawing.drawHot(state.running, state.failedNodes);
  }

  function setTick(n) {
    if (n == null || n === state.tick) return;
    state.tick = n;
    tickEl.textContent = String(n);
    tickEl.dataset.tick = String(n);
    // When each tick was shown (wall clock, ms), for the lag measurement of the tests.
    if (shown.length >= 20000) shown.splice(0, 10000);
    shown.push([n, performance.timeOrigin + performance.now()]);
  }

  function setBreakpoints(list) {
    state.breakpoints = new Map(list.map((b) => [b.node, b.when]));
    drawing.clearMarks("data-breakpoint");
    for (const [id, when] of state.breakpoints) drawing.mark(id, "data-breakpoint", when);
    renderSelected();
  }

  function renderRunState() {
    const el = $(".run-state");
    const p = state.paused;
    drawing.clearMarks("data-paused-at");
    if (state.ended) {
      el.dataset.runState = "ended";
      el.textContent = `ended: ${state.ended}`;
    } else if (p && state.rewind?.at != null) {
      el.dataset.runState = "paused";
      el.textContent = `back at tick ${state.rewind.at} of ${state.rewind.newest}: step or continue to go on from here (the later ticks are dropped)`;
    } else if (p) {
      el.dataset.runState = "paused";
      const node = p.node != null ? state.tree?.nodes[p.node] : null;
      el.textContent = p.why === "breakpoint" && node
        ? `paused at breakpoint: ${node.path}${p.status ? ` returned ${p.status}` : " (before its tick)"}`
        : `paused (${p.why})`;
      if (p.node != null) drawing.mark(p.node, "data-paused-at", true);
    } else if (state.tree) {
      el.dataset.runState = "running";
      el.textContent = "running";
    } else {
      el.dataset.runState = "none";
      el.textContent = "";
    }
    $('[data-action="pause"]').disabled = !state.tree || !!p || !!state.ended;
    $('[data-action="step"]').disabled = !p;
    $('[data-action="continue"]').disabled = !p;
    section.dataset.at = state.rewind?.at ?? "";
    for (const way of ["back", "forward"]) {
      const button = $(`[data-action="${way}"]`);
      const why = travelRefused(way);
      button.disabled = why != null;
      button.title = why ?? (way === "back" ? "show the tick before" : "show the tick after");
    }
  }

  // Why going `way` ("back" or "forward") is not possible now, or null: the server checks
  // the same (PROTOCOL.md, "Rewind").
  function travelRefused(way) {
    const p = state.paused;
    const r = state.rewind;
    if (state.ended || !state.tree) return "the run is not going";
    if (!p) return `pause the run to go ${way}`;
    if (p.why === "breakpoint") return `the run is held inside a tick: step to its end to go ${way}`;
    if (!r || !r.window) return "this run keeps no ticks (--rewind-window 0)";
    if (r.blocked && r.at == null) return `cannot go back from this tick: ${r.blocked}`;
    const from = r.at ?? state.tick;
    if (way === "back" && (r.oldest == null || from <= r.oldest)) {
      return `tick ${from} is the oldest kept: the run keeps its last ${r.window} ticks (--rewind-window)`;
    }
    if (way === "forward" && r.at == null) return `tick ${from} is the latest`;
    return null;
  }

  function renderRunning() {
    const list = $(".running-list");
    const nodes = state.tree?.nodes || [];
    const ids = [...state.running].sort((a, b) => a - b);
    $(".running-count").textContent = ids.length ? `(${ids.length})` : "";
    list.innerHTML = "";
    for (const i of ids.slice(0, 200)) {
      const li = document.createElement("li");
      li.textContent = nodes[i]?.path ?? String(i);
      li.dataset.nodeId = String(i);
      li.addEventListener("click", () => {
        drawing.select(i, { reveal: true });
        actions.select(i);
      });
      list.append(li);
    }
  }

  let failureShown = "";
  function renderFailure() {
    const box = $(".failure");
    const f = state.failure;
    const key = JSON.stringify(f);
    if (key === failureShown) return;
    failureShown = key;
    const nodes = new Set(f?.nodes || []);
    for (const id of state.failedNodes) if (!nodes.has(id)) drawing.mark(id, "data-failed", null);
    for (const id of nodes) if (!state.failedNodes.has(id)) drawing.mark(id, "data-failed", true);
    state.failedNodes = nodes;
    drawHot();
    if (!f) {
      box.innerHTML = '<p class="hint">none</p>';
      return;
    }
    box.innerHTML = "";
    const head = document.createElement("p");
    head.innerHTML = "<b></b>";
    head.firstChild.textContent = f.path;
    if (f.reason) head.append(`: ${f.reason}`);
    if (f.code != null) head.append(` (code ${f.code})`);
    const chain = document.createElement("pre");
    chain.textContent = f.chain || "";
    box.append(head, chain);
  }

  // The entries' fields are made again only when the scopes or their keys change; a new
  // value only rewrites the fields not being edited, so a field can be clicked and typed
  // into while the run writes the blackboard every tick.
  let bbShape = "";
  function renderBlackboards() {
    const box = $(".blackboards");
    const shape = JSON.stringify(state.blackboards.map((s) => [s.scope, s.path, s.entries.map((e) => [e.key, e.type])]));
    if (shape === bbShape) {
      for (const scope of state.blackboards) {
        for (const entry of scope.entries) {
          const input = box.querySelector(`input[data-scope="${scope.scope}"][data-entry="${CSS.escape(entry.key)}"]`);
          if (!input || input === document.activeElement) continue;
          const text = entry.value === null ? "" : typeof entry.value === "string" ? entry.value : JSON.stringify(entry.value);
          if (input.title !== text) {
            input.value = text;
            input.title = text;
          }
          input.previous = entry.value;
        }
      }
      showRefusedEdits();
      return;
    }
    if (box.contains(document.activeElement) && document.activeElement.tagName === "INPUT") return;
    bbShape = shape;
    box.innerHTML = "";
    for (const scope of state.blackboards) {
      const details = document.createElement("details");
      details.open = true;
      details.dataset.scope = String(scope.scope);
      const summary = document.createElement("summary");
      summary.textContent = scope.path ? scope.path : "root";
      details.append(summary);
      const table = document.createElement("div");
      table.className = "entries";
      for (const entry of scope.entries) {
        const row = document.createElement("label");
        row.className = "entry";
        const k = document.createElement("span");
        k.className = "entry-key";
        k.textContent = entry.key;
        const t = document.createElement("span");
        t.className = "entry-type";
        t.textContent = entry.type || "";
        const input = document.createElement("input");
        input.dataset.entry = entry.key;
        input.dataset.scope = String(scope.scope);
        if (entry.value === null) input.placeholder = "not written yet";
        else input.value = typeof entry.value === "string" ? entry.value : JSON.stringify(entry.value);
        input.title = input.value;
        // Sent when the value is committed: Enter, or leaving the field; Escape drops it.
        input.previous = entry.value;
        input.addEventListener("change", () => actions.setEntry(scope.scope, entry.key, parseValue(input.value, input.previous)));
        input.addEventListener("keydown", (e) => {
          if (e.key === "Enter") input.blur();
          else if (e.key === "Escape") {
            input.value = input.title;
            input.blur();
          }
        });
        input.addEventListener("blur", () => setTimeout(renderBlackboards, 0));
        const error = document.createElement("span");
        error.className = "field-error";
        error.dataset.fieldError = "";
        error.hidden = true;
        row.append(k, t, input, error);
        table.append(row);
      }
      if (!scope.entries.length) table.innerHTML = "<p class='hint'>empty</p>";
      details.append(table);
      box.append(details);
    }
    showRefusedEdits();
  }

  // A refused edit is shown at its field, with why; the field shows the entry's value,
  // which the edit left as it was.
  function showRefusedEdits() {
    const why = new Map(state.refusedEdits.map((r) => [`${r.scope}\u0000${r.key}`, r.why]));
    for (const input of $(".blackboards").querySelectorAll("input[data-entry]")) {
      const reason = why.get(`${input.dataset.scope}\u0000${input.dataset.entry}`);
      const error = input.parentElement.querySelector("[data-field-error]");
      if (reason == null) {
        input.removeAttribute("aria-invalid");
        if (error) {
          error.hidden = true;
          error.textContent = "";
        }
      } else {
        input.setAttribute("aria-invalid", "true");
        if (error) {
          error.hidden = false;
          error.textContent = reason;
        }
      }
    }
  }

  function showSelectedStatus() {
    const el = section.querySelector("[data-selected-status]");
    if (el && state.selected != null) el.textContent = state.statuses[state.selected] || "";
  }

  function renderSelected() {
    const box = $(".selected-node");
    const i = state.selected;
    const node = i != null ? state.tree?.nodes[i] : null;
    if (!node) {
      box.innerHTML = '<p class="hint">Click a node to set a breakpoint on it.</p>';
      return;
    }
    const when = state.breakpoints.get(node.id) || "off";
    box.innerHTML = `<h3></h3><p class="node-type"></p><p>status <b data-selected-status></b></p>
      <label class="field">breakpoint <select data-breakpoint-select>
        <option value="off">none</option><option value="before">before its tick</option>
        <option value="SUCCESS">when it returns SUCCESS</option><option value="FAILURE">when it returns FAILURE</option>
        <option value="RUNNING">when it returns RUNNING</option></select></label>
      <div class="ports"></div>`;
    box.querySelector("h3").textContent = node.path;
    box.querySelector(".node-type").textContent = `${node.type} (${node.category})`;
    box.querySelector("[data-selected-status]").textContent = state.statuses[i] || "";
    const sel = box.querySelector("select");
    sel.value = when;
    sel.addEventListener("change", () => actions.breakpoint(node.id, sel.value));
    const ports = box.querySelector(".ports");
    for (const [k, v] of Object.entries(node.ports || {})) {
      const p = document.createElement("div");
      p.className = "port";
      p.textContent = `${k} = ${v}`;
      ports.append(p);
    }
    forces.menu(box, node);
  }

  // Space pauses and continues, S (or F10) steps, as debuggers do.
  document.addEventListener("keydown", (e) => {
    if (!app.isShown("watch") || /^(INPUT|TEXTAREA|SELECT)$/.test(document.activeElement?.tagName || "")) return;
    if (e.key === " ") {
      e.preventDefault();
      state.paused ? actions.continue() : actions.pause();
    } else if (e.key === "s" || e.key === "F10") {
      e.preventDefault();
      actions.step();
    }
  });

  section.addEventListener("click", (e) => {
    const a = e.target.closest("[data-action]")?.dataset.action;
    if (a === "pause") actions.pause();
    else if (a === "step") actions.step();
    else if (a === "continue") actions.continue();
    else if (a === "back") actions.back();
    else if (a === "forward") actions.forward();
  });

  return {
    actions,
    state,
    drawing,
    forces,
    shownTicks: shown,
    show() {
      actions.connect();
      if (state.tree) drawing.fit();
    },
  };
}

// A typed value back to JSON: numbers and booleans when the entry held one, else text.
function parseValue(text, previous) {
  if (typeof previous === "number") {
    const n = Number(text);
    return Number.isFinite(n) ? n : text;
  }
  if (typeof previous === "boolean") return text === "true";
  if (typeof previous === "string") return text;
  try {
    return JSON.parse(text);
  } catch {
    return text;
  }
}

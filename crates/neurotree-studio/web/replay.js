// The replay view: a recorded run (a `--jsonl` trace with its tree file, a BehaviorTree.CPP
// `.btlog`, or its SQLite log) read by the server (`/api/replay`) and scrubbed on a
// timeline: the statuses after any step, forward and back, play at a chosen speed, jump to
// the next (or previous) failure, and a `--coverage-json` file drawn over the tree.
//
// Position p on the timeline means "steps 0..p-1 applied" (0: before the first step, all
// IDLE). Statuses at p are computed from the nearest keyframe (every KEYFRAME steps), so a
// jump anywhere costs at most KEYFRAME steps; a move touches only the nodes that differ.

import * as api from "./api.js";
import { TreeDrawing, drawingToolbar, nodesOfTreeView } from "./tree.js";

const KEYFRAME = 64;
const SPEEDS = [0.25, 0.5, 1, 2, 5, 10, 50];

export function mountReplay(section, app) {
  const state = {
    path: null,
    treePath: null,
    replay: null,
    keyframes: [],
    position: 0,
    playing: false,
    speed: 1,
    coverage: null,
    coveragePath: null,
  };

  section.innerHTML = `
    <div class="replay-main">
      <div class="toolbar">
        <label>log <select class="log-select" aria-label="log"></select></label>
        <label class="tree-for">tree <select class="tree-select" aria-label="tree file of a trace"></select></label>
        <button data-action="open-log">open</button>
        <span class="sep"></span>
        <label>coverage <select class="coverage-select"></select></label>
        <button data-action="coverage">overlay</button>
        <span class="replay-status"></span>
      </div>
      <div class="timeline">
        <button data-action="start" title="to the start">|◂</button>
        <button data-action="back" title="one step back (←)">◂</button>
        <button data-action="play" title="play / pause (space)">▶ play</button>
        <button data-action="forward" title="one step forward (→)">▸</button>
        <button data-action="end" title="to the end">▸|</button>
        <button data-action="prev-failure" title="previous failure">◂ failure</button>
        <button data-action="next-failure" title="next failure">failure ▸</button>
        <label>speed <select class="speed">${SPEEDS.map((s) => `<option value="${s}"${s === 1 ? " selected" : ""}>${s}×</option>`).join("")}</select></label>
        <input type="range" class="scrub" data-timeline min="0" max="0" value="0" aria-label="timeline">
        <span class="position" data-step="0">0 / 0</span>
      </div>
      <div class="canvas"></div>
    </div>
    <aside class="side-panel replay-side">
      <section><h3>This step</h3><ul class="step-changes"></ul></section>
      <section class="coverage-box"><h3>Coverage</h3><p class="hint">Pick a --coverage-json file and “overlay”.</p></section>
      <section class="selected-node"></section>
    </aside>`;

  const $ = (sel) => section.querySelector(sel);
  const drawing = new TreeDrawing($(".canvas"), { onSelect: (i) => renderSelected(i) });
  $(".canvas").before(drawingToolbar(drawing));
  let timer = null;

  const actions = {
    async open(path, treePath) {
      if (!path) return;
      actions.pause();
      $(".replay-status").textContent = `reading ${path}…`;
      let replay;
      try {
        replay = await api.get("/api/replay", { path, tree: treePath || null });
      } catch (e) {
        $(".replay-status").textContent = e.message;
        section.dataset.loaded = "";
        return;
      }
      state.path = path;
      state.treePath = treePath || null;
      state.replay = replay;
      state.keyframes = keyframes(replay);
      state.position = 0;
      const drawn = drawing.setTree(nodesOfTreeView(replay.tree), { key: state.treePath || path });
      drawing.setStatuses(statusesAt(0));
      if (state.coverage) applyCoverage();
      const scrub = $(".scrub");
      scrub.max = String(replay.steps.length);
      scrub.value = "0";
      $(".replay-status").textContent = `${replay.source}: ${replay.tree.nodes.length} nodes, ${replay.steps.length} steps`;
      app.remember({ view: "replay", file: path, tree: treePath || undefined });
      // Loaded once drawn (the layout comes from the server).
      drawn.then(() => (section.dataset.loaded = path));
      $(".log-select").value = path;
      if (treePath) $(".tree-select").value = treePath;
      showTreeFor();
      renderPosition();
    },

    seek(p) {
      if (!state.replay) return;
      const n = state.replay.steps.length;
      p = Math.max(0, Math.min(n, p));
      state.position = p;
      const statuses = statusesAt(p);
      for (let i = 0; i < statuses.length; i++) drawing.setStatus(i, statuses[i]);
      drawing.drawHot();
      // A node that ended the step Idle may have failed or succeeded in it: glow it so.
      drawing.clearMarks("data-stepped");
      const step = p > 0 ? state.replay.steps[p - 1] : null;
      const passed = new Map();
      for (const [id, st] of step?.changes || []) if (st === "FAILURE" || st === "SUCCESS") passed.set(id, st);
      for (const [id, st] of passed) if (statuses[id] === "IDLE") drawing.mark(id, "data-stepped", st);
      renderPosition();
    },

    play() {
      if (!state.replay || state.playing) return;
      if (state.position >= state.replay.steps.length) actions.seek(0);
      state.playing = true;
      renderPlay();
      advance();
    },

    pause() {
      state.playing = false;
      clearTimeout(timer);
      renderPlay();
    },

    setSpeed(s) {
      state.speed = s;
    },

    // The next step (after the current position) in which a node fails; -1 looks back.
    failure(direction) {
      const steps = state.replay?.steps || [];
      const fails = (s) => s.changes.some(([, st]) => st === "FAILURE");
      if (direction > 0) {
        for (let k = state.position; k < steps.length; k++) if (fails(steps[k])) return actions.seek(k + 1);
      } else {
        for (let k = state.position - 2; k >= 0; k--) if (fails(steps[k])) return actions.seek(k + 1);
      }
      app.toast(direction > 0 ? "no failure after this step" : "no failure before this step");
      return undefined;
    },

    async coverage(path) {
      if (!path) return;
      try {
        state.coverage = await api.get("/api/coverage", { path });
        state.coveragePath = path;
        applyCoverage();
      } catch (e) {
        app.toast(`coverage: ${e.message}`);
      }
    },
  };

  // Plays one step, then waits as long as the run did between it and the next (scaled by
  // the speed; a tenth of a second where the log has no times).
  function advance() {
    if (!state.playing) return;
    const steps = state.replay.steps;
    if (state.position >= steps.length) {
      actions.pause();
      return;
    }
    actions.seek(state.position + 1);
    const here = steps[state.position - 1];
    const next = steps[state.position];
    let wait = 100;
    if (next && here && next.time_us != null && here.time_us != null) wait = Math.min(2000, (next.time_us - here.time_us) / 1000);
    timer = setTimeout(advance, Math.max(4, wait / state.speed));
  }

  function keyframes(replay) {
    const n = replay.tree.nodes.length;
    const frames = [];
    let current = new Array(n).fill("IDLE");
    frames.push(current.slice());
    replay.steps.forEach((step, k) => {
      for (const [id, st] of step.changes) current[id] = st;
      if ((k + 1) % KEYFRAME === 0) frames.push(current.slice());
    });
    return frames;
  }

  function statusesAt(p) {
    const base = Math.floor(p / KEYFRAME);
    const statuses = state.keyframes[base].slice();
    const steps = state.replay.steps;
    for (let k = base * KEYFRAME; k < p; k++) for (const [id, st] of steps[k].changes) statuses[id] = st;
    return statuses;
  }

  function renderPosition() {
    const steps = state.replay?.steps || [];
    const p = state.position;
    $(".scrub").value = String(p);
    const step = p > 0 ? steps[p - 1] : null;
    const pos = $(".position");
    pos.dataset.step = String(p);
    let text = `${p} / ${steps.length}`;
    // A log without ticks (.btlog, SQLite) says when, not which tick: its steps are the
    // ticks that changed something, so their count is not the run's tick.
    if (step?.tick != null) text += ` · tick ${step.tick}`;
    if (step?.time_us != null) text += ` · ${(step.time_us / 1e6).toFixed(3)} s`;
    pos.textContent = text;
    const list = $(".step-changes");
    list.innerHTML = "";
    const nodes = state.replay?.tree.nodes || [];
    for (const [id, st] of step?.changes || []) {
      const li = document.createElement("li");
      li.dataset.status = st;
      li.textContent = `${nodes[id]?.path ?? id} → ${st}`;
      li.addEventListener("click", () => drawing.select(id, { reveal: true }));
      list.append(li);
    }
  }

  function renderPlay() {
    const b = $('[data-action="play"]');
    b.textContent = state.playing ? "❚❚ pause" : "▶ play";
    section.dataset.playing = String(state.playing);
  }

  function renderSelected(i) {
    const box = $(".selected-node");
    const node = i != null ? state.replay?.tree.nodes[i] : null;
    if (!node) {
      box.innerHTML = "";
      return;
    }
    box.innerHTML = "<h3></h3><p class='node-type'></p><p class='cov'></p>";
    box.querySelector("h3").textContent = node.path;
    box.querySelector(".node-type").textContent = `${node.type} (${node.category})`;
    const c = coverageOf(node.path);
    if (c) box.querySelector(".cov").textContent = `seen: ${c.seen.join(", ") || "nothing"}; not seen: ${c.not_seen.join(", ") || "nothing"}`;
  }

  function coverageOf(path) {
    return state.coverage?.nodes.find((n) => n.path === path) || null;
  }

  // Coverage entries are matched to nodes by path; paths may repeat, so each entry is
  // given to the first node with that path not yet given one.
  function applyCoverage() {
    drawing.clearMarks("data-coverage");
    const cov = state.coverage;
    const box = $(".coverage-box");
    if (!cov || !state.replay) return;
    const byPath = new Map();
    for (const entry of cov.nodes) {
      if (!byPath.has(entry.path)) byPath.set(entry.path, []);
      byPath.get(entry.path).push(entry);
    }
    let matched = 0;
    state.replay.tree.nodes.forEach((node, i) => {
      const entry = byPath.get(node.path)?.shift();
      if (!entry) return;
      matched++;
      const full = entry.reached && !entry.not_seen.length;
      drawing.mark(i, "data-coverage", !entry.reached ? "unreached" : full ? "full" : "partial");
    });
    box.innerHTML = `<h3>Coverage</h3><p>${cov.covered} of ${cov.possible} outcomes seen; ${matched} nodes matched.</p>
      <p><span class="swatch full"></span> every outcome seen <span class="swatch partial"></span> some <span class="swatch unreached"></span> never reached</p>`;
    section.dataset.coverage = state.coveragePath;
  }

  section.addEventListener("click", (e) => {
    const a = e.target.closest("[data-action]")?.dataset.action;
    if (a === "open-log") actions.open($(".log-select").value, $(".tree-select").value);
    else if (a === "play") (state.playing ? actions.pause() : actions.play());
    else if (a === "start") actions.seek(0);
    else if (a === "end") actions.seek(Infinity);
    else if (a === "back") actions.seek(state.position - 1);
    else if (a === "forward") actions.seek(state.position + 1);
    else if (a === "next-failure") actions.failure(1);
    else if (a === "prev-failure") actions.failure(-1);
    else if (a === "coverage") actions.coverage($(".coverage-select").value);
  });
  $(".scrub").addEventListener("input", (e) => {
    actions.pause();
    actions.seek(Number(e.target.value));
  });
  $(".speed").addEventListener("change", (e) => actions.setSpeed(Number(e.target.value)));
  $(".log-select").addEventListener("change", showTreeFor);
  document.addEventListener("keydown", (e) => {
    if (!app.isShown("replay") || /^(INPUT|TEXTAREA|SELECT)$/.test(document.activeElement?.tagName || "")) return;
    if (e.key === "ArrowRight") actions.seek(state.position + 1);
    else if (e.key === "ArrowLeft") actions.seek(state.position - 1);
    else if (e.key === " ") {
      e.preventDefault();
      state.playing ? actions.pause() : actions.play();
    }
  });

  function showTreeFor() {
    const path = $(".log-select").value;
    $(".tree-for").hidden = !path.endsWith(".jsonl");
  }

  async function listFiles() {
    try {
      const { files } = await api.get("/api/files");
      const fill = (sel, kinds, empty) => {
        sel.innerHTML = empty ? `<option value="">${empty}</option>` : "";
        for (const f of files.filter((f) => kinds.includes(f.kind))) sel.add(new Option(f.path, f.path));
      };
      fill($(".log-select"), ["trace", "btlog", "sqlite"]);
      fill($(".tree-select"), ["tree"]);
      fill($(".coverage-select"), ["coverage"], "—");
      if (state.path) $(".log-select").value = state.path;
      if (state.treePath) $(".tree-select").value = state.treePath;
      showTreeFor();
    } catch (e) {
      $(".replay-status").textContent = e.message;
    }
  }
  listFiles();

  return { actions, state, drawing, show: () => state.replay && drawing.fit(), refresh: listFiles };
}

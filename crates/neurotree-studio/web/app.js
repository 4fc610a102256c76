// The shell: three views (edit, watch, replay) behind tabs, the session the server was
// started with, and the page's address (`#view=edit&file=P`, `#view=watch`,
// `#view=replay&file=LOG&tree=XML`) so that a reload or a link opens the same thing.

import * as api from "./api.js";
import { mountEditor } from "./editor.js";
import { mountReplay } from "./replay.js";
import { mountWatch } from "./watch.js";

const VIEWS = ["edit", "watch", "replay"];

const app = {
  shown: null,
  views: {},
  isShown: (name) => app.shown === name,
  show(name) {
    if (!VIEWS.includes(name)) return;
    app.shown = name;
    for (const v of VIEWS) {
      document.getElementById(`${v}-view`).hidden = v !== name;
      const tab = document.querySelector(`nav [data-view="${v}"]`);
      tab.setAttribute("aria-selected", String(v === name));
    }
    document.body.dataset.view = name;
    app.views[name].show();
    if (name === "watch") app.remember({ view: "watch" });
  },
  remember(params) {
    const h = new URLSearchParams();
    for (const [k, v] of Object.entries(params)) if (v != null) h.set(k, v);
    history.replaceState(null, "", `${location.pathname}${location.search}#${h}`);
  },
  setTitle(text) {
    document.title = text ? `${text} · NeuroTree Studio` : "NeuroTree Studio";
  },
  toast(message) {
    const box = document.getElementById("toasts");
    const t = document.createElement("div");
    t.className = "toast";
    t.textContent = message;
    box.append(t);
    setTimeout(() => t.remove(), 5000);
  },
};

async function start() {
  app.views.edit = mountEditor(document.getElementById("edit-view"), app);
  app.views.watch = mountWatch(document.getElementById("watch-view"), app);
  app.views.replay = mountReplay(document.getElementById("replay-view"), app);
  document.querySelector("nav").addEventListener("click", (e) => {
    const v = e.target.closest("[data-view]")?.dataset.view;
    if (v) app.show(v);
  });
  // The session is asked for while the address's view opens: it is needed only when the
  // address names nothing.
  const asked = api.get("/api/session").then(
    (s) => {
      document.getElementById("version").textContent = `v${s.version}`;
      return s;
    },
    (e) => {
      app.toast(`session: ${e.message}`);
      return { open: [], watch: false };
    },
  );
  if (await route()) return;
  const session = await asked;
  // What the command line opened: trees in the editor, logs in replay; a run's watch first.
  const trees = session.open.filter((p) => /\.xml$/i.test(p));
  const logs = session.open.filter((p) => /\.(jsonl|btlog|db|sqlite|db3)$/i.test(p));
  if (trees.length) await app.views.edit.actions.open(trees[0]);
  if (logs.length) {
    const log = logs[0];
    await app.views.replay.actions.open(log, log.endsWith(".jsonl") ? trees[0] : null);
  }
  app.show(session.watch ? "watch" : logs.length && !trees.length ? "replay" : "edit");
}

// Opens what the address names; false when it names nothing.
async function route() {
  const hash = new URLSearchParams(location.hash.slice(1));
  const view = hash.get("view");
  if (view === "edit" && hash.get("file")) {
    app.show("edit");
    await app.views.edit.actions.open(hash.get("file"));
    return true;
  }
  if (view === "replay" && hash.get("file")) {
    app.show("replay");
    await app.views.replay.actions.open(hash.get("file"), hash.get("tree"));
    return true;
  }
  if (VIEWS.includes(view)) {
    app.show(view);
    return true;
  }
  return false;
}

window.addEventListener("hashchange", route);
window.studio = app;
start();

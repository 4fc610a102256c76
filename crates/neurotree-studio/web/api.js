// The page's side of PROTOCOL.md: HTTP requests and the watch socket, each carrying the
// token the page was opened with (`?token=T`), if any.

const token = new URLSearchParams(location.search).get("token");

/** An error answer of the server: its HTTP status and the `error` text. */
export class ApiError extends Error {
  constructor(status, body) {
    super((body && body.error) || `HTTP ${status}`);
    this.status = status;
    this.body = body;
  }
}

/** The address of `path` with `params` and the page's token. */
export function url(path, params = {}) {
  const u = new URL(path, location.origin);
  for (const [k, v] of Object.entries(params)) if (v != null) u.searchParams.set(k, v);
  if (token) u.searchParams.set("token", token);
  return u;
}

async function answer(res) {
  const type = res.headers.get("content-type") || "";
  const body = type.includes("json") ? await res.json().catch(() => null) : await res.text();
  if (!res.ok) throw new ApiError(res.status, typeof body === "object" ? body : { error: body || res.statusText });
  return body;
}

export async function get(path, params) {
  return answer(await fetch(url(path, params), { cache: "no-store" }));
}

export async function post(path, body) {
  return answer(await fetch(url(path), {
    method: "POST",
    headers: { "content-type": "application/json" },
    body: JSON.stringify(body),
  }));
}

/** POST whose answer is a file (the SVG export): returns a Blob. */
export async function postBlob(path, body) {
  const res = await fetch(url(path), {
    method: "POST",
    headers: { "content-type": "application/json" },
    body: JSON.stringify(body),
  });
  if (!res.ok) await answer(res);
  return res.blob();
}

/**
 * The watch socket, reconnecting by itself when it drops: `onMessage(msg)` for every
 * message, `onState("open" | "closed")` when the connection changes. Returns `{send, close}`.
 */
export function watchSocket(onMessage, onState) {
  let ws = null;
  let closed = false;
  let delay = 250;
  const open = () => {
    const u = url("/ws");
    u.protocol = location.protocol === "https:" ? "wss:" : "ws:";
    ws = new WebSocket(u);
    ws.onopen = () => {
      delay = 250;
      onState?.("open");
    };
    ws.onmessage = (e) => {
      let msg;
      try {
        msg = JSON.parse(e.data);
      } catch {
        return;
      }
      onMessage(msg);
    };
    ws.onclose = () => {
      onState?.("closed");
      if (!closed) setTimeout(open, delay);
      delay = Math.min(2000, delay * 2);
    };
  };
  open();
  return {
    send(msg) {
      if (ws && ws.readyState === WebSocket.OPEN) {
        ws.send(JSON.stringify(msg));
        return true;
      }
      return false;
    },
    close() {
      closed = true;
      ws?.close();
    },
  };
}

/** Offers `blob` as a download named `name`. */
export function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  setTimeout(() => {
    URL.revokeObjectURL(a.href);
    a.remove();
  }, 1000);
}

//! The studio's server: one [`Router`] (below, in [`router`]), handlers that call the
//! loader, the engine's watch state and the log readers, and the checks every request
//! passes (token, Host, Origin).

use std::net::SocketAddr;
use std::path::Path;
use std::sync::Arc;

use axum::body::Body;
use axum::extract::ws::WebSocketUpgrade;
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::{header, HeaderMap, Method, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use neurotree_toolkit::{Registry, XmlLoader};
use serde::Deserialize;
use serde_json::{json, Value};

use crate::check::check_text;
use crate::palette::palette;
use crate::replay::{self, Replay, ReplayError};
use crate::watch::{serve_page, Hub};
use crate::workspace::{FileKind, PathError, Workspace, MAX_FILE_BYTES};

/// Makes the registry the editor checks with and the palette lists (the built-ins, the
/// program's own node types, `--model` files).
pub type RegistryFactory = Arc<dyn Fn() -> Registry<()> + Send + Sync>;

/// What the handlers share.
pub(crate) struct Shared {
    pub hub: Arc<Hub>,
    pub workspace: Workspace,
    pub registry: RegistryFactory,
    pub open: Vec<String>,
    pub token: Option<String>,
    pub max_nodes: usize,
    /// What an unknown node type's error advises.
    pub unknown_type_advice: &'static str,
    /// `Host` headers a request may carry when no token is asked for (against DNS
    /// rebinding: a page of another site resolving its name to 127.0.0.1).
    pub hosts: Vec<String>,
}

type App = State<Arc<Shared>>;

/// The page's files, embedded in the binary (read from `web/` in debug builds).
#[derive(rust_embed::RustEmbed)]
#[folder = "web/"]
struct Assets;

/// Every route of the studio.
pub(crate) fn router(shared: Arc<Shared>) -> Router {
    let api = Router::new()
        .route("/api/session", get(session))
        .route("/api/files", get(files))
        .route("/api/file", get(file))
        .route("/api/stat", get(stat))
        .route("/api/check", post(check))
        .route("/api/save", post(save))
        .route("/api/palette", get(palette_of))
        .route("/api/svg", post(svg))
        .route("/api/drawing", get(drawing))
        .route("/api/layout", post(crate::layout::layout))
        .route("/api/replay", get(replay_of))
        .route("/api/coverage", get(coverage))
        .route("/api/stats", get(stats))
        .route("/api/agents", get(crate::watch::agents_page))
        .route("/api/agents/watch", post(crate::watch::choose_agent))
        .route("/api/agents/together", post(crate::watch::agents_together))
        .route("/ws", get(ws))
        .layer(middleware::from_fn_with_state(Arc::clone(&shared), guard));
    Router::new()
        .merge(api)
        .route("/", get(index))
        .route("/drawing-metrics.js", get(drawing_module))
        .route("/{*path}", get(asset))
        .layer(DefaultBodyLimit::max(MAX_FILE_BYTES as usize + 64 * 1024))
        .with_state(shared)
}

/// An error answer: `{"error": …}` with a status.
pub(crate) struct Refusal(pub(crate) StatusCode, pub(crate) String);

impl IntoResponse for Refusal {
    fn into_response(self) -> Response {
        (self.0, Json(json!({"error": self.1}))).into_response()
    }
}

impl From<PathError> for Refusal {
    fn from(e: PathError) -> Self {
        let status = match e {
            PathError::Outside(_) => StatusCode::FORBIDDEN,
            PathError::NotFound(_) => StatusCode::NOT_FOUND,
            PathError::TooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            _ => StatusCode::INTERNAL_SERVER_ERROR,
        };
        Refusal(status, e.to_string())
    }
}

/// The checks before any API call or WebSocket: the token if one is set, else a Host of
/// this machine; for anything but a plain read, an Origin (if sent) of the studio itself.
async fn guard(State(shared): App, request: Request, next: Next) -> Response {
    let headers = request.headers();
    let host = headers
        .get(header::HOST)
        .and_then(|h| h.to_str().ok())
        .unwrap_or("");
    match &shared.token {
        Some(token) => {
            let given = request
                .uri()
                .query()
                .and_then(|q| q.split('&').find_map(|kv| kv.strip_prefix("token=")));
            if given != Some(token.as_str()) {
                return Refusal(
                    StatusCode::UNAUTHORIZED,
                    "this studio asks for its token: open the URL it printed, with ?token=".into(),
                )
                .into_response();
            }
        }
        None => {
            if !shared.hosts.iter().any(|h| h == host) {
                return Refusal(
                    StatusCode::FORBIDDEN,
                    format!("the studio answers requests for {} only", shared.hosts[0]),
                )
                .into_response();
            }
        }
    }
    let upgrade = headers.contains_key(header::UPGRADE);
    if upgrade || request.method() != Method::GET {
        if let Some(origin) = headers.get(header::ORIGIN) {
            let origin = origin.to_str().unwrap_or("");
            if origin != format!("http://{host}") {
                shared.hub.count_refused();
                return Refusal(
                    StatusCode::FORBIDDEN,
                    format!("requests from `{origin}` are not accepted"),
                )
                .into_response();
            }
        }
    }
    next.run(request).await
}

async fn index() -> Response {
    asset_response("index.html")
}

async fn asset(axum::extract::Path(path): axum::extract::Path<String>) -> Response {
    asset_response(&path)
}

fn asset_response(path: &str) -> Response {
    match Assets::get(path) {
        Some(file) => {
            let mime = file.metadata.mimetype().to_string();
            (
                [
                    (header::CONTENT_TYPE, mime),
                    (header::CACHE_CONTROL, "no-cache".to_string()),
                ],
                Body::from(file.data.into_owned()),
            )
                .into_response()
        }
        None => Refusal(StatusCode::NOT_FOUND, format!("no page file `{path}`")).into_response(),
    }
}

async fn session(State(shared): App) -> Json<Value> {
    Json(json!({
        "version": env!("CARGO_PKG_VERSION"),
        "open": shared.open,
        "watch": shared.hub.lock().run.is_some() || shared.hub.desk.is_active(),
        "token": shared.token.is_some(),
    }))
}

async fn files(State(shared): App) -> Json<Value> {
    let shared2 = Arc::clone(&shared);
    let list = tokio::task::spawn_blocking(move || shared2.workspace.list())
        .await
        .unwrap_or_default();
    Json(json!({ "files": list }))
}

#[derive(Deserialize)]
struct PathQuery {
    path: String,
    tree: Option<String>,
}

async fn file(State(shared): App, Query(q): Query<PathQuery>) -> Result<Json<Value>, Refusal> {
    let text = shared.workspace.read(&q.path)?;
    let mtime = shared.workspace.mtime(&q.path)?;
    let check = run_check(&shared, &q.path, text.clone()).await?;
    Ok(Json(
        json!({"path": q.path, "text": text, "mtime": mtime, "check": check}),
    ))
}

async fn stat(State(shared): App, Query(q): Query<PathQuery>) -> Result<Json<Value>, Refusal> {
    Ok(Json(json!({"mtime": shared.workspace.mtime(&q.path)?})))
}

#[derive(Deserialize)]
struct TextBody {
    path: String,
    text: String,
    #[serde(default)]
    mtime: Option<u64>,
    #[serde(default)]
    tree: Option<String>,
}

async fn run_check(shared: &Arc<Shared>, path: &str, text: String) -> Result<Value, Refusal> {
    let abs = shared.workspace.resolve(path)?;
    let shared = Arc::clone(shared);
    let shown = path.to_string();
    tokio::task::spawn_blocking(move || {
        let check = check_text(
            (shared.registry)(),
            &abs,
            &shown,
            &text,
            shared.max_nodes,
            shared.unknown_type_advice,
        );
        serde_json::to_value(check).unwrap_or(Value::Null)
    })
    .await
    .map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))
}

async fn check(State(shared): App, Json(body): Json<TextBody>) -> Result<Json<Value>, Refusal> {
    Ok(Json(run_check(&shared, &body.path, body.text).await?))
}

async fn save(State(shared): App, Json(body): Json<TextBody>) -> Result<Response, Refusal> {
    let options = crate::check::xml_options();
    if let Err(e) = roxmltree::Document::parse_with_options(&body.text, options) {
        return Err(Refusal(
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("not saved: the text is not well-formed XML ({e})"),
        ));
    }
    if let (Some(read), Ok(now)) = (body.mtime, shared.workspace.mtime(&body.path)) {
        if now != read {
            let error = format!(
                "`{}` changed on disk since it was opened: reload it, or save again to overwrite",
                body.path
            );
            return Ok((
                StatusCode::CONFLICT,
                Json(json!({"error": error, "mtime": now})),
            )
                .into_response());
        }
    }
    shared.workspace.write(&body.path, &body.text)?;
    let mtime = shared.workspace.mtime(&body.path)?;
    let check = run_check(&shared, &body.path, body.text).await?;
    Ok(Json(json!({"mtime": mtime, "check": check})).into_response())
}

#[derive(Deserialize)]
struct MaybePath {
    path: Option<String>,
}

async fn palette_of(
    State(shared): App,
    Query(q): Query<MaybePath>,
) -> Result<Json<Value>, Refusal> {
    let mut registry = (shared.registry)();
    if let Some(path) = &q.path {
        let text = shared.workspace.read(path)?;
        // A model that does not load is reported by the check; the palette goes without.
        let _ = registry.add_model_str(&text, path);
    }
    // The names files may write for a type (`<inverter>`), so that the page draws each
    // as the type it loads as.
    let aliases: Vec<Value> = registry
        .aliases()
        .map(|(name, target)| json!({ "name": name, "type": target.name }))
        .collect();
    Ok(Json(
        json!({ "types": palette(&registry), "aliases": aliases }),
    ))
}

async fn svg(State(shared): App, Json(body): Json<TextBody>) -> Result<Response, Refusal> {
    let abs = shared.workspace.resolve(&body.path)?;
    let shared = Arc::clone(&shared);
    let drawn = tokio::task::spawn_blocking(move || -> Result<String, String> {
        let blueprint = with_lenient_loader(&shared, &abs, &body.path, &body.text, |loader| {
            match &body.tree {
                Some(id) => loader.build(id),
                None => loader.build_main(),
            }
            .map_err(|e| e.to_string())
        })??;
        Ok(neurotree_toolkit::render::render_svg(&blueprint, None))
    })
    .await
    .map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))?
    .map_err(|e| Refusal(StatusCode::UNPROCESSABLE_ENTITY, e))?;
    Ok(([(header::CONTENT_TYPE, "image/svg+xml")], drawn).into_response())
}

/// The sizes and font widths `neurotree show --format svg` draws with, so that the page's
/// boxes are the command's.
async fn drawing() -> Json<neurotree_toolkit::render::DrawingMetrics> {
    Json(neurotree_toolkit::render::drawing_metrics())
}

/// The same as a module the page imports, fetched with the page's other modules rather
/// than after them.
async fn drawing_module() -> Response {
    let json = serde_json::to_string(&neurotree_toolkit::render::drawing_metrics())
        .unwrap_or_else(|_| "{}".into());
    (
        [
            (header::CONTENT_TYPE, "text/javascript; charset=utf-8"),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        format!("// The sizes and font widths of `neurotree show --format svg`.\nexport default {json};\n"),
    )
        .into_response()
}

async fn replay_of(State(shared): App, Query(q): Query<PathQuery>) -> Result<Response, Refusal> {
    let kind = FileKind::of(Path::new(&q.path));
    let abs = shared.workspace.resolve(&q.path)?;
    let shared2 = Arc::clone(&shared);
    let replay = tokio::task::spawn_blocking(move || -> Result<Replay, Refusal> {
        let bad = |e: ReplayError| Refusal(StatusCode::UNPROCESSABLE_ENTITY, format!("{}: {e}", q.path));
        match kind {
            Some(FileKind::Btlog) => replay::from_btlog(&shared2.workspace.read_bytes(&q.path)?).map_err(bad),
            Some(FileKind::Trace) => {
                let tree = q.tree.as_deref().ok_or_else(|| {
                    Refusal(
                        StatusCode::BAD_REQUEST,
                        "a .jsonl trace names nodes by the tree it was run from: give that file as `tree`".into(),
                    )
                })?;
                let text = shared2.workspace.read(&q.path)?;
                jsonl_replay(&shared2, tree, &text).map_err(|e| match e {
                    JsonlError::Path(p) => p.into(),
                    JsonlError::Load(m) => Refusal(StatusCode::UNPROCESSABLE_ENTITY, m),
                    JsonlError::Replay(r) => bad(r),
                })
            }
            #[cfg(feature = "sqlite")]
            Some(FileKind::Sqlite) => {
                shared2.workspace.read_bytes(&q.path)?;
                replay::from_sqlite(&abs).map_err(bad)
            }
            _ => {
                let _ = &abs;
                Err(Refusal(
                    StatusCode::UNPROCESSABLE_ENTITY,
                    format!("`{}` is not a log the studio replays (.jsonl, .btlog{})", q.path,
                        if cfg!(feature = "sqlite") { ", .db" } else { "; this build has no SQLite" }),
                ))
            }
        }
    })
    .await
    .map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))??;
    Ok(Json(replay).into_response())
}

enum JsonlError {
    Path(PathError),
    Load(String),
    Replay(ReplayError),
}

/// A trace replayed on the tree it names: the tree file's main tree, else whichever of
/// its trees the trace matches.
fn jsonl_replay(shared: &Shared, tree_path: &str, text: &str) -> Result<Replay, JsonlError> {
    let tree_text = shared.workspace.read(tree_path).map_err(JsonlError::Path)?;
    let abs = shared
        .workspace
        .resolve(tree_path)
        .map_err(JsonlError::Path)?;
    with_lenient_loader(shared, &abs, tree_path, &tree_text, |loader| {
        let mut ids: Vec<String> = loader.tree_ids().map(String::from).collect();
        if let Some(main) = loader.main_tree() {
            let main = main.to_string();
            ids.retain(|i| *i != main);
            ids.insert(0, main);
        }
        let mut first_error = None;
        for id in &ids {
            let Ok(blueprint) = loader.build(id) else {
                continue;
            };
            match replay::from_jsonl(text, &blueprint, id) {
                Ok(r) => return Ok(r),
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        Err(match first_error {
            Some(e) => JsonlError::Replay(e),
            None => JsonlError::Load(format!("no tree of `{tree_path}` builds")),
        })
    })
    .map_err(JsonlError::Load)?
}

/// Runs `f` on a loader holding `text` (the file `path`, its includes beside `abs`) with
/// every unknown leaf mocked: drawing a tree or replaying its run needs no implementation
/// of its leaves. `Err` with the loader's message when the text does not load.
fn with_lenient_loader<R>(
    shared: &Shared,
    abs: &Path,
    path: &str,
    text: &str,
    f: impl FnOnce(&mut XmlLoader<'_, ()>) -> R,
) -> Result<R, String> {
    let mut registry = (shared.registry)();
    // A model that does not load is the check's to report; the loader goes without it.
    let _ = registry.add_model_str(text, path);
    let mut loader = XmlLoader::new(&registry)
        .mock_unknown(true)
        .max_nodes(shared.max_nodes);
    if let Some(dir) = abs.parent() {
        loader = loader.base_dir(dir);
    }
    loader.load_str(text, path).map_err(|e| e.to_string())?;
    Ok(f(&mut loader))
}

async fn coverage(State(shared): App, Query(q): Query<MaybePath>) -> Result<Json<Value>, Refusal> {
    let path = q.path.unwrap_or_default();
    let text = shared.workspace.read(&path)?;
    let value: Value = serde_json::from_str(&text).map_err(|e| {
        Refusal(
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("{path}: not JSON: {e}"),
        )
    })?;
    if !value.get("nodes").is_some_and(Value::is_array) {
        return Err(Refusal(
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("{path}: not a coverage file (`run --coverage-json` writes one)"),
        ));
    }
    Ok(Json(value))
}

async fn stats(State(shared): App) -> Json<Value> {
    Json(json!({"refused": shared.hub.refused(), "pages": shared.hub.pages()}))
}

async fn ws(State(shared): App, upgrade: WebSocketUpgrade, _headers: HeaderMap) -> Response {
    let hub = Arc::clone(&shared.hub);
    upgrade
        // Past this a frame is a protocol error and the socket closes; below it, a message
        // over the page limit is refused and counted, the socket stays.
        .max_message_size(1024 * 1024)
        .on_upgrade(move |socket| serve_page(socket, hub))
}

/// The `Host` values a loopback studio on `addr` answers.
pub(crate) fn hosts(addr: SocketAddr) -> Vec<String> {
    let port = addr.port();
    let mut hosts = vec![
        format!("127.0.0.1:{port}"),
        format!("localhost:{port}"),
        format!("[::1]:{port}"),
    ];
    let own = addr.to_string();
    if !hosts.contains(&own) {
        hosts.push(own);
    }
    hosts
}

//! NeuroTree Studio: see, edit, watch and replay behavior trees in a browser.
//!
//! [`Studio::serve`] starts a local web server (axum, on a thread of its own) whose page,
//! embedded in the binary, has three views:
//!
//! - **edit** a BehaviorTree.CPP file: the tree drawn as `neurotree show` draws it, a
//!   palette of every node type, ports checked by the loader as you type, undo, save;
//! - **watch** a running tree: statuses live, the blackboards (editable between ticks), the
//!   failure chain, breakpoints, pause, step and continue; back and forth through the
//!   last few hundred ticks, and a fork from any of them; the world the tree acts on drawn
//!   beside it (a [`World`]'s [scene](neurotree_toolkit::scene)); or one agent of a crowd
//!   at a time, the others running on ([`Studio::watch_crowd`], [`Agents`]);
//! - **replay** a recorded run (`--jsonl`, `.btlog`, SQLite log) on a timeline.
//!
//! Every view draws the tree with the boxes of `neurotree show --format svg` (ports under
//! each name; sizes and font widths served from the renderer), top-down or left to right,
//! at a legible zoom with an overview, big trees folded to fit (docs/guide/studio-canvas.md).
//!
//! The page is a view: edits go through the loader, runs through the engine, replays
//! through the log readers. The messages between them are in `PROTOCOL.md`.
//!
//! Watching a tree takes one line, and one call between ticks:
//!
//! ```no_run
//! use std::sync::Arc;
//! use neurotree_studio::{Studio, StudioOptions};
//! use neurotree_toolkit::{Registry, Status, Tree, XmlLoader};
//!
//! let registry = Registry::<()>::new();
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_file("tree.xml").unwrap();
//! let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
//!
//! let studio = Studio::serve(StudioOptions::default(), Registry::new).unwrap();
//! eprintln!("studio: {}", studio.url());
//! let mut watch = studio.watch(&mut tree, "tree.xml");
//! while watch.tick_once(&mut tree, &mut ()).unwrap() == Status::Running {}
//! ```
//!
//! # Safety on the network
//! The server listens on 127.0.0.1 unless [`StudioOptions::bind`] says otherwise, and
//! then asks every API call and WebSocket for a random token (in the URL it prints).
//! Without a token it answers only requests whose `Host` is this machine, so a web page
//! elsewhere cannot reach it through DNS rebinding; WebSockets and writes must come from
//! the studio's own origin. Files are read and written only inside the folder given as
//! [`StudioOptions::root`], never through `..`, absolute paths or links out of it. A page's
//! malformed, oversized (over 64 KiB) or flooding (over 100 a second) messages are refused
//! and counted ([`Studio::refused`]); the tick thread never waits on the network.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod check;
mod layout;
mod palette;
mod replay;
mod server;
mod view;
mod watch;
mod workspace;

use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpListener};
use std::path::PathBuf;
use std::sync::Arc;
use std::thread::JoinHandle;

use neurotree_core::Tree;
use neurotree_toolkit::Registry;

pub use check::{check_text, Check, Diagnostic, UNKNOWN_TYPE_ADVICE};
pub use palette::palette;
pub use replay::{Replay, ReplayError, Step};
pub use server::RegistryFactory;
pub use view::{NodeView, TreeView};
pub use watch::{
    AgentEntry, Agents, CrowdWatch, Forced, StudioObserver, Watch, World, DEFAULT_REWIND_WINDOW,
    MAX_AGENTS_PAGE, MAX_SCENE_BYTES,
};
pub use workspace::{FileEntry, FileKind, PathError, Workspace};

/// How to serve the studio.
#[derive(Clone, Debug)]
pub struct StudioOptions {
    /// The address to listen on: 127.0.0.1 unless the studio is to be reached from other
    /// machines (it then asks for a token).
    pub bind: IpAddr,
    /// The port; 0 picks a free one ([`Studio::url`] says which).
    pub port: u16,
    /// The folder the page may read and write files in.
    pub root: PathBuf,
    /// Files (relative to `root`) the page opens at start.
    pub open: Vec<String>,
    /// The most nodes a tree may expand to when the editor checks it.
    pub max_nodes: usize,
    /// What the editor's error for a node type the registry does not know advises:
    /// [`UNKNOWN_TYPE_ADVICE`] (the `neurotree` command's flags) unless the program serving
    /// the studio says how its registry is extended.
    pub unknown_type_advice: &'static str,
}

impl Default for StudioOptions {
    fn default() -> Self {
        Self {
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: 0,
            root: PathBuf::from("."),
            open: Vec::new(),
            max_nodes: 2_000_000,
            unknown_type_advice: UNKNOWN_TYPE_ADVICE,
        }
    }
}

/// Why the studio could not start.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum StudioError {
    /// The address could not be listened on.
    #[error("the studio cannot listen on {addr}: {source}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// What the system said.
        source: std::io::Error,
    },
    /// The folder does not exist or cannot be read.
    #[error("the studio's folder {path}: {source}")]
    Root {
        /// The folder.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The server's runtime could not start.
    #[error("the studio's server could not start: {0}")]
    Runtime(std::io::Error),
    /// No random token could be made for a studio reached from other machines.
    #[error("no random token for the studio: {0}")]
    Token(String),
}

neurotree_core::debug_shows_message!(enum StudioError {
    Bind { addr, source },
    Root { path, source },
    Runtime(source),
    Token(source),
});

/// A running studio server; dropping it stops the server.
pub struct Studio {
    addr: SocketAddr,
    token: Option<String>,
    hub: Arc<watch::Hub>,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Studio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Studio")
            .field("addr", &self.addr)
            .finish_non_exhaustive()
    }
}

impl Studio {
    /// Starts the server on a thread of its own; `registry` makes the registry the editor
    /// checks files with and lists in its palette (add your own node types and models to
    /// it).
    pub fn serve(
        options: StudioOptions,
        registry: impl Fn() -> Registry<()> + Send + Sync + 'static,
    ) -> Result<Studio, StudioError> {
        let workspace = Workspace::new(&options.root).map_err(|source| StudioError::Root {
            path: options.root.clone(),
            source,
        })?;
        let wanted = SocketAddr::new(options.bind, options.port);
        let listener = TcpListener::bind(wanted).map_err(|source| StudioError::Bind {
            addr: wanted,
            source,
        })?;
        let addr = listener.local_addr().map_err(StudioError::Runtime)?;
        listener
            .set_nonblocking(true)
            .map_err(StudioError::Runtime)?;
        let token = if options.bind.is_loopback() {
            None
        } else {
            let mut bytes = [0u8; 16];
            getrandom::fill(&mut bytes).map_err(|e| StudioError::Token(e.to_string()))?;
            Some(bytes.iter().map(|b| format!("{b:02x}")).collect::<String>())
        };
        let hub = watch::Hub::new();
        let shared = Arc::new(server::Shared {
            hub: Arc::clone(&hub),
            workspace,
            registry: Arc::new(registry),
            open: options.open,
            token: token.clone(),
            max_nodes: options.max_nodes,
            unknown_type_advice: options.unknown_type_advice,
            hosts: server::hosts(addr),
        });
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("neurotree-studio")
            .enable_all()
            .build()
            .map_err(StudioError::Runtime)?;
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let thread = std::thread::Builder::new()
            .name("neurotree-studio".into())
            .spawn(move || {
                runtime.block_on(async move {
                    let Ok(listener) = tokio::net::TcpListener::from_std(listener) else {
                        return;
                    };
                    let app = server::router(shared);
                    let _ = axum::serve(listener, app)
                        .with_graceful_shutdown(async {
                            let _ = stopped.await;
                        })
                        .await;
                });
                // The pages' sockets are not waited for: the run is over.
                runtime.shutdown_background();
            })
            .map_err(StudioError::Runtime)?;
        Ok(Studio {
            addr,
            token,
            hub,
            stop: Some(stop),
            thread: Some(thread),
        })
    }

    /// Where the page is: `http://ADDR:PORT/`, with `?token=` when one is asked for.
    pub fn url(&self) -> String {
        match &self.token {
            Some(t) => format!("http://{}/?token={t}", self.addr),
            None => format!("http://{}/", self.addr),
        }
    }

    /// The address the server listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Shows `tree` to the pages; returns the observer to set on it (beside others, as a
    /// pair) and the [`Watch`] to call between ticks.
    pub fn attach<C>(&self, tree: &Tree<C>, name: &str) -> (StudioObserver, Watch) {
        let observer = self.hub.attach(tree, name);
        (observer, Watch::new(Arc::clone(&self.hub)))
    }

    /// The hook wrapper to build the tree watched with ([`XmlLoader::wrap_hooks`]), so
    /// that pages can force its nodes' results; `inner` (faults of the run's own) wraps
    /// first. A tree built without it is watched all the same, without forces.
    ///
    /// [`XmlLoader::wrap_hooks`]: neurotree_toolkit::XmlLoader::wrap_hooks
    pub fn force_hooks<C: 'static>(
        &self,
        inner: Option<neurotree_toolkit::xml::SharedHookWrapper<C>>,
    ) -> neurotree_toolkit::xml::SharedHookWrapper<C> {
        self.hub.forces.hand_out();
        let live: Arc<dyn neurotree_toolkit::fault::LiveFaults> = self.hub.clone();
        neurotree_toolkit::fault::live_wrapper(live, inner)
    }

    /// [`attach`](Self::attach), with the observer set on `tree` (replacing any other).
    pub fn watch<C>(&self, tree: &mut Tree<C>, name: &str) -> Watch {
        let (observer, watch) = self.attach(tree, name);
        tree.set_observer(observer);
        watch
    }

    /// Shows the agents of a crowd to the pages, which watch one of them at a time (the
    /// first until a page chooses another); `name` names the crowd (its tree file, say).
    /// Call the [`CrowdWatch`] around each frame. Watch one crowd, or one tree
    /// ([`attach`](Self::attach)), per studio.
    pub fn watch_crowd(&self, name: &str) -> CrowdWatch {
        CrowdWatch::new(Arc::clone(&self.hub), name)
    }

    /// Messages refused from pages (malformed, oversized, flooding, foreign origin).
    pub fn refused(&self) -> u64 {
        self.hub.refused()
    }

    /// Pages attached now.
    pub fn pages(&self) -> usize {
        self.hub.pages()
    }
}

impl Drop for Studio {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

//! The studio itself, in a build with the `studio` feature.

use std::io::{self, Write};
use std::path::PathBuf;
use std::time::Duration;

use neurotree::sim::nav2::Nav2Sim;
use neurotree::{Registry, Status, Tree};
use neurotree_cli::demo::{
    self, DemoOptions, DemoRun, DemoSaved, DemoSummary, DemoWatch, DemoWorld,
};
use neurotree_studio::{Studio, StudioObserver, StudioOptions, Watch, World};

use super::{StudioArgs, StudioFlags};
use crate::registry::{with_nav2_controls, Nav2Args};
use crate::{files, Outcome};

/// The registry the page checks with: the built-ins, Nav2's nodes (all of them with
/// `--nav2`), and the `TreeNodesModel` of every model file and file given.
fn registry_factory(
    nav2: Nav2Args,
    model_files: &[PathBuf],
    err: &mut impl Write,
) -> io::Result<Result<impl Fn() -> Registry<()> + Send + Sync + 'static, ()>> {
    let mut models = Vec::new();
    for path in model_files {
        match files::read(path) {
            Ok(text) => {
                let shown = files::shown(path);
                // Refused now, with its place, rather than on every check.
                if let Err(e) = Registry::<()>::new().add_model_str(&text, &shown) {
                    writeln!(err, "{e}")?;
                    return Ok(Err(()));
                }
                models.push((text, shown));
            }
            Err(e) => {
                writeln!(err, "{e}")?;
                return Ok(Err(()));
            }
        }
    }
    Ok(Ok(move || {
        let mut registry = with_nav2_controls::<()>(nav2);
        for (text, shown) in &models {
            // Each loaded when the studio started.
            let _ = registry.add_model_str(text, shown);
        }
        registry
    }))
}

/// `files` relative to the current folder, or the first that is not inside it.
fn inside(files: &[PathBuf]) -> Result<Vec<String>, String> {
    let here = std::env::current_dir().map_err(|e| e.to_string())?;
    let here = std::fs::canonicalize(here).map_err(|e| e.to_string())?;
    files
        .iter()
        .map(|f| {
            let real = std::fs::canonicalize(f)
                .map_err(|e| format!("neurotree: {}: {e}", files::shown(f)))?;
            let rel = real.strip_prefix(&here).map_err(|_| {
                format!(
                    "neurotree: {} is outside the current folder, which is all the studio \
                     serves: start it in a folder that holds the file",
                    files::shown(f)
                )
            })?;
            Ok(rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/"))
        })
        .collect()
}

/// Serves the studio until the process is stopped.
pub fn execute(args: &StudioArgs, err: &mut impl Write) -> io::Result<Outcome> {
    let open = match inside(&args.files) {
        Ok(open) => open,
        Err(e) => {
            writeln!(err, "{e}")?;
            return Ok(Outcome::Refused);
        }
    };
    let Ok(registry) = registry_factory(args.nav2, &args.models, err)? else {
        return Ok(Outcome::Refused);
    };
    let options = StudioOptions {
        bind: args.bind,
        port: args.port,
        open,
        ..StudioOptions::default()
    };
    let studio = match Studio::serve(options, registry) {
        Ok(s) => s,
        Err(e) => {
            writeln!(err, "neurotree: {e}")?;
            return Ok(Outcome::Refused);
        }
    };
    writeln!(err, "studio: {}", studio.url())?;
    err.flush()?;
    loop {
        std::thread::park();
    }
}

/// A run served to the studio (`run --studio`, `demo --studio`).
pub struct Served {
    studio: Studio,
    watch: Option<Watch>,
    linger: Duration,
    rewind_window: usize,
}

impl Served {
    /// Starts the studio if `--studio` was given, serving the current folder with `files`
    /// open; says where on `err`. `Err` when it cannot start (said on `err`).
    pub fn start(
        flags: &StudioFlags,
        files: &[PathBuf],
        nav2: Nav2Args,
        err: &mut impl Write,
    ) -> io::Result<Result<Option<Served>, ()>> {
        let Some(port) = flags.port else {
            return Ok(Ok(None));
        };
        let Ok(registry) = registry_factory(nav2, &[], err)? else {
            return Ok(Err(()));
        };
        // Files outside the folder are run, but not opened in the page.
        let open = files
            .iter()
            .filter_map(|f| inside(std::slice::from_ref(f)).ok())
            .flatten()
            .collect();
        let options = StudioOptions {
            bind: flags.bind,
            port,
            open,
            ..StudioOptions::default()
        };
        match Studio::serve(options, registry) {
            Ok(studio) => {
                writeln!(err, "studio: {}", studio.url())?;
                err.flush()?;
                Ok(Ok(Some(Served {
                    studio,
                    watch: None,
                    linger: flags.linger,
                    rewind_window: flags.rewind_window as usize,
                })))
            }
            Err(e) => {
                writeln!(err, "neurotree: {e}")?;
                Ok(Err(()))
            }
        }
    }

    /// The hooks to build the watched tree with, so that pages force its nodes' results;
    /// `inner` (the run's own faults) wraps first.
    pub fn force_hooks<C: 'static>(
        &self,
        inner: Option<neurotree::xml::SharedHookWrapper<C>>,
    ) -> neurotree::xml::SharedHookWrapper<C> {
        self.studio.force_hooks(inner)
    }

    /// The results pages forced since the last call, as the run's JSON lines say them:
    /// `{"tick","node","status","until"}`.
    pub fn forced(&mut self) -> Vec<serde_json::Value> {
        self.watch.as_mut().map_or_else(Vec::new, |w| {
            w.forced()
                .iter()
                .map(neurotree_studio::Forced::json)
                .collect()
        })
    }

    /// Shows `tree` to the pages; the observer to set on it.
    pub fn attach<C>(&mut self, tree: &Tree<C>, name: &str) -> Box<dyn neurotree::Observer> {
        let (observer, watch): (StudioObserver, Watch) = self.studio.attach(tree, name);
        self.watch = Some(watch.rewind_window(self.rewind_window));
        Box::new(observer)
    }

    /// Between two ticks of a tree of Nav2's nodes acting on a world the run does not keep
    /// (`ros2 navigator`: the robot and its servers are other processes): the pages'
    /// edits, pauses and steps, and going back to the tree's kept states, whose blackboards
    /// hold Nav2's values; the tick a page went back to when the run forks there.
    #[cfg(feature = "ros2")]
    pub fn between_nav2_ticks<C>(&mut self, tree: &mut Tree<C>) -> Option<u64> {
        self.between_ticks_with(tree, &mut Nav2Values)
    }

    /// Between two ticks of a tree acting on `world`, which is kept and restored with it:
    /// the pages' edits, pauses and steps; the tick a page went back to when the run forks
    /// there.
    pub fn between_ticks_with<C, W: World<C>>(
        &mut self,
        tree: &mut Tree<C>,
        world: &mut W,
    ) -> Option<u64> {
        self.watch.as_mut()?.between_ticks_with(tree, world)
    }

    /// After a reload: the pages get the new tree.
    pub fn reattach<C>(&mut self, tree: &Tree<C>, name: &str) {
        if let Some(w) = &mut self.watch {
            w.reattach(tree, name);
        }
    }

    /// The run ended with `status`: the pages are told.
    pub fn end<C>(&mut self, tree: &mut Tree<C>, status: Status) {
        if let Some(w) = &mut self.watch {
            w.finish(tree, status);
        }
    }

    /// Serves on for `--studio-linger`, so that a page still shows the run's last state.
    pub fn linger(self, err: &mut impl Write) -> io::Result<()> {
        if !self.linger.is_zero() {
            writeln!(
                err,
                "studio: the run ended; serving its last state for {} s",
                self.linger.as_secs_f64()
            )?;
            err.flush()?;
            std::thread::sleep(self.linger);
        }
        Ok(())
    }
}

/// No world kept beside the tree, but the codecs of the values Nav2's nodes keep on the
/// blackboard, so that the tree's state can be kept.
#[cfg(feature = "ros2")]
struct Nav2Values;

#[cfg(feature = "ros2")]
impl<C> World<C> for Nav2Values {
    type Saved = ();

    fn save(&self, _: &Tree<C>) -> Result<(), String> {
        Ok(())
    }

    fn restore(&mut self, _: &()) {}

    fn codecs(&self) -> neurotree::state::StateCodecs {
        DemoWorld::codecs()
    }
}

/// Runs the demo shown in the studio, which serves on for `--studio-linger` after it.
pub fn run_demo(
    served: Served,
    opts: &DemoOptions,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Option<DemoSummary>> {
    let mut watched = DemoWatched { served };
    let summary = demo::run_watched(opts, out, err, &mut watched)?;
    out.flush()?;
    watched.served.linger(err)?;
    Ok(summary)
}

/// The demo's run shown in the studio.
struct DemoWatched {
    served: Served,
}

impl DemoWatch for DemoWatched {
    fn hooks(&mut self) -> Option<neurotree::xml::SharedHookWrapper<Nav2Sim>> {
        Some(self.served.force_hooks(None))
    }

    fn attach(&mut self, demo: &mut DemoRun) {
        let name = demo.tree_file().to_string();
        let observer = self.served.attach(demo.tree_mut(), &name);
        demo.add_observer(observer);
    }

    fn before_tick(&mut self, demo: &mut DemoRun) {
        let (tree, world) = demo.watched();
        let mut world = Warehouse(world);
        if let Some(to) = self.served.between_ticks_with(tree, &mut world) {
            world.0.note(format!(
                "back to tick {to}: the run goes on from there, the later ticks dropped"
            ));
        }
        // Those of the tick before, told as it ends.
        for forced in self.served.forced() {
            world.0.note(format!(
                "forced {} to {} at tick {}",
                forced["node"].as_str().unwrap_or(""),
                forced["status"].as_str().unwrap_or(""),
                forced["tick"]
            ));
        }
    }

    fn finish(&mut self, demo: &mut DemoRun) {
        let status = demo.summary().outcome;
        self.served.end(demo.tree_mut(), status);
    }
}

/// The demo's warehouse and counters, kept and restored with the tree, and drawn beside it.
struct Warehouse<'a>(DemoWorld<'a>);

impl World<Nav2Sim> for Warehouse<'_> {
    type Saved = DemoSaved;

    fn save(&self, _: &Tree<Nav2Sim>) -> Result<DemoSaved, String> {
        Ok(self.0.save())
    }

    fn restore(&mut self, saved: &DemoSaved) {
        self.0.restore(saved);
    }

    fn codecs(&self) -> neurotree::state::StateCodecs {
        DemoWorld::codecs()
    }

    fn scene(&self, tree: &Tree<Nav2Sim>) -> Option<neurotree::scene::Scene> {
        Some(self.0.scene(tree))
    }
}

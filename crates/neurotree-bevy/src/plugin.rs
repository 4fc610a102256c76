//! The plugin: the crowd resource, the systems, the messages and the tree asset.

use std::marker::PhantomData;
use std::sync::Arc;
use std::time::Duration;

use bevy_app::{App, Plugin, TaskPoolOptions, TaskPoolPlugin, Update};
use bevy_asset::{AssetApp, AssetServer};
use bevy_ecs::component::Component;
use bevy_ecs::entity::Entity;
use bevy_ecs::message::Message;
use bevy_ecs::query::QueryItem;
use bevy_ecs::schedule::{InternedScheduleLabel, IntoScheduleConfigs, ScheduleLabel, SystemSet};
use bevy_ecs::system::SystemParamItem;
use neurotree::crowd::{Crowd, ThreadPool, ThreadPoolBuildError, ThreadPoolBuilder};
use neurotree::{ManualClock, Registry};

use bevy_diagnostic::RegisterDiagnostic;

use crate::agent::{AgentSummary, TreeAgent};
use crate::asset::{TreeAsset, TreeAssetLoader};
use crate::awake::AwakeAgents;
use crate::context::AgentContext;
use crate::crowd::AgentCrowd;
use crate::events::{TreeFinished, TreeReloaded};
use crate::systems;

/// The systems that run the agents' trees, in this order, once per run of the plugin's
/// schedule (`Update` by default). Order your own systems against them: write what the
/// trees should see before [`Tick`](TreeSystems::Tick), read what they did after it.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TreeSystems {
    /// New agents join the crowd; agents whose tree asset changed are reloaded.
    Join,
    /// Sleeping agents wake on the component changes and the messages the app named
    /// ([`NeuroTreePlugin::wake_on_change`], [`NeuroTreePlugin::wake_on_message`]).
    Wake,
    /// On all cores, each agent due is visited once: its context is loaded from its
    /// components, its tree ticked and what changed written back; then results are
    /// reported. Sleeping agents are skipped; when fewer than one agent in 8 is awake,
    /// the awake ones are visited by entity on one thread, and the others not at all.
    Tick,
}

/// Runs the trees of every [`TreeAgent<C>`](crate::TreeAgent) through one
/// [`AgentCrowd<C>`] (one plugin per context type).
///
/// With Bevy's `AssetPlugin` added before it, it also loads `.xml` files as
/// [`TreeAsset<C>`] with the app's registry, and reloads agents when their asset changes.
pub struct NeuroTreePlugin<C> {
    registry: Arc<Registry<C>>,
    pool: Option<Arc<ThreadPool>>,
    /// Frames without a budget run on Bevy's compute task pool rather than `pool`.
    compute_pool: bool,
    step: Option<Duration>,
    schedule: InternedScheduleLabel,
    /// The systems that wake agents, added with the others.
    wakes: Vec<AddWake>,
    /// The studio's port and the crowd's name there.
    #[cfg(feature = "studio")]
    studio: Option<(u16, String)>,
    _context: PhantomData<fn(C)>,
}

/// Adds one waking system to an app's schedule.
type AddWake = Box<dyn Fn(&mut App, InternedScheduleLabel) + Send + Sync>;

impl<C: AgentContext> NeuroTreePlugin<C> {
    /// A plugin whose tree files are built from the nodes `registry` knows, ticking in
    /// `Update` on every core (a pool of its own, one thread per core:
    /// [`AgentCrowd::threads`]), with a clock that follows the app's virtual time
    /// (`Time<Virtual>`), or, without Bevy's `TimePlugin`, moves 1/60 s per frame.
    pub fn new(registry: Registry<C>) -> Self {
        Self {
            registry: Arc::new(registry),
            pool: None,
            compute_pool: false,
            step: None,
            schedule: Update.intern(),
            wakes: Vec::new(),
            #[cfg(feature = "studio")]
            studio: None,
            _context: PhantomData,
        }
    }

    /// Serves the studio on 127.0.0.1:`port` (0: a free port) when the plugin is added:
    /// a browser page that lists the agents by entity and watches one at a time (the first
    /// until another is chosen), with its statuses, blackboard, Utility scores and why it
    /// is awake; a pause or a breakpoint holds that agent alone while the rest of the crowd
    /// runs on, or the whole crowd, as the page chooses. The [`TreeStudio`](crate::TreeStudio)
    /// resource says where the page is. Unwatched agents cost nothing. A port that cannot
    /// be listened on is reported on standard error, and the app runs without the studio.
    /// (Feature `studio`, on by default.)
    #[cfg(feature = "studio")]
    pub fn with_studio(mut self, port: u16, name: &str) -> Self {
        self.studio = Some((port, name.to_string()));
        self
    }

    /// Runs frames on a pool of `threads` threads of its own (0: rayon's default,
    /// `RAYON_NUM_THREADS` or every core) instead of one thread per core.
    pub fn with_threads(mut self, threads: usize) -> Result<Self, ThreadPoolBuildError> {
        let pool = ThreadPoolBuilder::new().num_threads(threads).build()?;
        self.pool = Some(Arc::new(pool));
        Ok(self)
    }

    /// Runs frames without a budget on Bevy's compute task pool, with the rest of the
    /// game's parallel systems, instead of a pool of its own: the trees then get the
    /// threads `TaskPoolPlugin` gives that pool (one on a 2-core machine by default; see
    /// [`task_pools`]). Frames under a budget still run on the plugin's pool.
    pub fn on_compute_pool(mut self) -> Self {
        self.compute_pool = true;
        self
    }

    /// Moves the trees' clock by `step` after each frame, whatever the virtual time says
    /// (frames still stop while it is paused): runs that repeat exactly.
    pub fn with_step(mut self, step: Duration) -> Self {
        self.step = Some(step);
        self
    }

    /// Wakes an agent whose tree [sleeps](neurotree::tree::sleep) when its entity's
    /// component `T` is inserted or changed, before the frame's tick: for a leaf that reads
    /// `T` through its context and, while Running, waits for it to change (it says so with
    /// [`Handle::wake_on_handle`](neurotree::Handle::wake_on_handle), which lets its tree
    /// sleep until then). Only the agents whose `T` changed wake; a tree that writes `T`
    /// back through [`AgentContext::store`] wakes itself when the value it stores differs.
    ///
    /// ```
    /// use bevy_ecs::component::Component;
    /// # use bevy_ecs::query::QueryItem;
    /// # use bevy_ecs::system::SystemParamItem;
    /// use neurotree::Registry;
    /// use neurotree_bevy::{AgentContext, NeuroTreePlugin};
    ///
    /// #[derive(Component)]
    /// struct Door { open: bool }
    /// # struct Guard;
    /// # impl AgentContext for Guard {
    /// #     type Components = &'static Door;
    /// #     type Shared = ();
    /// #     fn load(&mut self, _: &QueryItem<'_, '_, Self::Components>, _: &SystemParamItem<'_, '_, ()>) {}
    /// #     fn store(&self, _: &mut QueryItem<'_, '_, Self::Components>) {}
    /// # }
    /// let plugin = NeuroTreePlugin::new(Registry::<Guard>::new()).wake_on_change::<Door>();
    /// ```
    pub fn wake_on_change<T: Component>(mut self) -> Self {
        self.wakes.push(Box::new(|app, schedule| {
            app.add_systems(
                schedule,
                systems::wake_on_change::<C, T>.in_set(TreeSystems::Wake),
            );
        }));
        self
    }

    /// Wakes the agent whose entity `target` names in each message `M` written since the
    /// last frame, before the frame's tick: for a leaf that, while Running, waits for such
    /// a message ([`Handle::wake_on_handle`](neurotree::Handle::wake_on_handle)) and reads
    /// what it brought through its context or its blackboard. Only those agents wake.
    /// Adds the message type to the app if it was not.
    pub fn wake_on_message<M: Message>(mut self, target: fn(&M) -> Entity) -> Self {
        self.wakes.push(Box::new(move |app, schedule| {
            app.add_message::<M>().add_systems(
                schedule,
                systems::wake_on_message::<C, M>(target).in_set(TreeSystems::Wake),
            );
        }));
        self
    }

    /// Runs [`TreeSystems`] in `schedule` (e.g. `FixedUpdate`) instead of `Update`.
    pub fn in_schedule(mut self, schedule: impl ScheduleLabel) -> Self {
        self.schedule = schedule.intern();
        self
    }
}

impl<C: AgentContext> Plugin for NeuroTreePlugin<C>
where
    for<'w, 's> SystemParamItem<'w, 's, C::Shared>: Sync,
    for<'w, 's> QueryItem<'w, 's, C::Components>: Send,
{
    fn build(&self, app: &mut App) {
        let clock = ManualClock::new();
        let pool = match &self.pool {
            Some(pool) => Arc::clone(pool),
            None => Arc::new(own_pool()),
        };
        let crowd = Crowd::<C>::new(clock.clone()).with_pool(Arc::clone(&pool));
        let pool = (!self.compute_pool).then_some(pool);
        for diagnostic in crate::awake::diagnostics() {
            app.register_diagnostic(diagnostic);
        }
        app.insert_resource(AgentCrowd::new(crowd, clock, self.step, pool))
            .init_resource::<AwakeAgents>()
            .register_type::<TreeAgent<C>>()
            .register_type::<AgentSummary>()
            .register_type::<AwakeAgents>()
            .add_message::<TreeFinished>()
            .add_message::<TreeReloaded>()
            .configure_sets(
                self.schedule,
                (TreeSystems::Join, TreeSystems::Wake, TreeSystems::Tick).chain(),
            )
            .add_systems(
                self.schedule,
                (
                    systems::join::<C>.in_set(TreeSystems::Join),
                    (systems::tick::<C>, systems::summarize::<C>)
                        .chain()
                        .in_set(TreeSystems::Tick),
                ),
            )
            .add_observer(systems::arrive::<C>)
            .add_observer(systems::leave::<C>);
        for add in &self.wakes {
            add(app, self.schedule);
        }
        #[cfg(feature = "studio")]
        if let Some((port, name)) = &self.studio {
            match crate::studio::TreeStudio::<C>::serve(*port, name) {
                Ok(studio) => {
                    app.insert_resource(studio).add_systems(
                        self.schedule,
                        (
                            crate::studio::before::<C>
                                .after(TreeSystems::Wake)
                                .before(TreeSystems::Tick),
                            crate::studio::after::<C>.after(TreeSystems::Tick),
                        ),
                    );
                }
                Err(e) => eprintln!("neurotree: {e}"),
            }
        }
        if app.world().contains_resource::<AssetServer>() {
            app.init_asset::<TreeAsset<C>>()
                .register_asset_loader(TreeAssetLoader::new(Arc::clone(&self.registry)))
                .add_systems(
                    self.schedule,
                    systems::reload::<C>
                        .in_set(TreeSystems::Join)
                        .before(systems::join::<C>),
                );
        }
    }
}

/// A pool of one thread per core: the plugin's default.
fn own_pool() -> ThreadPool {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("neurotree-{i}"))
        .build()
        .or_else(|_| ThreadPoolBuilder::new().num_threads(1).build())
        // A pool of one thread is what a machine that cannot start threads gets from
        // rayon itself; failing that too, nothing would run anyway.
        .expect("a pool of one thread")
}

/// Bevy's task pools with the compute pool on `threads` threads (0: every core), for
/// `App::add_plugins` in place of `TaskPoolPlugin::default()` (or `DefaultPlugins.set(…)`):
/// with [`NeuroTreePlugin::on_compute_pool`], the plugin's frames run on the compute pool,
/// which Bevy by default gives what is left after the IO and async pools (one thread on a
/// 2-core machine).
///
/// ```
/// let pools = neurotree_bevy::task_pools(0);
/// assert!(pools.task_pool_options.compute.min_threads >= 1);
/// ```
pub fn task_pools(threads: usize) -> TaskPoolPlugin {
    let threads = if threads == 0 {
        bevy_tasks::available_parallelism()
    } else {
        threads
    };
    let mut options = TaskPoolOptions::default();
    options.compute.min_threads = threads;
    options.compute.max_threads = threads;
    TaskPoolPlugin {
        task_pool_options: options,
    }
}

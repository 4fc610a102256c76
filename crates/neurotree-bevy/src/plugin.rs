//! The plugin: the crowd resource, the systems, the messages and the tree asset.

use std::marker::PhantomData;
use std::sync::Arc;
use std::time::Duration;

use bevy_app::{App, Plugin, Update};
use bevy_asset::{AssetApp, AssetServer};
use bevy_ecs::schedule::{InternedScheduleLabel, IntoScheduleConfigs, ScheduleLabel, SystemSet};
use bevy_ecs::system::SystemParamItem;
use neurotree::crowd::{Crowd, ThreadPool, ThreadPoolBuildError, ThreadPoolBuilder};
use neurotree::{ManualClock, Registry};

use crate::asset::{TreeAsset, TreeAssetLoader};
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
    /// On all cores, each agent due is visited once: its context is loaded from its
    /// components, its tree ticked and what changed written back; then results are
    /// reported.
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
    step: Duration,
    schedule: InternedScheduleLabel,
    _context: PhantomData<fn(C)>,
}

impl<C: AgentContext> NeuroTreePlugin<C> {
    /// A plugin whose tree files are built from the nodes `registry` knows, ticking in
    /// `Update` on Bevy's compute task pool (a frame under a budget, set through
    /// [`AgentCrowd::crowd_mut`], runs on rayon's global pool: `RAYON_NUM_THREADS`, or all
    /// cores), with a clock that moves 1/60 s per frame.
    pub fn new(registry: Registry<C>) -> Self {
        Self {
            registry: Arc::new(registry),
            pool: None,
            step: Duration::from_secs(1) / 60,
            schedule: Update.intern(),
            _context: PhantomData,
        }
    }

    /// Runs frames under a budget on a rayon pool of `threads` threads of its own (0:
    /// rayon's default); other frames run on Bevy's compute task pool, whose size
    /// `TaskPoolPlugin` sets.
    pub fn with_threads(mut self, threads: usize) -> Result<Self, ThreadPoolBuildError> {
        let pool = ThreadPoolBuilder::new().num_threads(threads).build()?;
        self.pool = Some(Arc::new(pool));
        Ok(self)
    }

    /// Moves the trees' clock by `step` after each frame.
    pub fn with_step(mut self, step: Duration) -> Self {
        self.step = step;
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
{
    fn build(&self, app: &mut App) {
        let clock = ManualClock::new();
        let mut crowd = Crowd::<C>::new(clock.clone());
        if let Some(pool) = &self.pool {
            crowd = crowd.with_pool(Arc::clone(pool));
        }
        app.insert_resource(AgentCrowd::new(crowd, clock, self.step))
            .add_message::<TreeFinished>()
            .add_message::<TreeReloaded>()
            .configure_sets(
                self.schedule,
                (TreeSystems::Join, TreeSystems::Tick).chain(),
            )
            .add_systems(
                self.schedule,
                (
                    systems::join::<C>.in_set(TreeSystems::Join),
                    systems::tick::<C>.in_set(TreeSystems::Tick),
                ),
            )
            .add_observer(systems::arrive::<C>)
            .add_observer(systems::leave::<C>);
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

//! A bench for the leaves' tests: one leaf (or a small tree) on a small world.

use neurotree_core::{Status, Tree};

use super::{register_nav2_leaves, Nav2Sim};
use crate::GridWorld;
use neurotree_nav2 as nav2;
use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::{Registry, XmlLoader};

/// A tree made of `xml` (the body of a `<BehaviorTree>`) on a world, ticked by hand.
pub(super) struct Bench {
    pub(super) sim: Nav2Sim,
    pub(super) tree: Tree<Nav2Sim>,
}

impl Bench {
    /// On the map `text` (1 m cells).
    pub(super) fn new(text: &str, xml: &str) -> Self {
        Self::with_world(GridWorld::parse(text, 1.0).unwrap(), xml)
    }

    pub(super) fn with_world(world: GridWorld, xml: &str) -> Self {
        let mut registry = Registry::<Nav2Sim>::new();
        nav2::register_controls(&mut registry).unwrap();
        register_nav2_leaves(&mut registry).unwrap();
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(
                &format!(
                    r#"<root BTCPP_format="4"><BehaviorTree ID="T">{xml}</BehaviorTree></root>"#
                ),
                "bench.xml",
            )
            .unwrap();
        let sim = Nav2Sim::new(world);
        let tree = Tree::with_clock(loader.build_main().unwrap().into(), sim.world.clock());
        Self { sim, tree }
    }

    pub(super) fn set_goal(&mut self, goal: Pose2D) {
        self.tree.blackboard_mut().set("goal", goal).unwrap();
    }

    pub(super) fn set<T: std::any::Any + Send + Sync>(&mut self, key: &str, value: T) {
        self.tree.blackboard_mut().set(key, value).unwrap();
    }

    pub(super) fn get<T: std::any::Any + Clone>(&self, key: &str) -> T {
        self.tree.blackboard().get(key).unwrap()
    }

    /// The reason the tree's last tick failed for, in words (`blocked (error 106)`).
    pub(super) fn reason(&self) -> Option<String> {
        let failure = self.tree.last_failure()?;
        failure.reason().map(ToString::to_string)
    }

    /// One tick.
    pub(super) fn tick(&mut self) -> Status {
        self.tree.tick_once(&mut self.sim).unwrap()
    }

    /// Ticks until the tree completes or `limit` ticks, stepping the world after each
    /// Running tick; the statuses.
    pub(super) fn run(&mut self, limit: usize) -> Vec<Status> {
        let mut seen = Vec::new();
        while seen.len() < limit {
            let status = self.tick();
            seen.push(status);
            if status != Status::Running {
                break;
            }
            self.sim.step();
        }
        seen
    }
}

/// `condition` as the condition of a WhileDoElse, which keeps its result while the else
/// branch runs: the condition is ticked from its last result rather than from Idle, the
/// tree succeeds when the condition does, and starts it afresh then.
pub(super) fn watched(condition: &str) -> String {
    format!(
        r#"<WhileDoElse>{condition}<AlwaysSuccess/>
             <KeepRunningUntilFailure><AlwaysSuccess/></KeepRunningUntilFailure>
           </WhileDoElse>"#
    )
}

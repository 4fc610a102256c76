//! One action server of the simulator: the goals it takes, the one-leaf tree each runs,
//! preemption by another motion, cancels.

use std::sync::Arc;
use std::time::Duration;

use neurotree_sim::nav2::{FailureNotes, Nav2Sim};
use neurotree_toolkit::{Blueprint, Registry, Status, Tree, XmlLoader};
use ros2_client::action::GoalStatusEnum;

use super::actions::SimAction;
use super::stats::SimStatsHandle;
use crate::nav2::goal_server::{GoalServer, Request};
use crate::nav2::NavigatorError;
use crate::{Ros2Error, RosNode};

/// One action server and the tree of its running goal.
pub(super) struct Served<A: SimAction>
where
    A::Result: Default,
{
    goals: GoalServer<A>,
    blueprint: Arc<Blueprint<Nav2Sim>>,
    running: Option<(Tree<Nav2Sim>, Duration)>,
}

impl<A: SimAction> Served<A>
where
    A::Result: Default,
{
    pub(super) fn new(
        ros: &RosNode,
        name: &str,
        registry: &Registry<Nav2Sim>,
    ) -> Result<Self, NavigatorError> {
        let mut loader = XmlLoader::new(registry);
        let xml = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Server">{}</BehaviorTree></root>"#,
            A::XML
        );
        loader.load_str(&xml, name)?;
        Ok(Self {
            goals: GoalServer::new(ros, name)?,
            blueprint: Arc::new(loader.build_main()?),
            running: None,
        })
    }

    /// Reads the requests; `true` if a new goal started.
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error> {
        let mut started = false;
        for request in self.goals.poll()? {
            match request {
                Request::Goal(goal) => {
                    if let Some((mut tree, _)) = self.running.take() {
                        // The server already ended the preempted goal.
                        tree.halt(sim);
                        A::counts(&mut stats.lock()).aborted += 1;
                    }
                    let mut tree = Tree::with_clock(Arc::clone(&self.blueprint), sim.world.clock());
                    if let Some(log) = sim.log() {
                        // The leaf's failures, with their reasons, in the sim's log.
                        tree.set_observer(FailureNotes::new(&self.blueprint, log.clone()));
                    }
                    A::put(&goal, tree.blackboard_mut());
                    self.running = Some((tree, sim.world.now()));
                    let mut stats = stats.lock();
                    A::counts(&mut stats).goals += 1;
                    A::record(&goal, &mut stats);
                    started = true;
                }
                Request::Cancel => {
                    // Counted before the answer goes out, which a client may act on at once.
                    A::counts(&mut stats.lock()).cancels += 1;
                    if let Some((mut tree, since)) = self.running.take() {
                        tree.halt(sim);
                        let elapsed = sim.world.now().saturating_sub(since);
                        let result = A::result(tree.blackboard(), 0, String::new(), elapsed);
                        self.goals.finish(GoalStatusEnum::Canceled, result);
                        started = false;
                    }
                }
            }
        }
        Ok(started)
    }

    /// Aborts the running goal: another server took the robot.
    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        if let Some((mut tree, since)) = self.running.take() {
            tree.halt(sim);
            let elapsed = sim.world.now().saturating_sub(since);
            let message = "preempted by another motion".to_owned();
            let result = A::result(tree.blackboard(), 0, message, elapsed);
            A::counts(&mut stats.lock()).aborted += 1;
            self.goals.finish(GoalStatusEnum::Aborted, result);
        }
    }

    fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// Ticks the running goal's tree; sends feedback or ends the goal.
    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        let Some((tree, since)) = &mut self.running else {
            return;
        };
        let status = tree.tick_once(sim);
        if status == Ok(Status::Running) {
            if let Some(feedback) = A::feedback(tree.blackboard(), sim) {
                self.goals.feedback(feedback);
            }
            return;
        }
        let bb = tree.blackboard();
        let elapsed = sim.world.now().saturating_sub(*since);
        let code = bb.get::<u16>("error_code").unwrap_or(0);
        let message = bb.get::<String>("error_msg").unwrap_or_default();
        let (status, result) = match status {
            Ok(Status::Success) => (
                GoalStatusEnum::Succeeded,
                A::result(bb, 0, String::new(), elapsed),
            ),
            Ok(_) => (
                GoalStatusEnum::Aborted,
                A::result(bb, code, message, elapsed),
            ),
            Err(e) => (
                GoalStatusEnum::Aborted,
                A::result(bb, code, e.to_string(), elapsed),
            ),
        };
        {
            let mut stats = stats.lock();
            let counts = A::counts(&mut stats);
            if status == GoalStatusEnum::Succeeded {
                counts.succeeded += 1;
            } else {
                counts.aborted += 1;
            }
        }
        self.running = None;
        self.goals.finish(status, result);
    }
}

/// An action server whose goals the sim runs.
pub(super) trait Serving {
    /// Reads the requests; `true` if a new goal started.
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error>;
    /// Aborts the running goal: another server took the robot.
    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle);
    /// A goal runs.
    fn is_running(&self) -> bool;
    /// Works on the running goal for one step.
    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle);
}

impl<A: SimAction> Serving for Served<A>
where
    A::Result: Default,
{
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error> {
        Served::poll(self, sim, stats)
    }
    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        Served::preempt(self, sim, stats);
    }
    fn is_running(&self) -> bool {
        Served::is_running(self)
    }
    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        Served::tick(self, sim, stats);
    }
}

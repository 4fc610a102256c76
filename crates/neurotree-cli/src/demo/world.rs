//! What a watcher of the demo keeps and draws beside the tree: the simulated warehouse and
//! the run's counters, saved after each tick so that the studio can go back to a tick (the
//! robot goes back with it), and the warehouse as a scene.

use neurotree::robotics::{Path, Pose2D};
use neurotree::scene::Scene;
use neurotree::sim::nav2::{Nav2Sim, Nav2SimState, RecoveryCounter, TrackingFeedback};
use neurotree::sim::GridWorld;
use neurotree::state::StateCodecs;
use neurotree::{Status, Tree};

use super::scenario::Scenario;

/// The demo's run around its tree, borrowed from a [`DemoRun`](super::DemoRun)
/// ([`watched`](super::DemoRun::watched)).
pub struct DemoWorld<'a> {
    pub(super) sim: &'a mut Nav2Sim,
    pub(super) ticks: &'a mut u32,
    pub(super) status: &'a mut Status,
    pub(super) error: &'a mut Option<String>,
    pub(super) notes: &'a mut Vec<String>,
    pub(super) plans_in_tick: &'a mut u32,
    pub(super) recoveries: &'a RecoveryCounter,
    pub(super) scenario: &'a Scenario,
}

/// The demo's world as of one tick ([`DemoWorld::save`]).
#[derive(Clone, Debug)]
pub struct DemoSaved {
    sim: Nav2SimState,
    ticks: u32,
    status: Status,
    error: Option<String>,
    notes: Vec<String>,
    plans_in_tick: u32,
    recoveries: Vec<(String, u32)>,
}

impl DemoWorld<'_> {
    /// The world and the counters now.
    pub fn save(&self) -> DemoSaved {
        DemoSaved {
            sim: self.sim.snapshot(),
            ticks: *self.ticks,
            status: *self.status,
            error: self.error.clone(),
            notes: self.notes.clone(),
            plans_in_tick: *self.plans_in_tick,
            recoveries: self.recoveries.branches(),
        }
    }

    /// Puts the world and the counters back as `saved` has them (the clock too).
    pub fn restore(&mut self, saved: &DemoSaved) {
        self.sim.restore(&saved.sim);
        *self.ticks = saved.ticks;
        *self.status = saved.status;
        self.error.clone_from(&saved.error);
        self.notes.clone_from(&saved.notes);
        *self.plans_in_tick = saved.plans_in_tick;
        self.recoveries.set_branches(&saved.recoveries);
    }

    /// The codecs of the values Nav2's navigators keep on their blackboards: poses, goal
    /// lists, paths, tracking feedback.
    pub fn codecs() -> StateCodecs {
        StateCodecs::new()
            .with::<Pose2D>()
            .with::<Vec<Pose2D>>()
            .with::<Path>()
            .with::<TrackingFeedback>()
    }

    /// The warehouse, the costmap's marks, the obstacle, the plan ahead of the robot, the
    /// goal and the robot.
    pub fn scene(&self, tree: &Tree<Nav2Sim>) -> Scene {
        let world = &self.sim.world;
        world.scene_with(&plan_ahead(tree, world), Some(self.scenario.goal))
    }

    /// Writes `line` where the demo's notes are read.
    pub fn note(&self, line: String) {
        if let Some(log) = self.sim.log() {
            log.push(line);
        }
    }
}

/// The latest plan from the pose nearest the robot on: the root's `path` entry, or the
/// path the robot follows when the tree keeps no such entry.
pub(super) fn plan_ahead(tree: &Tree<Nav2Sim>, world: &GridWorld) -> Vec<Pose2D> {
    match tree.blackboard().get_ref::<Path>("path") {
        Ok(path) => {
            let from = path.closest_index(&world.robot()).unwrap_or(0);
            path.poses[from..].to_vec()
        }
        Err(_) => world.path_ahead().to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo::{DemoConfig, DemoRun};

    #[test]
    fn a_demo_taken_back_to_a_tick_runs_on_to_the_same_end() {
        let straight = DemoRun::new(&DemoConfig::default()).unwrap().run_to_end();
        let mut run = DemoRun::new(&DemoConfig::default()).unwrap();
        let codecs = DemoWorld::codecs();
        let mut kept = None;
        // Tick 240 is in the spin that the obstacle of seed 0 causes; 300 is past it.
        while run.ticks() < 300 {
            run.tick();
            if run.ticks() == 240 {
                let (tree, world) = run.watched();
                kept = Some((tree.save_state_with(&codecs).unwrap(), world.save()));
            }
        }
        let (state, saved) = kept.unwrap();
        let (tree, mut world) = run.watched();
        world.restore(&saved);
        tree.restore_state_with(&state, &codecs).unwrap();
        assert_eq!(run.ticks(), 240);
        assert_eq!(run.run_to_end(), straight);
        assert_eq!((straight.replans, straight.recoveries), (38, 4));
    }
}

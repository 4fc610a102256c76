//! What a watcher of the demo keeps and draws beside the tree: the simulated warehouse and
//! the run's counters, saved after each tick so that the studio can go back to a tick (the
//! robot goes back with it), and the warehouse as a scene.

use neurotree::robotics::{Path, Pose2D};
use neurotree::scene::Scene;
use neurotree::sim::nav2::{Nav2Sim, Nav2SimState, RecoveryCounter};
use neurotree::sim::GridWorld;
use neurotree::state::StateCodecs;
use neurotree::{Registry, Status, Tree};

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

    /// The codecs of the values Nav2's nodes keep on their blackboards: poses, goal lists,
    /// paths, routes, tracking feedback and the rest that
    /// [`nav2::register_values`](neurotree::nav2::register_values) registers, as the demo's
    /// tree is loaded with them.
    pub fn codecs() -> StateCodecs {
        let mut registry = Registry::<Nav2Sim>::new();
        neurotree::nav2::register_values(&mut registry);
        StateCodecs::clone(registry.value_codecs())
    }

    /// The warehouse, the costmap's inflated and marked cells, the obstacle, the plan ahead
    /// of the robot, the goal and the robot.
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
    use std::f64::consts::{FRAC_PI_2, PI};
    use std::time::Duration;

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

    #[test]
    fn the_warehouse_scene_shows_the_inflated_cells_within_a_pages_bounds() {
        let mut run = DemoRun::new(&DemoConfig::default()).unwrap();
        // Tick 240: the obstacle seen and marked, the robot spinning in front of it.
        while run.ticks() < 240 {
            run.tick();
        }
        let (tree, world) = run.watched();
        let scene = world.scene(tree);
        assert_eq!(scene.check(), Ok(()));
        let count = |id: &str| scene.items().iter().filter(|i| i.id == id).count();
        assert!(count("costmap") >= 1);
        // The cells beside the walls and the shelves, in rectangles (some forty), not a
        // square a cell.
        let inflation = count("inflation");
        assert!((20..80).contains(&inflation), "{inflation}");
        assert!(scene.items().len() < 120, "{}", scene.items().len());
    }

    /// Each of Nav2's trees in the corpus, with what it needs to run to its end as
    /// `neurotree demo` runs it (`tests/demo.rs` runs them all the same way).
    fn nav2_trees() -> Vec<(String, DemoConfig)> {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus/nav2");
        let mut trees: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "xml"))
            .filter(|p| !p.ends_with("nav2_tree_nodes.xml"))
            .collect();
        trees.sort();
        trees
            .into_iter()
            .map(|path| {
                let name = path.file_name().unwrap().to_string_lossy().into_owned();
                let mut config = DemoConfig {
                    tree: Some(path),
                    ..DemoConfig::default()
                };
                match name.as_str() {
                    // It never ends by itself.
                    "follow_point.xml" => config.duration = Some(Duration::from_secs(60)),
                    // Its square turns left: from the corner the robot starts in, facing south.
                    "odometry_calibration.xml" => config.start_heading = -FRAC_PI_2,
                    // On its dock, charging, facing the way it docks: it undocks first.
                    "opennav_docking_bt__application_example.xml" => {
                        config.battery = 90.0;
                        config.start_heading = PI;
                    }
                    _ => {}
                }
                (name, config)
            })
            .collect()
    }

    /// What a tick of the demo shows: its status, where the robot is, the replans so far.
    fn shown(run: &DemoRun, status: Status) -> (Status, Pose2D, u32) {
        (status, run.sim().world.robot(), run.sim().replans())
    }

    #[test]
    fn every_tick_of_each_nav2_tree_the_demo_runs_is_kept_and_the_run_goes_on_from_it_the_same() {
        let codecs = DemoWorld::codecs();
        let trees = nav2_trees();
        assert_eq!(trees.len(), 16);
        for (name, config) in trees {
            let straight = DemoRun::new(&config).unwrap().run_to_end();
            let mut run = DemoRun::new(&config).unwrap();
            let mut kept = Vec::new();
            let mut ticks = Vec::new();
            while !run.is_over() {
                let status = run.tick();
                ticks.push(shown(&run, status));
                let tick = run.ticks();
                let (tree, world) = run.watched();
                // The simulated leaves are all synchronous or stateful: no tick is refused
                // for an asynchronous action under way, nor for a leaf that cannot save.
                let state = tree
                    .save_state_with(&codecs)
                    .unwrap_or_else(|e| panic!("{name}: tick {tick} cannot be kept: {e}"));
                kept.push((state, world.save()));
            }
            assert_eq!(kept.len(), straight.ticks as usize, "{name}");
            let back_to = |run: &mut DemoRun, at: usize| {
                let (state, saved) = &kept[at];
                let (tree, mut world) = run.watched();
                world.restore(saved);
                tree.restore_state_with(state, &codecs).unwrap();
                assert_eq!(run.ticks() as usize, at + 1, "{name}");
                // The robot goes back with the tree.
                assert_eq!(run.sim().world.robot(), ticks[at].1, "{name}");
            };
            // Back to every tenth tick: the ten ticks after it show what they showed.
            for at in (0..kept.len()).step_by(10) {
                back_to(&mut run, at);
                let mut again = Vec::new();
                while again.len() < 10 && !run.is_over() {
                    let status = run.tick();
                    again.push(shown(&run, status));
                }
                let end = (at + 11).min(ticks.len());
                assert_eq!(again, ticks[at + 1..end], "{name}, back to tick {}", at + 1);
            }
            // Back to a tick a quarter, half and three quarters in: the same end each time.
            for at in [1, 2, 3].map(|q| q * kept.len() / 4) {
                back_to(&mut run, at);
                assert_eq!(
                    run.run_to_end(),
                    straight,
                    "{name}, back to tick {}",
                    at + 1
                );
            }
        }
    }
}

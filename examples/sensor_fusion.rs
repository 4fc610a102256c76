//! Sensor fusion while navigating: lidar and camera fused beside a navigation action, on the
//! simulated grid world.
//!
//! ```text
//! Parallel main_loop (success 1, failure 1)
//! ├── KeepRunningUntilFailure keep_sensing
//! │   └── Sequence sensor_fusion
//! │       ├── Sensor lidar → {lidar_data}
//! │       ├── ForceSuccess camera_optional
//! │       │   └── Sensor camera (min_quality 0.7) → {camera_data}
//! │       └── Action fuse → {obstacles}
//! └── Fallback navigation
//!     ├── Navigate navigate (goal {goal}, obstacles {obstacles})
//!     └── Action emergency_stop
//! ```
//!
//! Every tick the lidar and the camera are read and fused into a list of obstacles (the
//! lidar's returns off the known walls, and the camera's detections when its frame was good
//! enough); a blurred camera frame is skipped rather than stopping the robot. Alongside,
//! the navigation node drives to the goal, planning around the fused obstacles. A pallet is
//! dropped in the doorway the robot is heading for; the robot senses it and replans through
//! the other door. If both doors are blocked there is no path: navigation fails and the
//! emergency stop runs, failing the mission with the robot standing still.
//!
//! Run it with `cargo run -p neurotree --example sensor_fusion`.

use std::io::Write;
use std::time::Duration;

use neurotree::render::LastTickStatuses;
use neurotree::robotics::{Obstacle, Pose2D, RoboticsBuilder, SensorData};
use neurotree::sim::{Cell, GridWorld, TimedObstacle, LEGEND};
use neurotree::{Action, Blueprint, Handle, Port, Status, Tree};

/// The warehouse: two rooms joined by two doors in the wall at x = 7.
const MAP: &str = "
    ################
    #R.....#......C#
    #......#..###..#
    #..##......##..#
    #..##..#.......#
    #..............#
    ################";

/// Where the robot is sent.
const GOAL: Pose2D = Pose2D::new(13.5, 1.5, 0.0);

/// The upper door, which the first plan goes through; the lower one is the detour.
const UPPER_DOOR: Cell = Cell::new(7, 3);
const LOWER_DOOR: Cell = Cell::new(7, 1);

/// World time per tick.
const STEP: Duration = Duration::from_millis(250);

/// Ticks after which the run is abandoned.
const MAX_TICKS: u32 = 1_000;

/// What to simulate.
#[derive(Clone, Copy, Debug)]
pub struct Scenario {
    /// Seed of the sensors' noise.
    pub seed: u64,
    /// Also block the lower door, so that no route is left.
    pub block_both_doors: bool,
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The tree's final status (Running if it was abandoned).
    pub status: Status,
    /// Ticks until it completed.
    pub ticks: u32,
    /// Where the robot ended.
    pub pose: Pose2D,
    /// World time at the end.
    pub time: Duration,
    /// Paths planned (the first plan and every replan).
    pub plans: u32,
    /// Fusions done; `with_camera` of them had a good camera frame.
    pub fusions: u32,
    /// Fusions that had a good camera frame.
    pub with_camera: u32,
    /// Metres driven.
    pub distance: f64,
    /// Battery left, in percent.
    pub battery: f64,
    /// Times the emergency stop ran.
    pub emergency_stops: u32,
}

/// The robot: the simulated world and what the tree's own actions count.
pub struct Robot {
    /// The world the robot lives in.
    pub world: GridWorld,
    fusions: u32,
    with_camera: u32,
    emergency_stops: u32,
}

/// Merges the latest lidar scan and camera frame into obstacles to plan around.
struct Fuse;

impl Action<Robot> for Fuse {
    fn tick(&self, h: &mut Handle<'_, Robot>) -> Status {
        let Ok(lidar) = h.get::<SensorData>("lidar_data") else {
            return Status::Failure;
        };
        // The camera's node may have rejected this tick's frame; an older one is stale.
        let camera = h
            .get::<SensorData>("camera_data")
            .ok()
            .filter(|frame| frame.timestamp == lidar.timestamp);
        let map = h.ctx().world.map();
        let resolution = map.resolution();
        let mut cells: Vec<Cell> = Vec::new();
        let lidar_hits = lidar.poses("hits").unwrap_or_default();
        let camera_objects = camera
            .as_ref()
            .and_then(|c| c.poses("objects"))
            .unwrap_or_default();
        for pose in lidar_hits.iter().chain(camera_objects) {
            // Returns from the known walls are not news.
            if let Some(cell) = map.cell_at(pose).filter(|c| !map.is_wall(*c))
                && !cells.contains(&cell)
            {
                cells.push(cell);
            }
        }
        let obstacles: Vec<Obstacle> = cells
            .iter()
            .map(|c| {
                let centre = map.centre(*c);
                Obstacle::new(centre.x, centre.y, resolution / 2.0)
            })
            .collect();
        let robot = h.ctx_mut();
        robot.fusions += 1;
        robot.with_camera += u32::from(camera.is_some());
        match h.set("obstacles", obstacles) {
            Ok(()) => Status::Success,
            Err(_) => Status::Failure,
        }
    }
}

/// The tree drawn at the top of this file, with the grid world's sensors and planner.
fn blueprint() -> std::sync::Arc<Blueprint<Robot>> {
    Blueprint::<Robot>::builder()
        .parallel("main_loop", 1, 1, |p| {
            p.keep_running_until_failure("keep_sensing", |k| {
                k.sequence("sensor_fusion", |s| {
                    s.sensor("lidar", "lidar_data", 0.9, |r: &mut Robot| r.world.lidar())
                        .force_success("camera_optional", |f| {
                            f.sensor("camera", "camera_data", 0.7, |r: &mut Robot| {
                                r.world.camera()
                            })
                        })
                        .action_node("fuse", Fuse)
                })
            })
            .fallback("navigation", |f| {
                f.navigate("navigate", "goal", 0.1, |r: &mut Robot| &mut r.world)
                    .ports([Port::entry("obstacles", "obstacles")])
                    .action("emergency_stop", |r: &mut Robot| {
                        r.world.stop();
                        r.emergency_stops += 1;
                        Status::Failure
                    })
            })
        })
        .build_shared()
        // The tree above is fixed and valid; a failure here is a bug in this example.
        .expect("the example's tree is valid")
}

/// The warehouse, with the pallet (or pallets) that will be dropped in the doors.
fn world(scenario: Scenario) -> GridWorld {
    let pallet = |cell| TimedObstacle::new(cell, Duration::from_secs(3));
    let mut world = GridWorld::parse(MAP, 1.0)
        .expect("the example's map is valid")
        .with_seed(scenario.seed)
        .with_timed_obstacle(pallet(UPPER_DOOR));
    if scenario.block_both_doors {
        world = world.with_timed_obstacle(pallet(LOWER_DOOR));
    }
    world.camera().set_quality(0.9, 0.4);
    world
}

/// Runs the scenario, writing what happens to `out`, and says how it ended.
pub fn run(scenario: Scenario, out: &mut dyn Write) -> Outcome {
    let bp = blueprint();
    let mut robot = Robot {
        world: world(scenario),
        fusions: 0,
        with_camera: 0,
        emergency_stops: 0,
    };
    let mut tree = Tree::with_clock(bp, robot.world.clock());
    let seen = LastTickStatuses::for_tree(&tree);
    tree.set_observer(seen.clone());
    // The tree is fresh, so `goal` is free to take a pose.
    let _ = tree.blackboard_mut().set("goal", GOAL);

    let _ = writeln!(out, "{LEGEND}\n\n{}", robot.world.render());
    let mut status = Status::Running;
    let mut ticks = 0;
    let mut plans = 0;
    while status == Status::Running && ticks < MAX_TICKS {
        ticks += 1;
        status = match tree.tick_once(&mut robot) {
            Ok(status) => status,
            Err(error) => {
                let _ = writeln!(out, "tick {ticks}: {error}");
                Status::Failure
            }
        };
        if robot.world.plan_count() != plans {
            plans = robot.world.plan_count();
            let _ = writeln!(out, "tick {ticks}: plan {plans}\n{}", robot.world.render());
        }
        if status == Status::Running {
            robot.world.step(STEP);
        }
    }
    let _ = writeln!(
        out,
        "tick {ticks}: {status}\n{}\n{}",
        robot.world.render(),
        seen.render(tree.blueprint(), false)
    );
    Outcome {
        status,
        ticks,
        pose: robot.world.robot(),
        time: robot.world.now(),
        plans: robot.world.plan_count(),
        fusions: robot.fusions,
        with_camera: robot.with_camera,
        distance: robot.world.distance_travelled(),
        battery: robot.world.battery().level(),
        emergency_stops: robot.emergency_stops,
    }
}

fn main() {
    let outcome = run(
        Scenario {
            seed: 7,
            block_both_doors: false,
        },
        &mut std::io::stdout(),
    );
    println!("{outcome:#?}");
}

//! The sensor-fusion example, run to the end in both of its scenarios.

#[path = "../../../examples/sensor_fusion.rs"]
#[allow(dead_code)] // `main` is for `cargo run --example`.
mod sensor_fusion;

use std::time::Duration;

use neurotree::robotics::Pose2D;
use neurotree::Status;
use sensor_fusion::{run, Outcome, Scenario};

const GOAL: Pose2D = Pose2D::new(13.5, 1.5, 0.0);

fn outcome(seed: u64, block_both_doors: bool) -> (Outcome, String) {
    let mut out = Vec::new();
    let outcome = run(
        Scenario {
            seed,
            block_both_doors,
        },
        &mut out,
    );
    (outcome, String::from_utf8(out).unwrap())
}

#[test]
fn the_robot_senses_the_pallet_replans_through_the_other_door_and_arrives() {
    let (o, text) = outcome(7, false);
    assert_eq!(o.status, Status::Success);
    assert_eq!(o.ticks, 60);
    assert_eq!(o.time, Duration::from_millis(14_750));
    // The first plan, and the replan when the pallet in the upper door was sensed.
    assert_eq!(o.plans, 2);
    assert!(text.contains("tick 20: plan 2"), "{text}");
    // Stopped within the 0.1 m tolerance, on the last straight.
    assert_eq!(o.pose, Pose2D::new(13.421572875253808, 1.5, 0.0));
    assert!(o.pose.distance(&GOAL) <= 0.1);
    assert_eq!(o.distance, 14.75);
    assert_eq!(o.battery, 85.25);
    // Sensing ran on every tick; the camera's blurred frames were skipped.
    assert_eq!((o.fusions, o.with_camera), (60, 36));
    assert_eq!(o.emergency_stops, 0);
    assert!(text.contains("#............R.#\n"), "{text}");
    assert!(text.contains("[S] navigate (StatefulAction)"), "{text}");
    assert!(text.is_ascii());
}

#[test]
fn the_seed_changes_the_camera_frames_not_the_route() {
    let (a, _) = outcome(7, false);
    let (b, _) = outcome(8, false);
    assert_eq!(b.with_camera, 34);
    assert_eq!(
        Outcome {
            with_camera: a.with_camera,
            ..b
        },
        a
    );
    // And the same seed, the same run.
    assert_eq!(outcome(7, false), outcome(7, false));
}

#[test]
fn with_both_doors_blocked_navigation_fails_and_the_emergency_stop_runs() {
    let (o, text) = outcome(7, true);
    assert_eq!(o.status, Status::Failure);
    // The replan, once the lidar saw both pallets, found no route.
    assert_eq!((o.ticks, o.plans), (20, 2));
    assert_eq!(o.emergency_stops, 1);
    assert_eq!(o.distance, 4.75);
    assert_eq!(o.fusions, 20);
    assert!(text.contains("[F] emergency_stop (Action)"), "{text}");
    // Stopped where the failed replan found it, motion idle.
    assert!(
        text.contains(
            "tick 20: FAILURE\n\
             t=4.75s pose=(5.74, 4.26, -0.79) battery=95.2% travelled=4.75m motion=idle\n"
        ),
        "{text}"
    );
}

//! The pick-and-place example's scenarios, tick for tick.

#[path = "../../../examples/pick_and_place.rs"]
#[allow(dead_code)]
mod pick_and_place;

use neurotree::Status;
use pick_and_place::{pick_and_place_tree, run, scenarios, Outcome, PLACE_SPOT};

fn run_logged(name: &str) -> (Outcome, Vec<String>) {
    let (_, scenario) = scenarios().into_iter().find(|(n, _)| *n == name).unwrap();
    let mut log = Vec::new();
    let outcome = run(&scenario, |line| log.push(line.to_string())).unwrap();
    (outcome, log)
}

/// A successful outcome, to be adjusted per scenario.
fn placed_in(ticks: u32) -> Outcome {
    Outcome {
        status: Status::Success,
        ticks,
        grasp_attempts: 1,
        halted: vec![],
        robot_at: PLACE_SPOT,
        object_at: PLACE_SPOT,
        placed: true,
    }
}

/// The log's events (indented lines), in order.
fn events(log: &[String]) -> Vec<&str> {
    log.iter()
        .filter_map(|l| l.strip_prefix("          "))
        .collect()
}

#[test]
fn first_try_picks_and_places_in_nine_ticks() {
    let (outcome, log) = run_logged("first-try");
    // Scan 2 ticks (the approach starts on the second), approach to cell 3 by tick 4,
    // grasp on ticks 4-5, carry to cell 7 by tick 8, place on ticks 8-9.
    assert_eq!(outcome, placed_in(9));
    assert_eq!(
        events(&log),
        [
            "scanning the work area",
            "object seen at cell 3",
            "moving to cell 3",
            "grasp 1: closing the gripper",
            "object grasped",
            "moving to cell 7",
            "lowering the object",
            "object released at cell 7",
        ]
    );
}

#[test]
fn grasp_retries_then_succeeds() {
    let (outcome, log) = run_logged("grasp-retries");
    // Each failed grasp is followed, in the same tick, by the next attempt.
    assert_eq!(
        outcome,
        Outcome {
            grasp_attempts: 3,
            ..placed_in(11)
        }
    );
    let failures = events(&log)
        .iter()
        .filter(|e| **e == "the gripper closed on nothing")
        .count();
    assert_eq!(failures, 2);
}

#[test]
fn grasp_gives_up_after_three_attempts() {
    let (outcome, _) = run_logged("grasp-gives-up");
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Failure,
            ticks: 7,
            grasp_attempts: 3,
            halted: vec![],
            robot_at: 3,
            object_at: 3,
            placed: false,
        }
    );
}

#[test]
fn a_slipped_object_halts_the_move_once_and_is_grasped_again() {
    let (outcome, log) = run_logged("object-slips");
    // The object slips before tick 7 at cell 5: the reactive sequence finds it no longer
    // grasped, halts move_to_place, grasps again (ticks 7-8) and carries on.
    assert_eq!(
        outcome,
        Outcome {
            grasp_attempts: 2,
            halted: vec!["move_to_place".to_string()],
            ..placed_in(10)
        }
    );
    let tick_7 = log.iter().position(|l| l.starts_with("tick   7")).unwrap();
    assert_eq!(
        &log[tick_7 + 1..tick_7 + 4],
        [
            "          the object slips out of the gripper at cell 5",
            "          grasp 2: closing the gripper",
            "          move_to_place halted",
        ]
    );
}

#[test]
fn every_run_is_the_same() {
    for (name, _) in scenarios() {
        assert_eq!(run_logged(name), run_logged(name));
    }
}

#[test]
fn the_tree_is_a_goal_check_over_a_reactive_sequence_of_steps() {
    let bp = pick_and_place_tree();
    assert_eq!(bp.len(), 17);
    let kind = |path: &str| bp.kind(bp.find(path).unwrap()).type_name().to_string();
    assert_eq!(kind("pick_and_place"), "Fallback");
    assert_eq!(kind("pick_and_place/object_placed"), "Condition");
    assert_eq!(kind("pick_and_place/place_the_object"), "ReactiveSequence");
    assert_eq!(
        kind("pick_and_place/place_the_object/grasp/grasp_retry"),
        "RetryUntilSuccessful"
    );
    assert_eq!(
        kind("pick_and_place/place_the_object/grasp/grasp_retry/grasp_object"),
        "StatefulAction"
    );
}

//! The patrol example's scenarios, tick for tick.

#[path = "../../../examples/patrol.rs"]
#[allow(dead_code)]
mod patrol;

use std::time::Duration;

use neurotree::Status;
use patrol::{patrol_tree, patrol_tree_from_macro, run, scenarios, Outcome, Scenario};

fn scenario(name: &str) -> Scenario {
    scenarios()
        .into_iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| s)
        .unwrap()
}

/// Runs `s`, returning the outcome and the log.
fn run_logged(s: &Scenario) -> (Outcome, Vec<String>) {
    let mut log = Vec::new();
    let outcome = run(s, |line| log.push(line.to_string())).unwrap();
    (outcome, log)
}

const ALL_CORNERS: [(i32, i32); 4] = [(4, 0), (4, 4), (0, 4), (0, 0)];

#[test]
fn normal_patrol_visits_every_corner_without_charging() {
    let (outcome, _) = run_logged(&scenario("normal"));
    // Four legs of four cells, one cell per tick, 1% per cell; a scan before each leg.
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 16,
            visited: ALL_CORNERS.to_vec(),
            scans: 4,
            charges: 0,
            halted: vec![],
            emergency_stopped: false,
            position: (0, 0),
            battery: 84,
        }
    );
}

#[test]
fn low_battery_returns_to_charge_then_resumes_the_patrol() {
    let (outcome, log) = run_logged(&scenario("low-battery"));
    // 28% -> two legs (ticks 1-8) leave 20%, not above the threshold; 8 cells home (ticks
    // 9-16) leave 12%; charging 20% per tick fills up on tick 20; two more legs (21-28).
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 28,
            visited: ALL_CORNERS.to_vec(),
            scans: 4,
            charges: 1,
            halted: vec![],
            emergency_stopped: false,
            position: (0, 0),
            battery: 92,
        }
    );
    let charging_starts: Vec<&String> = log.iter().filter(|l| l.contains("docked")).collect();
    assert_eq!(charging_starts.len(), 1);
    let home = log.iter().position(|l| l.starts_with("tick  16")).unwrap();
    assert!(log[home..].iter().take(4).any(|l| l.contains("docked")));
}

#[test]
fn emergency_stop_halts_the_running_move_exactly_once() {
    let (outcome, log) = run_logged(&scenario("emergency-stop"));
    // Pressed at 0.6 s, before tick 7, while move_patrol runs its second leg.
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 7,
            visited: vec![(4, 0)],
            scans: 2,
            charges: 0,
            halted: vec!["move_patrol".to_string()],
            emergency_stopped: true,
            position: (4, 2),
            battery: 94,
        }
    );
    let halts: Vec<&String> = log.iter().filter(|l| l.contains("halted")).collect();
    assert_eq!(halts, ["          move_patrol halted at (4, 2)"]);
}

#[test]
fn emergency_stop_while_charging_halts_the_charge() {
    let s = Scenario {
        estop_at: Some(Duration::from_millis(1750)),
        ..scenario("low-battery")
    };
    let (outcome, _) = run_logged(&s);
    // Charging began on tick 16 (32%, 52%, 72%); the stop comes before tick 19.
    assert_eq!(
        outcome,
        Outcome {
            status: Status::Success,
            ticks: 19,
            visited: vec![(4, 0), (4, 4)],
            scans: 2,
            charges: 0,
            halted: vec!["charge_battery".to_string()],
            emergency_stopped: true,
            position: (0, 0),
            battery: 72,
        }
    );
}

#[test]
fn from_any_battery_level_the_robot_gets_home_and_patrols() {
    for battery in 0..=100 {
        let s = Scenario {
            battery,
            legs: 8,
            estop_at: None,
        };
        let (outcome, _) = run_logged(&s);
        assert_eq!(outcome.status, Status::Success, "battery {battery}");
        assert_eq!(outcome.visited.len(), 8, "battery {battery}");
        assert!(outcome.halted.is_empty(), "battery {battery}");
    }
}

#[test]
fn every_run_is_the_same() {
    for (_, s) in scenarios() {
        assert_eq!(run_logged(&s), run_logged(&s));
    }
}

#[test]
fn builder_and_macro_make_the_same_tree() {
    let built = patrol_tree();
    let from_macro = patrol_tree_from_macro();
    assert_eq!(built.len(), 12);
    assert_eq!(format!("{built:?}"), format!("{from_macro:?}"));
}

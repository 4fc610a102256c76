//! The navigation-recovery example: each scenario reaches its own level of the escalation.

#[path = "../../../examples/navigation_recovery.rs"]
#[allow(dead_code)]
mod navigation_recovery;

use std::time::Duration;

use navigation_recovery::{
    registry, run, scenarios, Outcome, Recovery, Scenario, GOAL, NAVIGATION_XML,
};
use neurotree::robotics::Pose2D;
use neurotree::{Status, XmlLoader};

fn outcome_of(name: &str) -> Outcome {
    let (_, scenario) = scenarios().into_iter().find(|(n, _)| *n == name).unwrap();
    run(&scenario, |_| {}).unwrap()
}

/// An outcome with no recovery, to be adjusted per scenario.
fn reached_in(ticks: u32) -> Outcome {
    Outcome {
        status: Status::Success,
        ticks,
        level: Recovery::Normal,
        attempts: 1,
        costmap_clears: 0,
        backups: 0,
        help_calls: 0,
        halted: vec![],
        pose: GOAL,
        elapsed: Duration::from_millis(250) * (ticks - 1),
    }
}

#[test]
fn a_clear_path_needs_no_recovery() {
    // 4 m at 0.5 m per tick.
    assert_eq!(outcome_of("normal"), reached_in(8));
}

#[test]
fn one_blocked_drive_clears_the_costmap_and_retries() {
    // Stuck on tick 3 at 1 m; the costmap is cleared and the Sleep of 1 s runs from 0.5 s
    // to 1.5 s (tick 7), when the second drive starts and covers the last 3 m by tick 12.
    assert_eq!(
        outcome_of("clear-costmap"),
        Outcome {
            level: Recovery::ClearCostmap,
            attempts: 2,
            costmap_clears: 1,
            ..reached_in(12)
        }
    );
}

#[test]
fn two_blocked_drives_back_up_and_retry() {
    // The second drive is stuck on tick 9 at 2 m; backing up 0.5 m takes ticks 9 and 10,
    // and the third drive covers 2.5 m from tick 10 to tick 14.
    assert_eq!(
        outcome_of("back-up"),
        Outcome {
            level: Recovery::BackUp,
            attempts: 3,
            costmap_clears: 1,
            backups: 1,
            ..reached_in(14)
        }
    );
}

#[test]
fn three_blocked_drives_ask_for_help() {
    // The third drive is stuck on tick 12 (2.75 s); help arrives 2 s later, at tick 20,
    // clears the way, and the fourth drive covers the last 1.5 m by tick 22.
    assert_eq!(
        outcome_of("ask-for-help"),
        Outcome {
            level: Recovery::AskForHelp,
            attempts: 4,
            costmap_clears: 1,
            backups: 1,
            help_calls: 1,
            ..reached_in(22)
        }
    );
}

#[test]
fn help_that_never_comes_times_out_and_halts_the_wait_once() {
    // The 5 s deadline runs from 2.75 s; at 7.75 s (tick 32) the Timeout halts WaitForHelp.
    assert_eq!(
        outcome_of("no-help"),
        Outcome {
            status: Status::Failure,
            level: Recovery::AskForHelp,
            attempts: 3,
            costmap_clears: 1,
            backups: 1,
            help_calls: 1,
            halted: vec!["WaitForHelp".to_string()],
            pose: Pose2D::new(2.5, 0.0, 0.0),
            ..reached_in(32)
        }
    );
}

#[test]
fn more_blocked_drives_than_levels_still_end_with_help() {
    // The human clears every remaining blockage, so the fourth drive goes through.
    let many = Scenario {
        blocked_attempts: 10,
        help_after: Some(Duration::from_secs(2)),
    };
    assert_eq!(run(&many, |_| {}).unwrap(), outcome_of("ask-for-help"));
}

#[test]
fn every_run_is_the_same() {
    for (_, s) in scenarios() {
        let mut first = Vec::new();
        let mut second = Vec::new();
        let a = run(&s, |l| first.push(l.to_string())).unwrap();
        let b = run(&s, |l| second.push(l.to_string())).unwrap();
        assert_eq!(a, b);
        assert_eq!(first, second);
    }
}

#[test]
fn the_xml_is_checked_against_the_registered_ports() {
    let registry = registry().unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(NAVIGATION_XML, "nav.xml").unwrap();
    let bp = loader.build_main().unwrap();
    assert_eq!(bp.len(), 14);
    assert!(bp
        .find("navigate_with_recovery/ask_for_help/help_deadline/WaitForHelp")
        .is_some());
    // A misspelt port is refused before anything runs.
    let bad = NAVIGATION_XML.replace("distance=\"0.5\"", "distanse=\"0.5\"");
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(&bad, "nav.xml").unwrap();
    let err = loader.build_main().unwrap_err();
    assert!(err.message.contains("distanse"), "{err}");
}

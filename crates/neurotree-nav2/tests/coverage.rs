//! Coverage reads the outcomes of Nav2's controls and decorators from the registry the tree
//! was loaded with: without it they could have any outcome.

use std::sync::Arc;

use neurotree::observe::{Coverage, Outcome, OutcomeSet};
use neurotree::{Blueprint, ManualClock, Registry, Status, Tree, XmlLoader};

use Outcome::{Failure, Halted, Running, Success};

fn load(registry: &Registry<()>, body: &str) -> Arc<Blueprint<()>> {
    let xml = format!(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\
         <BehaviorTree ID=\"Main\">{body}</BehaviorTree></root>"
    );
    let mut loader = XmlLoader::new(registry);
    loader.load_str(&xml, "main.xml").unwrap();
    Arc::new(loader.build_main().unwrap())
}

fn nav2() -> Registry<()> {
    let mut registry = Registry::new();
    neurotree::nav2::register_controls(&mut registry).unwrap();
    registry
}

#[test]
fn a_recovery_node_over_an_action_that_fails_can_only_fail() {
    let registry = nav2();
    let blueprint = load(
        &registry,
        "<RecoveryNode name=\"recover\" number_of_retries=\"1\">\
         <AlwaysFailure name=\"act\"/><AlwaysSuccess name=\"fix\"/></RecoveryNode>",
    );
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), ManualClock::new());
    let coverage = Coverage::with_registry(&blueprint, &registry);
    tree.set_observer(coverage.clone());
    // The action fails, the recovery succeeds, the action fails again: the one retry is
    // spent, so the node fails.
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Failure));
    let report = coverage.report(&blueprint);
    // The action can only fail, so the node cannot succeed; the recovery cannot run, so
    // neither can the node: Failure is all it can have, and all three nodes are covered.
    let recover = report.node_by_path("recover").unwrap();
    assert_eq!(recover.possible, OutcomeSet::of(&[Failure]));
    assert_eq!(recover.seen, OutcomeSet::of(&[Failure]));
    assert!(recover.is_covered());
    assert_eq!(
        (report.covered_outcomes(), report.possible_outcomes()),
        (3, 3)
    );

    // Without the registry the node declares nothing: Success, Failure, Running and Halted
    // are possible, 4 for it and 1 for each leaf.
    let blind = Coverage::new(&blueprint);
    let report = blind.report(&blueprint);
    assert_eq!(
        report.node_by_path("recover").unwrap().possible,
        OutcomeSet::of(&[Success, Failure, Running, Halted])
    );
    assert_eq!(report.possible_outcomes(), 6);
}

#[test]
fn a_rate_controller_over_a_success_cannot_fail() {
    let registry = nav2();
    // `hz` is left to its declared default, 10: a literal, so the controller cannot fail to
    // read it.
    let blueprint = load(
        &registry,
        "<RateController name=\"rate\"><AlwaysSuccess name=\"plan\"/></RateController>",
    );
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(Arc::clone(&blueprint), clock.clone());
    let coverage = Coverage::with_registry(&blueprint, &registry);
    tree.set_observer(coverage.clone());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    let report = coverage.report(&blueprint);
    // Its child's Success, and Running (so Halted) while it waits for the period; never
    // Failure, for the child cannot fail and `hz` is read from a literal.
    let rate = report.node_by_path("rate").unwrap();
    assert_eq!(rate.possible, OutcomeSet::of(&[Success, Running, Halted]));
    assert_eq!(rate.missing(), OutcomeSet::of(&[Running, Halted]));
    // Rate: 1 of 3; the child: 1 of 1.
    assert_eq!(
        (report.covered_outcomes(), report.possible_outcomes()),
        (2, 4)
    );
}

#[test]
fn a_rate_controller_reading_hz_from_the_blackboard_may_fail() {
    let registry = nav2();
    let blueprint = load(
        &registry,
        "<RateController name=\"rate\" hz=\"{hz}\"><AlwaysSuccess/></RateController>",
    );
    let report = Coverage::with_registry(&blueprint, &registry).report(&blueprint);
    // An entry may be missing or not a number: the controller then fails.
    assert_eq!(
        report.node_by_path("rate").unwrap().possible,
        OutcomeSet::of(&[Success, Failure, Running, Halted])
    );
}

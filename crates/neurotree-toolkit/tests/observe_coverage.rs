//! Coverage: the exact outcomes each node was seen with, for scripted runs of a builder tree
//! and of an XML tree, against the outcomes each could have.

use crate::patrol;

use std::sync::Arc;

use neurotree::observe::{possible_outcomes, Coverage, CoverageReport, Outcome, OutcomeSet};
use neurotree::{Handle, ManualClock, Registry, StatefulAction, Status, Tree, XmlLoader};

use Outcome::{Failure, Halted, Running, Skipped, Success};

fn set(outcomes: &[Outcome]) -> OutcomeSet {
    OutcomeSet::of(outcomes)
}

/// `(path, seen, possible)` of every node, in pre-order.
fn rows(report: &neurotree::observe::CoverageReport) -> Vec<(&str, OutcomeSet, OutcomeSet)> {
    report
        .nodes()
        .iter()
        .map(|n| (n.path.as_str(), n.seen, n.possible))
        .collect()
}

#[test]
fn patrol_outcomes_seen_and_missing() {
    let (mut tree, clock) = patrol::start();
    let coverage = Coverage::new(tree.blueprint());
    tree.set_observer(coverage.clone());
    // Running, Failure (battery low: move and route halted), Running (once skipped),
    // Running, Success.
    patrol::run(&mut tree, &clock);

    let report = coverage.report(tree.blueprint());
    let all = set(&[Success, Failure, Running, Halted]);
    assert_eq!(
        rows(&report),
        [
            ("patrol", set(&[Success, Failure, Running]), all),
            (
                "patrol/battery_ok",
                set(&[Success, Failure]),
                set(&[Success, Failure])
            ),
            ("patrol/route", set(&[Success, Running, Halted]), all),
            // A RunOnce that skips after its run; its action cannot run, so neither can it.
            (
                "patrol/route/once",
                set(&[Success, Skipped]),
                set(&[Success, Failure, Skipped])
            ),
            (
                "patrol/route/once/wave",
                set(&[Success]),
                set(&[Success, Failure])
            ),
            ("patrol/route/move", set(&[Success, Running, Halted]), all),
            (
                "patrol/route/scan",
                set(&[Success]),
                set(&[Success, Failure])
            ),
        ]
    );
    assert_eq!(coverage.seen()[5], set(&[Success, Running, Halted]));
    assert_eq!(report.never_reached().count(), 0);
    assert_eq!(
        (report.covered_outcomes(), report.possible_outcomes()),
        (15, 21)
    );
    assert_eq!(
        report.to_string(),
        "coverage: 15 of 21 outcomes (71.4%), 7 of 7 nodes reached\n\
         node                    type              seen                       not seen\n\
         patrol                  ReactiveSequence  success, failure, running  halted\n\
         patrol/battery_ok       Condition         success, failure           -\n\
         patrol/route            Sequence          success, running, halted   failure\n\
         patrol/route/once       RunOnce           success, skipped           failure\n\
         patrol/route/once/wave  Action            success                    failure\n\
         patrol/route/move       StatefulAction    success, running, halted   failure\n\
         patrol/route/scan       Action            success                    failure\n"
    );
}

#[test]
fn a_fresh_record_has_reached_nothing() {
    let (tree, _clock) = patrol::start();
    let report = Coverage::new(tree.blueprint()).report(tree.blueprint());
    assert_eq!(report.never_reached().count(), 7);
    assert_eq!(report.covered_outcomes(), 0);
    assert_eq!(report.percent(), 0.0);
    assert!(report
        .to_string()
        .starts_with("coverage: 0 of 21 outcomes (0.0%), 0 of 7 nodes reached\n"));
}

/// Running for `ticks` ticks, then Success.
struct Work {
    ticks: u32,
    left: u32,
}

impl<C> StatefulAction<C> for Work {
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.left = self.ticks;
        self.on_running(h)
    }
    fn on_running(&mut self, _h: &mut Handle<'_, C>) -> Status {
        if self.left == 0 {
            return Status::Success;
        }
        self.left -= 1;
        Status::Running
    }
}

const XML: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
  <Fallback name="root">
    <Sequence name="guarded">
      <Inverter name="not_done"><AlwaysFailure name="done" _successIf="finished"/></Inverter>
      <Work name="work" _while="go"/>
    </Sequence>
    <AlwaysSuccess name="idle" _skipIf="quiet"/>
    <ForceSuccess name="rescue"><AlwaysFailure name="attempt"/></ForceSuccess>
    <AlwaysSuccess name="spare"/>
  </Fallback>
</BehaviorTree></root>"#;

#[test]
fn xml_tree_outcomes_with_a_halt_and_a_skip() {
    let mut registry = Registry::<()>::new();
    registry
        .register_stateful("Work", vec![], || Work { ticks: 5, left: 0 })
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "coverage.xml").unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    let mut tree = Tree::with_clock(blueprint.clone(), ManualClock::new());
    let coverage = Coverage::new(&blueprint);
    tree.set_observer(coverage.clone());
    let set_entries = |tree: &mut Tree<()>, go: bool, quiet: bool, finished: bool| {
        let b = tree.blackboard_mut();
        b.set("go", go).unwrap();
        b.set("quiet", quiet).unwrap();
        b.set("finished", finished).unwrap();
    };

    // 1: the guard holds and the work starts.
    set_entries(&mut tree, true, false, false);
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    // 2: `go` turns false: the `_while` halts and skips the work; the sequence, with one
    // child done and the other skipped, succeeds.
    set_entries(&mut tree, false, false, false);
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    // 3: `finished` fails the guard, `idle` is skipped, and the rescue succeeds, so
    // `spare` is never reached.
    set_entries(&mut tree, false, true, true);
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));

    let report = coverage.report(&blueprint);
    let all = set(&[Success, Failure, Running, Halted]);
    assert_eq!(
        rows(&report),
        [
            // The Fallback cannot fail: `rescue` is a ForceSuccess, which only succeeds, so
            // a pass that reaches it ends there with Success.
            (
                "root",
                set(&[Success, Running]),
                set(&[Success, Running, Halted])
            ),
            ("root/guarded", set(&[Success, Failure, Running]), all),
            (
                "root/guarded/not_done",
                set(&[Success, Failure]),
                set(&[Success, Failure])
            ),
            // `_successIf` gives AlwaysFailure a Success to see.
            (
                "root/guarded/not_done/done",
                set(&[Success, Failure]),
                set(&[Success, Failure])
            ),
            (
                "root/guarded/work",
                set(&[Running, Halted, Skipped]),
                set(&[Success, Failure, Running, Halted, Skipped])
            ),
            ("root/idle", set(&[Skipped]), set(&[Success, Skipped])),
            ("root/rescue", set(&[Success]), set(&[Success])),
            ("root/rescue/attempt", set(&[Failure]), set(&[Failure])),
            ("root/spare", set(&[]), set(&[Success])),
        ]
    );
    let never: Vec<&str> = report.never_reached().map(|n| n.path.as_str()).collect();
    assert_eq!(never, ["root/spare"]);
    assert_eq!(
        possible_outcomes(&blueprint, neurotree::NodeId(4)),
        set(&[Success, Failure, Running, Halted, Skipped])
    );
    assert_eq!(
        (report.covered_outcomes(), report.possible_outcomes()),
        // 22 outcomes less the root's Failure, which no run can have.
        (15, 21)
    );
}

#[test]
fn only_reachable_outcomes_of_std_nodes_and_conditions_are_possible() {
    // Conditions never run over ticks; a Precondition returns its `else` status. A Script
    // whose code fails to evaluate when it runs (an entry of the wrong type, say) returns
    // Failure with the error as its reason, as its declaration says, so it can fail.
    let mut registry = Registry::<()>::new();
    registry
        .register_condition("IsOk", vec![], |_| true)
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                 <Sequence>
                   <Script code="x := 1"/>
                   <ScriptCondition code="x == 1"/>
                   <IsOk/>
                   <Precondition if="x == 1" else="SKIPPED"><AlwaysSuccess/></Precondition>
                   <SetBlackboard value="1" output_key="y"/>
                   <WasEntryUpdated entry="y"/>
                 </Sequence>
               </BehaviorTree></root>"#,
            "reachable.xml",
        )
        .unwrap();
    let bp = loader.build_main().unwrap();
    let possible = |i| possible_outcomes(&bp, neurotree::NodeId(i));
    for i in 0..bp.len() {
        eprintln!(
            "DBG {i} {} {} {:?}",
            bp.type_id(neurotree::NodeId(i as u32)),
            bp.kind(neurotree::NodeId(i as u32)).type_name(),
            possible(i as u32)
        );
    }
    assert_eq!(possible(0), set(&[Success, Failure]), "Sequence");
    assert_eq!(possible(1), set(&[Success, Failure]), "Script");
    assert_eq!(possible(2), set(&[Success, Failure]), "ScriptCondition");
    assert_eq!(possible(3), set(&[Success, Failure]), "IsOk");
    assert_eq!(
        possible(4),
        set(&[Success, Failure, Skipped]),
        "Precondition"
    );
    assert_eq!(possible(6), set(&[Success]), "SetBlackboard");
    assert_eq!(possible(7), set(&[Success, Failure]), "WasEntryUpdated");
    assert!(!possible(0).contains(Running));
    assert!(!possible(0).contains(Halted));
}

#[test]
fn possible_outcomes_follow_each_declared_signature_over_literals_and_children() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                 <Sequence name="root">
                   <Repeat name="forever" num_cycles="-1"><AlwaysSuccess/></Repeat>
                   <Repeat name="once" num_cycles="1"><AlwaysFailure/></Repeat>
                   <Repeat name="never" num_cycles="0"><AlwaysFailure/></Repeat>
                   <Delay name="late" delay_msec="10"><AlwaysFailure/></Delay>
                   <KeepRunningUntilFailure name="keep"><AlwaysSuccess/></KeepRunningUntilFailure>
                   <RunOnce name="first" then_skip="false"><AlwaysSuccess/></RunOnce>
                   <RunOnce name="skips"><AlwaysSuccess/></RunOnce>
                   <Inverter name="flip"><AlwaysSuccess/></Inverter>
                 </Sequence>
               </BehaviorTree></root>"#,
            "signatures.xml",
        )
        .unwrap();
    let bp = loader.build_main().unwrap();
    let report = CoverageReport::new(&bp, &[], &[]);
    let possible = |path: &str| report.node_by_path(path).unwrap().possible;
    // A child that always succeeds is repeated forever: the Repeat never ends.
    assert_eq!(possible("root/forever"), set(&[Running, Halted]));
    // The Sequence never gets past it, so it too can only run.
    assert_eq!(possible("root"), set(&[Running, Halted]));
    // One cycle of a failing child: its failure, and no Running between cycles.
    assert_eq!(possible("root/once"), set(&[Failure]));
    // No cycle: Success at once, the child never ticked.
    assert_eq!(possible("root/never"), set(&[Success]));
    // A Delay waits (Running), then returns what its child does; Failure also when its
    // wait is aborted, as BehaviorTree.CPP's does. Never Success over a failing child.
    assert_eq!(possible("root/late"), set(&[Failure, Running, Halted]));
    // A child that always succeeds keeps it Running: it never fails, never succeeds.
    assert_eq!(possible("root/keep"), set(&[Running, Halted]));
    // `then_skip="false"` gives the first run's status again, never Skipped; the default
    // skips after the run.
    assert_eq!(possible("root/first"), set(&[Success]));
    assert_eq!(possible("root/skips"), set(&[Success, Skipped]));
    assert_eq!(possible("root/flip"), set(&[Failure]));
}

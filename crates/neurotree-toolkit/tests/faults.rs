//! Faults injected into a node (`neurotree::fault`): the fault lands on the call it names,
//! counted in calls (starts), not ticks, and the node's own code does not run for it.

use std::sync::{Arc, Mutex};

use neurotree::fault::{build_with_faults, FaultLog, NodeFault};
use neurotree::nodes::leaf::Handle;
use neurotree::{ManualClock, Registry, StatefulAction, Status, TickError, Tree, XmlLoader};
use proptest::prelude::*;

/// Takes `ticks` ticks per call (Running, then Success); logs each start.
struct Work {
    ticks: u32,
    left: u32,
    starts: Arc<Mutex<u32>>,
}

impl StatefulAction<()> for Work {
    fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        *self.starts.lock().unwrap() += 1;
        self.left = self.ticks;
        self.on_running(_h)
    }

    fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        self.left -= 1;
        if self.left == 0 {
            Status::Success
        } else {
            Status::Running
        }
    }
}

/// Runs `<Repeat num_cycles=cycles><Sequence><AlwaysSuccess/><Work/></Sequence></Repeat>`
/// with `faults`: the root's last status, the ticks, Work's starts, the hits.
fn run(
    cycles: u32,
    ticks: u32,
    faults: &[NodeFault],
) -> (Status, u32, u32, Vec<neurotree::fault::FaultHit>) {
    let starts = Arc::new(Mutex::new(0));
    let mut registry = Registry::<()>::new();
    let counted = Arc::clone(&starts);
    registry
        .register_stateful("Work", vec![], move || Work {
            ticks,
            left: 0,
            starts: Arc::clone(&counted),
        })
        .unwrap();
    let xml = format!(
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
            <Repeat num_cycles="{cycles}"><Sequence><AlwaysSuccess/><Work name="work"/></Sequence></Repeat>
        </BehaviorTree></root>"#
    );
    let log = FaultLog::default();
    let blueprint = build_with_faults(faults, &log, |wrap| {
        let mut loader = XmlLoader::new(&registry);
        if let Some(wrap) = wrap {
            loader = loader.wrap_hooks(wrap);
        }
        loader.load_str(&xml, "work.xml")?;
        loader.build_main()
    })
    .unwrap();
    let mut tree = Tree::with_clock(Arc::new(blueprint), ManualClock::new());
    let (mut status, mut n) = (Status::Running, 0);
    while status == Status::Running && n < 10_000 {
        status = tree.tick_once(&mut ()).unwrap();
        n += 1;
    }
    let starts = *starts.lock().unwrap();
    (status, n, starts, log.hits())
}

proptest! {
    #[test]
    fn a_fault_lands_on_the_call_it_names(
        cycles in 1u32..8,
        ticks in 1u32..4,
        call in 1u32..10,
        fail in any::<bool>(),
        by_path in any::<bool>(),
    ) {
        let node = if by_path { "Repeat/Sequence/work" } else { "Work" };
        let status = if fail { Status::Failure } else { Status::Success };
        let fault = NodeFault::new(node, call, status);
        let (root, tick_count, starts, hits) = run(cycles, ticks, &[fault]);
        let (plain_root, plain_ticks, plain_starts, _) = run(cycles, ticks, &[]);
        prop_assert_eq!(plain_root, Status::Success);
        prop_assert_eq!(plain_starts, cycles);
        // A call that completes lets Repeat start the next in the same tick.
        prop_assert_eq!(plain_ticks, cycles * (ticks - 1) + 1);
        if call > cycles {
            // Never reached: the run is the plain one.
            prop_assert!(hits.is_empty());
            prop_assert_eq!((root, tick_count, starts), (plain_root, plain_ticks, plain_starts));
        } else {
            prop_assert_eq!(hits.len(), 1);
            prop_assert_eq!(hits[0].path.as_str(), "Repeat/Sequence/work");
            prop_assert_eq!(hits[0].call, call);
            prop_assert_eq!(hits[0].status, status);
            if fail {
                // The calls before it ran; the faulted one answered within its first tick.
                prop_assert_eq!(root, Status::Failure);
                prop_assert_eq!(starts, call - 1);
                prop_assert_eq!(tick_count, (call - 1) * (ticks - 1) + 1);
            } else {
                prop_assert_eq!(root, Status::Success);
                prop_assert_eq!(starts, cycles - 1);
                prop_assert_eq!(tick_count, (cycles - 1) * (ticks - 1) + 1);
            }
        }
    }
}

#[test]
fn a_call_that_is_never_answered_runs_until_halted() {
    let fault = NodeFault::new("work", 2, Status::Running);
    let (_, ticks, starts, hits) = run(3, 1, &[fault]);
    // The first call succeeded; the second hangs until the loop gives up.
    assert_eq!(starts, 1);
    assert_eq!(ticks, 10_000);
    assert_eq!(hits.len(), 1);
}

#[test]
fn a_panic_fault_panics_on_its_call_and_the_tree_names_the_node() {
    // Three calls: a panic on the 4th never comes.
    let (root, _, starts, hits) = run(3, 2, &[NodeFault::panic("work", 4)]);
    assert_eq!((root, starts, hits.len()), (Status::Success, 3, 0));
    // On the 2nd it does; the tick catches it and names the node.
    let registry = Registry::<()>::new();
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
        <Repeat num_cycles="3"><AlwaysSuccess name="work"/></Repeat>
    </BehaviorTree></root>"#;
    let log = FaultLog::default();
    let blueprint = build_with_faults(&[NodeFault::panic("work", 2)], &log, |wrap| {
        let mut loader = XmlLoader::new(&registry);
        if let Some(wrap) = wrap {
            loader = loader.wrap_hooks(wrap);
        }
        loader.load_str(xml, "work.xml")?;
        loader.build_main()
    })
    .unwrap();
    let mut tree = Tree::with_clock(Arc::new(blueprint), ManualClock::new());
    match tree.tick_once(&mut ()) {
        Err(TickError::Panicked { path, message, .. }) => {
            assert_eq!(path, "Repeat/work");
            assert_eq!(message, "injected fault: Repeat/work panics on its call 2");
        }
        other => panic!("expected the 2nd call to panic, got {other:?}"),
    }
    assert!(log.hits().is_empty());
}

#[test]
fn a_fault_that_names_no_node_is_refused() {
    let log = FaultLog::default();
    let registry = Registry::<()>::new();
    let err = build_with_faults(&["Nothing=FAILURE@1".parse().unwrap()], &log, |wrap| {
        let mut loader = XmlLoader::new(&registry);
        if let Some(wrap) = wrap {
            loader = loader.wrap_hooks(wrap);
        }
        loader.load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#,
            "m.xml",
        )?;
        loader.build_main()
    })
    .unwrap_err()
    .to_string();
    assert!(err.contains("`Nothing=FAILURE@1` names no node"), "{err}");
}

#[test]
fn faults_read_and_write_back() {
    let fault: NodeFault = "a/b=FAILURE@3#106".parse().unwrap();
    assert_eq!(
        fault,
        NodeFault::new("a/b", 3, Status::Failure).with_error_code(106)
    );
    assert_eq!(fault.to_string(), "a/b=FAILURE@3#106");
    let panic: NodeFault = "a/b=panic@2".parse().unwrap();
    assert_eq!(panic, NodeFault::panic("a/b", 2));
    assert_eq!(panic.to_string(), "a/b=PANIC@2");
    for bad in [
        "a",
        "a=FAILURE",
        "a=NOPE@1",
        "a=FAILURE@0",
        "=FAILURE@1",
        "a=FAILURE@1#x",
    ] {
        assert!(bad.parse::<NodeFault>().is_err(), "{bad}");
    }
}

/// A result forced by hand on one node: what `LiveFaults` answers, set between ticks; and
/// the nodes hanging under a forced RUNNING.
#[derive(Default)]
struct ByHand(Mutex<Option<(u32, Status)>>, Mutex<Vec<u32>>);

impl ByHand {
    fn force(&self, force: Option<(u32, Status)>) {
        *self.0.lock().unwrap() = force;
    }

    /// The run went back to before any node hung (as a studio's rewind does).
    fn go_back(&self) {
        self.1.lock().unwrap().clear();
    }
}

impl neurotree::fault::LiveFaults for ByHand {
    fn forced(&self, node: neurotree::NodeId) -> Option<Status> {
        self.0
            .lock()
            .unwrap()
            .filter(|(at, _)| *at == node.0)
            .map(|(_, s)| s)
    }

    fn hanging(&self, node: neurotree::NodeId) -> bool {
        self.1.lock().unwrap().contains(&node.0)
    }

    fn set_hanging(&self, node: neurotree::NodeId, hanging: bool) {
        let mut hangs = self.1.lock().unwrap();
        hangs.retain(|n| *n != node.0);
        if hanging {
            hangs.push(node.0);
        }
    }
}

/// Counts its starts, running ticks and halts; runs for ever.
#[derive(Default, Clone)]
struct Counts(Arc<Mutex<(u32, u32, u32)>>);

impl Counts {
    fn get(&self) -> (u32, u32, u32) {
        *self.0.lock().unwrap()
    }
}

struct Endless(Counts);

impl StatefulAction<()> for Endless {
    fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        self.0 .0.lock().unwrap().0 += 1;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        self.0 .0.lock().unwrap().1 += 1;
        Status::Running
    }
    fn on_halted(&mut self, _h: &mut Handle<'_, ()>) {
        self.0 .0.lock().unwrap().2 += 1;
    }
    // Its counts are the test's, not the tree's: nothing to save.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(Vec::new())
    }
}

/// A tree of `body` whose `Endless` leaves count into the counts given back, built with
/// the hooks through which the source given back forces results.
fn forced_by_hand(body: &str) -> (Counts, Arc<ByHand>, Tree<()>) {
    let counts = Counts::default();
    let mut registry = Registry::<()>::new();
    let c = counts.clone();
    registry
        .register_stateful("Endless", vec![], move || Endless(c.clone()))
        .unwrap();
    let live = Arc::new(ByHand::default());
    let source: Arc<dyn neurotree::fault::LiveFaults> = live.clone();
    let mut loader =
        XmlLoader::new(&registry).wrap_hooks(neurotree::fault::live_wrapper(source, None));
    let xml =
        format!(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">{body}</BehaviorTree></root>"#);
    loader.load_str(&xml, "work.xml").unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    (
        counts,
        live,
        Tree::with_clock(blueprint, ManualClock::new()),
    )
}

#[test]
fn a_result_forced_on_a_running_node_halts_it_and_a_forced_running_is_never_ticked() {
    let (counts, live, mut tree) = forced_by_hand("<Inverter><Endless name=\"work\"/></Inverter>");
    let blueprint = tree.blueprint();
    let work = blueprint
        .ids()
        .find(|id| blueprint.name(*id) == "work")
        .unwrap();
    let tick = |tree: &mut Tree<()>| tree.tick_once(&mut ()).unwrap();
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (1, 1, 0));
    // FAILURE on the running leaf: halted once, its tick not called; the Inverter turns it.
    live.force(Some((work.0, Status::Failure)));
    assert_eq!(tick(&mut tree), Status::Success);
    assert_eq!(counts.get(), (1, 1, 1));
    live.force(None);
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (2, 1, 1), "started afresh");
    // RUNNING: a call never answered; the leaf is not ticked until halted, forced or not.
    live.force(Some((work.0, Status::Running)));
    assert_eq!(tick(&mut tree), Status::Running);
    live.force(None);
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (2, 1, 1), "not ticked");
    tree.halt(&mut ());
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (3, 1, 2), "halted, then started afresh");
}

#[test]
fn a_forced_running_does_not_outlive_a_rewind_to_before_it() {
    let (counts, live, mut tree) = forced_by_hand("<Endless name=\"work\"/>");
    let tick = |tree: &mut Tree<()>| tree.tick_once(&mut ()).unwrap();
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (1, 0, 0));
    let before = tree.save_state().unwrap();
    // Forced RUNNING, then cleared: a call never answered, the leaf not ticked.
    live.force(Some((0, Status::Running)));
    assert_eq!(tick(&mut tree), Status::Running);
    live.force(None);
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (1, 0, 0));
    assert!(
        neurotree::fault::LiveFaults::hanging(&*live, neurotree::NodeId(0)),
        "the source knows it hangs"
    );
    // Back before the force: the run goes on as it did then, the leaf ticked. The hooks
    // ask the source, which the rewind reached, not a flag of their own, which it did not.
    tree.restore_state(&before).unwrap();
    live.go_back();
    assert_eq!(tick(&mut tree), Status::Running);
    assert_eq!(counts.get(), (1, 1, 0), "ticked as before the force");
}

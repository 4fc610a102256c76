//! A tree loaded from BehaviorTree.CPP XML is halted from another thread as a built one is:
//! ticked by hand, and run by `FixedRate` with a long period.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use neurotree_toolkit::runtime::{ManualPacer, Pacer};
use neurotree_toolkit::{
    Clock, FixedRate, Handle, ManualClock, Registry, StatefulAction, Status, TickError, Tree,
    XmlLoader, HALT_POLL_PERIOD,
};

/// Starts and halts of every `Work` node, shared with the test's threads.
#[derive(Default)]
struct Counts {
    starts: AtomicU32,
    halts: AtomicU32,
}

/// Runs until halted.
struct Work;

impl StatefulAction<Arc<Counts>> for Work {
    fn on_start(&mut self, h: &mut Handle<'_, Arc<Counts>>) -> Status {
        h.ctx().starts.fetch_add(1, Ordering::Relaxed);
        Status::Running
    }
    fn on_running(&mut self, _: &mut Handle<'_, Arc<Counts>>) -> Status {
        Status::Running
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Arc<Counts>>) {
        h.ctx().halts.fetch_add(1, Ordering::Relaxed);
    }
}

const XML: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Parallel success_count="-1" failure_count="1">
      <Work/>
      <SubTree ID="Inner"/>
    </Parallel>
  </BehaviorTree>
  <BehaviorTree ID="Inner">
    <Sequence><AlwaysSuccess/><Work/></Sequence>
  </BehaviorTree>
</root>"#;

fn blueprint() -> Arc<neurotree_toolkit::Blueprint<Arc<Counts>>> {
    let mut registry = Registry::<Arc<Counts>>::new();
    registry.register_stateful("Work", vec![], || Work).unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "halt.xml").unwrap();
    Arc::new(loader.build_main().unwrap())
}

#[test]
fn a_tree_from_xml_is_halted_from_another_thread_at_its_next_tick() {
    let mut tree = Tree::with_clock(blueprint(), ManualClock::new());
    let handle = tree.halt_handle();
    let mut counts = Arc::new(Counts::default());
    assert_eq!(tree.tick_once(&mut counts), Ok(Status::Running));
    std::thread::spawn(move || handle.request()).join().unwrap();
    assert_eq!(tree.tick_once(&mut counts), Err(TickError::HaltRequested));
    assert_eq!(counts.starts.load(Ordering::Relaxed), 2);
    assert_eq!(counts.halts.load(Ordering::Relaxed), 2);
    assert!(tree
        .statuses()
        .iter()
        .all(|s| *s == neurotree_toolkit::NodeStatus::Idle));
}

/// A manual pacer whose first sleep lets another thread act before it ends: the test
/// knows the loop sleeps when the other thread acts, with no wall time involved.
struct Gate {
    time: ManualPacer,
    asleep: Option<mpsc::Sender<()>>,
    go: mpsc::Receiver<()>,
}

impl Pacer for Gate {
    fn now(&self) -> Duration {
        self.time.now()
    }
    fn sleep_until(&mut self, deadline: Duration) {
        if let Some(asleep) = self.asleep.take() {
            asleep.send(()).unwrap();
            self.go.recv().unwrap();
        }
        self.time.sleep_until(deadline);
    }
}

#[test]
fn a_fixed_rate_run_of_a_tree_from_xml_ends_promptly_on_a_request() {
    let clock = ManualClock::new();
    let mut tree = Tree::with_clock(blueprint(), clock.clone());
    let handle = tree.halt_handle();
    let (asleep, sleeping) = mpsc::channel();
    let (go, gate) = mpsc::channel();
    let mut pacer = Gate {
        time: ManualPacer::new(clock.clone()),
        asleep: Some(asleep),
        go: gate,
    };
    let requester = std::thread::spawn(move || {
        sleeping.recv().unwrap();
        handle.request();
        go.send(()).unwrap();
    });
    let mut counts = Arc::new(Counts::default());
    let result = FixedRate::new(Duration::from_secs(10)).run_with(
        &mut tree,
        &mut counts,
        &mut pacer,
        |_| {},
    );
    requester.join().unwrap();
    assert_eq!(result, Err(TickError::HaltRequested));
    // The sleep of 10 s ended after the slice in which the request came.
    assert_eq!(clock.now(), HALT_POLL_PERIOD);
    assert_eq!(counts.halts.load(Ordering::Relaxed), 2);
}

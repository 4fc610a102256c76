//! Async actions from the outside: registered by name and loaded from XML, ticked without
//! allocating, and run on tokio (spawned tasks aborted on halt, the runner ticking on its
//! period and on wakes, a dropped run halting the tree).

use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicU32, Ordering::SeqCst};
use std::sync::Arc;
use std::task::{Context, Poll};

use neurotree::{Blueprint, ManualClock, NodeStatus, PortSpec, Registry, Status, Tree, XmlLoader};

use crate::counting_alloc;
use counting_alloc::count;

/// Counts the polls and drops of the futures it is shared with.
#[derive(Default)]
struct Probe {
    polls: AtomicU32,
    drops: AtomicU32,
}

impl Probe {
    fn counts(&self) -> (u32, u32) {
        (self.polls.load(SeqCst), self.drops.load(SeqCst))
    }
}

/// Pending until it has been polled `ready_after` times, then Success; allocates nothing.
struct Countdown {
    probe: Arc<Probe>,
    ready_after: u32,
}

impl Future for Countdown {
    type Output = Status;
    fn poll(mut self: Pin<&mut Self>, _cx: &mut Context<'_>) -> Poll<Status> {
        self.probe.polls.fetch_add(1, SeqCst);
        self.ready_after = self.ready_after.saturating_sub(1);
        if self.ready_after == 0 {
            Poll::Ready(Status::Success)
        } else {
            Poll::Pending
        }
    }
}

impl Drop for Countdown {
    fn drop(&mut self) {
        self.probe.drops.fetch_add(1, SeqCst);
    }
}

#[test]
fn registered_async_actions_read_their_ports_at_start() {
    let probe = Arc::new(Probe::default());
    let mut registry = Registry::<Vec<u32>>::new();
    let shared = Arc::clone(&probe);
    registry
        .register_async("Hover", vec![PortSpec::input::<u32>("ticks")], move |h| {
            let ticks: u32 = h.input("ticks").unwrap_or(1);
            h.ctx_mut().push(ticks);
            Countdown {
                probe: Arc::clone(&shared),
                ready_after: ticks,
            }
        })
        .unwrap();
    assert_eq!(
        registry.get("Hover").unwrap().category,
        neurotree::Category::Action
    );
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="main">
                 <Sequence>
                   <Hover ticks="2"/>
                   <Hover ticks="{n}"/>
                 </Sequence>
               </BehaviorTree></root>"#,
            "hover.xml",
        )
        .unwrap();
    let blueprint = Arc::new(loader.build_main().unwrap());
    assert_eq!(
        blueprint.kind(neurotree::NodeId(1)).type_name(),
        "AsyncAction"
    );
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.blackboard_mut().set("n", 3_u32).unwrap();
    let mut started = Vec::new();
    let statuses: Vec<_> = (0..4).map(|_| tree.tick_once(&mut started)).collect();
    // The second run starts in the tick the first one completes.
    assert_eq!(
        statuses,
        [
            Ok(Status::Running),
            Ok(Status::Running),
            Ok(Status::Running),
            Ok(Status::Success)
        ]
    );
    assert_eq!(started, [2, 3]);
    // Two polls for the first run, three for the second, each dropped as it completed.
    assert_eq!(probe.counts(), (5, 2));
}

#[test]
fn a_start_allocates_only_its_future_and_polls_allocate_nothing() {
    let probe = Arc::new(Probe::default());
    let shared = Arc::clone(&probe);
    let blueprint = Blueprint::<()>::builder()
        .reactive_sequence("guarded", |s| {
            s.condition("ok", |_| true)
                .async_action("hover", move |_| Countdown {
                    probe: Arc::clone(&shared),
                    ready_after: 100,
                })
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    let (start, status) = count(|| tree.tick_once(&mut ()));
    assert_eq!(status, Ok(Status::Running));
    assert_eq!(start, 1, "the boxed future");
    let (polls, _) = count(|| {
        for _ in 0..98 {
            assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
        }
        assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Success));
    });
    assert_eq!(polls, 0);
    assert_eq!(probe.counts(), (100, 1));
    let (restart_and_halt, _) = count(|| {
        assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
        tree.halt(&mut ());
    });
    assert_eq!(restart_and_halt, 1);
    assert_eq!(probe.counts(), (101, 2));
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
}

#[cfg(feature = "tokio")]
mod on_tokio {
    use super::*;
    use std::time::Duration;

    use neurotree::runtime::tokio::{spawn_abort_on_drop, tick_until_done, RunSummary, TokioClock};
    use tokio::sync::oneshot;
    use tokio::time::Instant;

    /// Counts how the tasks spawned by the tree's action ended.
    #[derive(Default)]
    struct Tasks {
        finished: AtomicU32,
        /// Tasks dropped before they finished: aborted.
        aborted: AtomicU32,
    }

    /// Counts an unfinished task as aborted when its future is dropped.
    struct TaskGuard {
        tasks: Arc<Tasks>,
        finished: bool,
        /// Dropped with the task, to tell the test that the abort went through.
        _gone: oneshot::Sender<()>,
    }

    impl Drop for TaskGuard {
        fn drop(&mut self) {
            if !self.finished {
                self.tasks.aborted.fetch_add(1, SeqCst);
            }
        }
    }

    /// The world of these trees: whether the guard condition holds, and the receiving ends
    /// that tell when each spawned task is gone.
    struct World {
        go: bool,
        gone: Vec<oneshot::Receiver<()>>,
    }

    /// `ReactiveSequence(go, scan)`, where `scan` spawns a task that works for `work` and
    /// awaits its result.
    fn scanner(tasks: &Arc<Tasks>, work: Duration) -> Tree<World> {
        let tasks = Arc::clone(tasks);
        let blueprint = Blueprint::<World>::builder()
            .reactive_sequence("guarded", |s| {
                s.condition("go", |w: &World| w.go)
                    .async_action("scan", move |h| {
                        let (gone_tx, gone_rx) = oneshot::channel();
                        h.ctx_mut().gone.push(gone_rx);
                        let mut guard = TaskGuard {
                            tasks: Arc::clone(&tasks),
                            finished: false,
                            _gone: gone_tx,
                        };
                        async move {
                            let task = spawn_abort_on_drop(async move {
                                tokio::time::sleep(work).await;
                                guard.finished = true;
                                guard.tasks.finished.fetch_add(1, SeqCst);
                                7_u32
                            });
                            match task.await {
                                Ok(7) => Status::Success,
                                _ => Status::Failure,
                            }
                        }
                    })
            })
            .build_shared()
            .unwrap();
        Tree::with_clock(blueprint, TokioClock::new())
    }

    fn world() -> World {
        World {
            go: true,
            gone: Vec::new(),
        }
    }

    #[tokio::test(start_paused = true)]
    async fn halting_the_node_aborts_its_spawned_task() {
        let tasks = Arc::new(Tasks::default());
        let mut tree = scanner(&tasks, Duration::from_secs(10));
        let mut world = world();
        assert_eq!(tree.tick_once(&mut world), Ok(Status::Running));
        tokio::time::sleep(Duration::from_secs(1)).await;
        assert_eq!(tree.tick_once(&mut world), Ok(Status::Running));

        world.go = false;
        assert_eq!(tree.tick_once(&mut world), Ok(Status::Failure));
        // The task's future is dropped once the runtime processes the abort.
        let gone = world.gone.pop().unwrap();
        assert!(gone.await.is_err());
        assert_eq!(tasks.aborted.load(SeqCst), 1);
        assert_eq!(tasks.finished.load(SeqCst), 0);
        assert_eq!(tree.now(), Duration::from_secs(1));
    }

    #[tokio::test(start_paused = true)]
    async fn a_task_that_finishes_completes_the_node() {
        let tasks = Arc::new(Tasks::default());
        let mut tree = scanner(&tasks, Duration::from_millis(250));
        let mut world = world();
        let run = tick_until_done(&mut tree, &mut world, Duration::from_millis(100))
            .await
            .unwrap();
        // Ticks at 0, 100 and 200 ms on the period; at 250 ms because the task woke the tree.
        assert_eq!(
            run,
            RunSummary {
                status: Status::Success,
                ticks: 4,
                early_ticks: 1
            }
        );
        assert_eq!(tree.now(), Duration::from_millis(250));
        assert_eq!(tasks.finished.load(SeqCst), 1);
        assert_eq!(tasks.aborted.load(SeqCst), 0);
    }

    #[tokio::test(start_paused = true)]
    async fn without_wakes_the_runner_ticks_on_its_period() {
        // Sleep reads the tree's clock and wakes nothing: only the period ticks it.
        let blueprint = Blueprint::<()>::builder()
            .sleep("wait", Duration::from_millis(350))
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(blueprint, TokioClock::new());
        let started = Instant::now();
        let run = tick_until_done(&mut tree, &mut (), Duration::from_millis(100))
            .await
            .unwrap();
        assert_eq!(
            (run.status, run.ticks, run.early_ticks),
            (Status::Success, 5, 0)
        );
        assert_eq!(started.elapsed(), Duration::from_millis(400));
    }

    #[tokio::test(start_paused = true)]
    async fn a_timeout_on_the_tokio_clock_halts_an_awaiting_action() {
        let probe = Arc::new(Probe::default());
        let shared = Arc::clone(&probe);
        let blueprint = Blueprint::<()>::builder()
            .timeout("limit", Duration::from_millis(500), |t| {
                t.async_action("slow", move |_| {
                    let probe = Arc::clone(&shared);
                    async move {
                        let _counted = Countdown {
                            probe,
                            ready_after: u32::MAX,
                        };
                        tokio::time::sleep(Duration::from_secs(2)).await;
                        Status::Success
                    }
                })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(blueprint, TokioClock::new());
        let run = tick_until_done(&mut tree, &mut (), Duration::from_millis(100))
            .await
            .unwrap();
        // Ticks at 0, 100, ..., 500 ms; the last one times out.
        assert_eq!((run.status, run.ticks), (Status::Failure, 6));
        assert_eq!(probe.counts(), (0, 1));
        assert_eq!(tree.now(), Duration::from_millis(500));
    }

    #[tokio::test(start_paused = true)]
    async fn dropping_a_run_halts_the_tree() {
        let tasks = Arc::new(Tasks::default());
        let mut tree = scanner(&tasks, Duration::from_secs(60));
        let mut world = world();
        let cut_short = tokio::time::timeout(
            Duration::from_secs(1),
            tick_until_done(&mut tree, &mut world, Duration::from_millis(100)),
        )
        .await;
        assert!(cut_short.is_err());
        assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
        let gone = world.gone.pop().unwrap();
        assert!(gone.await.is_err());
        assert_eq!(tasks.aborted.load(SeqCst), 1);
        assert_eq!(tasks.finished.load(SeqCst), 0);
    }

    #[tokio::test(start_paused = true)]
    async fn the_tokio_clock_follows_paused_time() {
        let clock = TokioClock::new();
        assert_eq!(neurotree::Clock::now(&clock), Duration::ZERO);
        tokio::time::advance(Duration::from_millis(1500)).await;
        assert_eq!(neurotree::Clock::now(&clock), Duration::from_millis(1500));
    }
}

/// Runs until halted; its halt then takes `halt_polls` more polls (a cancel being
/// acknowledged), counted in `probe`.
struct SlowStop {
    probe: Arc<Probe>,
    halt_polls: u32,
}

impl neurotree::AsyncAction<()> for SlowStop {
    fn start(&self, _h: &mut neurotree::Handle<'_, ()>) -> neurotree::ActionFuture {
        Box::pin(std::future::pending())
    }

    fn on_halt_requested(
        &self,
        run: neurotree::ActionFuture,
        _h: &mut neurotree::Handle<'_, ()>,
    ) -> Option<neurotree::HaltFuture> {
        drop(run);
        let probe = Arc::clone(&self.probe);
        let mut left = self.halt_polls;
        Some(Box::pin(std::future::poll_fn(move |_| {
            probe.polls.fetch_add(1, SeqCst);
            if left == 0 {
                probe.drops.fetch_add(1, SeqCst);
                return Poll::Ready(());
            }
            left -= 1;
            Poll::Pending
        })))
    }
}

#[test]
fn a_registered_async_action_object_halts_over_ticks_from_xml() {
    let probe = Arc::new(Probe::default());
    let mut registry = Registry::<()>::new();
    registry
        .register_async_action(
            "Drive",
            vec![],
            SlowStop {
                probe: Arc::clone(&probe),
                halt_polls: 2,
            },
        )
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                 <Sequence><Drive/></Sequence>
               </BehaviorTree></root>"#,
            "drive.xml",
        )
        .unwrap();
    let mut tree = Tree::with_clock(Arc::new(loader.build_main().unwrap()), ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    // The halt future is polled at once (pending), then once per tick_halt: done on the
    // third poll.
    assert!(!tree.halt(&mut ()));
    assert_eq!(probe.counts(), (1, 0));
    assert!(!tree.tick_halt(&mut ()));
    assert_eq!(probe.counts(), (2, 0));
    assert!(tree.tick_halt(&mut ()));
    assert_eq!(probe.counts(), (3, 1));
    assert!(tree.statuses().iter().all(|s| *s == NodeStatus::Idle));
    // The next tick starts a new run.
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
}

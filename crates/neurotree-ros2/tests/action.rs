//! The action node against a fake action server written with ros2-client, each on its own
//! participant in this process, over 127.0.0.1.

use crate::common;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use common::{free_domain, node, tick_until_done, tree};
use neurotree_ros2::msg::nav2_msgs::{Spin, SpinFeedback, SpinGoal, SpinResult};
use neurotree_ros2::ros2_client::action::{GetResultResponse, GoalStatusEnum, SendGoalResponse};
use neurotree_ros2::ros2_client::builtin_interfaces::Time;
use neurotree_ros2::{ActionError, ActionSpec, RosActionNode, RosNode};
use neurotree_toolkit::{Blueprint, Handle, Port, PortSpec, Status};

/// What the tree saw: feedback received, the failure reported.
#[derive(Default)]
struct Seen {
    feedback: Vec<f32>,
    failure: Option<ActionError>,
}

/// Spins by the `yaw` port; records feedback and failures in the shared [`Seen`].
struct SpinBy(Arc<Mutex<Seen>>);

impl ActionSpec<()> for SpinBy {
    type Action = Spin;

    fn ports() -> Vec<PortSpec> {
        vec![PortSpec::input::<f32>("yaw")]
    }

    fn goal(&mut self, h: &mut Handle<'_, ()>) -> Result<SpinGoal, String> {
        let yaw: f32 = h.input("yaw").map_err(|e| e.to_string())?;
        Ok(SpinGoal {
            target_yaw: yaw,
            time_allowance: Duration::from_secs(5).into(),
        })
    }

    fn on_feedback(&mut self, _h: &mut Handle<'_, ()>, feedback: &SpinFeedback) -> Status {
        self.0
            .lock()
            .unwrap()
            .feedback
            .push(feedback.angular_distance_traveled);
        Status::Running
    }

    fn on_result(&mut self, _h: &mut Handle<'_, ()>, result: &SpinResult) -> Status {
        if result.error_code == SpinResult::NONE {
            Status::Success
        } else {
            Status::Failure
        }
    }

    fn on_failure(
        &mut self,
        _h: &mut Handle<'_, ()>,
        error: &ActionError,
        _result: Option<&SpinResult>,
    ) -> Status {
        self.0.lock().unwrap().failure = Some(error.clone());
        Status::Failure
    }
}

/// A one-node tree: the Spin action on `ros`, with ports `yaw` and the extra ones given.
fn spin_tree(
    ros: &RosNode,
    seen: &Arc<Mutex<Seen>>,
    ports: &[(&str, &str)],
) -> neurotree_toolkit::Tree<()> {
    let ros = ros.clone();
    let seen = Arc::clone(seen);
    let mut bound = vec![Port::literal("yaw", "1.5")];
    bound.extend(ports.iter().map(|(k, v)| Port::literal(k, v)));
    let blueprint = Blueprint::<()>::builder()
        .stateful("spin", move || {
            RosActionNode::new(ros.clone(), "spin", SpinBy(Arc::clone(&seen)))
        })
        .ports(bound)
        .build_shared()
        .unwrap();
    tree(blueprint)
}

/// How the fake server answers a goal.
#[derive(Clone, Copy)]
enum Script {
    /// Accepts, sends `feedback` feedbacks 50 ms apart, then succeeds.
    Succeed { feedback: usize },
    /// Rejects every goal.
    Reject,
    /// Accepts and never ends: waits for a cancel request.
    RunForever,
}

/// What the fake server saw.
#[derive(Default)]
struct ServerLog {
    goals: AtomicUsize,
    cancels: AtomicUsize,
}

/// A fake server's thread; dropping it stops the thread and its participant, so that
/// nothing of the test is left in the domain when the domain is released.
struct FakeServer {
    log: Arc<ServerLog>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Drop for FakeServer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Serves action `spin` on its own participant in `domain` until dropped, at most `limit`.
fn fake_server(domain: u16, script: Script, limit: Duration) -> FakeServer {
    let log = Arc::new(ServerLog::default());
    let server_log = Arc::clone(&log);
    let stop = Arc::new(AtomicBool::new(false));
    let stopped = Arc::clone(&stop);
    let handle = std::thread::spawn(move || {
        let ros = node("fake_server", domain);
        let server = ros.action_server::<Spin>("spin").unwrap();
        let until = Instant::now() + limit;
        // The goal being executed, its result request, and feedback still to send.
        let mut goal = None;
        let mut result_request = None;
        let mut feedback_left = 0;
        while Instant::now() < until && !stopped.load(Ordering::SeqCst) {
            if let Some((request, sent)) = server.receive_goal().unwrap() {
                server_log.goals.fetch_add(1, Ordering::SeqCst);
                let accepted = !matches!(script, Script::Reject);
                let response = SendGoalResponse {
                    accepted,
                    stamp: Time::now(),
                };
                server.send_goal_response(request, response).unwrap();
                if accepted {
                    goal = Some(sent.goal_id);
                    if let Script::Succeed { feedback } = script {
                        feedback_left = feedback;
                    }
                }
            }
            if let Some((request, _)) = server.receive_result_request().unwrap() {
                result_request = Some(request);
            }
            if server.receive_cancel_request().unwrap().is_some() {
                server_log.cancels.fetch_add(1, Ordering::SeqCst);
            }
            if let (Some(goal_id), Script::Succeed { feedback }) = (goal, script) {
                if feedback_left > 0 {
                    let travelled = (feedback - feedback_left + 1) as f32 * 0.5;
                    let fb = SpinFeedback {
                        angular_distance_traveled: travelled,
                    };
                    server.send_feedback(goal_id, fb).unwrap();
                    feedback_left -= 1;
                } else if let Some(request) = result_request.take() {
                    let response = GetResultResponse {
                        status: GoalStatusEnum::Succeeded,
                        result: SpinResult::default(),
                    };
                    server.send_result(request, response).unwrap();
                    goal = None;
                }
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    });
    FakeServer {
        log,
        stop,
        thread: Some(handle),
    }
}

pub(crate) fn an_accepted_goal_runs_with_feedback_and_succeeds_with_the_result() {
    let domain = free_domain();
    let server = fake_server(
        domain.id,
        Script::Succeed { feedback: 3 },
        Duration::from_secs(15),
    );
    let ros = node("tree", domain.id);
    let seen = Arc::new(Mutex::new(Seen::default()));
    let mut tree = spin_tree(&ros, &seen, &[("wait_for_server_timeout", "5000")]);

    assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Running);
    let status = tick_until_done(&mut tree, &mut (), common::HANG);

    assert_eq!(status, Status::Success);
    assert_eq!(server.log.goals.load(Ordering::SeqCst), 1);
    let seen = seen.lock().unwrap();
    assert_eq!(
        seen.feedback,
        [0.5, 1.0, 1.5],
        "every feedback, in order, before the result"
    );
    assert_eq!(seen.failure, None);
}

pub(crate) fn a_rejected_goal_fails_with_the_reason() {
    let domain = free_domain();
    let server = fake_server(domain.id, Script::Reject, Duration::from_secs(15));
    let ros = node("tree", domain.id);
    let seen = Arc::new(Mutex::new(Seen::default()));
    let mut tree = spin_tree(&ros, &seen, &[("wait_for_server_timeout", "5000")]);

    let status = tick_until_done(&mut tree, &mut (), common::HANG);

    assert_eq!(status, Status::Failure);
    assert_eq!(server.log.goals.load(Ordering::SeqCst), 1);
    let failure = seen.lock().unwrap().failure.clone();
    assert_eq!(
        failure,
        Some(ActionError::GoalRejected {
            action: "spin".into()
        })
    );
}

pub(crate) fn without_a_server_the_node_fails_after_wait_for_server_timeout() {
    let domain = free_domain();
    let ros = node("tree", domain.id);
    let seen = Arc::new(Mutex::new(Seen::default()));
    let mut tree = spin_tree(&ros, &seen, &[("wait_for_server_timeout", "300")]);
    let started = Instant::now();

    let first = tree.tick_once(&mut ()).unwrap();
    let status = tick_until_done(&mut tree, &mut (), common::HANG);
    let took = started.elapsed();

    assert_eq!(
        first,
        Status::Running,
        "waiting for the server does not block the tick"
    );
    assert_eq!(status, Status::Failure);
    // At least the timeout; that it ends at all is `tick_until_done`'s bound, which a busy
    // machine may stretch, so no upper bound on the time is asserted here.
    assert!(took >= Duration::from_millis(300), "{took:?}");
    let failure = seen.lock().unwrap().failure.clone();
    match failure {
        Some(ActionError::ServerUnreachable { action, waited }) => {
            assert_eq!(action, "spin");
            assert!(waited >= Duration::from_millis(300));
        }
        other => panic!("expected ServerUnreachable, got {other:?}"),
    }
}

pub(crate) fn halting_a_running_goal_sends_the_server_a_cancel_request() {
    let domain = free_domain();
    let server = fake_server(domain.id, Script::RunForever, Duration::from_secs(15));
    let ros = node("tree", domain.id);
    let seen = Arc::new(Mutex::new(Seen::default()));
    let mut tree = spin_tree(&ros, &seen, &[("wait_for_server_timeout", "5000")]);

    // Running until the server has the goal.
    let until = Instant::now() + common::HANG;
    while server.log.goals.load(Ordering::SeqCst) == 0 && Instant::now() < until {
        let status = tree.tick_once(&mut ()).unwrap();
        assert_eq!(
            status,
            Status::Running,
            "{:?}",
            seen.lock().unwrap().failure
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(server.log.goals.load(Ordering::SeqCst), 1);
    // Accepted and still Running a little later.
    for _ in 0..20 {
        let status = tree.tick_once(&mut ()).unwrap();
        assert_eq!(
            status,
            Status::Running,
            "{:?}",
            seen.lock().unwrap().failure
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    tree.halt(&mut ());

    let until = Instant::now() + common::HANG;
    while server.log.cancels.load(Ordering::SeqCst) == 0 && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(server.log.cancels.load(Ordering::SeqCst), 1);
}

pub(crate) fn registered_for_xml_the_node_has_behaviortree_ros2_ports_and_reports_why_it_failed() {
    let domain = free_domain();
    let ros = node("tree", domain.id);
    let mut registry = neurotree_toolkit::Registry::<()>::new();
    let seen = Arc::new(Mutex::new(Seen::default()));
    let shared = Arc::clone(&seen);
    RosActionNode::register(&mut registry, "Spin", &ros, "spin", move || {
        SpinBy(Arc::clone(&shared))
    })
    .unwrap();
    let ports = RosActionNode::<(), SpinBy>::ports("spin");
    let names: Vec<&str> = ports.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "yaw",
            "action_name",
            "server_timeout",
            "wait_for_server_timeout",
            "error_msg"
        ]
    );
    let mut loader = neurotree_toolkit::XmlLoader::new(&registry);
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="T">
        <Spin action_name="/robot1/spin" yaw="0.5" wait_for_server_timeout="100"
              server_timeout="500" error_msg="{why}"/>
      </BehaviorTree></root>"#;
    loader.load_str(xml, "t.xml").unwrap();
    let mut tree = neurotree_toolkit::Tree::new(Arc::new(loader.build_main().unwrap()));

    let status = tick_until_done(&mut tree, &mut (), common::HANG);

    assert_eq!(status, Status::Failure);
    let why: String = tree.blackboard().get("why").unwrap();
    assert!(
        why.starts_with("action server `/robot1/spin` not found within"),
        "{why}"
    );
}

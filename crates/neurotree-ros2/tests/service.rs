//! The service node against a fake `ClearEntireCostmap` server written with ros2-client.

use crate::common;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use common::{free_domain, node, tick_until_done};
use neurotree_ros2::msg::nav2_msgs::{
    ClearEntireCostmap, ClearEntireCostmapRequest, ClearEntireCostmapResponse,
};
use neurotree_ros2::{RosNode, RosServiceNode, ServiceError, ServiceSpec};
use neurotree_toolkit::{Handle, Port, Registry, Status, Tree, XmlLoader};

/// Clears a costmap; records the failure reason.
struct Clear(Arc<Mutex<Option<ServiceError>>>);

impl ServiceSpec<()> for Clear {
    type Service = ClearEntireCostmap;

    fn request(&mut self, _h: &mut Handle<'_, ()>) -> Result<ClearEntireCostmapRequest, String> {
        Ok(ClearEntireCostmapRequest::default())
    }

    fn on_response(&mut self, _h: &mut Handle<'_, ()>, _r: &ClearEntireCostmapResponse) -> Status {
        Status::Success
    }

    fn on_failure(&mut self, _h: &mut Handle<'_, ()>, error: &ServiceError) -> Status {
        *self.0.lock().unwrap() = Some(error.clone());
        Status::Failure
    }
}

/// Answers `clear` requests on its own participant until dropped.
struct FakeServer {
    requests: Arc<AtomicUsize>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl FakeServer {
    fn start(domain: u16) -> Self {
        let requests = Arc::new(AtomicUsize::new(0));
        let stop = Arc::new(AtomicBool::new(false));
        let (counted, stopped) = (Arc::clone(&requests), Arc::clone(&stop));
        let thread = std::thread::spawn(move || {
            let ros = node("costmap", domain);
            let server = ros.service_server::<ClearEntireCostmap>("clear").unwrap();
            let until = Instant::now() + common::HANG;
            while Instant::now() < until && !stopped.load(Ordering::SeqCst) {
                if let Some((id, _)) = server.receive_request().unwrap() {
                    counted.fetch_add(1, Ordering::SeqCst);
                    server
                        .send_response(id, ClearEntireCostmapResponse::default())
                        .unwrap();
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        Self {
            requests,
            stop,
            thread: Some(thread),
        }
    }
}

impl Drop for FakeServer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn clear_tree(
    ros: &RosNode,
    failure: &Arc<Mutex<Option<ServiceError>>>,
    wait_ms: &str,
) -> Tree<()> {
    let (ros, failure) = (ros.clone(), Arc::clone(failure));
    let blueprint = neurotree_toolkit::Blueprint::<()>::builder()
        .stateful("clear", move || {
            RosServiceNode::new(ros.clone(), "clear", Clear(Arc::clone(&failure)))
        })
        .ports([Port::literal("wait_for_server_timeout", wait_ms)])
        .build_shared()
        .unwrap();
    Tree::new(blueprint)
}

pub(crate) fn a_request_is_answered_and_the_node_succeeds() {
    let domain = free_domain();
    let server = FakeServer::start(domain.id);
    let ros = node("tree", domain.id);
    let failure = Arc::new(Mutex::new(None));
    let mut tree = clear_tree(&ros, &failure, "5000");

    assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Running);
    let status = tick_until_done(&mut tree, &mut (), common::HANG);

    assert_eq!(status, Status::Success, "{:?}", failure.lock().unwrap());
    assert_eq!(server.requests.load(Ordering::SeqCst), 1);
}

pub(crate) fn without_a_server_the_node_fails_and_writes_the_reason_to_error_msg() {
    let domain = free_domain();
    let ros = node("tree", domain.id);
    let mut registry = Registry::<()>::new();
    let failure = Arc::new(Mutex::new(None));
    let seen = Arc::clone(&failure);
    RosServiceNode::register(
        &mut registry,
        "ClearEntireCostmap",
        &ros,
        "clear",
        move || Clear(Arc::clone(&seen)),
    )
    .unwrap();
    let mut loader = XmlLoader::new(&registry);
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="T">
        <ClearEntireCostmap service_name="/global_costmap/clear_entirely_global_costmap"
                            wait_for_server_timeout="200" error_msg="{why}"/>
      </BehaviorTree></root>"#;
    loader.load_str(xml, "t.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));

    let status = tick_until_done(&mut tree, &mut (), common::HANG);

    assert_eq!(status, Status::Failure);
    let why: String = tree.blackboard().get("why").unwrap();
    assert!(
        why.starts_with("service `/global_costmap/clear_entirely_global_costmap` not found within"),
        "{why}"
    );
    assert!(matches!(
        *failure.lock().unwrap(),
        Some(ServiceError::ServerUnreachable { .. })
    ));
}

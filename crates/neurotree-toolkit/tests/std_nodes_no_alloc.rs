//! The std nodes of XML-loaded trees allocate nothing per tick: the loops (taking an
//! element, writing `value`, and for a `Vec` of numbers the copy made at each run's start,
//! once the node's buffer has grown) and SetBlackboard writing a literal into a text entry;
//! and the builder's leaves that read their ports through the handle. A counting allocator
//! watches the ticks.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use neurotree::nodes::loops::SharedQueue;
use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};

use crate::counting_alloc;
use counting_alloc::allocations;

/// A tree repeating, forever, a loop over `{q}` into `{x}`.
fn tree(loop_node: &str) -> Tree<()> {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            &format!(
                r#"<root BTCPP_format="4"><BehaviorTree ID="T">
                     <Repeat num_cycles="-1">
                       <{loop_node} queue="{{q}}" value="{{x}}"><AlwaysSuccess/></{loop_node}>
                     </Repeat>
                   </BehaviorTree></root>"#
            ),
            "loop.xml",
        )
        .unwrap();
    Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new())
}

#[test]
fn a_loop_over_a_vector_entry_ticks_without_allocating() {
    let mut tree = tree("LoopDouble");
    tree.blackboard_mut()
        .set("q", vec![1.0_f64, 2.0, 3.0])
        .unwrap();
    // The first run grows the copy buffer and creates `x`.
    for _ in 0..4 {
        assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
    }
    let n = allocations(|| {
        // 25 runs of 3 elements, each starting with a copy of the entry.
        for _ in 0..100 {
            assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(
        tree.blackboard().get::<Vec<f64>>("q"),
        Ok(vec![1.0, 2.0, 3.0])
    );
}

#[test]
fn a_loop_over_a_shared_queue_ticks_without_allocating() {
    let mut tree = tree("LoopInt");
    let queue: SharedQueue<i32> = Arc::new(Mutex::new(VecDeque::with_capacity(8)));
    queue.lock().unwrap().extend([1, 2]);
    tree.blackboard_mut().set("q", Arc::clone(&queue)).unwrap();
    assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
    let n = allocations(|| {
        for i in 0..50 {
            queue.lock().unwrap().push_back(i);
            assert_eq!(tree.tick_exactly_once(&mut ()), Ok(Status::Running));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(tree.blackboard().get::<i32>("x"), Ok(48));
}

#[test]
fn set_blackboard_writes_a_literal_without_allocating() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree ID="T">
                 <Sequence>
                   <SetBlackboard value="docking" output_key="mode"/>
                   <SetBlackboard value="idle" output_key="mode"/>
                 </Sequence>
               </BehaviorTree></root>"#,
            "set.xml",
        )
        .unwrap();
    let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    // The first tick creates the entry.
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    let before = tree.blackboard().info("mode").unwrap().sequence;
    let n = allocations(|| {
        for _ in 0..100 {
            assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(tree.blackboard().get::<String>("mode"), Ok("idle".into()));
    // Every write counts: two per tick.
    let after = tree.blackboard().info("mode").unwrap().sequence;
    assert_eq!(after - before, 200);
}

#[test]
fn builder_leaves_reading_their_ports_tick_without_allocating() {
    use neurotree::{Blueprint, Port};

    let blueprint = Blueprint::<i64>::builder()
        .repeat("forever", -1, |r| {
            r.sequence("step", |s| {
                s.condition_with("enabled", [Port::entry("on", "enabled")], |h| {
                    h.input::<bool>("on").unwrap_or(false)
                })
                .action_with(
                    "advance",
                    [Port::literal("by", "3"), Port::entry("limit", "limit")],
                    |h| {
                        let (Ok(by), Ok(limit)) = (h.input::<i64>("by"), h.input::<i64>("limit"))
                        else {
                            return Status::Failure;
                        };
                        let at = h.ctx_mut();
                        *at = (*at + by) % limit;
                        Status::Success
                    },
                )
            })
        })
        .build_shared()
        .unwrap();
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    tree.blackboard_mut().set("enabled", true).unwrap();
    tree.blackboard_mut().set("limit", 1000_i64).unwrap();
    let mut at = 0;
    assert_eq!(tree.tick_exactly_once(&mut at), Ok(Status::Running));
    let n = allocations(|| {
        for _ in 0..100 {
            assert_eq!(tree.tick_exactly_once(&mut at), Ok(Status::Running));
        }
    });
    assert_eq!(n, 0);
    assert_eq!(at, 303);
}

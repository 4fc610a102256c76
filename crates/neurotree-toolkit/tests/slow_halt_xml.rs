//! A registered action whose halt takes ticks, in a tree loaded from BehaviorTree.CPP XML:
//! the README's example, and the tree's own halt. The engine's rules are tested on built
//! trees in `neurotree-core/tests/slow_halt.rs`; this shows the XML path reaches them.

use std::sync::Arc;

use neurotree_toolkit::{
    Blueprint, HaltProgress, Handle, ManualClock, Registry, StatefulAction, Status, Tree, XmlLoader,
};

/// The README's arm: moves until halted, then decelerates for three ticks.
#[derive(Default)]
struct Arm {
    braking: u32,
}

impl StatefulAction<Vec<&'static str>> for Arm {
    fn on_start(&mut self, h: &mut Handle<'_, Vec<&'static str>>) -> Status {
        h.ctx_mut().push("move");
        Status::Running
    }
    fn on_running(&mut self, h: &mut Handle<'_, Vec<&'static str>>) -> Status {
        h.ctx_mut().push("move");
        Status::Running
    }
    fn on_halt_requested(&mut self, h: &mut Handle<'_, Vec<&'static str>>) -> HaltProgress {
        h.ctx_mut().push("brake");
        self.braking = 2;
        HaltProgress::Halting
    }
    fn on_halting(&mut self, h: &mut Handle<'_, Vec<&'static str>>) -> HaltProgress {
        self.braking -= 1;
        if self.braking > 0 {
            h.ctx_mut().push("brake");
            HaltProgress::Halting
        } else {
            h.ctx_mut().push("stopped");
            HaltProgress::Done
        }
    }
}

const XML: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Fallback>
      <ReactiveSequence>
        <CheckClear/>
        <Arm/>
      </ReactiveSequence>
      <Retreat/>
    </Fallback>
  </BehaviorTree>
</root>"#;

fn blueprint() -> Arc<Blueprint<Vec<&'static str>>> {
    let mut registry = Registry::<Vec<&'static str>>::new();
    registry
        .register_stateful("Arm", vec![], Arm::default)
        .unwrap();
    // Clear for the first two checks.
    registry
        .register_condition("CheckClear", vec![], |h| h.ctx().len() < 2)
        .unwrap();
    registry
        .register_action("Retreat", vec![], |h| {
            h.ctx_mut().push("retreat");
            Status::Success
        })
        .unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(XML, "arm.xml").unwrap();
    Arc::new(loader.build_main().unwrap())
}

#[test]
fn the_alternative_starts_only_once_the_arm_has_stopped() {
    let mut tree = Tree::with_clock(blueprint(), ManualClock::new());
    let mut log = Vec::new();
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    // Blocked now: the arm brakes over three ticks before the retreat starts.
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
    assert_eq!(
        log,
        ["move", "move", "brake", "brake", "stopped", "retreat"]
    );
}

#[test]
fn a_tree_from_xml_halted_mid_run_finishes_the_halt_with_tick_halt() {
    let mut tree = Tree::with_clock(blueprint(), ManualClock::new());
    let mut log = Vec::new();
    assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    assert!(!tree.halt(&mut log));
    assert!(!tree.tick_halt(&mut log));
    assert!(tree.tick_halt(&mut log));
    assert_eq!(log, ["move", "brake", "brake", "stopped"]);
}

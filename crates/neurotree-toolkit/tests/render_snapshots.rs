//! Every picture format, pinned by snapshots: a builder-made tree with a status of each kind,
//! and a tree loaded from XML drawn without statuses.
//!
//! A change to a picture shows here as a diff; accept it with `cargo insta review` (or
//! `INSTA_UPDATE=always cargo test`) once it looks right.

use std::sync::Arc;

use neurotree::render::Format;
use neurotree::{
    Blueprint, Handle, NodeStatus, PortSpec, Registry, StatefulAction, Status, SubTreeScope,
    XmlLoader,
};

struct Drive;

impl StatefulAction<()> for Drive {
    fn on_start(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, ()>) -> Status {
        Status::Running
    }
}

/// A robot's tree with every family of node and names that need escaping in each format.
fn robot() -> Arc<Blueprint<()>> {
    Blueprint::<()>::builder()
        .reactive_sequence("robot", |s| {
            s.condition("battery_ok", |_: &()| true)
                .fallback("reach goal", |f| {
                    f.inverter("", |i| i.condition(r#"path "blocked""#, |_: &()| false))
                        .sequence("replan & go", |s| {
                            s.retry("", 3, |r| {
                                r.action("plan <A*> #1", |_: &mut ()| Status::Success)
                            })
                            .parallel("move", -1, 1, |p| {
                                p.stateful("drive", || Drive)
                                    .action("watch `lidar`", |_: &mut ()| Status::Failure)
                            })
                        })
                })
                .subtree("dock", SubTreeScope::default(), |t| {
                    t.sequence("docking", |s| {
                        s.always_success("align")
                            .sleep("settle", std::time::Duration::from_millis(500))
                    })
                })
        })
        .build_shared()
        .unwrap()
}

/// One status per node of [`robot`], in pre-order, with each status at least once.
fn robot_statuses() -> Vec<NodeStatus> {
    use NodeStatus::*;
    vec![
        Running, // robot
        Success, // battery_ok
        Running, // reach goal
        Failure, // Inverter
        Success, // path "blocked"
        Running, // replan & go
        Success, // RetryUntilSuccessful
        Success, // plan <A*> #1
        Running, // move
        Running, // drive
        Failure, // watch `lidar`
        Skipped, // dock
        Idle,    // docking
        Idle,    // align
        Idle,    // settle
    ]
}

const XML: &str = r#"
<root BTCPP_format="4" main_tree_to_execute="Patrol">
  <BehaviorTree ID="Patrol">
    <ReactiveFallback name="keep going">
      <IsCharging/>
      <Sequence name="patrol">
        <Timeout msec="5000">
          <MoveTo name="to kitchen" goal="kitchen"/>
        </Timeout>
        <SubTree ID="LookAround" _autoremap="true"/>
      </Sequence>
    </ReactiveFallback>
  </BehaviorTree>
  <BehaviorTree ID="LookAround">
    <Parallel success_count="1" failure_count="2">
      <Scan/>
      <Delay delay_msec="200">
        <Beep/>
      </Delay>
    </Parallel>
  </BehaviorTree>
</root>"#;

/// The XML tree, with its leaves registered as a robot's would be (`Scan` and `Beep` are
/// left to the loader's mocks).
fn patrol() -> Blueprint<()> {
    let mut registry = Registry::<()>::new();
    registry
        .register_condition("IsCharging", vec![], |_| false)
        .unwrap();
    registry
        .register_stateful("MoveTo", vec![PortSpec::input::<String>("goal")], || Drive)
        .unwrap();
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    loader.load_str(XML, "patrol.xml").unwrap();
    loader.build_main().unwrap()
}

fn draw_robot(format: Format) -> String {
    assert_eq!(robot().len(), robot_statuses().len());
    format.render(&robot(), Some(&robot_statuses()))
}

fn draw_patrol(format: Format) -> String {
    format.render(&patrol(), None)
}

#[test]
fn builder_tree_with_statuses_ascii() {
    insta::assert_snapshot!(draw_robot(Format::Ascii));
}

#[test]
fn builder_tree_with_statuses_unicode() {
    insta::assert_snapshot!(draw_robot(Format::Unicode));
}

#[test]
fn builder_tree_with_statuses_dot() {
    insta::assert_snapshot!(draw_robot(Format::Dot));
}

#[test]
fn builder_tree_with_statuses_mermaid() {
    insta::assert_snapshot!(draw_robot(Format::Mermaid));
}

#[test]
fn builder_tree_with_statuses_svg() {
    insta::assert_snapshot!(draw_robot(Format::Svg));
}

#[test]
fn xml_tree_ascii() {
    insta::assert_snapshot!(draw_patrol(Format::Ascii));
}

#[test]
fn xml_tree_unicode() {
    insta::assert_snapshot!(draw_patrol(Format::Unicode));
}

#[test]
fn xml_tree_dot() {
    insta::assert_snapshot!(draw_patrol(Format::Dot));
}

#[test]
fn xml_tree_mermaid() {
    insta::assert_snapshot!(draw_patrol(Format::Mermaid));
}

#[test]
fn xml_tree_svg() {
    insta::assert_snapshot!(draw_patrol(Format::Svg));
}

//! # NeuroTree for robots and Nav2
//!
//! [`robotics`]: the building blocks of a robot's tree (poses and paths, a sensor node, a
//! navigation node over a [`MotionPlanner`](robotics::MotionPlanner)); and ROS 2 Nav2's
//! control and decorator nodes, so that Nav2's navigator trees load and run.
//!
//! # Nav2's nodes
//!
//! Nav2 (`nav2_behavior_tree`) adds its own nodes to BehaviorTree.CPP. Its navigators are
//! built from the few below: a [`PipelineSequence`] that keeps planning and following a path
//! at once, a [`RateController`] that replans at a fixed rate, [`RecoveryNode`]s that retry
//! an action after a recovery, a [`RoundRobin`] that takes turns among recoveries, and three
//! nodes that notice a new goal. [`register_controls`] adds all seven to a [`Registry`] under
//! their Nav2 names, with Nav2's ports and defaults; each type also has a `spec()` for the
//! [`Builder`](neurotree_toolkit::Builder).
//!
//! | node | in short |
//! |---|---|
//! | [PipelineSequence] | a sequence whose earlier children keep running |
//! | [RecoveryNode] | run an action; when it fails, a recovery, then the action again |
//! | [RoundRobin] | each use of the node runs the next child |
//! | [RateController] | start the child again at most `hz` times per second |
//! | [GoalUpdated] | a condition: the goal changed while its parent ran |
//! | [GlobalUpdatedGoal] | a condition: the goal changed since it last looked |
//! | [GoalUpdatedController] | start the child again only for a new goal |
//!
//! # Goals
//!
//! The goal nodes read `goal` as a [`Pose2D`] and `goals` as a `Vec<Pose2D>`, as Nav2 reads
//! them: the port if it is given and readable, else the blackboard entry of the port's own
//! name. A goal that can be read nowhere counts as Nav2's empty value (the origin, no goals)
//! when it is compared, and leaves the remembered value as it was when the node remembers.
//! Values are compared, not writes: writing the same pose again is no update (a `Pose2D` has
//! no time stamp, unlike Nav2's `PoseStamped`). An entry holding a value of another type is
//! an error of the tick. A text entry or literal is converted; `goals` as text is a
//! `;`-separated list of poses that are themselves `;`-separated, so only an empty list
//! reads from text.
//!
//! Like Nav2's, these nodes see "the tick from Idle" through their stored status
//! ([`NodeCtx::previous_status`](crate::NodeCtx::previous_status)). So a GoalUpdated placed
//! first in a ReactiveFallback whose next child keeps running is reset to Idle on every tick
//! (the reactive node resets its other children), and never reports an update: that is
//! what Nav2 does on BehaviorTree.CPP 4 too. GlobalUpdatedGoal, which remembers across
//! resets, is the node for such places.
//!
//! ```
//! use neurotree::robotics::Pose2D;
//! use neurotree::{nav2, ManualClock, Registry, Status, Tree, XmlLoader};
//!
//! let mut registry = Registry::<u32>::new();
//! nav2::register_controls(&mut registry).unwrap();
//! registry
//!     .register_action("Plan", vec![], |h| { *h.ctx_mut() += 1; Status::Success })
//!     .unwrap();
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_str(r#"
//!     <root BTCPP_format="4">
//!       <BehaviorTree ID="Navigate">
//!         <PipelineSequence>
//!           <GoalUpdatedController><Plan/></GoalUpdatedController>
//!           <KeepRunningUntilFailure><AlwaysSuccess/></KeepRunningUntilFailure>
//!         </PipelineSequence>
//!       </BehaviorTree>
//!     </root>"#, "navigate.xml").unwrap();
//! let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
//! tree.blackboard_mut().set("goal", Pose2D::new(1.0, 2.0, 0.0)).unwrap();
//! let mut plans = 0;
//! assert_eq!(tree.tick_once(&mut plans), Ok(Status::Running));
//! assert_eq!(tree.tick_once(&mut plans), Ok(Status::Running));
//! assert_eq!(plans, 1);
//! // A new goal: planned again, while the second child keeps running.
//! tree.blackboard_mut().set("goal", Pose2D::new(4.0, 2.0, 0.0)).unwrap();
//! assert_eq!(tree.tick_once(&mut plans), Ok(Status::Running));
//! assert_eq!(plans, 2);
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod distance_controller;
mod event_log;
mod global_updated_goal;
mod goal_updated;
mod goal_updated_controller;
mod goal_updater;
mod goals;
mod nonblocking_sequence;
mod path_longer_on_approach;
mod pause_resume_controller;
mod persistent_sequence;
mod pipeline_sequence;
mod rate_controller;
mod recoveries;
mod recovery_node;
mod release;
pub mod robotics;
mod round_robin;
mod single_trigger;
mod speed_controller;
#[cfg(test)]
mod testing;

use std::any::Any;

pub use distance_controller::{DistanceController, ROBOT_POSE};
pub use event_log::EventLog;
pub use global_updated_goal::GlobalUpdatedGoal;
pub use goal_updated::GoalUpdated;
pub use goal_updated_controller::GoalUpdatedController;
pub use goal_updater::{GoalUpdater, GOALS_UPDATE, GOAL_UPDATE};
pub use nonblocking_sequence::NonblockingSequence;
pub use path_longer_on_approach::PathLongerOnApproach;
pub use pause_resume_controller::{PauseResumeController, PauseState};
pub use persistent_sequence::PersistentSequence;
pub use pipeline_sequence::PipelineSequence;
pub use rate_controller::RateController;
pub use recoveries::RecoveryCounter;
pub use recovery_node::RecoveryNode;
pub use release::{
    register_release, Nav2Release, UnknownRelease, NAV2_JAZZY_TREE_NODES_MODEL,
    NAV2_KILTED_TREE_NODES_MODEL, RENAMED,
};
pub use round_robin::RoundRobin;
pub use single_trigger::SingleTrigger;
pub use speed_controller::{SpeedController, ROBOT_SPEED};

/// Nav2's model of every node type it registers (`nav2_tree_nodes.xml` of Nav2 main): 81
/// types, whose conditions and actions NeuroTree knows only by their ports. Add it to a
/// registry with [`Registry::add_model_str`] after [`register_controls`], so that Nav2's trees
/// load with the controls and decorators implemented and the leaves declared.
pub const NAV2_TREE_NODES_MODEL: &str = include_str!("nav2_tree_nodes.xml");

use neurotree_core::{Arity, Category, CustomSpec, FromPortStr, NodeCtx, PortValue};

use crate::robotics::{Path, Pose2D};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// The names [`register_controls`] registers: Nav2's six controls, seven decorators and
/// two goal conditions.
pub const CONTROLS: [&str; 15] = [
    "PipelineSequence",
    "RecoveryNode",
    "RoundRobin",
    "NonblockingSequence",
    "PauseResumeController",
    "PersistentSequence",
    "RateController",
    "DistanceController",
    "SingleTrigger",
    "GoalUpdater",
    "SpeedController",
    "PathLongerOnApproach",
    "GoalUpdatedController",
    "GoalUpdated",
    "GlobalUpdatedGoal",
];

/// Registers the value types Nav2's nodes keep on the blackboard (poses, goal lists, paths,
/// routes, obstacles, sensor readings), so that the studio and `run` show them as JSON and a
/// tree's state saves them ([`Registry::register_value`]). [`register_controls`] calls it.
pub fn register_values<C: 'static>(registry: &mut Registry<C>) {
    use robotics::{Obstacle, Path, Pose2D, Route, SensorData, TrackingFeedback};
    registry.register_value::<Pose2D>();
    registry.register_value::<Vec<Pose2D>>();
    registry.register_value::<Path>();
    registry.register_value::<Route>();
    registry.register_value::<Obstacle>();
    registry.register_value::<Vec<Obstacle>>();
    registry.register_value::<SensorData>();
    registry.register_value::<TrackingFeedback>();
    registry.register_value::<Vec<i64>>();
    registry.register_value::<Vec<String>>();
}

/// Registers every control and decorator of Nav2 (PipelineSequence, RecoveryNode,
/// RoundRobin, NonblockingSequence, PauseResumeController, PersistentSequence,
/// RateController, DistanceController, SingleTrigger, GoalUpdater, SpeedController,
/// PathLongerOnApproach, GoalUpdatedController) and the conditions GoalUpdated and
/// GlobalUpdatedGoal under their Nav2 names, with Nav2's ports and defaults. Fails if one of the names is taken (nothing after it is registered then).
pub fn register_controls<C: 'static>(registry: &mut Registry<C>) -> Result<(), RegistryError> {
    register_values(registry);
    registry.register_custom("PipelineSequence", Arity::AtLeast(1), vec![], || {
        Box::new(PipelineSequence::default())
    })?;
    registry.register_custom(
        "RecoveryNode",
        Arity::Range { min: 2, max: 2 },
        vec![PortSpec::input::<i32>("number_of_retries")
            .default_value("1")
            .describe("How many times the recovery may run before the node fails.")],
        || Box::new(RecoveryNode::default()),
    )?;
    registry.register_custom(
        "RoundRobin",
        Arity::AtLeast(1),
        vec![PortSpec::input::<bool>("wrap_around")
            .default_value("false")
            .describe("Start again at the first child after the last one, instead of failing.")],
        || Box::new(RoundRobin::default()),
    )?;
    registry.register_custom(
        "RateController",
        Arity::One,
        vec![PortSpec::input::<f64>("hz")
            .default_value("10.0")
            .describe("How many times per second the child may start again.")],
        || Box::new(RateController::default()),
    )?;
    registry.register_custom("GoalUpdatedController", Arity::One, goal_ports(), || {
        Box::new(GoalUpdatedController::default())
    })?;
    registry.register_custom("NonblockingSequence", Arity::AtLeast(1), vec![], || {
        Box::new(NonblockingSequence)
    })?;
    registry.register_custom(
        "PauseResumeController",
        Arity::Range { min: 1, max: 4 },
        vec![
            PortSpec::input::<String>("pause_service_name")
                .describe("The `bool` entry that, set to true, asks for a pause."),
            PortSpec::input::<String>("resume_service_name")
                .describe("The `bool` entry that, set to true, asks for a resume."),
        ],
        || Box::new(PauseResumeController::default()),
    )?;
    registry.register_custom(
        "PersistentSequence",
        Arity::AtLeast(1),
        vec![PortSpec::inout::<i32>("current_child_idx")
            .describe("The index of the current child, kept in the blackboard.")],
        || Box::new(PersistentSequence),
    )?;
    registry.register_custom(
        "DistanceController",
        Arity::One,
        vec![
            PortSpec::input::<f64>("distance")
                .default_value("1.0")
                .describe("Metres travelled between two ticks of the child."),
            PortSpec::input::<String>("global_frame")
                .describe("Accepted for Nav2's trees; there is one frame."),
            PortSpec::input::<String>("robot_base_frame")
                .describe("Accepted for Nav2's trees; there is one frame."),
        ],
        || Box::new(DistanceController::default()),
    )?;
    registry.register_custom("SingleTrigger", Arity::One, vec![], || {
        Box::new(SingleTrigger::default())
    })?;
    registry.register_custom(
        "GoalUpdater",
        Arity::One,
        vec![
            PortSpec::input::<Pose2D>("input_goal").describe("The original goal."),
            PortSpec::input::<Vec<Pose2D>>("input_goals").describe("The original goals."),
            PortSpec::output::<Pose2D>("output_goal")
                .describe("The goal: `goal_update` if newer, else the input."),
            PortSpec::output::<Vec<Pose2D>>("output_goals")
                .describe("The goals: `goals_update` if newer, else the input."),
        ],
        || Box::new(GoalUpdater),
    )?;
    let mut speed_ports = vec![
        PortSpec::input::<f64>("min_rate")
            .default_value("0.1")
            .describe("The rate (Hz) at `min_speed` and below."),
        PortSpec::input::<f64>("max_rate")
            .default_value("1.0")
            .describe("The rate (Hz) at `max_speed` and above."),
        PortSpec::input::<f64>("min_speed")
            .default_value("0.0")
            .describe("The speed (m/s) of the lowest rate."),
        PortSpec::input::<f64>("max_speed")
            .default_value("0.5")
            .describe("The speed (m/s) of the highest rate."),
    ];
    speed_ports.extend(goal_ports());
    registry.register_custom("SpeedController", Arity::One, speed_ports, || {
        Box::new(SpeedController::default())
    })?;
    registry.register_custom(
        "PathLongerOnApproach",
        Arity::One,
        vec![
            PortSpec::input::<Path>("path").describe("The planned path."),
            PortSpec::input::<f64>("prox_len")
                .default_value("3.0")
                .describe("Metres of old path under which the robot is near the goal."),
            PortSpec::input::<f64>("length_factor")
                .default_value("2.0")
                .describe("How many times longer the new path must be."),
        ],
        || Box::new(PathLongerOnApproach::default()),
    )?;
    register_condition(registry, "GoalUpdated", GoalUpdated::spec)?;
    register_condition(registry, "GlobalUpdatedGoal", GlobalUpdatedGoal::spec)?;
    // What each control can return and how it ticks its children, declared in its module.
    for (name, semantics) in [
        ("PipelineSequence", pipeline_sequence::SEMANTICS),
        ("RecoveryNode", recovery_node::SEMANTICS),
        ("RoundRobin", round_robin::SEMANTICS),
        ("RateController", rate_controller::SEMANTICS),
        ("DistanceController", distance_controller::SEMANTICS),
        ("SpeedController", speed_controller::SEMANTICS),
        ("GoalUpdatedController", goal_updated_controller::SEMANTICS),
        ("SingleTrigger", single_trigger::SEMANTICS),
        ("PersistentSequence", persistent_sequence::SEMANTICS),
        ("PauseResumeController", pause_resume_controller::SEMANTICS),
        ("NonblockingSequence", nonblocking_sequence::SEMANTICS),
        ("GoalUpdater", goal_updater::SEMANTICS),
        ("PathLongerOnApproach", path_longer_on_approach::SEMANTICS),
    ] {
        registry.declare_semantics(name, semantics)?;
    }
    registry.describe(
        "PipelineSequence",
        "Ticks its children from the first every tick; earlier children keep running.",
    );
    registry.describe(
        "RecoveryNode",
        "Runs the first child; when it fails, runs the second, then the first again.",
    );
    registry.describe(
        "RoundRobin",
        "Ticks one child per use, the next one each time; fails when all have failed.",
    );
    registry.describe(
        "RateController",
        "Ticks its child at most `hz` times per second, and on while it runs.",
    );
    registry.describe(
        "GoalUpdated",
        "Succeeds when the goal changed since its last look in this run.",
    );
    registry.describe(
        "GlobalUpdatedGoal",
        "Succeeds on its first tick, then when the goal changed since its last look.",
    );
    registry.describe(
        "GoalUpdatedController",
        "Ticks its child on a new goal, and on while it runs.",
    );
    for (name, text) in [
        (
            "NonblockingSequence",
            "Ticks every child every tick; fails at the first failure.",
        ),
        (
            "PauseResumeController",
            "Runs child 0; on request pauses (2, then 1) and resumes (3).",
        ),
        (
            "PersistentSequence",
            "A sequence whose current child is the `current_child_idx` entry.",
        ),
        (
            "DistanceController",
            "Ticks its child again each `distance` metres the robot moves.",
        ),
        (
            "SingleTrigger",
            "Ticks its child to completion once per run, then fails.",
        ),
        (
            "GoalUpdater",
            "Writes the goal, or a newer `goal_update`, then ticks its child.",
        ),
        (
            "SpeedController",
            "Ticks its child at a rate that grows with the robot's speed.",
        ),
        (
            "PathLongerOnApproach",
            "Ticks its child when a new path near the goal is much longer.",
        ),
    ] {
        registry.describe(name, text);
    }
    Ok(())
}

/// A goal condition: a custom leaf (it keeps the goals it saw), listed as a Condition.
fn register_condition<C: 'static>(
    registry: &mut Registry<C>,
    name: &str,
    spec: fn() -> CustomSpec<C>,
) -> Result<(), RegistryError> {
    let make = move || (spec().factory)();
    registry.register_custom_as(name, Category::Condition, Arity::Leaf, goal_ports(), make)
}

/// The ports of the three goal nodes.
fn goal_ports() -> Vec<PortSpec> {
    vec![
        PortSpec::input::<Pose2D>("goal")
            .describe("The goal to watch; the `goal` entry when not given."),
        PortSpec::input::<Vec<Pose2D>>("goals")
            .describe("The goals to watch; the `goals` entry when not given."),
    ]
}

/// Reads port `port`, or `default` when the node has no such port (the XML loader fills in
/// declared defaults, but a tree built in Rust may leave the port out). A port that cannot
/// be read is reported through [`NodeCtx::fail`] and gives `None`; the node then fails.
fn port_or<C, T: FromPortStr + Any + Clone>(
    node: &mut NodeCtx<'_, '_, C>,
    port: &str,
    default: T,
) -> Option<T> {
    // Checked first so that a missing port costs no error value on every tick.
    if !node.ports().iter().any(|p| p.name == port) {
        return Some(default);
    }
    match node.input(port) {
        Ok(value) => Some(value),
        Err(e) => {
            node.fail(e.to_string());
            None
        }
    }
}

/// Reads port `port` as Nav2's plain `getInput` does: `None` when the port is not given or
/// its entry was never written (Nav2 then keeps the variable as it was); a value that does
/// not convert is an error of the tick.
fn port_value<C, T: FromPortStr + Any + Clone>(
    node: &mut NodeCtx<'_, '_, C>,
    port: &str,
) -> Result<Option<T>, String> {
    let Some(binding) = node.ports().iter().find(|p| p.name == port) else {
        return Ok(None);
    };
    if let PortValue::Entry(key) = &binding.value {
        let scope = node.scope();
        if node.blackboard().get_any_in(scope, key).is_none() {
            return Ok(None);
        }
    }
    node.input(port).map(Some).map_err(|e| e.to_string())
}

/// Writes output port `port` as Nav2's `setOutput` does: into the entry it is bound to; a
/// port that is not given, or given a literal, is left alone (Nav2 ignores that error). An
/// entry that holds a value of another type is an error of the tick.
fn write_output<C, T: Any + Send + Sync>(
    node: &mut NodeCtx<'_, '_, C>,
    port: &str,
    value: T,
) -> Result<(), String> {
    let Some(PortValue::Entry(key)) = node
        .ports()
        .iter()
        .find(|p| p.name == port)
        .map(|p| &p.value)
    else {
        return Ok(());
    };
    let (scope, now) = (node.scope(), node.now());
    node.blackboard()
        .set_in(scope, key, value, now)
        .map_err(|e| format!("`{port}`: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_toolkit::Status;

    #[test]
    fn registers_all_seven_with_their_families_and_ports() {
        let mut r = Registry::<()>::new();
        register_controls(&mut r).unwrap();
        let family = |name: &str| r.get(name).unwrap().category;
        assert_eq!(family("PipelineSequence"), Category::Control);
        assert_eq!(family("RecoveryNode"), Category::Control);
        assert_eq!(family("RoundRobin"), Category::Control);
        assert_eq!(family("RateController"), Category::Decorator);
        assert_eq!(family("GoalUpdatedController"), Category::Decorator);
        assert_eq!(family("GoalUpdated"), Category::Condition);
        assert_eq!(family("GlobalUpdatedGoal"), Category::Condition);
        let default =
            |name: &str, port: &str| r.get(name).unwrap().port(port).unwrap().default.clone();
        assert_eq!(
            default("RecoveryNode", "number_of_retries").as_deref(),
            Some("1")
        );
        assert_eq!(
            default("RoundRobin", "wrap_around").as_deref(),
            Some("false")
        );
        assert_eq!(default("RateController", "hz").as_deref(), Some("10.0"));
        for name in ["GoalUpdated", "GlobalUpdatedGoal", "GoalUpdatedController"] {
            let t = r.get(name).unwrap();
            let ports: Vec<&str> = t.ports.iter().map(|p| p.name.as_str()).collect();
            assert_eq!(ports, ["goal", "goals"], "{name}");
            assert!(t.ports.iter().all(|p| p.default.is_none()), "{name}");
        }
        assert!(r.get("PipelineSequence").unwrap().ports.is_empty());
        // Literals are checked against the port types.
        assert!(!r.get("RateController").unwrap().ports[0].accepts("fast"));
        assert!(r.get("GoalUpdated").unwrap().ports[0].accepts("1;2;0.5"));
    }

    #[test]
    fn registering_twice_is_refused() {
        let mut r = Registry::<()>::new();
        r.register_action("RoundRobin", vec![], |_| Status::Success)
            .unwrap();
        assert_eq!(
            register_controls(&mut r),
            Err(RegistryError::Duplicate("RoundRobin".into()))
        );
        let mut again = Registry::<()>::new();
        register_controls(&mut again).unwrap();
        assert_eq!(
            register_controls(&mut again),
            Err(RegistryError::Duplicate("PipelineSequence".into()))
        );
    }

    #[test]
    fn the_model_lists_them_for_groot() {
        let mut r = Registry::<()>::new();
        register_controls(&mut r).unwrap();
        let model = r.tree_nodes_model();
        assert!(model.contains(r#"<Control ID="RecoveryNode">"#), "{model}");
        assert!(model.contains(r#"<Condition ID="GoalUpdated">"#), "{model}");
        assert!(
            model.contains(r#"<Decorator ID="RateController">"#),
            "{model}"
        );
        assert!(
            model.contains(r#"<input_port name="hz" type="f64" default="10.0">"#),
            "{model}"
        );
    }
}

//! The six selectors: which planner, controller, goal checker, progress checker, path
//! handler and smoother the navigator uses.
//!
//! ProgressCheckerSelector, GoalCheckerSelector, PathHandlerSelector, ControllerSelector,
//! PlannerSelector and SmootherSelector are sync actions: write `default_*` to `selected_*`, Success; Failure
//! without a default.
//!
//! In Nav2 a selector listens on `topic_name` for a message that switches plugins at run
//! time and writes the last one chosen, the default until a message comes. The simulation
//! has no topics, so the default is always the choice.

use neurotree_core::{Handle, Status};

use super::{ports, Nav2Context};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// The selectors: the node name and the word in their port names.
const SELECTORS: [(&str, &str, &str); 6] = [
    (
        "ProgressCheckerSelector",
        "progress_checker",
        "ProgressChecker",
    ),
    ("GoalCheckerSelector", "goal_checker", "GoalChecker"),
    ("PathHandlerSelector", "path_handler", "PathHandler"),
    ("ControllerSelector", "controller", "Controller"),
    ("PlannerSelector", "planner", "Planner"),
    ("SmootherSelector", "smoother", "Smoother"),
];

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    for (name, word, what) in SELECTORS {
        let default = format!("default_{word}");
        let selected = format!("selected_{word}");
        let ports = vec![
            PortSpec::input::<String>("topic_name")
                .default_value(&format!("{word}_selector"))
                .describe("Topic that would switch the selection (unused)."),
            PortSpec::input::<String>(&default).describe(&format!("The {what} to select.")),
            PortSpec::output::<String>(&selected).describe(&format!("The selected {what}.")),
        ];
        r.register_action(name, ports, move |h| select(h, &default, &selected))?;
        r.describe(name, &format!("Selects the default {what}."));
    }
    Ok(())
}

fn select<C>(h: &mut Handle<'_, C>, default: &str, selected: &str) -> Status {
    match ports::optional::<String, C>(h, default) {
        Ok(Some(choice)) if !choice.is_empty() => {
            ports::emit(h, selected, choice);
            Status::Success
        }
        _ => Status::Failure,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;

    #[test]
    fn each_selector_writes_its_default() {
        let mut b = Bench::new(
            "R.",
            r#"<Sequence>
                 <ProgressCheckerSelector selected_progress_checker="{p}" default_progress_checker="progress_checker"/>
                 <GoalCheckerSelector selected_goal_checker="{g}" default_goal_checker="general_goal_checker"/>
                 <PathHandlerSelector selected_path_handler="{h}" default_path_handler="PathHandler"/>
                 <ControllerSelector selected_controller="{c}" default_controller="FollowPath"/>
                 <PlannerSelector selected_planner="{pl}" default_planner="GridBased" topic_name="x"/>
                 <SmootherSelector selected_smoother="{s}" default_smoother="simple_smoother"/>
               </Sequence>"#,
        );
        assert_eq!(b.tick(), Status::Success);
        let got: Vec<String> = ["p", "g", "h", "c", "pl", "s"]
            .iter()
            .map(|k| b.get(k))
            .collect();
        assert_eq!(
            got,
            [
                "progress_checker",
                "general_goal_checker",
                "PathHandler",
                "FollowPath",
                "GridBased",
                "simple_smoother"
            ]
        );
    }

    #[test]
    fn without_a_default_a_selector_fails() {
        let mut b = Bench::new("R.", r#"<PlannerSelector selected_planner="{pl}"/>"#);
        assert_eq!(b.tick(), Status::Failure);
        assert!(b.tree.blackboard().get::<String>("pl").is_err());
        let mut b = Bench::new(
            "R.",
            r#"<PlannerSelector selected_planner="{pl}" default_planner=""/>"#,
        );
        assert_eq!(b.tick(), Status::Failure);
    }
}

//! The error-code conditions: WouldAPlannerRecoveryHelp, WouldAControllerRecoveryHelp,
//! WouldARouteRecoveryHelp, WouldASmootherRecoveryHelp and AreErrorCodesPresent.
//!
//! All five are conditions with the ports `error_code` and `error_codes_to_check`: Success
//! when `error_code` is one of the node's codes, else Failure.
//!
//! - **AreErrorCodesPresent**: its codes are `error_codes_to_check` (none when absent), read
//!   once, at its first tick, as Nav2 reads them once, when it builds the node.
//! - **WouldAPlannerRecoveryHelp**: UNKNOWN, NO_VALID_PATH and TIMEOUT of
//!   ComputePathToPose (200, 208, 207) and of ComputePathThroughPoses (300, 308, 307).
//! - **WouldAControllerRecoveryHelp**: UNKNOWN 100, PATIENCE_EXCEEDED 104,
//!   FAILED_TO_MAKE_PROGRESS 105, NO_VALID_CONTROL 106.
//! - **WouldARouteRecoveryHelp**: UNKNOWN 400, NO_VALID_ROUTE 405, TIMEOUT 404.
//! - **WouldASmootherRecoveryHelp**: UNKNOWN 500, TIMEOUT 502, FAILED_TO_SMOOTH_PATH 504,
//!   SMOOTHED_PATH_IN_COLLISION 503.
//!
//! The four `WouldA…` nodes are Nav2's AreErrorCodesPresent with their codes set by their
//! constructors after the port was read, so in Nav2 their `error_codes_to_check` is
//! declared and never used: here too. Nav2's navigator writes 0 to every error code entry
//! when a navigation starts; here an entry that was never written reads as 0 in the same
//! way, so a tree can ask about the planner before the planner ever failed. An entry of
//! another type is no code: Failure.

use neurotree_core::{Handle, StatefulAction, Status};

use super::codes::{
    CONTROLLER_RECOVERABLE, NONE, PLANNER_RECOVERABLE, ROUTE_RECOVERABLE, SMOOTHER_RECOVERABLE,
};
use super::{ports, Nav2Context};
use neurotree_core::Category;
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

fn ports(server: &str) -> Vec<PortSpec> {
    vec![
        PortSpec::input::<u16>("error_code").describe(&format!("The {server}'s last error code.")),
        PortSpec::input::<Vec<i64>>("error_codes_to_check")
            .describe("The codes to look for (AreErrorCodesPresent only)."),
    ]
}

/// The four `WouldA…` nodes: name, whose error, its codes, description.
const WOULD_HELP: [(&str, &str, &[u16], &str); 4] = [
    (
        "WouldAPlannerRecoveryHelp",
        "planner server",
        &PLANNER_RECOVERABLE,
        "Succeeds when the planner's error is one clearing the costmap may fix.",
    ),
    (
        "WouldAControllerRecoveryHelp",
        "controller server",
        &CONTROLLER_RECOVERABLE,
        "Succeeds when the controller's error is one a recovery may fix.",
    ),
    (
        "WouldARouteRecoveryHelp",
        "route server",
        &ROUTE_RECOVERABLE,
        "Succeeds when the route server's error is one a recovery may fix.",
    ),
    (
        "WouldASmootherRecoveryHelp",
        "smoother server",
        &SMOOTHER_RECOVERABLE,
        "Succeeds when the smoother's error is one a recovery may fix.",
    ),
];

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    for (name, server, codes, description) in WOULD_HELP {
        r.register_condition(name, ports(server), move |h| present(h, codes))?;
        r.describe(name, description);
    }
    r.register_stateful_as(
        "AreErrorCodesPresent",
        Category::Condition,
        ports("server"),
        AreErrorCodesPresent::default,
    )?;
    r.describe(
        "AreErrorCodesPresent",
        "Succeeds when `error_code` is one of `error_codes_to_check`.",
    );
    Ok(())
}

/// `true` when the node's `error_code` is one of `codes`.
fn present<C>(h: &Handle<'_, C>, codes: &[u16]) -> bool {
    match ports::optional::<u16, C>(h, "error_code") {
        Ok(code) => codes.contains(&code.unwrap_or(NONE)),
        Err(_) => false,
    }
}

/// AreErrorCodesPresent: see the [module documentation](self).
#[derive(Default)]
struct AreErrorCodesPresent {
    /// The codes, once the first tick read them.
    codes: Option<Vec<u16>>,
}

impl<C: Nav2Context> StatefulAction<C> for AreErrorCodesPresent {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&self.codes))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode::<Option<Vec<u16>>>(state)
            .map(|saved| self.codes = saved)
            .is_some()
    }

    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status {
        let codes = self.codes.get_or_insert_with(|| {
            let listed =
                ports::or(h, "error_codes_to_check", Vec::<i64>::new()).unwrap_or_default();
            listed
                .into_iter()
                .filter_map(|c| u16::try_from(c).ok())
                .collect()
        });
        if present(h, codes) {
            Status::Success
        } else {
            Status::Failure
        }
    }

    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status {
        self.on_start(h)
    }
}

#[cfg(test)]
mod tests {
    use super::super::codes::{compute_path, follow_path};
    use crate::nav2::testing::Bench;
    use neurotree_core::Status;

    fn bench(node: &str, extra: &str) -> Bench {
        Bench::new("R", &format!(r#"<{node} error_code="{{code}}" {extra}/>"#))
    }

    #[test]
    fn the_planner_recovery_helps_for_unknown_no_path_and_timeout() {
        let mut b = bench("WouldAPlannerRecoveryHelp", "");
        assert_eq!(b.tick(), Status::Failure, "never written: no error");
        let mut helped = Vec::new();
        for code in [
            0_u16, 200, 201, 203, 204, 205, 206, 207, 208, 106, 300, 306, 307, 308, 309,
        ] {
            b.set("code", code);
            if b.tick() == Status::Success {
                helped.push(code);
            }
        }
        assert_eq!(
            helped,
            [
                compute_path::UNKNOWN,
                compute_path::TIMEOUT,
                compute_path::NO_VALID_PATH,
                300,
                307,
                308
            ]
        );
    }

    #[test]
    fn the_route_and_smoother_recoveries_help_for_their_codes() {
        for (node, range, expected) in [
            (
                "WouldARouteRecoveryHelp",
                399..410_u16,
                &[400_u16, 404, 405][..],
            ),
            (
                "WouldASmootherRecoveryHelp",
                499..510,
                &[500, 502, 503, 504],
            ),
        ] {
            let mut b = bench(node, "");
            let helped: Vec<u16> = range
                .filter(|code| {
                    b.set("code", *code);
                    b.tick() == Status::Success
                })
                .collect();
            assert_eq!(helped, expected, "{node}");
        }
    }

    #[test]
    fn the_controller_recovery_helps_for_its_four_codes() {
        let mut b = bench("WouldAControllerRecoveryHelp", "");
        let mut helped = Vec::new();
        for code in 0..110_u16 {
            b.set("code", code);
            if b.tick() == Status::Success {
                helped.push(code);
            }
        }
        assert_eq!(
            helped,
            [
                follow_path::UNKNOWN,
                follow_path::PATIENCE_EXCEEDED,
                follow_path::FAILED_TO_MAKE_PROGRESS,
                follow_path::NO_VALID_CONTROL
            ]
        );
    }

    #[test]
    fn codes_to_check_are_ignored_by_the_would_nodes_and_read_once_by_are_codes_present() {
        // As in Nav2, whose constructors overwrite what the port gave.
        let mut b = bench(
            "WouldAControllerRecoveryHelp",
            r#"error_codes_to_check="101;103""#,
        );
        b.set("code", 106_u16);
        assert_eq!(b.tick(), Status::Success);
        b.set("code", 103_u16);
        assert_eq!(b.tick(), Status::Failure);
        let mut b = bench("AreErrorCodesPresent", r#"error_codes_to_check="{codes}""#);
        b.set("codes", vec![101_i64, 103]);
        b.set("code", 103_u16);
        assert_eq!(b.tick(), Status::Success);
        b.set("code", 106_u16);
        assert_eq!(b.tick(), Status::Failure);
        // Read once: a later list changes nothing.
        b.set("codes", vec![106_i64]);
        assert_eq!(b.tick(), Status::Failure);
        let mut b = bench("AreErrorCodesPresent", "");
        b.set("code", 0_u16);
        assert_eq!(b.tick(), Status::Failure, "no codes to check");
        // An entry of another type is no code at all.
        let mut b = bench("WouldAPlannerRecoveryHelp", "");
        b.set("code", "lost".to_string());
        assert_eq!(b.tick(), Status::Failure);
    }
}

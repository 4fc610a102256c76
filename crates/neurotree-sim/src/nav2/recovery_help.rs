//! WouldAPlannerRecoveryHelp and WouldAControllerRecoveryHelp: is the last error one that a
//! recovery can fix?
//!
//! Both are conditions with the ports `error_code` and `error_codes_to_check` (optional).
//!
//! - **WouldAPlannerRecoveryHelp**: `error_code` is UNKNOWN 200, NO_VALID_PATH 208 or
//!   TIMEOUT 207 (or one of `error_codes_to_check` when given). No such entry yet: code 0.
//! - **WouldAControllerRecoveryHelp**: `error_code` is UNKNOWN 100, PATIENCE_EXCEEDED 104,
//!   FAILED_TO_MAKE_PROGRESS 105 or NO_VALID_CONTROL 106 (or one of `error_codes_to_check`).
//!
//! These are Nav2's AreErrorCodesPresent with the codes its documentation lists. Nav2's
//! navigator writes 0 to every error code entry when a navigation starts; here an entry
//! that was never written reads as 0 in the same way, so a tree can ask about the planner
//! before the planner ever failed.

use neurotree_core::Handle;

use super::codes::{CONTROLLER_RECOVERABLE, NONE, PLANNER_RECOVERABLE};
use super::{ports, Nav2Context};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

fn ports(server: &str) -> Vec<PortSpec> {
    vec![
        PortSpec::input::<u16>("error_code")
            .describe(&format!("The {server} server's last error code.")),
        PortSpec::input::<Vec<i64>>("error_codes_to_check")
            .describe("The codes to look for, instead of the ones a recovery can fix."),
    ]
}

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    r.register_condition("WouldAPlannerRecoveryHelp", ports("planner"), |h| {
        would_help(h, &PLANNER_RECOVERABLE)
    })?;
    r.describe(
        "WouldAPlannerRecoveryHelp",
        "Succeeds when the planner's error is one clearing the costmap may fix.",
    );
    r.register_condition("WouldAControllerRecoveryHelp", ports("controller"), |h| {
        would_help(h, &CONTROLLER_RECOVERABLE)
    })?;
    r.describe(
        "WouldAControllerRecoveryHelp",
        "Succeeds when the controller's error is one a recovery may fix.",
    );
    Ok(())
}

fn would_help<C>(h: &Handle<'_, C>, recoverable: &[u16]) -> bool {
    let code = match ports::optional::<u16, C>(h, "error_code") {
        Ok(code) => code.unwrap_or(NONE),
        Err(_) => return false,
    };
    match ports::optional::<Vec<i64>, C>(h, "error_codes_to_check") {
        Ok(Some(codes)) => codes.contains(&i64::from(code)),
        Ok(None) => recoverable.contains(&code),
        Err(_) => false,
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
        for code in [0_u16, 200, 201, 203, 204, 205, 206, 207, 208, 106] {
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
                compute_path::NO_VALID_PATH
            ]
        );
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
    fn codes_to_check_replace_the_defaults() {
        let mut b = bench(
            "WouldAControllerRecoveryHelp",
            r#"error_codes_to_check="101;103""#,
        );
        b.set("code", 106_u16);
        assert_eq!(b.tick(), Status::Failure);
        b.set("code", 103_u16);
        assert_eq!(b.tick(), Status::Success);
        // An entry of another type is no code at all.
        let mut b = bench("WouldAPlannerRecoveryHelp", "");
        b.set("code", "lost".to_string());
        assert_eq!(b.tick(), Status::Failure);
    }
}

//! The cancel nodes: CancelSpin, CancelBackUp, CancelDriveOnHeading, CancelWait,
//! CancelAssistedTeleop, CancelComputeAndTrackRoute and CancelFollowObject.
//!
//! Sync actions with the ports `server_name` and `server_timeout` (unused). Each cancels
//! what its server is doing, if it is doing it, and succeeds, as Nav2's
//! `BtCancelActionNode` asks its server to cancel every goal and succeeds:
//!
//! - CancelSpin, CancelBackUp, CancelDriveOnHeading, CancelWait: stop the world's motion when
//!   it is that behavior's and under way (the behavior's node then ends with Success, as
//!   Nav2's does when its goal is cancelled);
//! - CancelComputeAndTrackRoute, CancelFollowObject: cancel the route tracking or the
//!   following under way (their node ends with Success at its next tick);
//! - CancelAssistedTeleop: the simulator has no assisted teleoperation, so there is never
//!   anything to cancel.
//!
//! (CancelControl, which stops FollowPath, is in [`controller`](super::controller).)

use neurotree_core::{Handle, Status};

use super::{GoalState, Nav2Context};
use crate::{MotionKind, MotionStatus};
use neurotree_toolkit::{PortSpec, Registry, RegistryError};

/// What a cancel node cancels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Motion(MotionKind),
    RouteTracking,
    Following,
    Nothing,
}

const CANCELS: [(&str, Target, &str); 7] = [
    ("CancelSpin", Target::Motion(MotionKind::Spin), "Spin"),
    ("CancelBackUp", Target::Motion(MotionKind::BackUp), "BackUp"),
    (
        "CancelDriveOnHeading",
        Target::Motion(MotionKind::DriveOnHeading),
        "DriveOnHeading",
    ),
    ("CancelWait", Target::Motion(MotionKind::Wait), "Wait"),
    ("CancelAssistedTeleop", Target::Nothing, "AssistedTeleop"),
    (
        "CancelComputeAndTrackRoute",
        Target::RouteTracking,
        "ComputeAndTrackRoute",
    ),
    ("CancelFollowObject", Target::Following, "FollowObject"),
];

pub(super) fn register<C: Nav2Context>(r: &mut Registry<C>) -> Result<(), RegistryError> {
    for (name, target, what) in CANCELS {
        let ports = vec![
            PortSpec::input::<String>("server_name").describe("Action server name (unused)."),
            PortSpec::input::<u64>("server_timeout").describe("Server timeout in ms (unused)."),
        ];
        r.register_action(name, ports, move |h| cancel(h, target))?;
        r.describe(name, &format!("Cancels what {what} is doing."));
    }
    Ok(())
}

fn cancel<C: Nav2Context>(h: &mut Handle<'_, C>, target: Target) -> Status {
    let sim = h.ctx_mut().nav2_mut();
    let goal = match target {
        Target::Motion(kind) => {
            let world = &mut sim.world;
            if world.motion_kind() == Some(kind) && world.motion_status() == MotionStatus::Active {
                world.stop();
            }
            return Status::Success;
        }
        Target::Nothing => return Status::Success,
        Target::RouteTracking => &mut sim.goals.route_tracking,
        Target::Following => &mut sim.goals.following,
    };
    if *goal == GoalState::Active {
        *goal = GoalState::Cancelled;
    }
    Status::Success
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nav2::testing::Bench;
    use Status::{Running as R, Success as S};

    #[test]
    fn a_cancel_stops_its_own_behavior_which_then_succeeds() {
        // The spin runs; 200 ms in, the cancel stops it, and at the next tick the spin
        // sees its motion cancelled and succeeds.
        let mut b = Bench::new(
            "...\n.R.\n...",
            r#"<Parallel success_count="2" failure_count="1">
                 <Spin spin_dist="3.0" error_code_id="{code}"/>
                 <Delay delay_msec="200"><CancelSpin/></Delay>
               </Parallel>"#,
        );
        assert_eq!(b.run(50), [R, R, R, S]);
        assert_eq!(b.sim.world.stop_count(), 1);
        assert_eq!(b.get::<u16>("code"), 0);
        // Two steps of 0.1 rad.
        assert!((b.sim.world.robot().theta - 0.2).abs() < 1e-9);
    }

    #[test]
    fn a_cancel_leaves_other_motions_alone() {
        let mut b = Bench::new(
            "...\n.R.\n...",
            r#"<Sequence><CancelBackUp/><CancelWait/></Sequence>"#,
        );
        b.sim.world.spin(1.0, 1.0);
        assert_eq!(b.tick(), S);
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Active);
        assert_eq!(b.sim.world.stop_count(), 0);
        let mut b = Bench::new("...\n.R.\n...", r#"<CancelSpin/>"#);
        b.sim.world.spin(1.0, 1.0);
        assert_eq!(b.tick(), S);
        assert_eq!(b.sim.world.motion_status(), MotionStatus::Idle);
    }

    #[test]
    fn cancelling_a_server_goal_marks_it_only_when_active() {
        let mut b = Bench::new("R", r#"<CancelFollowObject/>"#);
        assert_eq!(b.tick(), S);
        assert_eq!(b.sim.goals.following, GoalState::Idle);
        b.sim.goals.following = GoalState::Active;
        assert_eq!(b.tick(), S);
        assert_eq!(b.sim.goals.following, GoalState::Cancelled);
        let mut b = Bench::new("R", r#"<CancelAssistedTeleop/>"#);
        assert_eq!(b.tick(), S);
    }
}

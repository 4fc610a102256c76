//! The behavior server over ROS 2: Spin, BackUp, DriveOnHeading, Wait and AssistedTeleop.

use super::*;

pub(super) fn time_allowance() -> PortSpec {
    PortSpec::input::<f64>("time_allowance")
        .default_value("10.0")
        .describe("Seconds the behavior may take.")
}

pub(super) fn collision_checks() -> PortSpec {
    PortSpec::input::<bool>("disable_collision_checks")
        .default_value("false")
        .describe("Disable collision checking (unused).")
}

/// Spin: the behavior server turns the robot by `spin_dist`.
pub(super) struct SpinBy<A>(PhantomData<fn() -> A>);

impl<A> Default for SpinBy<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

/// Spin's goal in the layout of a release (Jazzy's has no `disable_collision_checks`).
pub(super) trait SpinLayout: RosAction<Result = SpinResult> {
    fn goal(yaw: f32, allowance: MsgDuration, disable_collision_checks: bool) -> Self::Goal;
}

impl SpinLayout for Spin {
    fn goal(yaw: f32, allowance: MsgDuration, _: bool) -> SpinGoal {
        SpinGoal {
            target_yaw: yaw,
            time_allowance: allowance,
        }
    }
}

impl SpinLayout for kilted::Spin {
    fn goal(yaw: f32, allowance: MsgDuration, disable: bool) -> kilted::SpinGoal {
        kilted::SpinGoal {
            target_yaw: yaw,
            time_allowance: allowance,
            disable_collision_checks: disable,
        }
    }
}

/// A straight drive's goal (BackUp's, DriveOnHeading's) in the layout of a release.
pub(super) trait StraightLayout: RosAction {
    fn goal(
        distance: f64,
        speed: f32,
        allowance: MsgDuration,
        disable_collision_checks: bool,
    ) -> Self::Goal;
}

/// Implements [`StraightLayout`] for a Jazzy goal and for a Kilted one.
macro_rules! straight_layouts {
    ($jazzy:ty: $jazzy_goal:ident, $kilted:ty: $kilted_goal:path) => {
        impl StraightLayout for $jazzy {
            fn goal(distance: f64, speed: f32, allowance: MsgDuration, _: bool) -> $jazzy_goal {
                $jazzy_goal {
                    target: Point {
                        x: distance,
                        y: 0.0,
                        z: 0.0,
                    },
                    speed,
                    time_allowance: allowance,
                }
            }
        }
        impl StraightLayout for $kilted {
            fn goal(
                distance: f64,
                speed: f32,
                allowance: MsgDuration,
                disable: bool,
            ) -> $kilted_goal {
                $kilted_goal {
                    target: Point {
                        x: distance,
                        y: 0.0,
                        z: 0.0,
                    },
                    speed,
                    time_allowance: allowance,
                    disable_collision_checks: disable,
                }
            }
        }
    };
}

straight_layouts!(BackUp: BackUpGoal, kilted::BackUp: kilted::BackUpGoal);
straight_layouts!(
    DriveOnHeading: DriveOnHeadingGoal,
    kilted::DriveOnHeading: kilted::DriveOnHeadingGoal
);

pub(super) fn disable_collision_checks<C>(h: &Handle<'_, C>) -> Result<bool, String> {
    Ok(optional(h, "disable_collision_checks")?.unwrap_or(false))
}

impl<C: 'static, A: SpinLayout> ActionSpec<C> for SpinBy<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("spin_dist")
                .default_value("1.57")
                .describe("Radians to turn."),
            time_allowance(),
            PortSpec::input::<bool>("is_recovery")
                .default_value("true")
                .describe("Used as a recovery (unused)."),
            collision_checks(),
            server_name_port(),
            error_code_port("spin"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let angle: f64 = required(h, "spin_dist")?;
        let allowance: f64 = required(h, "time_allowance")?;
        let disable = disable_collision_checks(h)?;
        Ok(A::goal(angle as f32, seconds(allowance), disable))
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &SpinResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&SpinResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, SpinResult::UNKNOWN, error, server)
    }
}

/// BackUp: the behavior server drives the robot `backup_dist` backwards.
pub(super) struct BackUpBy<A>(PhantomData<fn() -> A>);

impl<A> Default for BackUpBy<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<C: 'static, A: StraightLayout<Result = BackUpResult>> ActionSpec<C> for BackUpBy<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("backup_dist")
                .default_value("0.15")
                .describe("Metres to drive back."),
            PortSpec::input::<f64>("backup_speed")
                .default_value("0.025")
                .describe("Metres per second."),
            time_allowance(),
            collision_checks(),
            server_name_port(),
            error_code_port("back-up"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let distance: f64 = required(h, "backup_dist")?;
        let speed: f64 = required(h, "backup_speed")?;
        let allowance: f64 = required(h, "time_allowance")?;
        let disable = disable_collision_checks(h)?;
        Ok(A::goal(distance, speed as f32, seconds(allowance), disable))
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &BackUpResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&BackUpResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, BackUpResult::UNKNOWN, error, server)
    }
}

/// DriveOnHeading: the behavior server drives the robot `dist_to_travel` straight on.
pub(super) struct DriveOn<A>(PhantomData<fn() -> A>);

impl<A> Default for DriveOn<A> {
    fn default() -> Self {
        Self(PhantomData)
    }
}

impl<C: 'static, A: StraightLayout<Result = DriveOnHeadingResult>> ActionSpec<C> for DriveOn<A> {
    type Action = A;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("dist_to_travel")
                .default_value("0.15")
                .describe("Metres to drive, negative backwards."),
            PortSpec::input::<f64>("speed")
                .default_value("0.025")
                .describe("Metres per second, negative backwards."),
            time_allowance(),
            collision_checks(),
            server_name_port(),
            error_code_port("drive-on-heading"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<A::Goal, String> {
        let distance: f64 = required(h, "dist_to_travel")?;
        let speed: f64 = required(h, "speed")?;
        let allowance: f64 = required(h, "time_allowance")?;
        let disable = disable_collision_checks(h)?;
        Ok(A::goal(distance, speed as f32, seconds(allowance), disable))
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &DriveOnHeadingResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&DriveOnHeadingResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, DriveOnHeadingResult::UNKNOWN, error, server)
    }
}

/// Wait: the behavior server stands still for `wait_duration`.
pub(super) struct WaitFor;

impl<C: 'static> ActionSpec<C> for WaitFor {
    type Action = Wait;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<f64>("wait_duration")
                .default_value("1.0")
                .describe("Seconds to wait."),
            server_name_port(),
            error_code_port("wait"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<WaitGoal, String> {
        let secs: f64 = required(h, "wait_duration")?;
        Ok(WaitGoal {
            time: seconds(secs),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &WaitResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&WaitResult>,
    ) -> Status {
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        // Wait defines no error code of its own: Nav2's behaviors' UNKNOWN.
        failed(h, 700, error, server)
    }
}

/// AssistedTeleop: the behavior server passes a person's velocity commands on for up to
/// `time_allowance`. As Nav2's `assisted_teleop_action.cpp`, an aborted goal (the time
/// allowance ran out) writes the server's code and fails only as a recovery
/// (`is_recovery`); otherwise the node succeeds, the code telling why it ended.
#[derive(Default)]
pub(super) struct Teleop {
    is_recovery: bool,
}

impl<C: 'static> ActionSpec<C> for Teleop {
    type Action = AssistedTeleop;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<bool>("is_recovery")
                .default_value("false")
                .describe("Used as a recovery: an aborted goal fails the node."),
            time_allowance(),
            server_name_port(),
            error_code_port("assisted teleop"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<AssistedTeleopGoal, String> {
        let allowance: f64 = required(h, "time_allowance")?;
        self.is_recovery = optional(h, "is_recovery")?.unwrap_or(false);
        Ok(AssistedTeleopGoal {
            time_allowance: seconds(allowance),
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &AssistedTeleopResult) -> Status {
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&AssistedTeleopResult>,
    ) -> Status {
        let aborted = matches!(error, ActionError::Aborted { .. });
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        let status = failed(h, AssistedTeleopResult::UNKNOWN, error, server);
        if aborted && !self.is_recovery {
            Status::Success
        } else {
            status
        }
    }
}

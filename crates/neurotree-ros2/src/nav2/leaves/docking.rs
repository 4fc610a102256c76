//! The docking server over ROS 2: DockRobot and UndockRobot.

use super::*;

/// DockRobot: the docking server docks the robot at a dock of its database, or at a pose.
pub(super) struct Dock;

impl<C: 'static> ActionSpec<C> for Dock {
    type Action = DockRobot;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<bool>("use_dock_id")
                .default_value("true")
                .describe("Dock at `dock_id` rather than at `dock_pose`."),
            PortSpec::input::<String>("dock_id").describe("The dock's id."),
            PortSpec::input::<Pose2D>("dock_pose").describe("The dock's pose."),
            PortSpec::input::<String>("dock_type").describe("The dock's type."),
            PortSpec::input::<f64>("max_staging_time")
                .default_value("1000.0")
                .describe("Seconds to reach the staging pose."),
            PortSpec::input::<bool>("navigate_to_staging_pose")
                .default_value("true")
                .describe("Drive to the staging pose first."),
            server_name_port(),
            PortSpec::output::<bool>("success").describe("Whether it docked."),
            PortSpec::output::<u16>("num_retries").describe("Retries made."),
            error_code_port("docking"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<DockRobotGoal, String> {
        let mut goal = DockRobotGoal {
            use_dock_id: optional(h, "use_dock_id")?.unwrap_or(true),
            navigate_to_staging_pose: optional(h, "navigate_to_staging_pose")?.unwrap_or(true),
            ..DockRobotGoal::default()
        };
        // As Nav2's node: the id, or the pose with its type and staging time.
        if goal.use_dock_id {
            goal.dock_id = required(h, "dock_id")?;
        } else {
            goal.dock_pose = pose_stamped(required(h, "dock_pose")?);
            goal.dock_type = optional(h, "dock_type")?.unwrap_or_default();
            let staging: f64 = optional(h, "max_staging_time")?.unwrap_or(1000.0);
            goal.max_staging_time = staging as f32;
        }
        Ok(goal)
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &DockRobotResult) -> Status {
        emit(h, "success", result.success);
        emit(h, "num_retries", result.num_retries);
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&DockRobotResult>,
    ) -> Status {
        if let (Some(result), false) = (result, matches!(error, ActionError::Canceled { .. })) {
            emit(h, "success", result.success);
            emit(h, "num_retries", result.num_retries);
        }
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, DockRobotResult::UNKNOWN, error, server)
    }
}

/// UndockRobot: the docking server backs the robot off its dock to the staging pose.
pub(super) struct Undock;

impl<C: 'static> ActionSpec<C> for Undock {
    type Action = UndockRobot;

    fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::input::<String>("dock_type")
                .describe("The dock's type; empty for the one the server docked at."),
            PortSpec::input::<f64>("max_undocking_time")
                .default_value("30.0")
                .describe("Seconds undocking may take."),
            server_name_port(),
            PortSpec::output::<bool>("success").describe("Whether it undocked."),
            error_code_port("docking"),
        ]
    }

    fn goal(&mut self, h: &mut Handle<'_, C>) -> Result<UndockRobotGoal, String> {
        let allowed: f64 = optional(h, "max_undocking_time")?.unwrap_or(30.0);
        Ok(UndockRobotGoal {
            dock_type: optional(h, "dock_type")?.unwrap_or_default(),
            max_undocking_time: allowed as f32,
        })
    }

    fn on_result(&mut self, h: &mut Handle<'_, C>, result: &UndockRobotResult) -> Status {
        emit(h, "success", result.success);
        outcome(h, result.error_code, &result.error_msg)
    }

    fn on_failure(
        &mut self,
        h: &mut Handle<'_, C>,
        error: &ActionError,
        result: Option<&UndockRobotResult>,
    ) -> Status {
        if let (Some(result), false) = (result, matches!(error, ActionError::Canceled { .. })) {
            emit(h, "success", result.success);
        }
        let server = result.map(|r| (r.error_code, r.error_msg.as_str()));
        failed(h, UndockRobotResult::UNKNOWN, error, server)
    }
}

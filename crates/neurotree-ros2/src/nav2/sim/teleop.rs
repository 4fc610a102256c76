//! Assisted teleoperation on a robot no one drives.

use std::time::Duration;

use neurotree_sim::nav2::Nav2Sim;
use ros2_client::action::GoalStatusEnum;
use ros2_client::Subscription;

use super::served::Serving;
use super::stats::SimStatsHandle;
use crate::msg::nav2_msgs::{AssistedTeleop, AssistedTeleopFeedback, AssistedTeleopResult};
use crate::msg::std_msgs::Empty;
use crate::nav2::goal_server::{GoalServer, Request};
use crate::nav2::NavigatorError;
use crate::{Ros2Error, RosNode};

/// The topic on which a person ends assisted teleoperation with success (Nav2's
/// AssistedTeleop behavior listens on it).
pub const PREEMPT_TELEOP_TOPIC: &str = "preempt_teleop";

/// The behavior server's `assisted_teleop`. No one drives the simulated robot, so a goal
/// holds it still until its time allowance runs out (Aborted, TIMEOUT 731, as Nav2's
/// behavior ends), or a message on [`PREEMPT_TELEOP_TOPIC`] ends it (Succeeded, as Nav2's
/// does); a zero allowance runs until then.
pub(super) struct Teleop {
    goals: GoalServer<AssistedTeleop>,
    preempts: Subscription<Empty>,
    /// When the running goal started and its allowance.
    running: Option<(Duration, Duration)>,
    preempted: bool,
}

impl Teleop {
    pub(super) fn new(ros: &RosNode) -> Result<Self, NavigatorError> {
        Ok(Self {
            goals: GoalServer::new(ros, "assisted_teleop")?,
            preempts: ros.subscription(PREEMPT_TELEOP_TOPIC)?,
            running: None,
            preempted: false,
        })
    }

    fn result(&self, sim: &Nav2Sim, code: u16, message: &str) -> AssistedTeleopResult {
        let since = self.running.map_or(Duration::ZERO, |(since, _)| since);
        AssistedTeleopResult {
            total_elapsed_time: sim.world.now().saturating_sub(since).into(),
            error_code: code,
            error_msg: message.to_owned(),
        }
    }

    fn end(&mut self, sim: &Nav2Sim, stats: &SimStatsHandle, status: GoalStatusEnum, code: u16) {
        let message = if code == AssistedTeleopResult::TIMEOUT {
            "Exceeded time allowance before reaching the assisted_teleop goal"
        } else {
            ""
        };
        let result = self.result(sim, code, message);
        // Counted before the result goes out, which a client may act on at once.
        {
            let mut stats = stats.lock();
            if status == GoalStatusEnum::Succeeded {
                stats.assisted_teleop.succeeded += 1;
            } else {
                stats.assisted_teleop.aborted += 1;
            }
        }
        self.running = None;
        self.goals.finish(status, result);
    }
}

impl Serving for Teleop {
    fn poll(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) -> Result<bool, Ros2Error> {
        // A read error is a message lost; the next one still ends the goal.
        while let Ok(Some(_)) = self.preempts.take() {
            self.preempted = self.running.is_some();
        }
        let mut started = false;
        for request in self.goals.poll()? {
            match request {
                Request::Goal(goal) => {
                    if self.running.is_some() {
                        // The goal server already ended the replaced goal.
                        stats.lock().assisted_teleop.aborted += 1;
                    }
                    sim.world.stop();
                    self.running = Some((sim.world.now(), goal.time_allowance.into()));
                    self.preempted = false;
                    stats.lock().assisted_teleop.goals += 1;
                    started = true;
                }
                Request::Cancel => {
                    stats.lock().assisted_teleop.cancels += 1;
                    if self.running.is_some() {
                        let result = self.result(sim, 0, "");
                        self.running = None;
                        self.goals.finish(GoalStatusEnum::Canceled, result);
                        started = false;
                    }
                }
            }
        }
        Ok(started)
    }

    fn preempt(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        if self.running.is_some() {
            self.end(sim, stats, GoalStatusEnum::Aborted, 0);
        }
    }

    fn is_running(&self) -> bool {
        self.running.is_some()
    }

    fn tick(&mut self, sim: &mut Nav2Sim, stats: &SimStatsHandle) {
        let Some((since, allowance)) = self.running else {
            return;
        };
        let elapsed = sim.world.now().saturating_sub(since);
        if self.preempted {
            self.preempted = false;
            self.end(
                sim,
                stats,
                GoalStatusEnum::Succeeded,
                AssistedTeleopResult::NONE,
            );
        } else if !allowance.is_zero() && elapsed > allowance {
            self.end(
                sim,
                stats,
                GoalStatusEnum::Aborted,
                AssistedTeleopResult::TIMEOUT,
            );
        } else {
            self.goals.feedback(AssistedTeleopFeedback {
                current_teleop_duration: elapsed.into(),
            });
        }
    }
}

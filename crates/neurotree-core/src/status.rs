//! The statuses a node returns and the statuses the engine stores.
//!
//! Users see three outcomes, as in the theory (Colledanchise & Ögren, ch. 1.3): a node
//! succeeded, failed, or is still running. BehaviorTree.CPP v4 adds two internal ones that its
//! XML files rely on: `Idle` (not ticked yet, or reset by its parent) and `Skipped` (a
//! precondition told the node not to run). [`NodeStatus`] carries all five for code that asks
//! for them (observers, custom control nodes); [`Status`] carries the three that tick results
//! and leaves use.

use core::fmt;

/// The outcome of a tick: what leaves return and what the tree reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// The node achieved its goal.
    Success,
    /// The node could not achieve its goal.
    Failure,
    /// The node needs more ticks to finish.
    Running,
}

impl Status {
    /// `true` for [`Status::Success`] and [`Status::Failure`].
    #[inline]
    pub const fn is_completed(self) -> bool {
        !matches!(self, Status::Running)
    }

    /// The upper-case name BehaviorTree.CPP prints (`SUCCESS`, `FAILURE`, `RUNNING`).
    pub const fn as_str(self) -> &'static str {
        NodeStatus::from_status(self).as_str()
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl From<bool> for Status {
    /// `true` is [`Status::Success`], `false` is [`Status::Failure`].
    #[inline]
    fn from(ok: bool) -> Self {
        if ok {
            Status::Success
        } else {
            Status::Failure
        }
    }
}

/// A node's status as the engine stores and reports it to observers.
///
/// `Idle` is the stored status of a node that has not been ticked since its parent last reset
/// it. `Skipped` is returned (never stored) by a node whose precondition skipped it; a parent
/// treats a skipped child as absent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
#[repr(u8)]
pub enum NodeStatus {
    /// Not ticked since the last reset.
    #[default]
    Idle = 0,
    /// Ticked and not finished.
    Running = 1,
    /// Finished successfully.
    Success = 2,
    /// Finished unsuccessfully.
    Failure = 3,
    /// Not run this tick because a precondition skipped it.
    Skipped = 4,
}

impl NodeStatus {
    /// The stored form of a user-facing [`Status`].
    #[inline]
    pub const fn from_status(s: Status) -> Self {
        match s {
            Status::Success => NodeStatus::Success,
            Status::Failure => NodeStatus::Failure,
            Status::Running => NodeStatus::Running,
        }
    }

    /// The user-facing status, or `None` for `Idle` and `Skipped`.
    #[inline]
    pub const fn to_status(self) -> Option<Status> {
        match self {
            NodeStatus::Success => Some(Status::Success),
            NodeStatus::Failure => Some(Status::Failure),
            NodeStatus::Running => Some(Status::Running),
            NodeStatus::Idle | NodeStatus::Skipped => None,
        }
    }

    /// `true` for `Success` and `Failure`.
    #[inline]
    pub const fn is_completed(self) -> bool {
        matches!(self, NodeStatus::Success | NodeStatus::Failure)
    }

    /// `true` for `Running`, `Success` and `Failure`: the node has run since its last reset.
    #[inline]
    pub const fn is_active(self) -> bool {
        matches!(
            self,
            NodeStatus::Running | NodeStatus::Success | NodeStatus::Failure
        )
    }

    /// The upper-case name BehaviorTree.CPP prints (`IDLE`, `RUNNING`, ...).
    pub const fn as_str(self) -> &'static str {
        match self {
            NodeStatus::Idle => "IDLE",
            NodeStatus::Running => "RUNNING",
            NodeStatus::Success => "SUCCESS",
            NodeStatus::Failure => "FAILURE",
            NodeStatus::Skipped => "SKIPPED",
        }
    }
}

/// Reads the upper-case names BehaviorTree.CPP writes (`SUCCESS`, `FAILURE`, `RUNNING`).
impl core::str::FromStr for Status {
    type Err = ();
    fn from_str(text: &str) -> Result<Self, ()> {
        text.parse::<NodeStatus>()?.to_status().ok_or(())
    }
}

/// Reads the upper-case names [`NodeStatus::as_str`] writes.
impl core::str::FromStr for NodeStatus {
    type Err = ();
    fn from_str(text: &str) -> Result<Self, ()> {
        match text {
            "IDLE" => Ok(NodeStatus::Idle),
            "RUNNING" => Ok(NodeStatus::Running),
            "SUCCESS" => Ok(NodeStatus::Success),
            "FAILURE" => Ok(NodeStatus::Failure),
            "SKIPPED" => Ok(NodeStatus::Skipped),
            _ => Err(()),
        }
    }
}

impl From<Status> for NodeStatus {
    #[inline]
    fn from(s: Status) -> Self {
        NodeStatus::from_status(s)
    }
}

impl fmt::Display for NodeStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::ToString;

    #[test]
    fn conversions_round_trip() {
        for s in [Status::Success, Status::Failure, Status::Running] {
            assert_eq!(NodeStatus::from(s).to_status(), Some(s));
        }
        assert_eq!(NodeStatus::Idle.to_status(), None);
        assert_eq!(NodeStatus::Skipped.to_status(), None);
        assert_eq!(Status::from(true), Status::Success);
        assert_eq!(Status::from(false), Status::Failure);
    }

    #[test]
    fn activity_and_completion() {
        assert!(!NodeStatus::Idle.is_active());
        assert!(!NodeStatus::Skipped.is_active());
        assert!(NodeStatus::Running.is_active());
        assert!(!NodeStatus::Running.is_completed());
        assert!(NodeStatus::Failure.is_completed());
        assert_eq!(Status::Running.to_string(), "RUNNING");
        assert_eq!("FAILURE".parse::<Status>(), Ok(Status::Failure));
        assert_eq!("SKIPPED".parse::<Status>(), Err(()));
        assert_eq!("SKIPPED".parse::<NodeStatus>(), Ok(NodeStatus::Skipped));
        assert_eq!("success".parse::<NodeStatus>(), Err(()));
        assert_eq!(NodeStatus::Skipped.to_string(), "SKIPPED");
    }
}

//! Sleep(msec): a stateful leaf on the tree's clock, its start time kept in a state slot.
//!
//! - On the tick from Idle: Success at once if `msec` is 0, else note the time and return
//!   Running.
//! - Later ticks: Success once `msec` has passed, else Running.
//! - Halt forgets the start.
//!
//! It reads only the clock, so it is deterministic under a [`ManualClock`](crate::ManualClock).

use core::time::Duration;

use crate::clock::duration_to_nanos;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

pub(crate) fn tick<C>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    slot: usize,
    wait: Duration,
) -> NodeStatus {
    let now = t.now_nanos();
    if t.status(id) != NodeStatus::Running {
        if wait.is_zero() {
            return NodeStatus::Success;
        }
        t.aux[slot] = now;
        return NodeStatus::Running;
    }
    if now.saturating_sub(t.aux[slot]) >= duration_to_nanos(wait) {
        NodeStatus::Success
    } else {
        NodeStatus::Running
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn sleeps_on_the_clock() {
        let (mut tree, clock) = build(|b| b.sleep("nap", ms(100)));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(99));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(1));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
        // The root was reset, so the next tick sleeps again from now.
        assert_eq!(tick(&mut tree), Ok(Status::Running));
    }

    #[test]
    fn zero_succeeds_at_once() {
        let (mut tree, _) = build(|b| b.sleep("nap", ms(0)));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
    }

    #[test]
    fn halt_restarts_the_wait() {
        let (mut tree, clock) = build(|b| b.sleep("nap", ms(100)));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(80));
        tree.halt(&mut ());
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(80));
        assert_eq!(tick(&mut tree), Ok(Status::Running));
        clock.advance(ms(20));
        assert_eq!(tick(&mut tree), Ok(Status::Success));
    }
}

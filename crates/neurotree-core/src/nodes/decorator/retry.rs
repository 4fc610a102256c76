//! RetryUntilSuccessful(num_attempts): try a failing child again, up to `num_attempts` times.
//!
//! Mirror of [Repeat](super::repeat) on Failure. 0 attempts, or any negative count other than
//! −1 → Failure with no tick (BehaviorTree.CPP: `try_count < num_attempts || num_attempts == -1`).
//!
//! Some behavior-tree libraries return Running between attempts, others (Colledanchise & Ögren's)
//! retry within one tick. Both are this node: under
//! [`Tree::tick_exactly_once`](crate::Tree::tick_exactly_once) an instant failure yields Running,
//! under [`Tree::tick_once`](crate::Tree::tick_once) the attempts follow each other in the same
//! call. Exactly `-1` retries forever. Halt resets the count.
//!
//! A Retry that runs out gives its own [reason](crate::Reason) for its Failure: "gave up
//! after 3 attempts", code 0.

use crate::nodes::decl::{NodeDecl, PortDecl};
use crate::{Arity, Category};

/// RetryUntilSuccessful's declaration: its BehaviorTree.CPP name, family, children and ports.
pub const RETRY_UNTIL_SUCCESSFUL: NodeDecl = NodeDecl {
    name: "RetryUntilSuccessful",
    category: Category::Decorator,
    arity: Arity::One,
    ports: &[PortDecl::input(
        "num_attempts",
        "i32",
        "How many times a failing child is tried before the node fails; -1 retries forever.",
    )],
    summary: "Retries a failing child `num_attempts` times (-1: forever); a success succeeds.",
};

// The loop is Repeat's, mirrored: see `repeat::tick`.

#[cfg(test)]
mod tests {
    use crate::testing::*;

    #[test]
    fn retries_until_success() {
        let mut lab = Lab::new(&[&[F, F, S]]);
        let mut tree = lab.tree(|b| b.retry("r", 5, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn gives_up_after_the_attempts() {
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab.tree(|b| b.retry("r", 3, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn one_pass_per_call_is_running_between_attempts() {
        let mut lab = Lab::new(&[&[F, F, S]]);
        let mut tree = lab.tree(|b| b.retry("r", 5, |r| r.scripted(0)));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3]);
    }

    #[test]
    fn zero_attempts_fail_without_a_tick() {
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.retry("r", 0, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [0]);
    }

    #[test]
    fn only_minus_one_retries_forever_another_negative_count_fails_without_a_tick() {
        // BehaviorTree.CPP: `try_count_ < max_attempts_ || max_attempts_ == -1`.
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab.tree(|b| b.retry("r", -3, |r| r.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [0]);
        let mut lab = Lab::new(&[&[F]]);
        let mut tree = lab.tree(|b| b.retry("r", -1, |r| r.scripted(0)));
        for _ in 0..5 {
            assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Running));
        }
        assert_eq!(lab.ticks, [5]);
        assert_eq!(lab.halts, [0]);
    }
}

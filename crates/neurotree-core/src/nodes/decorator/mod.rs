//! Decorators: one child, its outcome or timing changed.
//!
//! | node | semantics in short |
//! |---|---|
//! | [Inverter](inverter) | Success ↔ Failure |
//! | [ForceSuccess / ForceFailure](force) | a completed child becomes the forced status |
//! | [Repeat](repeat) | run a succeeding child `num_cycles` times |
//! | [RetryUntilSuccessful](retry) | retry a failing child `num_attempts` times |
//! | [KeepRunningUntilFailure](keep_running) | Success becomes Running |
//! | [Delay](delay) | wait on the clock, then tick the child |
//! | [Timeout](timeout) | fail and halt the child when it runs too long |
//! | [Cooldown](cooldown) | after the child completes, fail for a while without ticking it |
//! | [RunOnce](run_once) | run the child to completion once, then skip |
//! | [SubTree](subtree) | give the child its own blackboard scope |

pub mod cooldown;
pub mod delay;
pub mod force;
pub mod inverter;
pub mod keep_running;
pub mod repeat;
pub mod retry;
pub mod run_once;
pub mod subtree;
pub mod timeout;

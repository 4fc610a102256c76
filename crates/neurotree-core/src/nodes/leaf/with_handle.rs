//! Leaves written as closures of the node's [`Handle`], for the leaves that read their ports,
//! the blackboard or the clock: the builder's
//! [`action_with`](crate::Builder::action_with) and
//! [`condition_with`](crate::Builder::condition_with), and the toolkit registry's leaf
//! closures. A closure of the context alone (`.action(name, |ctx| …)`) needs none of this.
//!
//! Each wraps its closure in the object the engine already calls ([`Action`],
//! [`Condition`]), so a tick makes no allocation and no extra indirection.

use super::{Action, Condition, Handle};
use crate::Status;

/// An [`Action`] that calls a closure of the node's [`Handle`].
///
/// ```
/// use neurotree_core::nodes::leaf::FnAction;
/// use neurotree_core::{Action, Status};
///
/// fn is_action<A: Action<()>>(_: &A) {}
/// is_action(&FnAction(|_h: &mut neurotree_core::Handle<'_, ()>| Status::Success));
/// ```
pub struct FnAction<F>(pub F);

impl<C, F> Action<C> for FnAction<F>
where
    F: Fn(&mut Handle<'_, C>) -> Status + Send + Sync,
{
    #[inline]
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        (self.0)(h)
    }
}

/// A [`Condition`] that calls a closure of the node's [`Handle`].
///
/// ```
/// use neurotree_core::nodes::leaf::FnCondition;
/// use neurotree_core::Condition;
///
/// fn is_condition<T: Condition<()>>(_: &T) {}
/// is_condition(&FnCondition(|h: &neurotree_core::Handle<'_, ()>| h.input::<bool>("on").unwrap_or(false)));
/// ```
pub struct FnCondition<F>(pub F);

impl<C, F> Condition<C> for FnCondition<F>
where
    F: Fn(&Handle<'_, C>) -> bool + Send + Sync,
{
    #[inline]
    fn check(&self, h: &Handle<'_, C>) -> bool {
        (self.0)(h)
    }
}

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

/// What a [`PortCondition`] sees: the node's ports and the blackboard, not the context nor
/// the clock.
pub struct Inputs<'h, 'a, C> {
    h: &'h Handle<'a, C>,
}

impl<C> Inputs<'_, '_, C> {
    /// Reads input port `port` (a literal, or the entry it names), as [`Handle::input`].
    pub fn input<T: crate::blueprint::FromPortStr + core::any::Any + Clone>(
        &self,
        port: &str,
    ) -> Result<T, crate::blueprint::PortError> {
        self.h.input(port)
    }

    /// Reads `key` in the node's scope, as [`Handle::get`].
    pub fn get<T: core::any::Any + Clone>(
        &self,
        key: &str,
    ) -> Result<T, crate::blackboard::BlackboardError> {
        self.h.get(key)
    }

    /// The node's name.
    pub fn name(&self) -> &str {
        self.h.name()
    }
}

/// A [`Condition`] of the node's ports and blackboard alone: since it cannot read the
/// context or the clock, a reactive node re-checking it lets the tree sleep (see
/// [`sleep`](crate::tree::sleep)).
///
/// ```
/// use neurotree_core::nodes::leaf::{Inputs, PortCondition};
/// use neurotree_core::Condition;
///
/// let hungry = PortCondition(|i: &Inputs<'_, '_, ()>| i.input::<u32>("food").unwrap_or(0) < 3);
/// assert!(Condition::<()>::reads_only_blackboard(&hungry));
/// ```
pub struct PortCondition<F>(pub F);

impl<C, F> Condition<C> for PortCondition<F>
where
    F: Fn(&Inputs<'_, '_, C>) -> bool + Send + Sync,
{
    #[inline]
    fn check(&self, h: &Handle<'_, C>) -> bool {
        (self.0)(&Inputs { h })
    }

    fn reads_only_blackboard(&self) -> bool {
        true
    }
}

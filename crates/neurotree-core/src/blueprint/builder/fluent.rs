//! The fluent half of the [`Builder`] for SubTree and the leaves of user code; each built-in
//! node's method is in the node's own module, beside its tick.

use alloc::boxed::Box;
use core::future::Future;

use super::Builder;
use crate::blueprint::{CustomSpec, NodeKind, SubTreeScope};
use crate::nodes::leaf::async_action::AsyncFn;
use crate::nodes::leaf::{Action, AsyncAction, Condition, StatefulAction};
use crate::Status;

/// SubTree and the leaves of user code.
impl<C> Builder<C> {
    /// A [SubTree](crate::nodes::decorator::subtree): its child sees its own blackboard scope.
    pub fn subtree(
        self,
        name: &str,
        scope: SubTreeScope,
        child: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::SubTree(Box::new(scope)), name, child)
    }
    /// A condition from a closure of the context.
    pub fn condition(self, name: &str, f: impl Fn(&C) -> bool + Send + Sync + 'static) -> Self {
        self.leaf(NodeKind::ConditionFn(Box::new(f)), name)
    }
    /// A condition from a [`Condition`] object.
    pub fn condition_node(self, name: &str, c: impl Condition<C> + 'static) -> Self {
        self.leaf(NodeKind::Condition(alloc::sync::Arc::new(c)), name)
    }
    /// A sync action from a closure of the context.
    pub fn action(self, name: &str, f: impl Fn(&mut C) -> Status + Send + Sync + 'static) -> Self {
        self.leaf(NodeKind::ActionFn(Box::new(f)), name)
    }
    /// A sync action from an [`Action`] object.
    pub fn action_node(self, name: &str, a: impl Action<C> + 'static) -> Self {
        self.leaf(NodeKind::Action(alloc::sync::Arc::new(a)), name)
    }
    /// A stateful action: `make` builds one object per tree instance.
    pub fn stateful<S, F>(self, name: &str, make: F) -> Self
    where
        S: StatefulAction<C> + 'static,
        F: Fn() -> S + Send + Sync + 'static,
    {
        let factory = move || -> Box<dyn StatefulAction<C>> { Box::new(make()) };
        self.leaf(NodeKind::Stateful(Box::new(factory)), name)
    }
    /// An [async action](crate::nodes::leaf::async_action): on each start, `start` reads
    /// what it needs from the handle and returns the future that does the work; the future
    /// is polled once per tick and dropped when the node is halted. Each start allocates
    /// once, to box the future.
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Status, Tree};
    ///
    /// let blueprint = Blueprint::<u32>::builder()
    ///     .async_action("double", |h| {
    ///         let n = *h.ctx();
    ///         async move { if n * 2 > 5 { Status::Success } else { Status::Failure } }
    ///     })
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut 3), Ok(Status::Success));
    /// ```
    pub fn async_action<F, Fut>(self, name: &str, start: F) -> Self
    where
        F: Fn(&mut crate::Handle<'_, C>) -> Fut + Send + Sync + 'static,
        Fut: Future<Output = Status> + Send + 'static,
    {
        self.async_action_node(name, AsyncFn(start))
    }
    /// An async action from an [`AsyncAction`] object.
    pub fn async_action_node(self, name: &str, a: impl AsyncAction<C> + 'static) -> Self {
        self.leaf(NodeKind::Async(Box::new(a)), name)
    }
    /// A user-defined control or decorator.
    pub fn custom(
        self,
        name: &str,
        spec: CustomSpec<C>,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::Custom(Box::new(spec)), name, children)
    }
}

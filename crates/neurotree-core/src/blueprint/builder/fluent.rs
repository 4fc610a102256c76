//! The fluent half of the [`Builder`]: a named method per built-in node, each a thin call
//! of [`Builder::node`] or [`Builder::leaf`] with the node's kind.

use alloc::boxed::Box;
use core::future::Future;
use core::time::Duration;

use super::Builder;
use crate::blueprint::{CustomSpec, NodeKind, ParallelPolicy, SubTreeScope};
use crate::nodes::leaf::async_action::AsyncFn;
use crate::nodes::leaf::{Action, AsyncAction, Condition, StatefulAction};
use crate::Status;

/// One method per built-in node: the controls, then the decorators, then the leaves, in the
/// order of the [node catalog](crate::nodes).
impl<C> Builder<C> {
    /// A [Sequence](crate::nodes::control::sequence).
    pub fn sequence(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Sequence, name, children)
    }
    /// A [SequenceWithMemory](crate::nodes::control::sequence).
    pub fn sequence_with_memory(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::SequenceWithMemory, name, children)
    }
    /// A [ReactiveSequence](crate::nodes::control::reactive).
    pub fn reactive_sequence(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ReactiveSequence, name, children)
    }
    /// A [Fallback](crate::nodes::control::fallback) (Colledanchise & Ögren's Selector).
    pub fn fallback(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Fallback, name, children)
    }
    /// A [Fallback](Self::fallback), under the name Colledanchise & Ögren and many libraries
    /// give it.
    pub fn selector(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.fallback(name, children)
    }
    /// A [ReactiveFallback](crate::nodes::control::reactive).
    pub fn reactive_fallback(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ReactiveFallback, name, children)
    }
    /// An [AsyncSequence](crate::nodes::control::sequence).
    pub fn async_sequence(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::AsyncSequence, name, children)
    }
    /// An [AsyncFallback](crate::nodes::control::fallback).
    pub fn async_fallback(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::AsyncFallback, name, children)
    }
    /// A [Parallel](crate::nodes::control::parallel) with BehaviorTree.CPP's thresholds.
    pub fn parallel(
        self,
        name: &str,
        success: i32,
        failure: i32,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        let policy = ParallelPolicy::Thresholds { success, failure };
        self.node(NodeKind::Parallel(policy), name, children)
    }
    /// A [Parallel](crate::nodes::control::parallel) with a [`ParallelPolicy`]: thresholds, or
    /// one of the shorthands `RequireAll`, `RequireOne`, `RequireCount(M)`.
    pub fn parallel_policy(
        self,
        name: &str,
        policy: ParallelPolicy,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::Parallel(policy), name, children)
    }
    /// A [ParallelAll](crate::nodes::control::parallel_all).
    pub fn parallel_all(
        self,
        name: &str,
        max_failures: i32,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(
            NodeKind::ParallelAll {
                max_failures: max_failures.into(),
            },
            name,
            children,
        )
    }
    /// An [IfThenElse](crate::nodes::control::if_then_else).
    pub fn if_then_else(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::IfThenElse, name, children)
    }
    /// A [WhileDoElse](crate::nodes::control::while_do_else).
    pub fn while_do_else(self, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::WhileDoElse, name, children)
    }
    /// A [TryCatch](crate::nodes::control::try_catch).
    pub fn try_catch(
        self,
        name: &str,
        catch_on_halt: bool,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(
            NodeKind::TryCatch {
                catch_on_halt: catch_on_halt.into(),
            },
            name,
            children,
        )
    }
    /// An [Inverter](crate::nodes::decorator::inverter).
    pub fn inverter(self, name: &str, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Inverter, name, child)
    }
    /// A [ForceSuccess](crate::nodes::decorator::force).
    pub fn force_success(self, name: &str, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ForceSuccess, name, child)
    }
    /// A [ForceFailure](crate::nodes::decorator::force).
    pub fn force_failure(self, name: &str, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::ForceFailure, name, child)
    }
    /// A [Repeat](crate::nodes::decorator::repeat); exactly `-1` repeats forever, another
    /// negative count runs no cycle.
    pub fn repeat(self, name: &str, num_cycles: i32, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(
            NodeKind::Repeat {
                num_cycles: num_cycles.into(),
            },
            name,
            child,
        )
    }
    /// A [RetryUntilSuccessful](crate::nodes::decorator::retry); exactly `-1` retries forever,
    /// another negative count makes no attempt.
    pub fn retry(self, name: &str, num_attempts: i32, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(
            NodeKind::RetryUntilSuccessful {
                num_attempts: num_attempts.into(),
            },
            name,
            child,
        )
    }
    /// A [KeepRunningUntilFailure](crate::nodes::decorator::keep_running).
    pub fn keep_running_until_failure(self, name: &str, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::KeepRunningUntilFailure, name, child)
    }
    /// A [Delay](crate::nodes::decorator::delay).
    pub fn delay(self, name: &str, delay: Duration, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Delay(delay.into()), name, child)
    }
    /// A [Timeout](crate::nodes::decorator::timeout).
    pub fn timeout(self, name: &str, limit: Duration, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Timeout(limit.into()), name, child)
    }
    /// A [Cooldown](crate::nodes::decorator::cooldown).
    pub fn cooldown(self, name: &str, period: Duration, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(NodeKind::Cooldown(period.into()), name, child)
    }
    /// A [RunOnce](crate::nodes::decorator::run_once).
    pub fn run_once(self, name: &str, then_skip: bool, child: impl FnOnce(Self) -> Self) -> Self {
        self.node(
            NodeKind::RunOnce {
                then_skip: then_skip.into(),
            },
            name,
            child,
        )
    }
    /// A [SubTree](crate::nodes::decorator::subtree): its child sees its own blackboard scope.
    pub fn subtree(
        self,
        name: &str,
        scope: SubTreeScope,
        child: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::SubTree(Box::new(scope)), name, child)
    }
    /// An [AlwaysSuccess](crate::nodes::leaf::always) leaf.
    pub fn always_success(self, name: &str) -> Self {
        self.leaf(NodeKind::AlwaysSuccess, name)
    }
    /// An [AlwaysFailure](crate::nodes::leaf::always) leaf.
    pub fn always_failure(self, name: &str) -> Self {
        self.leaf(NodeKind::AlwaysFailure, name)
    }
    /// A [Sleep](crate::nodes::leaf::sleep) leaf.
    pub fn sleep(self, name: &str, duration: Duration) -> Self {
        self.leaf(NodeKind::Sleep(duration.into()), name)
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

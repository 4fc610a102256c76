//! What a node is: the closed set of built-in kinds plus the open doors for user leaves and
//! user control nodes.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::sync::Arc;
use alloc::vec::Vec;
use core::fmt;
use core::time::Duration;

use crate::nodes::custom::CustomNode;
use crate::nodes::leaf::{Action, AsyncAction, Condition, StatefulAction};
use crate::Status;

/// A closure condition: a pure function of the user's context.
pub type ConditionFn<C> = Box<dyn Fn(&C) -> bool + Send + Sync>;
/// A closure sync action: may change the context, must complete in one tick.
pub type ActionFn<C> = Box<dyn Fn(&mut C) -> Status + Send + Sync>;
/// Makes one per-instance object of a stateful leaf.
pub type StatefulFactory<C> = Box<dyn Fn() -> Box<dyn StatefulAction<C>> + Send + Sync>;
/// Makes one per-instance object of a user control or decorator.
pub type CustomFactory<C> = Box<dyn Fn() -> Box<dyn CustomNode<C>> + Send + Sync>;

/// A built-in node's parameter (Repeat's `num_cycles`, Timeout's `msec`, ...): a value
/// fixed when the tree was built, or read from the node's port of that name each time the
/// node needs it, as BehaviorTree.CPP's `getInput` does, so that `num_cycles="{n}"` follows
/// the blackboard entry `n`. A value costs no look-up when the node ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param<T> {
    /// A value known when the tree was built (a literal in XML, a number in the builder).
    Value(T),
    /// Read from the node's port of the parameter's name (bound to an entry) at each use.
    Port,
}

impl<T> From<T> for Param<T> {
    fn from(value: T) -> Self {
        Param::Value(value)
    }
}

impl<T: fmt::Display> fmt::Display for Param<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Param::Value(v) => write!(f, "{v}"),
            Param::Port => f.write_str("port"),
        }
    }
}

/// How a Parallel node decides, before its number of children is known.
///
/// Thresholds follow BehaviorTree.CPP: a negative threshold `t` means `N + t + 1`, so `-1`
/// means "all children". `RequireAll`, `RequireOne` and `RequireCount` are shorthands for
/// thresholds, resolved when the node closes and its number of children is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParallelPolicy {
    /// Success once `success` children succeeded; Failure once `failure` failed or success
    /// became impossible.
    Thresholds {
        /// Successes needed (negative: counted from the number of children).
        success: i32,
        /// Failures that end it (negative: counted from the number of children).
        failure: i32,
    },
    /// Thresholds of which at least one is read from the node's `success_count` or
    /// `failure_count` port at each tick, as BehaviorTree.CPP reads them; checked against
    /// the number of children then rather than when the tree is built.
    Ports {
        /// Successes needed (negative: counted from the number of children).
        success: Param<i32>,
        /// Failures that end it (negative: counted from the number of children).
        failure: Param<i32>,
    },
    /// Every child must succeed; the first failure fails the node: `(-1, 1)`.
    RequireAll,
    /// The first success succeeds; fails only when all failed: `(1, -1)`.
    RequireOne,
    /// `M` successes needed: `(M, N - M + 1)`.
    RequireCount(u32),
}

impl Default for ParallelPolicy {
    /// BehaviorTree.CPP's defaults: `success_count = -1`, `failure_count = 1`.
    fn default() -> Self {
        ParallelPolicy::Thresholds {
            success: -1,
            failure: 1,
        }
    }
}

/// How many children a kind of node accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arity {
    /// No children.
    Leaf,
    /// Exactly one child.
    One,
    /// Between `min` and `max` children, inclusive.
    Range {
        /// Fewest children.
        min: u32,
        /// Most children.
        max: u32,
    },
    /// At least this many children.
    AtLeast(u32),
}

impl Arity {
    /// `true` if a node of this arity may have `n` children.
    pub fn accepts(self, n: u32) -> bool {
        match self {
            Arity::Leaf => n == 0,
            Arity::One => n == 1,
            Arity::Range { min, max } => (min..=max).contains(&n),
            Arity::AtLeast(min) => n >= min,
        }
    }
}

impl fmt::Display for Arity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Arity::Leaf => f.write_str("no children"),
            Arity::One => f.write_str("exactly 1 child"),
            Arity::Range { min, max } if min == max => write!(f, "exactly {min} children"),
            Arity::Range { min, max } => write!(f, "{min} to {max} children"),
            Arity::AtLeast(1) => f.write_str("at least 1 child"),
            Arity::AtLeast(n) => write!(f, "at least {n} children"),
        }
    }
}

/// The blackboard scope a SubTree opens for its child.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SubTreeScope {
    /// `(child_key, parent_key)`: the child's key is an alias of the parent's.
    pub remap: Vec<(String, String)>,
    /// Keys the child does not define resolve in the parent (except `_private` ones).
    pub autoremap: bool,
    /// `(child_key, text)`: entries the child scope starts with, as text (a literal port
    /// of a SubTree in XML); readers convert them to their type. Always stored in the child
    /// scope itself, never through `autoremap` in the parent.
    pub values: Vec<(String, String)>,
}

/// A user-defined control or decorator: its arity, its type name and how to make it.
pub struct CustomSpec<C> {
    /// The type name shown in paths and pictures (e.g. `ManualSelector`).
    pub type_name: String,
    /// How many children it accepts.
    pub arity: Arity,
    /// Makes the per-instance object.
    pub factory: CustomFactory<C>,
}

/// Which of its blueprint's shared [`Condition`] objects a
/// [`NodeKind::SharedCondition`] calls; only a [`Builder`](crate::Builder) makes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shared(pub(crate) u32);

impl Shared {
    /// Its place in the blueprint's table.
    pub(crate) fn index(self) -> usize {
        self.0 as usize
    }
}

/// Every kind of node the engine ticks.
///
/// The first group are BehaviorTree.CPP's built-in nodes with its semantics (see each node's
/// module under `nodes/`); the last group are the doors for user code.
#[non_exhaustive]
// A plain byte tag: the tick loop decodes it with one load instead of a niche computation.
#[repr(u8)]
pub enum NodeKind<C> {
    /// Ticks children in order, resuming at the running one; see [`crate::nodes::control::sequence`].
    Sequence,
    /// Sequence that keeps its place after a failure and a halt.
    SequenceWithMemory,
    /// Sequence that restarts from the first child every tick.
    ReactiveSequence,
    /// Tries children in order until one succeeds.
    Fallback,
    /// Fallback that restarts from the first child every tick.
    ReactiveFallback,
    /// Sequence that yields after each child that completes at once.
    AsyncSequence,
    /// Fallback that yields after each child that completes at once.
    AsyncFallback,
    /// Ticks all children, deciding by thresholds.
    Parallel(ParallelPolicy),
    /// Ticks all children to completion; fails if `max_failures` of them failed.
    ParallelAll {
        /// Failures that make it fail (negative: counted from the number of children).
        max_failures: Param<i32>,
    },
    /// `if` child 0 `then` child 1 `else` child 2.
    IfThenElse,
    /// Re-checks child 0 every tick and runs child 1 or 2.
    WhileDoElse,
    /// Children but the last as a Sequence; the last runs on failure.
    TryCatch {
        /// Run the catch child when halted while trying.
        catch_on_halt: Param<bool>,
    },
    /// Swaps Success and Failure.
    Inverter,
    /// Turns a completed child into Success.
    ForceSuccess,
    /// Turns a completed child into Failure.
    ForceFailure,
    /// Repeats a succeeding child.
    Repeat {
        /// Cycles to run; -1 forever, another negative value none.
        num_cycles: Param<i32>,
    },
    /// Retries a failing child.
    RetryUntilSuccessful {
        /// Attempts to make; -1 forever, another negative value none.
        num_attempts: Param<i32>,
    },
    /// Success becomes Running; Failure ends it.
    KeepRunningUntilFailure,
    /// Waits, then ticks the child.
    Delay(Param<Duration>),
    /// Fails and halts the child when it runs too long.
    Timeout(Param<Duration>),
    /// After the child completes, fails without ticking it for a while.
    Cooldown(Param<Duration>),
    /// Runs the child to completion once.
    RunOnce {
        /// After the first completion return Skipped (true) or the cached status (false).
        then_skip: Param<bool>,
    },
    /// Opens a blackboard scope for its child.
    SubTree(Box<SubTreeScope>),
    /// Always Success.
    AlwaysSuccess,
    /// Always Failure.
    AlwaysFailure,
    /// Running until the duration has passed, then Success.
    Sleep(Param<Duration>),
    /// A closure of the context that never runs.
    ConditionFn(ConditionFn<C>),
    /// A [`Condition`] object, shared by all instances.
    Condition(Arc<dyn Condition<C>>),
    /// A [`Condition`] object its blueprint holds once for every node that calls it, made
    /// by [`Builder::open_shared_condition`](crate::Builder::open_shared_condition):
    /// making such a node clones no `Arc`.
    SharedCondition(Shared),
    /// A closure sync action.
    ActionFn(ActionFn<C>),
    /// An [`Action`] object, shared by all instances.
    Action(Arc<dyn Action<C>>),
    /// A [`StatefulAction`], one object per instance.
    Stateful(StatefulFactory<C>),
    /// An [`AsyncAction`], shared by all instances; each instance keeps its running future.
    Async(Box<dyn AsyncAction<C>>),
    /// A user control or decorator, one object per instance.
    Custom(Box<CustomSpec<C>>),
}

impl<C> NodeKind<C> {
    /// The kind's type name, as BehaviorTree.CPP's XML spells it.
    pub fn type_name(&self) -> &str {
        match self {
            NodeKind::Sequence => "Sequence",
            NodeKind::SequenceWithMemory => "SequenceWithMemory",
            NodeKind::ReactiveSequence => "ReactiveSequence",
            NodeKind::Fallback => "Fallback",
            NodeKind::ReactiveFallback => "ReactiveFallback",
            NodeKind::AsyncSequence => "AsyncSequence",
            NodeKind::AsyncFallback => "AsyncFallback",
            NodeKind::Parallel(_) => "Parallel",
            NodeKind::ParallelAll { .. } => "ParallelAll",
            NodeKind::IfThenElse => "IfThenElse",
            NodeKind::WhileDoElse => "WhileDoElse",
            NodeKind::TryCatch { .. } => "TryCatch",
            NodeKind::Inverter => "Inverter",
            NodeKind::ForceSuccess => "ForceSuccess",
            NodeKind::ForceFailure => "ForceFailure",
            NodeKind::Repeat { .. } => "Repeat",
            NodeKind::RetryUntilSuccessful { .. } => "RetryUntilSuccessful",
            NodeKind::KeepRunningUntilFailure => "KeepRunningUntilFailure",
            NodeKind::Delay(_) => "Delay",
            NodeKind::Timeout(_) => "Timeout",
            NodeKind::Cooldown(_) => "Cooldown",
            NodeKind::RunOnce { .. } => "RunOnce",
            NodeKind::SubTree(_) => "SubTree",
            NodeKind::AlwaysSuccess => "AlwaysSuccess",
            NodeKind::AlwaysFailure => "AlwaysFailure",
            NodeKind::Sleep(_) => "Sleep",
            NodeKind::ConditionFn(_) | NodeKind::Condition(_) | NodeKind::SharedCondition(_) => {
                "Condition"
            }
            NodeKind::ActionFn(_) | NodeKind::Action(_) => "Action",
            NodeKind::Stateful(_) => "StatefulAction",
            NodeKind::Async(_) => "AsyncAction",
            NodeKind::Custom(spec) => &spec.type_name,
        }
    }

    /// The broad family: `Control`, `Decorator`, `Condition`, `Action` or `SubTree`, as the
    /// `TreeNodesModel` of BehaviorTree.CPP names them.
    pub fn category(&self) -> Category {
        match self.arity() {
            Arity::Leaf => match self {
                NodeKind::ConditionFn(_)
                | NodeKind::Condition(_)
                | NodeKind::SharedCondition(_) => Category::Condition,
                _ => Category::Action,
            },
            Arity::One => match self {
                NodeKind::SubTree(_) => Category::SubTree,
                _ => Category::Decorator,
            },
            Arity::Range { .. } | Arity::AtLeast(_) => Category::Control,
        }
    }

    /// How many children the kind accepts.
    pub fn arity(&self) -> Arity {
        match self {
            NodeKind::Sequence
            | NodeKind::SequenceWithMemory
            | NodeKind::ReactiveSequence
            | NodeKind::Fallback
            | NodeKind::ReactiveFallback
            | NodeKind::AsyncSequence
            | NodeKind::AsyncFallback
            | NodeKind::Parallel(_)
            | NodeKind::ParallelAll { .. } => Arity::AtLeast(1),
            NodeKind::IfThenElse | NodeKind::WhileDoElse => Arity::Range { min: 2, max: 3 },
            NodeKind::TryCatch { .. } => Arity::AtLeast(2),
            NodeKind::Inverter
            | NodeKind::ForceSuccess
            | NodeKind::ForceFailure
            | NodeKind::Repeat { .. }
            | NodeKind::RetryUntilSuccessful { .. }
            | NodeKind::KeepRunningUntilFailure
            | NodeKind::Delay(_)
            | NodeKind::Timeout(_)
            | NodeKind::Cooldown(_)
            | NodeKind::RunOnce { .. }
            | NodeKind::SubTree(_) => Arity::One,
            NodeKind::AlwaysSuccess
            | NodeKind::AlwaysFailure
            | NodeKind::Sleep(_)
            | NodeKind::ConditionFn(_)
            | NodeKind::Condition(_)
            | NodeKind::SharedCondition(_)
            | NodeKind::ActionFn(_)
            | NodeKind::Action(_)
            | NodeKind::Stateful(_)
            | NodeKind::Async(_) => Arity::Leaf,
            NodeKind::Custom(spec) => spec.arity,
        }
    }

    /// `true` for kinds with a per-instance object (stateful leaves, custom nodes, the
    /// running future of an async action).
    pub(crate) fn has_object(&self) -> bool {
        matches!(
            self,
            NodeKind::Stateful(_) | NodeKind::Custom(_) | NodeKind::Async(_)
        )
    }

    /// Per-instance state slots (`u64`) the kind needs: a cursor, a counter or a time.
    pub(crate) fn aux_slots(&self) -> u32 {
        match self {
            NodeKind::Sequence
            | NodeKind::SequenceWithMemory
            | NodeKind::Fallback
            | NodeKind::AsyncSequence
            | NodeKind::AsyncFallback
            | NodeKind::ReactiveSequence
            | NodeKind::ReactiveFallback
            | NodeKind::IfThenElse
            | NodeKind::TryCatch { .. }
            | NodeKind::Parallel(_)
            | NodeKind::Repeat { .. }
            | NodeKind::RetryUntilSuccessful { .. }
            | NodeKind::Delay(_)
            | NodeKind::Timeout(_)
            | NodeKind::Cooldown(_)
            | NodeKind::RunOnce { .. }
            | NodeKind::Sleep(_) => 1,
            _ => 0,
        }
    }
}

impl<C> fmt::Debug for NodeKind<C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NodeKind::Parallel(p) => write!(f, "Parallel({p:?})"),
            NodeKind::ParallelAll { max_failures } => {
                write!(f, "ParallelAll {{ max_failures: {max_failures} }}")
            }
            NodeKind::TryCatch { catch_on_halt } => {
                write!(f, "TryCatch {{ catch_on_halt: {catch_on_halt} }}")
            }
            NodeKind::Repeat { num_cycles } => write!(f, "Repeat {{ num_cycles: {num_cycles} }}"),
            NodeKind::RetryUntilSuccessful { num_attempts } => {
                write!(f, "RetryUntilSuccessful {{ num_attempts: {num_attempts} }}")
            }
            NodeKind::Delay(d) => write!(f, "Delay({d:?})"),
            NodeKind::Timeout(d) => write!(f, "Timeout({d:?})"),
            NodeKind::Cooldown(d) => write!(f, "Cooldown({d:?})"),
            NodeKind::Sleep(d) => write!(f, "Sleep({d:?})"),
            NodeKind::RunOnce { then_skip } => write!(f, "RunOnce {{ then_skip: {then_skip} }}"),
            NodeKind::SubTree(s) => write!(f, "SubTree({s:?})"),
            other => f.write_str(other.type_name()),
        }
    }
}

/// The broad family of a node, as BehaviorTree.CPP's `TreeNodesModel` names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Category {
    /// Has one or more children and decides which to tick.
    Control,
    /// Has exactly one child and changes its outcome.
    Decorator,
    /// A leaf that checks and never runs.
    Condition,
    /// A leaf that acts.
    Action,
    /// Opens a blackboard scope for a child tree.
    SubTree,
}

impl Category {
    /// The XML element name of the family.
    pub const fn as_str(self) -> &'static str {
        match self {
            Category::Control => "Control",
            Category::Decorator => "Decorator",
            Category::Condition => "Condition",
            Category::Action => "Action",
            Category::SubTree => "SubTree",
        }
    }
}

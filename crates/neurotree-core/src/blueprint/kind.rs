//! What a node is: the closed set of built-in kinds plus the open doors for user leaves and
//! user control nodes.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::sync::Arc;
use alloc::vec::Vec;
use core::fmt;

use super::{BuildErrorKind, PortBinding, PortBindingError};
use crate::nodes::built_in::{BuiltIn, Tick};
use crate::nodes::custom::CustomNode;
use crate::nodes::leaf::{Action, AsyncAction, Condition, StatefulAction};
use crate::nodes::NodeDecl;
use crate::Status;

/// A closure condition: a pure function of the user's context (any
/// `Fn(&C) -> bool + Send + Sync`, boxed).
pub type ConditionFn<C> = Box<dyn super::ConditionClosure<C>>;
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

/// A user-defined node (a control, a decorator, or a leaf that keeps state in `self`): its
/// arity, its type name, its family and how to make it.
pub struct CustomSpec<C> {
    /// The type name shown in paths and pictures (e.g. `ManualSelector`).
    pub type_name: String,
    /// How many children it accepts.
    pub arity: Arity,
    /// The family it is listed, drawn and saved as ([`NodeKind::category`]): what
    /// [`CustomSpec::new`] derives from the arity, or a leaf's [`Category::Condition`].
    pub category: Category,
    /// Makes the per-instance object.
    pub factory: CustomFactory<C>,
}

impl<C> CustomSpec<C> {
    /// A node of `arity` children, of the family that arity implies: a leaf is an
    /// [`Action`](Category::Action), one child a [`Decorator`](Category::Decorator), more a
    /// [`Control`](Category::Control). A leaf that only checks is made a condition with
    /// [`in_category`](Self::in_category).
    pub fn new(type_name: impl Into<String>, arity: Arity, factory: CustomFactory<C>) -> Self {
        let category = match arity {
            Arity::Leaf => Category::Action,
            Arity::One => Category::Decorator,
            Arity::Range { .. } | Arity::AtLeast(_) => Category::Control,
        };
        CustomSpec {
            type_name: type_name.into(),
            arity,
            category,
            factory,
        }
    }

    /// The same node listed, drawn and saved as `category` (a leaf that only checks as a
    /// [`Condition`](Category::Condition), as BehaviorTree.CPP's model of it says).
    pub fn in_category(mut self, category: Category) -> Self {
        self.category = category;
        self
    }
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

/// The user leaves' kinds, as one pattern: the seven doors for leaf code.
macro_rules! user_leaves {
    () => {
        NodeKind::ConditionFn(_)
            | NodeKind::Condition(_)
            | NodeKind::SharedCondition(_)
            | NodeKind::ActionFn(_)
            | NodeKind::Action(_)
            | NodeKind::Stateful(_)
            | NodeKind::Async(_)
    };
}

/// Every kind that is not a built-in (SubTree, the user leaves, custom nodes), as one
/// pattern: what the matches that only ask the built-ins answer for the rest at once.
macro_rules! doors {
    () => {
        NodeKind::SubTree(_) | user_leaves!() | NodeKind::Custom(_)
    };
}

/// Makes [`NodeKind`] and its matches from [the list of built-ins](crate::nodes): a
/// variant per built-in, carrying the node's own type, beside the engine's doors (SubTree,
/// the leaf kinds, custom nodes), each match listing every variant.
macro_rules! node_kinds {
    ($($name:ident in $($module:ident)::+;)*) => {
        /// Every kind of node the engine ticks.
        ///
        /// The first group are BehaviorTree.CPP's built-in nodes with its semantics, each
        /// carrying its node's type (see each node's module under [`nodes`](crate::nodes));
        /// the last group are the doors for user code.
        #[non_exhaustive]
        // A plain byte tag: the tick loop decodes it with one load instead of a niche
        // computation.
        #[repr(u8)]
        pub enum NodeKind<C> {
            $(
                #[doc = concat!("The built-in node `", stringify!($name), "`.")]
                $name(crate::nodes::$($module::)+$name),
            )*
            /// Opens a blackboard scope for its child.
            SubTree(Box<SubTreeScope>),
            /// A closure of the context that never runs.
            ConditionFn(ConditionFn<C>),
            /// A [`Condition`] object, shared by all instances.
            Condition(Arc<dyn Condition<C>>),
            /// A [`Condition`] object its blueprint holds once for every node that calls it,
            /// made by [`Builder::open_shared_condition`](crate::Builder::open_shared_condition):
            /// making such a node clones no `Arc`.
            SharedCondition(Shared),
            /// A closure sync action.
            ActionFn(ActionFn<C>),
            /// An [`Action`] object, shared by all instances.
            Action(Arc<dyn Action<C>>),
            /// A [`StatefulAction`], one object per instance.
            Stateful(StatefulFactory<C>),
            /// An [`AsyncAction`], shared by all instances; each instance keeps its running
            /// future.
            Async(Box<dyn AsyncAction<C>>),
            /// A user control or decorator, one object per instance.
            Custom(Box<CustomSpec<C>>),
        }

        impl<C> NodeKind<C> {
            /// The kind's type name, as BehaviorTree.CPP's XML spells it.
            pub fn type_name(&self) -> &str {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::DECL.name,)*
                    NodeKind::SubTree(_) => "SubTree",
                    NodeKind::ConditionFn(_)
                    | NodeKind::Condition(_)
                    | NodeKind::SharedCondition(_) => "Condition",
                    NodeKind::ActionFn(_) | NodeKind::Action(_) => "Action",
                    NodeKind::Stateful(_) => "StatefulAction",
                    NodeKind::Async(_) => "AsyncAction",
                    NodeKind::Custom(spec) => &spec.type_name,
                }
            }

            /// How many children the kind accepts.
            pub fn arity(&self) -> Arity {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::DECL.arity,)*
                    NodeKind::SubTree(_) => Arity::One,
                    NodeKind::Custom(spec) => spec.arity,
                    user_leaves!() => Arity::Leaf,
                }
            }

            /// The broad family: `Control`, `Decorator`, `Condition`, `Action` or
            /// `SubTree`, as the `TreeNodesModel` of BehaviorTree.CPP names them.
            pub fn category(&self) -> Category {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::DECL.category,)*
                    NodeKind::SubTree(_) => Category::SubTree,
                    NodeKind::ConditionFn(_)
                    | NodeKind::Condition(_)
                    | NodeKind::SharedCondition(_) => Category::Condition,
                    NodeKind::ActionFn(_)
                    | NodeKind::Action(_)
                    | NodeKind::Stateful(_)
                    | NodeKind::Async(_) => Category::Action,
                    NodeKind::Custom(spec) => spec.category,
                }
            }

            /// The declaration of a built-in kind; `None` for SubTree and the doors for user
            /// code.
            pub fn decl(&self) -> Option<&'static NodeDecl> {
                match self {
                    $(NodeKind::$name(_) => Some(<crate::nodes::$($module::)+$name as Tick>::DECL),)*
                    doors!() => None,
                }
            }

            /// What a built-in kind says of itself (its family, outcomes, port values);
            /// `None` for SubTree and the doors for user code.
            pub fn built_in(&self) -> Option<&dyn BuiltIn> {
                match self {
                    $(NodeKind::$name(node) => Some(node),)*
                    doors!() => None,
                }
            }

            /// Whether the node passes a Running child's tick straight through (see
            /// [`Tick::passes_through`]).
            pub(crate) fn passes_through(&self) -> bool {
                match self {
                    $(NodeKind::$name(node) => node.passes_through(),)*
                    doors!() => false,
                }
            }

            /// Per-instance 32-bit state slots a node of this kind with `children` children
            /// takes: one for a cursor, a counter or a flag, two for a 64-bit value (see
            /// [`Tick::aux_slots`]).
            pub(crate) fn aux_slots(&self, children: u32) -> u32 {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::aux_slots(children),)*
                    doors!() => 0,
                }
            }

            /// A node's state, its slots read as one value, as a saved state stores it (see
            /// [`Tick::saved_aux`]).
            pub(crate) fn saved_aux(&self, value: u64, children: u32) -> u64 {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::saved_aux(value, children),)*
                    doors!() => value,
                }
            }

            /// The inverse of [`saved_aux`](Self::saved_aux); `None` for a value no node of
            /// the kind keeps (see [`Tick::restored_aux`]).
            pub(crate) fn restored_aux(&self, saved: u64, children: u32) -> Option<u64> {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::restored_aux(saved, children),)*
                    doors!() => Some(saved),
                }
            }

            /// `true` for the kinds that re-check their children every tick and so ask
            /// whether the leaves under them read only what wakes the tree (see
            /// [`Tick::RECHECKS`]).
            pub(crate) fn rechecks(&self) -> bool {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::RECHECKS,)*
                    NodeKind::SubTree(_)
                    | NodeKind::ConditionFn(_)
                    | NodeKind::Condition(_)
                    | NodeKind::SharedCondition(_)
                    | NodeKind::ActionFn(_)
                    | NodeKind::Action(_)
                    | NodeKind::Stateful(_)
                    | NodeKind::Async(_)
                    | NodeKind::Custom(_) => false,
                }
            }

            /// `Some(true)` for a plain Sequence, `Some(false)` for a plain Fallback (see
            /// [`Tick::PLAIN_ORDER`]).
            pub(crate) fn plain_order(&self) -> Option<bool> {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::PLAIN_ORDER,)*
                    doors!() => None,
                }
            }

            /// `true` for a kind whose halt may wait for the halts below it (see
            /// [`Tick::WAITS_ON_HALTS`]).
            pub(crate) fn waits_on_halts(&self) -> bool {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::WAITS_ON_HALTS,)*
                    doors!() => false,
                }
            }

            /// A state slot saved at clock reading `saved`, for a clock at `now` (see
            /// [`Tick::shift_aux`]).
            pub(crate) fn shift_aux(&self, aux: u64, saved: u64, now: u64) -> u64 {
                match self {
                    $(NodeKind::$name(_) => <crate::nodes::$($module::)+$name as Tick>::shift_aux(aux, saved, now),)*
                    doors!() => aux,
                }
            }

            /// Checks a built-in once its number of children is known (see [`Tick::close`]).
            pub(crate) fn close(&mut self, children: u32) -> Result<(), BuildErrorKind> {
                match self {
                    $(NodeKind::$name(node) => node.close(children),)*
                    doors!() => Ok(()),
                }
            }

            /// The built-in kind named `name` with its ports bound by `port`; `Ok(None)` if
            /// no built-in of the engine has that name.
            pub(crate) fn make(
                name: &str,
                port: &dyn Fn(&str) -> PortBinding,
            ) -> Result<Option<Self>, PortBindingError> {
                $(
                    if name == <crate::nodes::$($module::)+$name as Tick>::DECL.name {
                        return <crate::nodes::$($module::)+$name as Tick>::from_ports(port)
                            .map(|node| Some(NodeKind::$name(node)));
                    }
                )*
                Ok(None)
            }
        }

        impl<C> fmt::Debug for NodeKind<C> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                match self {
                    $(NodeKind::$name(node) => fmt::Debug::fmt(node, f),)*
                    NodeKind::SubTree(s) => write!(f, "SubTree({s:?})"),
                    user_leaves!() | NodeKind::Custom(_) => f.write_str(self.type_name()),
                }
            }
        }

    };
}

crate::nodes::with_built_ins!(node_kinds);

impl<C> NodeKind<C> {
    /// `true` for kinds with a per-instance object (stateful leaves, custom nodes, the
    /// running future of an async action).
    pub(crate) fn has_object(&self) -> bool {
        matches!(
            self,
            NodeKind::Stateful(_) | NodeKind::Custom(_) | NodeKind::Async(_)
        )
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

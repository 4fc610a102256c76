//! What a built-in node's file says about the node beside its [`NodeDecl`]: how it is made
//! from its ports and written back, what it may return, how it ticks and halts.
//!
//! Each built-in is a type of its own (`Sequence`, `Repeat { num_cycles }`, ...) that carries
//! the node's configuration and implements two traits in the node's file:
//!
//! - [`BuiltIn`], public: what pictures, coverage, failure reasons and the XML writer ask of
//!   a node (its family of control, its ports' values);
//! - `Tick`, the engine's: its declaration, state slots, how it is made from its ports and
//!   checked once its children are known, its tick and its halt.
//!
//! The [one list](super) turns the types into the variants of
//! [`NodeKind`](crate::NodeKind), its dispatch and every other match over node kinds, so a
//! new built-in is its file and one line there.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

use crate::blueprint::{BuildErrorKind, NodeDef, PortBinding, PortBindingError};
use crate::nodes::NodeDecl;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

/// The family of control a built-in belongs to: what pictures mark it with (→, ?, ⇉) and how
/// a failure is explained through it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Children in turn, all must succeed (the Sequence family).
    Sequential,
    /// Children in turn until one succeeds: each failure is an alternative tried (the
    /// Fallback family).
    Alternative,
    /// Children ticked side by side (the Parallel family).
    Concurrent,
}

/// What the rest of the library asks of a built-in node, implemented in the node's file.
pub trait BuiltIn: fmt::Debug + Send + Sync + 'static {
    /// The family of control it belongs to, if one of the well-known ones.
    fn family(&self) -> Option<Family> {
        None
    }

    /// Why it fails when none of its children did (an Inverter whose child succeeded), as
    /// [`Tree::last_failure`](crate::Tree::last_failure) says it; `None` for a node that
    /// fails only through a child, or that gives its own reason when it fails.
    fn failed_alone(&self) -> Option<&'static str> {
        None
    }

    /// Its parameters as a file writes them, in the order of its declared ports; `None`
    /// for one read from a port (the writer writes the binding instead). `children`
    /// resolves shorthands that depend on their number.
    fn port_values(&self, children: usize) -> Vec<Option<String>> {
        let _ = children;
        Vec::new()
    }
}

/// The engine's side of a built-in node: its declaration, state, making, tick and halt.
pub(crate) trait Tick: BuiltIn + Sized {
    /// Its declaration.
    const DECL: &'static NodeDecl;
    /// Per-instance state slots, of 32 bits: one for a cursor, a counter or a flag; two for
    /// a 64-bit value (a moment), read through [`Ticker::aux64`](crate::tree::Ticker::aux64).
    const AUX_SLOTS: u32 = 0;
    /// `Some(true)` for the plain Sequence, `Some(false)` for the plain Fallback: controls a
    /// parent's loop ticks without the dispatcher (`ordered`'s fast paths).
    const PLAIN_ORDER: Option<bool> = None;
    /// `true` for a node whose halt may wait for the halts below it before it runs code of
    /// its own (TryCatch's catch); see [`slow_halt`](crate::tree::slow_halt).
    const WAITS_ON_HALTS: bool = false;
    /// `true` for a node that re-checks its children every tick through
    /// [`rechecking`](crate::nodes::control::reactive::rechecking): only under one does a
    /// condition's call note whether it may read more than the blackboard.
    const RECHECKS: bool = false;

    /// The node with its ports bound by `port`; an error names the port that is missing or
    /// whose literal does not convert.
    fn from_ports(port: &dyn Fn(&str) -> PortBinding) -> Result<Self, PortBindingError>;

    /// Checks the node once its number of children is known, and resolves what depends on
    /// it (the arity itself is checked before).
    fn close(&mut self, children: u32) -> Result<(), BuildErrorKind> {
        let _ = children;
        Ok(())
    }

    /// Whether the node passes a Running child's tick straight through: ticked while
    /// Running with a Running child, it ticks that child and nothing else, and if the child
    /// returns Running, returns Running with its state unchanged. A tree resting in a
    /// stateful action under such nodes starts its next pass at the action.
    fn passes_through(&self) -> bool {
        false
    }

    /// One tick of node `id`; the ticker stores what it returns.
    fn tick<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus;

    /// The state slots a node of `children` children takes: [`AUX_SLOTS`](Self::AUX_SLOTS)
    /// unless the number depends on the children.
    fn aux_slots(children: u32) -> u32 {
        let _ = children;
        Self::AUX_SLOTS
    }

    /// A node's state (its slot, or its two slots as one value, low first) as a saved state
    /// stores it: a saved state keeps one `u64` per node, in the form it had when slots were
    /// 64 bits, so that states saved then are read now.
    fn saved_aux(value: u64, children: u32) -> u64 {
        let _ = children;
        value
    }

    /// The inverse of [`saved_aux`](Self::saved_aux); `None` for a saved value no node of the
    /// kind keeps.
    fn restored_aux(saved: u64, children: u32) -> Option<u64> {
        let _ = children;
        Some(saved)
    }

    /// Node `id`'s state slot saved when the clock read `saved` (nanoseconds), as it reads
    /// on a clock at `now`: a slot that holds a moment keeps the time elapsed since it
    /// (see [`Tree::restore_state`](crate::Tree::restore_state)). Others are kept as they are.
    fn shift_aux(aux: u64, saved: u64, now: u64) -> u64 {
        let _ = (saved, now);
        aux
    }

    /// Halts node `id`'s children and resets its own state; the ticker then sets it Idle.
    /// By default the children are halted and the state slot, if any, is kept.
    fn halt<C>(&self, t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) {
        let _ = def;
        t.reset_children(id);
    }
}

/// A parameter read from its port `name`: its literal read as `T`, or
/// [`Param::Port`](crate::Param::Port) for a blackboard entry.
pub(crate) fn param<T: crate::blueprint::FromPortStr>(
    port: &dyn Fn(&str) -> PortBinding,
    name: &str,
) -> Result<crate::Param<T>, PortBindingError> {
    use crate::Param;
    match port(name) {
        PortBinding::Literal(text) => {
            T::from_port_str(&text)
                .map(Param::Value)
                .map_err(|()| PortBindingError::Unreadable {
                    port: String::from(name),
                    text,
                })
        }
        PortBinding::Entry => Ok(Param::Port),
        PortBinding::Missing => Err(PortBindingError::Missing {
            port: String::from(name),
        }),
    }
}

/// A duration parameter, whose port holds milliseconds as in BehaviorTree.CPP.
pub(crate) fn millis(
    port: &dyn Fn(&str) -> PortBinding,
    name: &str,
) -> Result<crate::Param<core::time::Duration>, PortBindingError> {
    use crate::Param;
    Ok(match param::<u64>(port, name)? {
        Param::Value(ms) => Param::Value(core::time::Duration::from_millis(ms)),
        Param::Port => Param::Port,
    })
}

/// A parameter as a file writes it; `None` for one read from a port.
pub(crate) fn text<T: alloc::string::ToString>(p: &crate::Param<T>) -> Option<String> {
    match p {
        crate::Param::Value(v) => Some(v.to_string()),
        crate::Param::Port => None,
    }
}

/// A duration parameter as a file writes it: milliseconds.
pub(crate) fn millis_text(p: &crate::Param<core::time::Duration>) -> Option<String> {
    match p {
        crate::Param::Value(d) => Some(alloc::string::ToString::to_string(&d.as_millis())),
        crate::Param::Port => None,
    }
}

//! The immutable tree: built once, validated once, shared by every instance.
//!
//! A [`Blueprint`] holds the structure (node kinds, their parameters, child lists, names) in
//! flat arrays indexed by [`NodeId`], in depth-first pre-order with the root at id 0. It
//! holds no per-run state: a [`Tree`](crate::Tree) instance keeps that, so one blueprint
//! serves any number of agents without copying its structure.

pub(crate) mod builder;
pub(crate) mod call;
mod declared;
mod error;
mod hash;
mod kind;
mod port;

pub use builder::{Builder, HookWrapper};
pub use call::ConditionClosure;
pub use declared::{PortBinding, PortBindingError};
pub use error::{BuildError, BuildErrorKind};
pub use kind::{
    ActionFn, Arity, Category, ConditionFn, CustomFactory, CustomSpec, NodeKind, ParallelPolicy,
    Param, Shared, StatefulFactory, SubTreeScope,
};
pub use port::{
    FromPortStr, Literal, Number, Port, PortDirections, PortError, PortType, PortValue,
};

use alloc::boxed::Box;
use alloc::string::String;
use alloc::sync::Arc;
use alloc::vec::Vec;
use core::fmt;

use crate::blackboard::ScopeId;
use crate::nodes::hooks::NodeHooks;
use crate::nodes::leaf::Condition;

/// The most nodes a blueprint holds: 2^31 - 1, so that a node's id leaves the top bit of a
/// 32-bit word free (a tree's record of failure reasons marks a word with it). A tree that
/// large would take hundreds of gigabytes.
pub(crate) const MAX_NODES: u32 = i32::MAX as u32;

/// The deepest tree a blueprint accepts unless told otherwise (BehaviorTree.CPP uses 256).
pub const DEFAULT_MAX_DEPTH: u32 = 256;

/// A node's index in its blueprint (pre-order, root = 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(transparent)]
pub struct NodeId(pub u32);

impl NodeId {
    /// The root of every blueprint.
    pub const ROOT: NodeId = NodeId(0);

    /// The id as an index into per-node arrays.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for NodeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// What the tick loop reads for one node; kept small and hot.
pub(crate) struct NodeDef<C> {
    pub(crate) kind: NodeKind<C>,
    /// Start of this node's children in `Blueprint::children`.
    pub(crate) first_child: u32,
    pub(crate) child_count: u32,
}

/// A child as its parent's loop sees it: its id and, for a condition without hooks (the
/// most common leaf, from the builder or from XML), the condition itself as its data and
/// the [entry](call::Entry) that calls it, so that ticking it needs no look-up of its
/// definition, no call through the dispatcher and no vtable. A plain Sequence or Fallback
/// without hooks (the most common control) is marked too, so that its parent calls its
/// loop without the dispatcher.
///
/// A guard's loop (see [`crate::tree::calls`]) reads these records as they are: the data at
/// offset 0, the entry at 8, the id at 16.
#[repr(C)]
pub(crate) struct Child {
    data: *const (),
    word: Word,
    pub(crate) id: NodeId,
    /// Which field of `word` is set, and what `data` points at.
    fast: Fast,
}

/// What [`Child::word`] holds.
#[derive(Clone, Copy)]
union Word {
    none: u64,
    /// A condition's entry, called with `data`.
    entry: call::Entry,
    /// A guard's children in `Blueprint::hot_children` (first, count), so that its
    /// parent's loop runs the guard's loop without looking its definition up.
    guard: [u32; 2],
}

/// What a child record holds.
#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
enum Fast {
    /// First, so that the hottest test is a test for zero.
    Closure,
    None,
    Condition,
    /// A `Condition` object that may read more than the blackboard, under a node that
    /// re-checks it: its call notes whether it declared a wake (see `call::entry_of`).
    TrackedCondition,
    /// A plain Sequence without hooks, which a parent's loop ticks without the dispatcher.
    Sequential,
    /// A plain Fallback without hooks, likewise.
    Alternative,
    /// A plain Sequence without hooks whose children are all closure conditions without
    /// hooks (a guard: it completes in every tick, and its loop needs no other case).
    SequenceOfClosures,
    /// A plain Fallback of closure conditions, likewise.
    FallbackOfClosures,
    /// A plain Sequence without hooks whose children are all `Condition` objects without
    /// hooks (the same guard, loaded from XML).
    SequenceOfObjects,
    /// A plain Fallback of `Condition` objects, likewise.
    FallbackOfObjects,
    /// A guard of `Condition` objects under a node that re-checks it, whose loop asks
    /// after the calls whether one may read more than the blackboard.
    SequenceOfTrackedObjects,
    /// A plain Fallback of `Condition` objects, likewise.
    FallbackOfTrackedObjects,
}

/// A child as a plain Sequence's or Fallback's quiet loop ticks it: a condition called
/// through its entry (a closure with the context, an object with a handle), a guard whose
/// loop runs in the parent's, or anything else.
pub(crate) enum Hot {
    Closure,
    /// A `Condition` object; `true` if its call notes what it reads (see
    /// [`Fast::TrackedCondition`]).
    Condition(bool),
    /// A guard: a Sequence (`.0`) or Fallback, of closures (`.1`) or of `Condition`
    /// objects, whose calls note what they read (`.2`), and its children's range in
    /// `Blueprint::hot_children` (first, count).
    Guard(bool, bool, bool, [u32; 2]),
    Other,
}

/// What a node's children all are, when its parent can use it (see [`Fast`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Guards {
    /// Closure conditions without hooks.
    Closures,
    /// `Condition` objects without hooks.
    Objects,
    /// Anything else.
    Mixed,
}

/// A plain Sequence (`sequence`) or Fallback without hooks, and what its children all are:
/// how a parent's loop ticks it without the dispatcher.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) struct FastControl {
    pub(crate) sequence: bool,
    pub(crate) guards: Guards,
}

impl Child {
    /// A child of kind `kind`; `hooked` when it has pre- or post-conditions; `rechecked`
    /// when a node above it re-checks its children every tick; `entries` are those of the
    /// blueprint's `shared` conditions, not `rechecked` and `rechecked`.
    pub(crate) fn new<C>(
        id: NodeId,
        def: &NodeDef<C>,
        hooked: bool,
        guards: Guards,
        rechecked: bool,
        shared: &[Arc<dyn Condition<C>>],
        entries: &[[call::Entry; 2]],
    ) -> Self {
        let condition = |data, entry| Self {
            data,
            word: Word { entry },
            id,
            fast: Fast::Condition,
        };
        // A `Condition` object, given the entry `call::entry_of` picks for it.
        let object = |c: &dyn Condition<C>, entry| Self {
            fast: if rechecked && !c.reads_only_blackboard() {
                Fast::TrackedCondition
            } else {
                Fast::Condition
            },
            ..condition(call::data_of(c), entry)
        };
        match (&def.kind, hooked) {
            (NodeKind::ConditionFn(f), false) => {
                let f: &ConditionDyn<C> = &**f;
                Self {
                    fast: Fast::Closure,
                    ..condition(f as *const ConditionDyn<C> as *const (), f.entry())
                }
            }
            (NodeKind::Condition(c), false) => object(&**c, call::entry_of(&**c, rechecked)),
            (NodeKind::SharedCondition(s), false) => {
                object(&*shared[s.index()], entries[s.index()][rechecked as usize])
            }
            (kind, false) if kind.plain_order().is_some() => {
                let sequence = kind.plain_order() == Some(true);
                let fast = match (sequence, guards) {
                    (true, Guards::Closures) => Fast::SequenceOfClosures,
                    (true, Guards::Objects) if rechecked => Fast::SequenceOfTrackedObjects,
                    (true, Guards::Objects) => Fast::SequenceOfObjects,
                    (true, Guards::Mixed) => Fast::Sequential,
                    (false, Guards::Closures) => Fast::FallbackOfClosures,
                    (false, Guards::Objects) if rechecked => Fast::FallbackOfTrackedObjects,
                    (false, Guards::Objects) => Fast::FallbackOfObjects,
                    (false, Guards::Mixed) => Fast::Alternative,
                };
                let word = if guards == Guards::Mixed {
                    Word { none: 0 }
                } else {
                    Word {
                        guard: [def.first_child, def.child_count],
                    }
                };
                Self {
                    data: core::ptr::null(),
                    word,
                    id,
                    fast,
                }
            }
            _ => Self {
                data: core::ptr::null(),
                word: Word { none: 0 },
                id,
                fast: Fast::None,
            },
        }
    }

    /// The child's entry, if it is a condition without hooks: a closure (`true`, called
    /// with the context) or a `Condition` object (called with a handle).
    #[inline(always)]
    pub(crate) fn condition(&self) -> Option<bool> {
        match self.fast {
            Fast::Closure => Some(true),
            Fast::Condition | Fast::TrackedCondition => Some(false),
            _ => None,
        }
    }

    /// Calls the child's condition with `args` (see [`call::Entry`]).
    ///
    /// # Safety
    /// The child is a condition ([`condition`](Self::condition)), and `args` is an
    /// `Args<*const C>` for a closure, an `Args<Handle<'_, C>>` for an object, of the `C`
    /// of the blueprint that holds this record.
    #[inline(always)]
    pub(crate) unsafe fn call<A>(&self, args: &mut call::Args<A>) -> u8 {
        debug_assert!(self.condition().is_some());
        // SAFETY: the caller's contract; `new` set `entry` for conditions.
        unsafe {
            (self.word.entry)(
                (self as *const Self).cast(),
                (args as *mut call::Args<A>).cast(),
            )
        }
    }

    /// Whether the child is one whose status a parent's quiet loop does not store: a
    /// condition it calls directly (a closure or a `Condition` object without hooks), or a
    /// guard whose loop it runs.
    #[inline(always)]
    pub(crate) fn is_fast(&self) -> bool {
        matches!(
            self.fast,
            Fast::Closure
                | Fast::Condition
                | Fast::TrackedCondition
                | Fast::SequenceOfClosures
                | Fast::FallbackOfClosures
                | Fast::SequenceOfObjects
                | Fast::FallbackOfObjects
                | Fast::SequenceOfTrackedObjects
                | Fast::FallbackOfTrackedObjects
        )
    }

    /// Whether the child is a `Condition` object whose call notes what it reads.
    #[inline(always)]
    pub(crate) fn tracked(&self) -> bool {
        self.fast == Fast::TrackedCondition
    }

    /// A plain Sequence or Fallback without hooks, which a parent's loop ticks without the
    /// dispatcher, and what its children all are.
    #[inline(always)]
    pub(crate) fn fast_control(&self) -> Option<FastControl> {
        let (sequence, guards) = match self.fast {
            Fast::Sequential => (true, Guards::Mixed),
            Fast::Alternative => (false, Guards::Mixed),
            Fast::SequenceOfClosures => (true, Guards::Closures),
            Fast::FallbackOfClosures => (false, Guards::Closures),
            Fast::SequenceOfObjects | Fast::SequenceOfTrackedObjects => (true, Guards::Objects),
            Fast::FallbackOfObjects | Fast::FallbackOfTrackedObjects => (false, Guards::Objects),
            Fast::Closure | Fast::Condition | Fast::TrackedCondition | Fast::None => return None,
        };
        Some(FastControl { sequence, guards })
    }

    /// What a parent's quiet loop does with this child (see [`Hot`]).
    #[inline(always)]
    pub(crate) fn hot(&self) -> Hot {
        // SAFETY: the guard variants set `guard` (see `new`).
        unsafe {
            match self.fast {
                Fast::Closure => Hot::Closure,
                Fast::Condition => Hot::Condition(false),
                Fast::TrackedCondition => Hot::Condition(true),
                Fast::SequenceOfClosures => Hot::Guard(true, true, false, self.word.guard),
                Fast::FallbackOfClosures => Hot::Guard(false, true, false, self.word.guard),
                Fast::SequenceOfObjects => Hot::Guard(true, false, false, self.word.guard),
                Fast::FallbackOfObjects => Hot::Guard(false, false, false, self.word.guard),
                Fast::SequenceOfTrackedObjects => Hot::Guard(true, false, true, self.word.guard),
                Fast::FallbackOfTrackedObjects => Hot::Guard(false, false, true, self.word.guard),
                Fast::Sequential | Fast::Alternative | Fast::None => Hot::Other,
            }
        }
    }
}

#[cfg(test)]
impl Child {
    /// The record of closure condition `f` as node `id`, for tests of the loops.
    pub(crate) fn of_closure<C, F: ConditionClosure<C>>(f: &F, id: NodeId) -> Self {
        Self {
            data: (f as *const F).cast(),
            word: Word { entry: f.entry() },
            id,
            fast: Fast::Closure,
        }
    }
}

// A guard's loop reads the entry at 8 (see `crate::tree::calls`).
const _: () = assert!(core::mem::offset_of!(Child, word) == 8);

// SAFETY: `data` points at a closure or `Condition` object, both `Send + Sync`, owned by the
// blueprint that holds the record, so sharing or sending a `Child` is sharing or sending a
// reference to it.
unsafe impl Send for Child {}
// SAFETY: as above.
unsafe impl Sync for Child {}

/// The closure behind a [`ConditionFn`].
type ConditionDyn<C> = dyn ConditionClosure<C>;

/// Where a name is in [`Blueprint::names`]: all the names of a blueprint share one buffer,
/// so that building one allocates per blueprint, not per node. In 32 bits, as the
/// builder refuses names past [`MAX_NAMES_BYTES`](builder::MAX_NAMES_BYTES): a large tree's
/// records take less memory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct NameSpan {
    start: u32,
    end: u32,
}

impl NameSpan {
    /// The span of bytes `start..end`, both within the builder's limit.
    pub(crate) fn new(start: usize, end: usize) -> Self {
        debug_assert!(end <= builder::MAX_NAMES_BYTES);
        // The builder checks the length of its names before it makes a span.
        Self {
            start: start as u32,
            end: end as u32,
        }
    }

    /// The range of [`Blueprint::names`] it stands for.
    pub(crate) fn range(self) -> core::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// What only tools read: names, parents, depths.
pub(crate) struct NodeMeta {
    pub(crate) name: NameSpan,
    pub(crate) parent: Option<NodeId>,
    pub(crate) depth: u32,
    pub(crate) ports: Vec<Port>,
    pub(crate) type_id: Option<NameSpan>,
}

/// An immutable, validated behavior tree, shared by its instances through `Arc`.
///
/// ```
/// use neurotree_core::{Blueprint, ManualClock, Status, Tree};
///
/// let blueprint = Blueprint::<u32>::builder()
///     .sequence("count_to_two", |s| {
///         s.action("inc", |n: &mut u32| { *n += 1; Status::Success })
///             .condition("reached", |n: &u32| *n >= 2)
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
/// let mut n = 0;
/// assert_eq!(tree.tick_once(&mut n), Ok(Status::Failure));
/// assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
/// ```
pub struct Blueprint<C> {
    pub(crate) nodes: Box<[NodeDef<C>]>,
    pub(crate) children: Box<[NodeId]>,
    /// `children` with their closure conditions at hand, for the controls' loops.
    pub(crate) hot_children: Box<[Child]>,
    /// Per node: its first per-instance 32-bit state slot (kinds that keep state), or its
    /// per-instance object (stateful leaves, custom nodes). Kept apart from `nodes` so that a
    /// `NodeDef` fits in 32 bytes, two to a cache line.
    pub(crate) slots: Box<[u32]>,
    /// Per node: the blackboard scope it reads and writes.
    pub(crate) node_scopes: Box<[ScopeId]>,
    pub(crate) meta: Box<[NodeMeta]>,
    /// The text of every name in `meta`.
    pub(crate) names: String,
    /// Per node: its pre- and post-conditions, if any.
    pub(crate) hooks: Box<[Option<Box<dyn NodeHooks<C>>>]>,
    /// Subtree scopes in creation order: scope `i + 1` is `scopes[i]`, opened by a SubTree.
    pub(crate) scopes: Box<[(ScopeId, SubTreeScope)]>,
    /// The `Condition` objects of its [`NodeKind::SharedCondition`] nodes, each once.
    pub(crate) shared: Box<[Arc<dyn Condition<C>>]>,
    /// The 32-bit state slots of a tree of it (see [`NodeKind::aux_slots`]).
    pub(crate) aux_slots: u32,
    /// The per-instance objects of a tree of it (its stateful leaves and custom nodes).
    pub(crate) objects: u32,
    pub(crate) max_depth: u32,
    /// Per node: it is a stateful action without hooks whose ancestors all pass a Running
    /// child's tick straight through (`Tick::passes_through`) and have no hooks, so that a
    /// tree resting in it may start its next pass at it.
    pub(crate) resting: Box<[bool]>,
    /// The value types its trees' blackboards save, show and edit values with.
    pub(crate) value_codecs: Option<Arc<crate::state::StateCodecs>>,
    /// Which way the ports of its node types carry data ([`Builder::port_directions`]).
    pub(crate) port_directions: Option<Arc<PortDirections>>,
    /// The [structure hash](Self::structure_hash) once made (0: not yet): saving and
    /// restoring a state ask for it each time.
    #[cfg(target_has_atomic = "64")]
    pub(crate) hash: core::sync::atomic::AtomicU64,
}

impl<C> Blueprint<C> {
    /// A builder for a new blueprint.
    pub fn builder() -> Builder<C> {
        Builder::new()
    }

    /// The value codecs its trees' blackboards get, if it was built with some
    /// ([`Builder::value_codecs`]).
    pub fn value_codecs(&self) -> Option<&Arc<crate::state::StateCodecs>> {
        self.value_codecs.as_ref()
    }

    /// Which way port `port` of node `id` carries data, as its type declares it: a
    /// built-in's declaration, else the directions the blueprint was built with
    /// ([`Builder::port_directions`]); `None` when its type declares no such port.
    pub fn port_direction(&self, id: NodeId, port: &str) -> Option<crate::PortDirection> {
        let type_name = self.type_id(id);
        let declared = crate::nodes::BUILT_INS
            .iter()
            .find(|decl| decl.name == type_name)
            .and_then(|decl| decl.ports.iter().find(|p| p.name == port));
        match declared {
            Some(decl) => Some(decl.direction),
            None => self.port_directions.as_ref()?.get(type_name, port),
        }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// A blueprint always has a root, so it is never empty.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Every node id, in pre-order.
    pub fn ids(&self) -> impl ExactSizeIterator<Item = NodeId> + '_ {
        (0..self.nodes.len() as u32).map(NodeId)
    }

    /// The node's kind.
    pub fn kind(&self, id: NodeId) -> &NodeKind<C> {
        &self.nodes[id.index()].kind
    }

    /// The node's name (its kind's type name when it was given none).
    pub fn name(&self, id: NodeId) -> &str {
        let span = self.meta[id.index()].name;
        debug_assert!(self.names.get(span.range()).is_some());
        // SAFETY: the builder recorded `span` around a whole `&str` it had just appended to
        // `names`, so both ends are char boundaries within it, and `names` does not change
        // once built. Unchecked because every tick of a leaf with a handle reads the name.
        unsafe { self.names.get_unchecked(span.range()) }
    }

    /// The node's type as a file names it: the registered name it was made from (see
    /// [`Builder::type_id`]), else its kind's [type name](NodeKind::type_name).
    pub fn type_id(&self, id: NodeId) -> &str {
        let meta = &self.meta[id.index()];
        match meta.type_id {
            Some(span) => &self.names[span.range()],
            None => self.kind(id).type_name(),
        }
    }

    /// The node's pre- and post-conditions, if it has any.
    pub fn node_hooks(&self, id: NodeId) -> Option<&dyn NodeHooks<C>> {
        self.hooks(id)
    }

    /// The node's children, in order.
    pub fn children(&self, id: NodeId) -> &[NodeId] {
        self.children_of(&self.nodes[id.index()])
    }

    /// The children of a node definition.
    #[inline(always)]
    pub(crate) fn children_of(&self, def: &NodeDef<C>) -> &[NodeId] {
        let range = def.first_child as usize..(def.first_child + def.child_count) as usize;
        debug_assert!(range.end <= self.children.len());
        // SAFETY: the builder set `first_child` and `child_count` of every node to a range it
        // had just filled in `children`, and neither changes after `finish`.
        unsafe { self.children.get_unchecked(range) }
    }

    /// The children of a node definition, as the controls' loops tick them.
    #[inline(always)]
    pub(crate) fn hot_children_of(&self, def: &NodeDef<C>) -> &[Child] {
        let range = def.first_child as usize..(def.first_child + def.child_count) as usize;
        debug_assert!(range.end <= self.hot_children.len());
        // SAFETY: `hot_children` mirrors `children` entry for entry (see `children_of`).
        unsafe { self.hot_children.get_unchecked(range) }
    }

    /// A guard's children, from the range its [`Hot::Guard`] holds.
    #[inline(always)]
    pub(crate) fn hot_range(&self, [first, count]: [u32; 2]) -> &[Child] {
        let range = first as usize..(first + count) as usize;
        debug_assert!(range.end <= self.hot_children.len());
        // SAFETY: `Child::new` took the range from a node definition of this blueprint, as
        // `hot_children_of` does.
        unsafe { self.hot_children.get_unchecked(range) }
    }

    /// The definition of a node of this blueprint.
    #[inline(always)]
    pub(crate) fn def(&self, id: NodeId) -> &NodeDef<C> {
        debug_assert!(id.index() < self.nodes.len());
        // SAFETY: the engine only handles ids of this blueprint (see `Ticker::status`).
        unsafe { self.nodes.get_unchecked(id.index()) }
    }

    /// The node's pre- and post-conditions.
    #[inline]
    pub(crate) fn hooks(&self, id: NodeId) -> Option<&dyn NodeHooks<C>> {
        self.hooks[id.index()].as_deref()
    }

    /// The node's ports and their bindings.
    pub fn ports(&self, id: NodeId) -> &[Port] {
        &self.meta[id.index()].ports
    }

    /// The node's parent, `None` for the root.
    pub fn parent(&self, id: NodeId) -> Option<NodeId> {
        self.meta[id.index()].parent
    }

    /// Depth of the node: the root is at depth 1.
    pub fn depth(&self, id: NodeId) -> u32 {
        self.meta[id.index()].depth
    }

    /// The blackboard scope the node uses.
    pub fn scope(&self, id: NodeId) -> ScopeId {
        self.node_scopes[id.index()]
    }

    /// The node's state slot or object index (see `slots`).
    #[inline(always)]
    pub(crate) fn slot(&self, id: NodeId) -> usize {
        debug_assert!(id.index() < self.slots.len());
        // SAFETY: `slots` has one entry per node (see `def`).
        (unsafe { *self.slots.get_unchecked(id.index()) }) as usize
    }

    /// The 32-bit state slots node `id` takes from [`slot`](Self::slot) on.
    pub(crate) fn aux_slots_of(&self, id: NodeId) -> usize {
        let def = self.def(id);
        def.kind.aux_slots(def.child_count) as usize
    }

    /// The depth limit this blueprint was validated against.
    pub fn max_depth(&self) -> u32 {
        self.max_depth
    }

    /// Names from the root down to the node, joined by `/`.
    pub fn path(&self, id: NodeId) -> String {
        let mut chain = Vec::new();
        let mut at = Some(id);
        while let Some(n) = at {
            chain.push(n);
            at = self.parent(n);
        }
        let mut out = String::new();
        for (i, n) in chain.iter().rev().enumerate() {
            if i > 0 {
                out.push('/');
            }
            out.push_str(self.name(*n));
        }
        out
    }

    /// Every node's [`path`](Self::path), indexed by [`NodeId`]: what loggers keep to name
    /// nodes without holding the blueprint. One pass, each path built on its parent's.
    pub fn paths(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::with_capacity(self.len());
        for id in self.ids() {
            let path = match self.parent(id) {
                // Pre-order: the parent's path is already in `out`.
                Some(parent) => alloc::format!("{}/{}", out[parent.index()], self.name(id)),
                None => String::from(self.name(id)),
            };
            out.push(path);
        }
        out
    }

    /// Per node, the id one past its last descendant: since ids are in pre-order, a node's
    /// subtree is the id range `id..ends[id]`.
    pub fn subtree_ends(&self) -> Vec<u32> {
        let mut ends: Vec<u32> = (1..=self.len() as u32).collect();
        // Children come after their parent, so walking backwards finishes them first.
        for id in (0..self.len() as u32).rev().map(NodeId) {
            if let Some(parent) = self.parent(id) {
                let end = ends[id.index()];
                let p = &mut ends[parent.index()];
                *p = (*p).max(end);
            }
        }
        ends
    }

    /// The first node, in pre-order, whose path is `path`.
    pub fn find(&self, path: &str) -> Option<NodeId> {
        self.ids().find(|id| self.path(*id) == path)
    }

    /// Bytes of per-instance node state a [`Tree`](crate::Tree) of this blueprint keeps on
    /// the heap: its block of slots, statuses, failure bits and stateful leaves' objects (a
    /// few words each, their boxes apart), what a fresh tree's
    /// [`state_bytes`](crate::Tree::state_bytes) says; not counting what the stateful leaves'
    /// objects point to, or blackboard entries.
    pub fn instance_state_bytes(&self) -> usize {
        crate::tree::node_state_bytes::<C>(
            self.nodes.len(),
            self.aux_slots as usize,
            self.objects as usize,
        )
    }
}

impl<C> fmt::Debug for Blueprint<C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut list = f.debug_list();
        for id in self.ids() {
            list.entry(&format_args!(
                "{}{} {:?}",
                "  ".repeat(self.depth(id) as usize - 1),
                self.name(id),
                self.kind(id)
            ));
        }
        list.finish()
    }
}

//! Building a blueprint: a fluent, closure-nested form for people and an `open`/`close` form
//! for programs (the XML loader, generators), both on the same flat, non-recursive core so
//! that no tree shape can overflow the stack while building.

use alloc::boxed::Box;
use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::sync::Arc;

use crate::state::StateCodecs;
use alloc::vec::Vec;

use super::{
    Blueprint, BuildError, BuildErrorKind, NameSpan, NodeDef, NodeId, NodeKind, NodeMeta, Port,
    Shared, DEFAULT_MAX_DEPTH,
};
use crate::nodes::hooks::NodeHooks;
use crate::Condition;

mod finish;
mod fluent;

/// `a == b`, inline: names are short, and `==` would call `memcmp`. The same text twice
/// (a loader naming a node after its type) is seen without reading it.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && (core::ptr::eq(a.as_ptr(), b.as_ptr()) || a.bytes().zip(b.bytes()).all(|(x, y)| x == y))
}

/// The longest text all the names and type ids of one tree may take together (they share
/// one buffer, addressed in 32 bits).
pub const MAX_NAMES_BYTES: usize = u32::MAX as usize;

/// `Some` if `more` bytes of names fit after `used`.
fn names_fit(used: usize, more: usize) -> Option<()> {
    (used.checked_add(more)? <= MAX_NAMES_BYTES).then_some(())
}

/// Builds a [`Blueprint`].
///
/// Every node method takes the node's name first (an empty name shows the kind's type name).
/// Nodes with children take a closure that adds them. Validation errors are kept and
/// reported by [`Builder::build`], so the chain never needs `?` in the middle.
///
/// ```
/// use core::time::Duration;
/// use neurotree_core::{Blueprint, ParallelPolicy, Status};
///
/// struct Robot { battery: f32 }
///
/// let blueprint = Blueprint::<Robot>::builder()
///     .fallback("root", |f| {
///         f.sequence("work", |s| {
///             s.condition("battery_ok", |r: &Robot| r.battery > 20.0)
///                 .timeout("limit", Duration::from_secs(5), |t| {
///                     t.action("patrol", |_r: &mut Robot| Status::Success)
///                 })
///         })
///         .action("charge", |r: &mut Robot| { r.battery = 100.0; Status::Success })
///     })
///     .build()
///     .unwrap();
/// assert_eq!(blueprint.len(), 6);
/// assert_eq!(blueprint.path(blueprint.find("root/work/limit/patrol").unwrap()), "root/work/limit/patrol");
/// ```
pub struct Builder<C> {
    /// Boxed: the fluent methods take and return the builder by value, which then moves a
    /// pointer rather than the whole state.
    s: Box<State<C>>,
}

/// What a [`Builder`] has gathered so far.
struct State<C> {
    /// The nodes, in the blueprint's own records: a node's children are not listed (each
    /// knows its parent, and `finish` lays the lists out), so that a node costs no
    /// allocation of its own and nothing is moved when the blueprint is made.
    defs: Vec<NodeDef<C>>,
    metas: Vec<NodeMeta>,
    /// The text of every node's name and type id.
    names: String,
    open: Vec<u32>,
    /// The ports and the hooks of the few nodes that have them, by node number in
    /// increasing order: kept apart, a pending node is half as large.
    ports: Vec<(u32, Vec<Port>)>,
    hooks: Vec<(u32, Box<dyn NodeHooks<C>>)>,
    /// The shared conditions, each once, and where each is by the address of its object.
    shared: Vec<Arc<dyn Condition<C>>>,
    shared_at: BTreeMap<usize, u32>,
    /// The two conditions called last, the last first: where each is, and its index.
    shared_last: [Option<(usize, u32)>; 2],
    /// The name appended to `names` last, which the next node may share.
    last_name: NameSpan,
    error: Option<BuildError>,
    /// Opens seen after an error, so their closes balance without storing nodes.
    ignored: usize,
    max_depth: u32,
    value_codecs: Option<Arc<StateCodecs>>,
    port_directions: Option<Arc<crate::PortDirections>>,
    /// Replaces each node's hooks as the blueprint is finished ([`Builder::wrap_hooks`]).
    wrap_hooks: Option<HookWrapper<C>>,
}

/// What [`Builder::wrap_hooks`] is given: called with each node and the hooks it has, it
/// returns the hooks it gets.
pub type HookWrapper<C> = Box<
    dyn FnMut(NodeId, Option<Box<dyn NodeHooks<C>>>) -> Option<Box<dyn NodeHooks<C>>> + Send + Sync,
>;

impl<C> Default for Builder<C> {
    fn default() -> Self {
        Self::new()
    }
}

impl<C> Builder<C> {
    /// An empty builder with the default depth limit.
    pub fn new() -> Self {
        Self::with_capacity(0)
    }

    /// An empty builder with room for `nodes` nodes: a program that knows how many it will
    /// add (the XML loader, from the elements it read) saves the list's growth.
    pub fn with_capacity(nodes: usize) -> Self {
        Self {
            s: Box::new(State {
                defs: Vec::with_capacity(nodes),
                metas: Vec::with_capacity(nodes),
                names: String::new(),
                open: Vec::new(),
                ports: Vec::new(),
                hooks: Vec::new(),
                shared: Vec::new(),
                shared_at: BTreeMap::new(),
                shared_last: [None; 2],
                last_name: NameSpan::new(0, 0),
                error: None,
                ignored: 0,
                max_depth: DEFAULT_MAX_DEPTH,
                value_codecs: None,
                port_directions: None,
                wrap_hooks: None,
            }),
        }
    }

    /// Sets the deepest tree accepted (the root is at depth 1).
    pub fn max_depth(mut self, limit: u32) -> Self {
        self.s.max_depth = limit;
        self
    }

    /// The value types the blueprint's trees save, show and edit their blackboard values
    /// with: each tree's blackboard gets them ([`Blackboard::codecs`](crate::Blackboard::codecs)).
    pub fn value_codecs(mut self, codecs: Arc<StateCodecs>) -> Self {
        self.s.value_codecs = Some(codecs);
        self
    }

    /// Which way the ports of the node types it is given carry data, for pictures of its
    /// trees to mark ([`Blueprint::port_direction`]); built-ins need none.
    pub fn port_directions(mut self, directions: Arc<crate::PortDirections>) -> Self {
        self.s.port_directions = Some(directions);
        self
    }

    /// `true` once a validation error has been recorded.
    pub fn has_error(&self) -> bool {
        self.s.error.is_some()
    }

    /// Starts a node; the nodes added until the matching [`close`](Self::close) are its children.
    pub fn open(mut self, kind: NodeKind<C>, name: &str) -> Self {
        if self.s.error.is_some() {
            self.s.ignored += 1;
            return self;
        }
        let parent = self.s.open.last().copied();
        if parent.is_none() && !self.s.defs.is_empty() {
            self.s.fail(Some(0), BuildErrorKind::SecondRoot);
            self.s.ignored += 1;
            return self;
        }
        let depth = self.s.open.len() as u32 + 1;
        if depth > self.s.max_depth {
            self.s.fail(
                parent,
                BuildErrorKind::TooDeep {
                    limit: self.s.max_depth,
                },
            );
            self.s.ignored += 1;
            return self;
        }
        if self.s.defs.len() >= crate::blueprint::MAX_NODES as usize {
            self.s.fail(
                parent,
                BuildErrorKind::TooManyNodes {
                    max: crate::blueprint::MAX_NODES,
                },
            );
            self.s.ignored += 1;
            return self;
        }
        let id = self.s.defs.len() as u32;
        let Some(name) = self.s.push_name(if name.is_empty() {
            kind.type_name()
        } else {
            name
        }) else {
            self.s.fail(
                parent,
                BuildErrorKind::NamesTooLong {
                    max: MAX_NAMES_BYTES,
                },
            );
            self.s.ignored += 1;
            return self;
        };
        self.s.push_node(kind, name, parent, depth, None);
        self.s.open.push(id);
        self
    }

    /// Starts a condition node that calls `condition`, which the blueprint holds once for
    /// all the nodes opened with it: unlike [`NodeKind::Condition`], which each node owns,
    /// this clones the `Arc` once per blueprint, not once per node (an atomic operation a
    /// large tree loaded from XML would pay per node, and again when dropped).
    pub fn open_shared_condition(mut self, condition: &Arc<dyn Condition<C>>, name: &str) -> Self {
        let index = self.s.shared_index(condition);
        self.open(NodeKind::SharedCondition(Shared(index)), name)
    }

    /// Adds a leaf that calls `condition` (held once by the blueprint, as
    /// [`open_shared_condition`](Self::open_shared_condition) holds it), named `name`, of
    /// registered type `type_id`: the same as `open_shared_condition`,
    /// [`type_id`](Self::type_id) and [`close`](Self::close), in one call, which a loader
    /// makes for most nodes of a large tree.
    pub fn shared_condition_leaf(
        mut self,
        name: &str,
        type_id: &str,
        condition: &Arc<dyn Condition<C>>,
    ) -> Self {
        let parent = self.s.open.last().copied();
        let depth = self.s.open.len() as u32 + 1;
        let fits = self.s.defs.len() < u32::MAX as usize;
        if self.s.error.is_some() || parent.is_none() || depth > self.s.max_depth || !fits {
            // An error to record, a root, or nothing to do: the long way says which.
            return self.shared_condition_leaf_long(name, type_id, condition);
        }
        let index = self.s.shared_index(condition);
        let Some(name_span) = self
            .s
            .push_name(if name.is_empty() { "Condition" } else { name })
        else {
            return self.shared_condition_leaf_long(name, type_id, condition);
        };
        let type_span = if same(type_id, name) {
            Some(name_span)
        } else {
            self.s.push_name(type_id)
        };
        let Some(type_span) = type_span else {
            return self.shared_condition_leaf_long(name, type_id, condition);
        };
        let kind = NodeKind::SharedCondition(Shared(index));
        self.s
            .push_node(kind, name_span, parent, depth, Some(type_span));
        self
    }

    /// [`shared_condition_leaf`](Self::shared_condition_leaf) the long way, where there is
    /// an error to record.
    #[cold]
    #[inline(never)]
    fn shared_condition_leaf_long(
        self,
        name: &str,
        type_id: &str,
        condition: &Arc<dyn Condition<C>>,
    ) -> Self {
        self.open_shared_condition(condition, name)
            .type_id(type_id)
            .close()
    }

    /// Ends the node opened last and checks its number of children.
    pub fn close(mut self) -> Self {
        if self.s.ignored > 0 {
            self.s.ignored -= 1;
            return self;
        }
        let Some(id) = self.s.open.pop() else {
            self.s.fail(None, BuildErrorKind::UnbalancedClose);
            return self;
        };
        if let Err(kind) = self.s.validate(id) {
            self.s.fail(Some(id), kind);
        }
        self
    }

    /// Binds ports of the node added last (a leaf just added, or a control just opened).
    pub fn ports(mut self, ports: impl IntoIterator<Item = Port>) -> Self {
        if self.s.ignored > 0 || self.s.error.is_some() {
            return self;
        }
        let Some(last) = self.s.defs.len().checked_sub(1) else {
            self.s.fail(None, BuildErrorKind::Empty);
            return self;
        };
        let last = last as u32;
        match self.s.ports.last_mut() {
            Some((id, bound)) if *id == last => bound.extend(ports),
            _ => self.s.ports.push((last, ports.into_iter().collect())),
        }
        self
    }

    /// Records the registered type name of the node added last (`MoveBase` for a leaf the
    /// registry made, a tree ID for a SubTree), which its kind alone does not tell: it is what
    /// [`Blueprint::type_id`] returns and what a saved XML file names the node by.
    pub fn type_id(mut self, type_id: &str) -> Self {
        if self.s.ignored > 0 || self.s.error.is_some() {
            return self;
        }
        let Some(name) = self.s.metas.last().map(|node| node.name) else {
            self.s.fail(None, BuildErrorKind::Empty);
            return self;
        };
        // Usually the node is named after its type: the name's text serves for both.
        let text = &self.s.names.as_bytes()[name.range()];
        // Compared inline: names are short, and `==` would call `memcmp`.
        let same =
            text.len() == type_id.len() && text.iter().zip(type_id.bytes()).all(|(a, b)| *a == b);
        let span = if same {
            name
        } else {
            let Some(span) = self.s.push_name(type_id) else {
                let last = self.s.defs.len() as u32 - 1;
                self.s.fail(
                    Some(last),
                    BuildErrorKind::NamesTooLong {
                        max: MAX_NAMES_BYTES,
                    },
                );
                return self;
            };
            span
        };
        if let Some(node) = self.s.metas.last_mut() {
            node.type_id = Some(span);
        }
        self
    }

    /// Attaches pre- and post-conditions to the node added last.
    pub fn hooks(mut self, hooks: impl NodeHooks<C> + 'static) -> Self {
        if self.s.ignored > 0 || self.s.error.is_some() {
            return self;
        }
        let Some(last) = self.s.defs.len().checked_sub(1) else {
            self.s.fail(None, BuildErrorKind::Empty);
            return self;
        };
        let last = last as u32;
        match self.s.hooks.last_mut() {
            Some((id, attached)) if *id == last => *attached = Box::new(hooks),
            _ => self.s.hooks.push((last, Box::new(hooks))),
        }
        self
    }

    /// Has `wrap` called, when the blueprint is built, with every node and the hooks it was
    /// given (`None` for most), and gives each node the hooks `wrap` returns: how a tool
    /// wraps chosen nodes of a tree it did not build (a fault injected into one node).
    /// The engine's fast paths are worked out after, so a wrapped node loses none of its
    /// semantics.
    pub fn wrap_hooks(mut self, wrap: HookWrapper<C>) -> Self {
        self.s.wrap_hooks = Some(wrap);
        self
    }

    /// Adds a node with children added by `children`.
    pub fn node(self, kind: NodeKind<C>, name: &str, children: impl FnOnce(Self) -> Self) -> Self {
        children(self.open(kind, name)).close()
    }

    /// Adds a node without children.
    pub fn leaf(self, kind: NodeKind<C>, name: &str) -> Self {
        self.open(kind, name).close()
    }

    /// Finishes and validates the blueprint.
    pub fn build(mut self) -> Result<Blueprint<C>, BuildError> {
        if let Some(e) = self.s.error.take() {
            return Err(e);
        }
        if !self.s.open.is_empty() {
            let at = self.s.open.last().copied();
            let open = self.s.open.len();
            self.s.fail(at, BuildErrorKind::Unclosed { open });
            return Err(self.s.error.take().expect("fail() just stored an error"));
        }
        if self.s.defs.is_empty() {
            return Err(BuildError {
                path: String::new(),
                kind: BuildErrorKind::Empty,
            });
        }
        Ok((*self.s).finish())
    }

    /// Finishes the blueprint and wraps it in an `Arc`, ready to instantiate.
    pub fn build_shared(self) -> Result<Arc<Blueprint<C>>, BuildError> {
        self.build().map(Arc::new)
    }
}

impl<C> State<C> {
    fn fail(&mut self, at: Option<u32>, kind: BuildErrorKind) {
        if self.error.is_none() {
            let path = at.map(|i| self.pending_path(i)).unwrap_or_default();
            self.error = Some(BuildError { path, kind });
        }
    }

    fn pending_path(&self, mut i: u32) -> String {
        // Deep chains make long paths; the first and last few names locate the node well.
        const KEEP: usize = 8;
        let mut chain = Vec::new();
        loop {
            chain.push(i);
            match self.metas[i as usize].parent {
                Some(p) => i = p.0,
                None => break,
            }
        }
        chain.reverse();
        let mut out = String::new();
        for (k, n) in chain.iter().enumerate() {
            if chain.len() > 2 * KEEP && k == KEEP {
                out.push_str("/…");
            }
            if chain.len() > 2 * KEEP && (KEEP..chain.len() - KEEP).contains(&k) {
                continue;
            }
            if k > 0 {
                out.push('/');
            }
            let name = self.metas[*n as usize].name;
            out.push_str(&self.names[name.range()]);
        }
        out
    }

    /// Adds a node under `parent`.
    #[inline(always)]
    fn push_node(
        &mut self,
        kind: NodeKind<C>,
        name: NameSpan,
        parent: Option<u32>,
        depth: u32,
        type_id: Option<NameSpan>,
    ) {
        self.defs.push(NodeDef {
            kind,
            first_child: 0,
            child_count: 0,
        });
        self.metas.push(NodeMeta {
            name,
            parent: parent.map(NodeId),
            depth,
            ports: Vec::new(),
            type_id,
        });
        if let Some(p) = parent {
            self.defs[p as usize].child_count += 1;
        }
    }

    /// Appends a name to the shared buffer, or gives the span of the name appended last
    /// when it is the same (the nodes of a large tree are mostly named after a few types,
    /// in runs); `None` if the buffer would pass its limit.
    fn push_name(&mut self, name: &str) -> Option<NameSpan> {
        // As bytes: slicing the `String` would check for character boundaries.
        let last = &self.names.as_bytes()[self.last_name.range()];
        if last.len() == name.len() && last.iter().zip(name.bytes()).all(|(a, b)| *a == b) {
            return Some(self.last_name);
        }
        names_fit(self.names.len(), name.len())?;
        let start = self.names.len();
        self.names.push_str(name);
        self.last_name = NameSpan::new(start, self.names.len());
        Some(self.last_name)
    }

    /// The index in `shared` of `condition`, added if it is not there yet.
    #[inline]
    fn shared_index(&mut self, condition: &Arc<dyn Condition<C>>) -> u32 {
        let at = Arc::as_ptr(condition).cast::<()>() as usize;
        // Most nodes call one of the two conditions called last (a run of checks and the
        // one that ends it).
        match self.shared_last {
            [Some((last, index)), _] if last == at => index,
            [other, Some((last, index))] if last == at => {
                self.shared_last = [Some((at, index)), other];
                index
            }
            _ => self.shared_index_slow(condition, at),
        }
    }

    /// [`shared_index`](Self::shared_index) for a condition not called lately.
    #[inline(never)]
    fn shared_index_slow(&mut self, condition: &Arc<dyn Condition<C>>, at: usize) -> u32 {
        let index = match self.shared_at.get(&at) {
            Some(&index) => index,
            None => {
                let index = self.shared.len() as u32;
                self.shared.push(Arc::clone(condition));
                self.shared_at.insert(at, index);
                index
            }
        };
        self.shared_last = [Some((at, index)), self.shared_last[0]];
        index
    }

    /// Checks the closed node's children and resolves thresholds that depend on their number.
    fn validate(&mut self, id: u32) -> Result<(), BuildErrorKind> {
        let node = &mut self.defs[id as usize];
        let n = node.child_count;
        let arity = node.kind.arity();
        if !arity.accepts(n) {
            return Err(BuildErrorKind::ChildCount {
                type_name: String::from(node.kind.type_name()),
                expected: arity,
                found: n,
            });
        }
        node.kind.close(n)
    }
}

/// BehaviorTree.CPP's rule: a negative threshold `t` means `n + t + 1`, floored at 0.
pub(crate) fn resolve_threshold(t: i32, n: u32) -> i64 {
    if t < 0 {
        (i64::from(n) + i64::from(t) + 1).max(0)
    } else {
        i64::from(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blackboard::ScopeId;
    use crate::blueprint::{Arity, SubTreeScope};
    use crate::nodes::control::{fallback::Fallback, parallel::Parallel, sequence::Sequence};
    use crate::nodes::decorator::inverter::Inverter;
    use crate::nodes::leaf::always::AlwaysFailure;
    use crate::ParallelPolicy;
    use alloc::string::ToString;

    /// Hooks that make the node succeed at once, so that a test can see which node has them.
    struct Succeed;
    impl NodeHooks<()> for Succeed {
        fn before(
            &self,
            _h: &mut crate::Handle<'_, ()>,
            _stored: crate::NodeStatus,
        ) -> Option<crate::NodeStatus> {
            Some(crate::NodeStatus::Success)
        }
    }

    #[test]
    fn ports_and_hooks_kept_apart_reach_their_own_nodes() {
        let bp = Builder::<()>::new()
            .open(NodeKind::Sequence(Sequence), "root")
            .ports([Port::literal("a", "1")])
            .ports([Port::literal("b", "2")])
            .leaf(NodeKind::AlwaysFailure(AlwaysFailure), "plain")
            .open(NodeKind::AlwaysFailure(AlwaysFailure), "hooked")
            .hooks(Succeed)
            .ports([Port::entry("c", "key")])
            .close()
            .open(NodeKind::AlwaysFailure(AlwaysFailure), "twice")
            .hooks(Succeed)
            .hooks(Succeed)
            .close()
            .close()
            .build()
            .unwrap();
        let names = |id: u32| -> Vec<&str> {
            bp.ports(NodeId(id))
                .iter()
                .map(|p| p.name.as_str())
                .collect()
        };
        assert_eq!(names(0), ["a", "b"]);
        assert!(names(1).is_empty());
        assert_eq!(names(2), ["c"]);
        assert!(names(3).is_empty());
        let hooked: Vec<bool> = (0..4).map(|i| bp.hooks(NodeId(i)).is_some()).collect();
        assert_eq!(hooked, [false, false, true, true]);
    }

    /// A condition object that answers what it was made with.
    struct Answer(bool);
    impl Condition<()> for Answer {
        fn check(&self, _h: &crate::Handle<'_, ()>) -> bool {
            self.0
        }
    }

    #[test]
    fn a_shared_condition_is_held_once_by_the_blueprint_whatever_its_nodes() {
        let yes: Arc<dyn Condition<()>> = Arc::new(Answer(true));
        let no: Arc<dyn Condition<()>> = Arc::new(Answer(false));
        let mut b = Builder::<()>::new().open(NodeKind::Fallback(Fallback), "root");
        for i in 0..500 {
            b = b
                .open(NodeKind::Sequence(Sequence), "seq")
                .open_shared_condition(&yes, "yes")
                .close()
                .open_shared_condition(if i == 499 { &yes } else { &no }, "last")
                .close()
                .close();
        }
        let bp = b.close().build_shared().unwrap();
        // One clone each for the blueprint, none per node.
        assert_eq!(Arc::strong_count(&yes), 2);
        assert_eq!(Arc::strong_count(&no), 2);
        assert_eq!(bp.shared.len(), 2);
        assert_eq!(bp.type_id(NodeId(2)), "Condition");
        let mut tree = crate::Tree::with_clock(Arc::clone(&bp), crate::ManualClock::new());
        // 499 sequences fail on `no`; the last succeeds.
        assert_eq!(tree.tick_once(&mut ()), Ok(crate::Status::Success));
        drop(tree);
        drop(bp);
        assert_eq!(Arc::strong_count(&yes), 1);
    }

    #[test]
    fn a_shared_condition_leaf_is_an_open_a_type_and_a_close() {
        let yes: Arc<dyn Condition<()>> = Arc::new(Answer(true));
        let no: Arc<dyn Condition<()>> = Arc::new(Answer(false));
        let third: Arc<dyn Condition<()>> = Arc::new(Answer(true));
        // Runs of names, a name that is not the type, an empty name, three conditions
        // taking turns (the two called last are looked up apart from the others).
        let leaves: [(&str, &str, &Arc<dyn Condition<()>>); 8] = [
            ("yes", "yes", &yes),
            ("yes", "yes", &yes),
            ("no", "no", &no),
            ("check", "yes", &yes),
            ("", "no", &no),
            ("third", "third", &third),
            ("yes", "yes", &yes),
            ("no", "no", &no),
        ];
        let long = leaves.iter().fold(
            Builder::<()>::new().open(NodeKind::Sequence(Sequence), "root"),
            |b, (name, type_id, c)| b.open_shared_condition(c, name).type_id(type_id).close(),
        );
        let short = leaves.iter().fold(
            Builder::<()>::new().open(NodeKind::Sequence(Sequence), "root"),
            |b, (name, type_id, c)| b.shared_condition_leaf(name, type_id, c),
        );
        let (long, short) = (
            long.close().build().unwrap(),
            short.close().build().unwrap(),
        );
        let seen = |bp: &Blueprint<()>| {
            bp.ids()
                .map(|id| {
                    let kind = alloc::format!("{:?}", bp.def(id).kind);
                    (bp.name(id).to_string(), bp.type_id(id).to_string(), kind)
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(seen(&short), seen(&long));
        assert_eq!(short.structure_hash(), long.structure_hash());
        assert_eq!(short.shared.len(), 3);
        assert_eq!(short.name(NodeId(5)), "Condition");
        assert_eq!(short.type_id(NodeId(4)), "yes");
        // A leaf at the root, or past the depth limit, is refused as the long way refuses it.
        let yes2 = Arc::clone(&yes);
        let root = Builder::<()>::new().shared_condition_leaf("a", "a", &yes2);
        assert_eq!(root.build().unwrap().len(), 1);
        let deep = Builder::<()>::new()
            .max_depth(1)
            .open(NodeKind::Sequence(Sequence), "root")
            .shared_condition_leaf("a", "a", &yes2)
            .close();
        assert!(matches!(
            err(deep).kind,
            BuildErrorKind::TooDeep { limit: 1 }
        ));
    }

    #[test]
    fn names_fit_up_to_the_limit_only() {
        assert_eq!(names_fit(0, MAX_NAMES_BYTES), Some(()));
        assert_eq!(names_fit(MAX_NAMES_BYTES - 3, 3), Some(()));
        assert_eq!(names_fit(MAX_NAMES_BYTES - 3, 4), None);
        assert_eq!(names_fit(usize::MAX, 1), None);
    }

    fn err<C>(b: Builder<C>) -> BuildError {
        match b.build() {
            Err(e) => e,
            Ok(_) => panic!("expected a build error"),
        }
    }

    #[test]
    fn pre_order_ids_and_paths() {
        let bp = Builder::<()>::new()
            .sequence("root", |s| {
                s.fallback("f", |f| f.always_failure("a").always_success("b"))
                    .always_success("c")
            })
            .build()
            .unwrap();
        let names: Vec<&str> = bp.ids().map(|i| bp.name(i)).collect();
        assert_eq!(names, ["root", "f", "a", "b", "c"]);
        assert_eq!(bp.children(NodeId(0)), &[NodeId(1), NodeId(4)]);
        assert_eq!(bp.children(NodeId(1)), &[NodeId(2), NodeId(3)]);
        assert_eq!(bp.parent(NodeId(3)), Some(NodeId(1)));
        assert_eq!(bp.path(NodeId(3)), "root/f/b");
        assert_eq!(
            bp.paths(),
            ["root", "root/f", "root/f/a", "root/f/b", "root/c"]
        );
        assert_eq!(bp.subtree_ends(), [5, 4, 3, 4, 5]);
        assert_eq!(bp.depth(NodeId(3)), 3);
        assert_eq!(bp.find("root/c"), Some(NodeId(4)));
    }

    #[test]
    fn unnamed_nodes_show_their_type() {
        let bp = Builder::<()>::new()
            .inverter("", |i| i.always_success(""))
            .build()
            .unwrap();
        assert_eq!(bp.path(NodeId(1)), "Inverter/AlwaysSuccess");
    }

    #[test]
    fn decorator_needs_one_child() {
        let e = err(Builder::<()>::new().sequence("root", |s| {
            s.inverter("inv", |i| i.always_success("a").always_success("b"))
        }));
        assert_eq!(e.path, "root/inv");
        assert_eq!(
            e.kind,
            BuildErrorKind::ChildCount {
                type_name: "Inverter".into(),
                expected: Arity::One,
                found: 2
            }
        );
        assert_eq!(
            e.to_string(),
            "root/inv: Inverter takes exactly 1 child, found 2"
        );
    }

    #[test]
    fn if_then_else_needs_two_or_three() {
        let e = err(Builder::<()>::new().if_then_else("ite", |i| i.always_success("a")));
        assert!(matches!(
            e.kind,
            BuildErrorKind::ChildCount { found: 1, .. }
        ));
        let e = err(Builder::<()>::new().if_then_else("ite", |i| {
            i.always_success("a")
                .always_success("b")
                .always_success("c")
                .always_success("d")
        }));
        assert!(matches!(
            e.kind,
            BuildErrorKind::ChildCount { found: 4, .. }
        ));
    }

    #[test]
    fn parallel_threshold_above_children_is_rejected() {
        let e =
            err(Builder::<()>::new()
                .parallel("p", 3, 1, |p| p.always_success("a").always_success("b")));
        assert_eq!(e.path, "p");
        assert_eq!(
            e.kind,
            BuildErrorKind::Threshold {
                type_name: "Parallel".into(),
                which: "success",
                value: 3,
                children: 2
            }
        );
    }

    #[test]
    fn negative_thresholds_and_policies_resolve() {
        let bp = Builder::<()>::new()
            .sequence("root", |s| {
                s.parallel("p", -2, -1, |p| {
                    p.always_success("a")
                        .always_success("b")
                        .always_success("c")
                })
                .parallel_policy("q", ParallelPolicy::RequireCount(2), |p| {
                    p.always_success("a")
                        .always_success("b")
                        .always_success("c")
                })
            })
            .build()
            .unwrap();
        let resolved = |id| match bp.kind(NodeId(id)) {
            NodeKind::Parallel(Parallel {
                policy: ParallelPolicy::Thresholds { success, failure },
            }) => (*success, *failure),
            other => panic!("unexpected {other:?}"),
        };
        assert_eq!(resolved(1), (-2, -1));
        assert_eq!(resolved(5), (2, 2));
    }

    #[test]
    fn second_root_and_empty_are_rejected() {
        let e = err(Builder::<()>::new().always_success("a").always_success("b"));
        assert_eq!(e.kind, BuildErrorKind::SecondRoot);
        assert_eq!(err(Builder::<()>::new()).kind, BuildErrorKind::Empty);
        let e = err(Builder::<()>::new().open(NodeKind::Sequence(Sequence), "s"));
        assert_eq!(e.kind, BuildErrorKind::Unclosed { open: 1 });
        let e = err(Builder::<()>::new().always_success("a").close());
        assert_eq!(e.kind, BuildErrorKind::UnbalancedClose);
    }

    #[test]
    fn depth_limit_is_enforced_without_recursion() {
        let mut b = Builder::<()>::new().max_depth(40);
        for _ in 0..10_000 {
            b = b.open(NodeKind::Inverter(Inverter), "i");
        }
        b = b.always_success("leaf");
        for _ in 0..10_000 {
            b = b.close();
        }
        let e = err(b);
        assert_eq!(e.kind, BuildErrorKind::TooDeep { limit: 40 });
        assert!(e.path.starts_with("i/i/"), "{}", e.path);
        assert!(e.path.contains('…'));
    }

    #[test]
    fn subtrees_open_scopes() {
        let scope = SubTreeScope {
            remap: alloc::vec![("goal".into(), "target".into())],
            autoremap: false,
            values: Vec::new(),
        };
        let bp = Builder::<()>::new()
            .sequence("root", |s| {
                s.subtree("sub", scope.clone(), |t| t.always_success("inner"))
                    .always_success("outer")
            })
            .build()
            .unwrap();
        assert_eq!(bp.scope(NodeId(1)), ScopeId::ROOT);
        assert_eq!(bp.scope(NodeId(2)), ScopeId(1));
        assert_eq!(bp.scope(NodeId(3)), ScopeId::ROOT);
        assert_eq!(bp.scopes.len(), 1);
        assert_eq!(bp.scopes[0], (ScopeId::ROOT, scope));
    }
}

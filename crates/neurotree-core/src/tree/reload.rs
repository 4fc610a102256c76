//! Reloading a running tree: a new blueprint under a running instance, keeping the state of
//! every node that did not change.
//!
//! Nodes are matched by their [path](crate::Blueprint::path) (the k-th node of a path
//! matches the k-th of the same path, for siblings of one name) and are *unchanged* when
//! everything they were built from is the same: their type, their kind with its
//! parameters, their ports, their pre- and post-conditions and their number of children (a
//! control whose children were added or removed starts afresh, since its state, a cursor
//! or the children it has seen, counts them); for a custom node, which may read its
//! children's ports (a UtilitySelector its Utilities' scores), its children's types, ports
//! and conditions too.
//! An unchanged node keeps its status, its state slot and its object; a node that was
//! removed or changed while Running is halted first, exactly as a halt would halt it (its
//! Running descendants first, each stateful action getting its one `on_halted`); new and
//! changed nodes start Idle. Blackboard entries are kept: the root's, and each SubTree's
//! whose SubTree node is matched.
//!
//! A halt that takes ticks ([`slow_halt`](super::slow_halt)) is waited for: the swap
//! happens when it is done, before the root is ticked again
//! ([`ReloadReport::waiting`]), so that no halt is cut short.

use alloc::boxed::Box;
use alloc::collections::BTreeMap;
use alloc::string::String;
use alloc::sync::Arc;
use alloc::vec::Vec;

use super::state::NodeState;
use super::ticker::Object;
use super::wake::TreeWake;
use super::{new_blackboard::new_blackboard, Tree};
use crate::blueprint::Blueprint;
use crate::{NodeId, NodeKind, NodeStatus};

/// What [`Tree::reload`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReloadReport {
    /// Nodes of the new tree that kept their state (unchanged).
    pub kept: usize,
    /// Nodes of the new tree that start afresh (new, or changed).
    pub restarted: usize,
    /// Nodes that were Running and were halted (removed or changed, or below one that was).
    pub halted: usize,
    /// The halts take ticks: the new tree takes over once they are done, when the tree is
    /// next ticked after that ([`Tree::tick_halt`] continues them too).
    pub waiting: bool,
}

/// Why [`Tree::reload`] refused; the tree runs on unchanged.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ReloadError {
    /// A halt that takes ticks is in progress, or an earlier reload still waits for one.
    #[error("a halt is in progress; reload once it is done")]
    Halting,
}

crate::debug_shows_message!(
    enum ReloadError {
        Halting,
    }
);

/// A reload that waits for its halts: the new blueprint, and for each of its nodes the old
/// node it keeps the state of.
pub(crate) struct Pending<C> {
    blueprint: Arc<Blueprint<C>>,
    kept_from: Vec<Option<NodeId>>,
}

/// What makes two nodes of the same path the same node: everything it was built from.
/// Its type (as the file names it), kind and parameters, ports, pre- and post-conditions,
/// number of children (a control's state counts its children: one whose children were
/// added or removed starts afresh); and for a custom node, which may read its children's
/// ports when it is made or first ticked (a UtilitySelector its Utilities' scores), the
/// type, ports and conditions of each child too.
fn signature<C>(bp: &Blueprint<C>, id: NodeId) -> String {
    use core::fmt::Write;
    let mut s = String::new();
    // Writing into a string cannot fail.
    let _ = write!(s, "{:?}|{}|", bp.kind(id), bp.children(id).len());
    own_signature(bp, id, &mut s);
    if matches!(bp.kind(id), NodeKind::Custom(_)) {
        for &child in bp.children(id) {
            s.push('[');
            own_signature(bp, child, &mut s);
            s.push(']');
        }
    }
    s
}

/// Appends what a node's file says of it: its type, its ports, its conditions.
fn own_signature<C>(bp: &Blueprint<C>, id: NodeId, s: &mut String) {
    use core::fmt::Write;
    // Writing into a string cannot fail.
    let _ = write!(s, "{}|", bp.type_id(id));
    for port in bp.ports(id) {
        let _ = write!(s, "{}={:?};", port.name, port.value);
    }
    if let Some(hooks) = bp.hooks(id) {
        hooks.attributes(&mut |name, value| {
            let _ = write!(s, "{name}={value:?};");
        });
    }
}

/// For each node of `new`, the node of `old` at the same path (the same occurrence of it)
/// with the same signature, if any.
fn match_nodes<C>(old: &Blueprint<C>, new: &Blueprint<C>) -> Vec<Option<NodeId>> {
    let mut by_path: BTreeMap<(String, usize), NodeId> = BTreeMap::new();
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    for (i, path) in old.paths().into_iter().enumerate() {
        let k = seen.entry(path.clone()).or_insert(0);
        by_path.insert((path, *k), NodeId(i as u32));
        *k += 1;
    }
    seen.clear();
    new.paths()
        .into_iter()
        .enumerate()
        .map(|(i, path)| {
            let k = seen.entry(path.clone()).or_insert(0);
            let occurrence = *k;
            *k += 1;
            let id = NodeId(i as u32);
            let o = *by_path.get(&(path, occurrence))?;
            (signature(old, o) == signature(new, id)).then_some(o)
        })
        .collect()
}

impl<C> Tree<C> {
    /// Swaps `blueprint` in under this running instance, keeping the state of every node
    /// that did not change and halting those removed or changed while Running; `ctx` is
    /// what their halts get. Between two ticks only.
    ///
    /// Nodes are matched by path (the k-th node of a path with the k-th of the same path)
    /// and are unchanged when their type, kind and parameters, ports, conditions and number
    /// of children are the same, and for a custom node its children's types, ports and
    /// conditions: an unchanged node keeps its status, state slot and object; a node
    /// removed or changed while Running is halted first, as a halt halts it (its Running
    /// descendants first, each stateful action getting its one `on_halted`), and new or
    /// changed nodes start Idle. Blackboard entries are kept (the root's, and those of each
    /// matched SubTree). A halt that takes ticks delays the swap until it is done
    /// ([`ReloadReport::waiting`]).
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Status, Tree};
    ///
    /// let v1 = Blueprint::<()>::builder()
    ///     .sequence_with_memory("patrol", |s| s.always_success("a").sleep("wait", std::time::Duration::from_secs(9)))
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(v1, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Running));
    ///
    /// // The wait is shortened: `patrol` and `a` keep their state, `wait` is halted and
    /// // starts afresh.
    /// let v2 = Blueprint::<()>::builder()
    ///     .sequence_with_memory("patrol", |s| s.always_success("a").sleep("wait", std::time::Duration::ZERO))
    ///     .build_shared()
    ///     .unwrap();
    /// let report = tree.reload(v2, &mut ()).unwrap();
    /// assert_eq!((report.kept, report.restarted, report.halted), (2, 1, 1));
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    /// ```
    pub fn reload(
        &mut self,
        blueprint: Arc<Blueprint<C>>,
        ctx: &mut C,
    ) -> Result<ReloadReport, ReloadError> {
        if self.is_halting()
            || self
                .rare
                .as_ref()
                .is_some_and(|r| r.pending_reload.is_some())
        {
            return Err(ReloadError::Halting);
        }
        let kept_from = match_nodes(&self.blueprint, &blueprint);
        let mut survives = alloc::vec![false; self.blueprint.len()];
        for o in kept_from.iter().flatten() {
            survives[o.index()] = true;
        }
        let running: Vec<bool> = self
            .state
            .statuses()
            .iter()
            .map(|s| *s == NodeStatus::Running)
            .collect();
        // In pre-order, so that a halted node's descendants are halted through it.
        {
            let mut t = self.ticker(ctx);
            for id in t.bp.ids() {
                if !survives[id.index()] && t.status(id) == NodeStatus::Running {
                    t.halt_node(id);
                }
            }
        }
        let halted = running
            .iter()
            .zip(self.state.statuses().iter())
            .filter(|(was, now)| **was && **now != NodeStatus::Running)
            .count();
        let kept = kept_from.iter().filter(|o| o.is_some()).count();
        let report = ReloadReport {
            kept,
            restarted: blueprint.len() - kept,
            halted,
            waiting: self.is_halting(),
        };
        let pending = Pending {
            blueprint,
            kept_from,
        };
        if report.waiting {
            self.rare_mut().pending_reload = Some(Box::new(pending));
        } else {
            self.swap(pending);
        }
        Ok(report)
    }

    /// Takes over a reload that waited for halts, once they are done.
    pub(super) fn finish_reload(&mut self) {
        if let Some(pending) = self
            .rare
            .as_deref_mut()
            .and_then(|r| r.pending_reload.take())
        {
            self.swap(*pending);
        }
    }

    /// Puts the new blueprint in, with the kept nodes' state.
    fn swap(&mut self, pending: Pending<C>) {
        let Pending {
            blueprint: new,
            kept_from,
        } = pending;
        // The tree keeps its old blueprint until its new state is in: the ticks read the
        // state by the blueprint's node indices unchecked, and a stateful leaf's factory or
        // an old object's drop below may panic, into a caller that keeps the tree.
        let old = Arc::clone(&self.blueprint);
        // The new nodes' objects are made first, while every kept one is still in the old
        // block: a factory that panics leaves the tree as it was. The kept objects are then
        // taken out of the old block (a vacant object left in their place), which cannot
        // panic; the others stay there, to be dropped with it.
        let old_objects = self.state.parts().objects;
        let old_len = old_objects.len();
        let kept = |id: NodeId| kept_from[id.index()].filter(|o| old.slot(*o) < old_len);
        let mut objects = Vec::with_capacity(new.objects as usize);
        for id in new.ids() {
            let kind = new.kind(id);
            if kind.has_object() {
                objects.push(match kept(id) {
                    Some(_) => Object::Vacant,
                    None => fresh_object(kind),
                });
            }
        }
        let mut at = 0;
        for id in new.ids() {
            if new.kind(id).has_object() {
                if let Some(o) = kept(id) {
                    objects[at] = core::mem::replace(&mut old_objects[old.slot(o)], Object::Vacant);
                }
                at += 1;
            }
        }
        let mut state = NodeState::new(new.len(), new.aux_slots as usize, objects);
        let parts = state.parts();
        let (statuses, aux) = (parts.statuses, parts.aux);
        for id in new.ids() {
            let Some(o) = kept_from[id.index()] else {
                continue;
            };
            statuses[id.index()] = self.state.statuses()[o.index()];
            // A kept node has the kind and children it had: its slots are as many.
            let slots = new.aux_slots_of(id);
            if slots > 0 {
                let (to, at) = (new.slot(id), old.slot(o));
                aux[to..to + slots].copy_from_slice(&self.state.aux()[at..at + slots]);
            }
        }
        let mut blackboard = new_blackboard(&new);
        let scope_of = |bp: &Blueprint<C>, id: NodeId| match bp.kind(id) {
            NodeKind::SubTree(_) => bp.children(id).first().map(|c| bp.scope(*c)),
            _ => None,
        };
        let mut scopes = BTreeMap::new();
        scopes.insert(0_u32, 0_u32);
        for id in new.ids() {
            if let Some(o) = kept_from[id.index()] {
                if let (Some(from), Some(to)) = (scope_of(&old, o), scope_of(&new, id)) {
                    scopes.insert(from.0, to.0);
                }
            }
        }
        for (scope, key, info, untyped, value) in self.blackboard.take_raw_entries() {
            if let Some(&to) = scopes.get(&scope) {
                blackboard.put_raw_entry(to, key, info, untyped, value);
            }
        }
        blackboard.set_last_stamp(self.blackboard.last_stamp());
        self.blackboard = blackboard;
        self.blueprint = Arc::clone(&new);
        let old_state = core::mem::replace(&mut self.state, state);
        self.resting = None;
        self.wake_up();
        // The halts are done, so the objects left behind are at rest; dropping them is all
        // a removed node's object gets. Last, once the tree is whole: a drop may panic.
        drop(old_state);
        let has_async = new
            .ids()
            .any(|id| matches!(new.kind(id), NodeKind::Async(_)));
        if has_async && self.wake().is_none() {
            self.rare_mut().wake = Some(Box::new(TreeWake::new()));
        }
        self.forget_notes();
    }
}

/// A node's object as its factory makes it.
fn fresh_object<C>(kind: &NodeKind<C>) -> Object<C> {
    match kind {
        NodeKind::Stateful(make) => Object::Stateful(make()),
        NodeKind::Custom(spec) => Object::Custom((spec.factory)()),
        _ => Object::Async(None),
    }
}

//! The last step of building: the nodes pushed in order become the blueprint's flat arrays
//! (children lists, the conditions called from their parents' lists, names, scopes).

use alloc::boxed::Box;
use alloc::vec::Vec;

use super::super::{Blueprint, Child, Guards, NodeId, NodeKind, SubTreeScope};
use super::*;
use crate::blackboard::ScopeId;

impl<C> State<C> {
    pub(super) fn finish(self) -> Blueprint<C> {
        let count = self.defs.len();
        let mut nodes = self.defs;
        let mut meta = self.metas;
        let mut slots = Vec::with_capacity(count);
        // Most nodes have no hooks and no ports: the few that do are put in place after.
        let mut hooks: Vec<Option<Box<dyn NodeHooks<C>>>> = (0..count).map(|_| None).collect();
        for (at, attached) in self.hooks {
            hooks[at as usize] = Some(attached);
        }
        if let Some(mut wrap) = self.wrap_hooks {
            for (id, slot) in hooks.iter_mut().enumerate() {
                *slot = wrap(NodeId(id as u32), slot.take());
            }
        }
        for (at, bound) in self.ports {
            meta[at as usize].ports = bound;
        }
        let mut node_scopes = Vec::with_capacity(count);
        // Every node but the root is the child of one node; a node's children are laid out
        // together, in order, after those of the nodes before it.
        let mut children = alloc::vec![NodeId::ROOT; count.saturating_sub(1)];
        // Per node: where its next child goes in `children`.
        let mut next_child: Vec<u32> = Vec::with_capacity(count);
        let mut laid_out = 0u32;
        let mut scopes: Vec<(ScopeId, SubTreeScope)> = Vec::new();
        // The scope each node's children use: a SubTree opens a new one.
        let mut child_scope: Vec<ScopeId> = Vec::with_capacity(count);
        let mut aux = 0u32;
        let mut objects = 0u32;
        // What each node's children all are, for its parent's loop (see `Guards`), made up
        // as they are laid out; `None` until the first child.
        let mut guards: Vec<Option<Guards>> = alloc::vec![None; count];
        for id in 0..count {
            let def = &mut nodes[id];
            def.first_child = laid_out;
            next_child.push(laid_out);
            laid_out += def.child_count;
            let def = &nodes[id];
            let hooked = hooks[id].is_some();
            let parent = meta[id].parent;
            let scope = match parent {
                Some(parent) => {
                    let p = parent.index();
                    // Pre-order: the parent came first, and its earlier children before
                    // this one.
                    let slot = &mut next_child[p];
                    children[*slot as usize] = NodeId(id as u32);
                    *slot += 1;
                    // A hooked condition takes the general path, which runs its hooks.
                    let guard = match (&def.kind, hooked) {
                        (NodeKind::ConditionFn(_), false) => Guards::Closures,
                        (NodeKind::Condition(_) | NodeKind::SharedCondition(_), false) => {
                            Guards::Objects
                        }
                        _ => Guards::Mixed,
                    };
                    let all = &mut guards[p];
                    *all = match *all {
                        None => Some(guard),
                        Some(so_far) if so_far == guard => Some(guard),
                        Some(_) => Some(Guards::Mixed),
                    };
                    child_scope[p]
                }
                None => ScopeId::ROOT,
            };
            let own_child_scope = match &def.kind {
                NodeKind::SubTree(spec) => {
                    scopes.push((scope, SubTreeScope::clone(spec)));
                    ScopeId(scopes.len() as u32)
                }
                _ => scope,
            };
            child_scope.push(own_child_scope);
            let object = match def.kind {
                NodeKind::Stateful(_) | NodeKind::Custom(_) | NodeKind::Async(_) => {
                    objects += 1;
                    objects - 1
                }
                _ => 0,
            };
            let own_slots = def.kind.aux_slots(def.child_count);
            slots.push(if own_slots > 0 { aux } else { object });
            node_scopes.push(scope);
            // Two slots a node at most, fewer than 2^32 nodes: the sum stays below 2^33,
            // and a block of more than 2^32 slots is beyond memory.
            aux = aux
                .checked_add(own_slots)
                .expect("a blueprint has fewer than 2^32 state slots");
        }
        let nodes = nodes.into_boxed_slice();
        let shared = self.shared.into_boxed_slice();
        // Per node, whether a node above it re-checks its children every tick: only
        // there does a condition's call note what it reads (see `call::entry_of`). In
        // pre-order a parent is known before its children.
        let mut rechecked: Vec<bool> = Vec::with_capacity(nodes.len());
        for node in &meta[..nodes.len()] {
            let under = node
                .parent
                .is_some_and(|p| rechecked[p.index()] || nodes[p.index()].kind.rechecks());
            rechecked.push(under);
        }
        // A shared condition's entries are looked up once, not for each of its nodes.
        let entries: Vec<_> = shared
            .iter()
            .map(|c| {
                [
                    crate::blueprint::call::entry_of(&**c, false),
                    crate::blueprint::call::entry_of(&**c, true),
                ]
            })
            .collect();
        let hot_children = children
            .iter()
            .map(|&id| {
                let i = id.index();
                let guard = guards[i].unwrap_or(Guards::Mixed);
                let hooked = hooks[i].is_some();
                Child::new(
                    id,
                    &nodes[i],
                    hooked,
                    guard,
                    rechecked[i],
                    &shared,
                    &entries,
                )
            })
            .collect();
        // Per node, whether every ancestor passes a Running child's tick straight through
        // and has no hooks: in pre-order a parent is known before its children, so one
        // pass (not a walk up from each node) tells it.
        // A tree without stateful actions (`objects` counts them) rests in none.
        let stateful = objects > 0;
        let mut clear_above: Vec<bool> = Vec::with_capacity(if stateful { nodes.len() } else { 0 });
        for i in (0..nodes.len()).filter(|_| stateful) {
            let clear = match meta[i].parent {
                Some(parent) => {
                    let p = parent.index();
                    clear_above[p] && hooks[p].is_none() && nodes[p].kind.passes_through()
                }
                None => true,
            };
            clear_above.push(clear);
        }
        let resting = (0..nodes.len())
            .map(|i| {
                stateful
                    && matches!(nodes[i].kind, NodeKind::Stateful(_))
                    && hooks[i].is_none()
                    && clear_above[i]
            })
            .collect();
        Blueprint {
            hot_children,
            resting,
            nodes,
            children: children.into_boxed_slice(),
            slots: slots.into_boxed_slice(),
            hooks: hooks.into_boxed_slice(),
            node_scopes: node_scopes.into_boxed_slice(),
            meta: meta.into_boxed_slice(),
            names: self.names,
            scopes: scopes.into_boxed_slice(),
            shared,
            aux_slots: aux,
            objects,
            max_depth: self.max_depth,
            value_codecs: self.value_codecs,
            port_directions: self.port_directions,
            #[cfg(target_has_atomic = "64")]
            hash: core::sync::atomic::AtomicU64::new(0),
        }
    }
}

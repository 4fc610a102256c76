//! The per-instance objects of a tree: the stateful leaves, the custom controls and
//! decorators, and the running futures of async actions, which keep their state in `self`;
//! how the ticker ticks, halts and lends them out.

use core::mem;

use super::slow_halt::Owner;
use super::ticker::{contain, Ticker};
use crate::nodes::custom::{CustomNode, NodeCtx};
use crate::nodes::leaf::{ActionFuture, HaltFuture, Handle, StatefulAction};
use crate::{NodeId, NodeStatus, TickError};

/// A per-instance object: the state a leaf or custom node keeps in `self`.
pub(crate) enum Object<C> {
    Stateful(alloc::boxed::Box<dyn StatefulAction<C>>),
    Custom(alloc::boxed::Box<dyn CustomNode<C>>),
    /// A stateful action whose halt is in progress, and the node that waits for it
    /// (`None`: the tree); see [`slow_halt`](super::slow_halt).
    Halting {
        action: alloc::boxed::Box<dyn StatefulAction<C>>,
        owner: Owner,
    },
    /// The running future of an async action, `None` between runs.
    Async(Option<ActionFuture>),
    /// An async action whose halt is in progress: the future of its halt, and the node
    /// that waits for it (`None`: the tree).
    AsyncHalting {
        halt: HaltFuture,
        owner: Owner,
    },
    /// A custom node's slot while its object is out ticking or halting (it needs the
    /// ticker, which holds the slot); left so only if that code panicked.
    Vacant,
}

impl<C> Object<C> {
    /// Whom a halt in progress waits for, if this is one.
    pub(crate) fn halt_owner(&mut self) -> Option<&mut Owner> {
        match self {
            Object::Halting { owner, .. } | Object::AsyncHalting { owner, .. } => Some(owner),
            _ => None,
        }
    }

    /// Whom a halt in progress waits for (`Some(None)`: the tree), if this is one.
    pub(crate) fn waits_for(&self) -> Option<Option<NodeId>> {
        match self {
            Object::Halting { owner, .. } | Object::AsyncHalting { owner, .. } => Some(owner.get()),
            _ => None,
        }
    }

    /// `true` for a halt in progress.
    pub(crate) fn is_halting(&self) -> bool {
        self.waits_for().is_some()
    }

    /// The object once its halt is done.
    pub(crate) fn halted(self) -> Self {
        match self {
            Object::Halting { action, .. } => Object::Stateful(action),
            Object::AsyncHalting { .. } => Object::Async(None),
            other => other,
        }
    }
}

impl<'t, C> Ticker<'t, C> {
    /// The node's per-instance object and a handle for it, borrowed side by side.
    pub(crate) fn split(&mut self, id: NodeId) -> (Option<&mut Object<C>>, Handle<'_, C>) {
        let bp = self.bp;
        let object = if bp.nodes[id.index()].kind.has_object() {
            self.objects.get_mut(bp.slot(id))
        } else {
            None
        };
        let handle = Handle {
            ctx: &mut *self.ctx,
            blackboard: &mut *self.bb,
            clock: self.clock,
            node: id,
            bp,
            out: &mut *self.out,
            waits: &mut self.waits,
        };
        (object, handle)
    }

    pub(super) fn tick_stateful(&mut self, id: NodeId) -> NodeStatus {
        let prev = self.status(id);
        let (Some(Object::Stateful(action)), mut h) = self.split(id) else {
            // Objects are laid out from the same blueprint that chose this kind; the other
            // case is an action still halting, which only a custom control can tick (the
            // others wait): it fails, so that it is not taken for Running.
            return NodeStatus::Failure;
        };
        match prev {
            NodeStatus::Idle | NodeStatus::Skipped => action.on_start(&mut h).into(),
            NodeStatus::Running => action.on_running(&mut h).into(),
            // Completed and not yet reset by its parent: BehaviorTree.CPP repeats the result.
            done => done,
        }
    }

    pub(super) fn tick_custom(&mut self, id: NodeId) -> NodeStatus {
        let slot = self.bp.slot(id);
        let Object::Custom(node) = mem::replace(&mut self.objects[slot], Object::Vacant) else {
            return NodeStatus::Failure;
        };
        let mut node = node;
        // Not marked Running first: a custom leaf goes Idle → result, as in BehaviorTree.CPP;
        // a node that wants the mark sets it (`NodeCtx::set_running`), as BT.CPP's do.
        let previous = self.status(id);
        let mut node_ctx = NodeCtx {
            t: self,
            id,
            previous,
            reset_completed: false,
            declared: false,
        };
        let status = node.tick(&mut node_ctx);
        let reset_completed = node_ctx.reset_completed;
        if !node_ctx.declared {
            self.stay_awake(crate::AwakeReason::UndeclaredCustom, id);
            self.waits.opaque(id);
        }
        self.objects[slot] = Object::Custom(node);
        if reset_completed {
            // Only an observer can tell the reset from one after the store: without one,
            // doing it now spares the store a check.
            if self.observed() {
                self.reset_after_store = Some(id);
            } else {
                self.reset_completed_children(id);
            }
        }
        if status == NodeStatus::Idle {
            let bp = self.bp;
            self.out.fault(|| TickError::ReturnedIdle {
                node: id,
                path: bp.path(id),
            });
            return NodeStatus::Failure;
        }
        status
    }

    /// Halts a custom node: its own `halt` if it is Running, then its children.
    pub(super) fn halt_custom(&mut self, id: NodeId) {
        let obj = self.bp.slot(id);
        if self.status(id) == NodeStatus::Running {
            self.current = id;
            if let Object::Custom(mut node) = mem::replace(&mut self.objects[obj], Object::Vacant) {
                contain(self, id, |t| {
                    node.halt(&mut NodeCtx {
                        t,
                        id,
                        previous: NodeStatus::Running,
                        reset_completed: false,
                        declared: false,
                    });
                });
                self.objects[obj] = Object::Custom(node);
            }
        }
        self.reset_children(id);
    }

    /// Puts back the objects of custom nodes that a panic left vacant (the object was out
    /// of its slot while it ran), made anew by their factories.
    #[cfg(feature = "std")]
    pub(crate) fn replace_vacant_objects(&mut self) {
        for id in self.bp.ids() {
            if let crate::NodeKind::Custom(spec) = &self.bp.def(id).kind {
                let slot = self.bp.slot(id);
                if matches!(self.objects[slot], Object::Vacant) {
                    self.objects[slot] = Object::Custom((spec.factory)());
                }
            }
        }
    }
}

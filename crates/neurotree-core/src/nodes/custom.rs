//! User-defined controls and decorators.
//!
//! A [`CustomNode`] decides which children to tick, like the built-in controls do, through a
//! [`NodeCtx`]. One object is made per tree instance, so it may keep state in `self`. After
//! [`CustomNode::halt`] the engine halts any child still Running, so the halting rules hold
//! for user nodes too.
//!
//! As in BehaviorTree.CPP, the engine stores what `tick` returns and nothing before: a
//! custom leaf goes from Idle straight to Success in a trace. A control or decorator that,
//! like BehaviorTree.CPP's own (`setStatus(RUNNING)` at the top of their `tick`), should be
//! seen Running while its children tick calls [`NodeCtx::set_running`].
//!
//! BehaviorTree.CPP's `DecoratorNode::executeTick` resets a child that completed after the
//! decorator's own status is set; a custom node that wants that order calls
//! [`NodeCtx::reset_completed_children_after_tick`] instead of resetting inside its `tick`.

use alloc::string::String;
use core::any::Any;
use core::time::Duration;

use crate::blackboard::Blackboard;
use crate::nodes::leaf::read_input;
use crate::tree::Ticker;
use crate::{FromPortStr, NodeId, NodeStatus, PortError};

/// A control or decorator written by the user.
///
/// ```
/// use neurotree_core::{Arity, Blueprint, CustomNode, CustomSpec, ManualClock, NodeCtx, NodeStatus, Status, Tree};
///
/// /// Ticks its children in reverse order, as a Sequence would.
/// struct ReverseSequence;
/// impl<C> CustomNode<C> for ReverseSequence {
///     fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
///         for i in (0..node.child_count()).rev() {
///             match node.tick_child(i) {
///                 NodeStatus::Success | NodeStatus::Skipped => {}
///                 other => return other,
///             }
///         }
///         node.reset_children();
///         NodeStatus::Success
///     }
/// }
///
/// let spec = CustomSpec::<Vec<&str>>::new(
///     "ReverseSequence",
///     Arity::AtLeast(1),
///     Box::new(|| Box::new(ReverseSequence)),
/// );
/// let bp = Blueprint::builder()
///     .custom("rev", spec, |c| {
///         c.action("a", |log: &mut Vec<&str>| { log.push("a"); Status::Success })
///             .action("b", |log: &mut Vec<&str>| { log.push("b"); Status::Success })
///     })
///     .build_shared()
///     .unwrap();
/// let mut tree = Tree::with_clock(bp, ManualClock::new());
/// let mut log = Vec::new();
/// assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
/// assert_eq!(log, ["b", "a"]);
/// ```
pub trait CustomNode<C>: Send {
    /// Ticks the node; return Running, Success, Failure or Skipped (never Idle).
    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus;

    /// Called when the node is halted while Running, before the engine halts its running
    /// children. Reset the node's own state here. The node's halt is over when this
    /// returns; a stop that takes ticks belongs in a child action, whose halt then waits
    /// for whoever halted this node (see [`slow_halt`](crate::tree::slow_halt)).
    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {}

    /// Opt-in: the state this node keeps in `self` between ticks, as bytes, for
    /// [`Tree::save_state`](crate::Tree::save_state); `None` (the default) means it cannot
    /// be saved, and saving a tree that holds it is an error naming the node. A node that
    /// keeps nothing in `self` returns `Some(Vec::new())`.
    fn save_state(&self) -> Option<alloc::vec::Vec<u8>> {
        None
    }

    /// Takes back what [`save_state`](Self::save_state) gave, into a node fresh from its
    /// factory; `false` if the bytes are not its state (the restore is then refused).
    fn restore_state(&mut self, state: &[u8]) -> bool {
        state.is_empty()
    }
}

/// What a [`CustomNode`] sees: its children, the context, the blackboard and the clock.
pub struct NodeCtx<'a, 't, C> {
    pub(crate) t: &'a mut Ticker<'t, C>,
    pub(crate) id: NodeId,
    /// The node's stored status when the call began (kept, as `set_running` changes the
    /// stored one).
    pub(crate) previous: NodeStatus,
    /// Set by [`reset_completed_children_after_tick`](Self::reset_completed_children_after_tick).
    pub(crate) reset_completed: bool,
    /// The node said what its result waits on, so the tree may sleep (see
    /// [`sleep`](crate::tree::sleep)).
    pub(crate) declared: bool,
}

impl<'t, C> NodeCtx<'_, 't, C> {
    /// The node's id.
    pub fn id(&self) -> NodeId {
        self.id
    }

    /// The node's stored status before this tick: `Idle` on a tick that starts a run (the
    /// first, or the first after its parent reset or halted it), `Running` while it runs,
    /// or the Success or Failure it returned and its parent has not reset yet. This is what
    /// a BehaviorTree.CPP node reads as `status()` at the top of its `tick`. In
    /// [`CustomNode::halt`] it is `Running`.
    pub fn previous_status(&self) -> NodeStatus {
        self.previous
    }

    /// Marks the node Running now, as BehaviorTree.CPP's `setStatus(RUNNING)` does at the
    /// top of most controls' and decorators' `tick` (Sequence, Repeat, Loop, Nav2's
    /// RecoveryNode...): an observer then sees the node Running before its children's
    /// changes. The engine does not do it for you, so that a custom leaf goes straight from
    /// Idle to its result, as a BehaviorTree.CPP leaf does. What the node returns is stored
    /// afterwards either way.
    pub fn set_running(&mut self) {
        self.t.set_status(self.id, NodeStatus::Running);
    }

    /// Number of children.
    pub fn child_count(&self) -> usize {
        self.t.bp.children(self.id).len()
    }

    /// Ticks child `i` and returns what it returned.
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn tick_child(&mut self, i: usize) -> NodeStatus {
        let child = self.t.bp.children(self.id)[i];
        self.t.tick(child)
    }

    /// The stored status of child `i`.
    pub fn child_status(&self, i: usize) -> NodeStatus {
        let child = self.t.bp.children(self.id)[i];
        self.t.status(child)
    }

    /// The ports of child `i` and their bindings: what a control that reads its children's
    /// parameters (a UtilitySelector reads each Utility's `score`) looks at.
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn child_ports(&self, i: usize) -> &'t [crate::Port] {
        let bp: &'t crate::Blueprint<C> = self.t.bp;
        bp.ports(bp.children(self.id)[i])
    }

    /// Tells the tree's observer, if any, that child `i` was given `score` in this tick
    /// ([`Observer::on_node_score`](crate::Observer::on_node_score)): a control that
    /// chooses by score reports what it chose by, for live views. Costs a branch without
    /// an observer.
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn report_child_score(&mut self, i: usize, score: f64) {
        let child = self.t.bp.children(self.id)[i];
        if let Some(observer) = self.t.observer.as_deref_mut() {
            observer.on_node_score(child, score);
        }
    }

    /// The type name of child `i`'s kind ([`NodeKind::type_name`](crate::NodeKind::type_name)).
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn child_type_name(&self, i: usize) -> &'t str {
        let bp: &'t crate::Blueprint<C> = self.t.bp;
        bp.kind(bp.children(self.id)[i]).type_name()
    }

    /// Reads input port `port` of child `i`, as the child would read it.
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn child_input<T: FromPortStr + Any + Clone>(
        &self,
        i: usize,
        port: &str,
    ) -> Result<T, PortError> {
        let child = self.t.bp.children(self.id)[i];
        read_input(self.t.bb, self.t.bp, child, port)
    }

    /// Reports a runtime error of child `i` (one this node evaluates for it): the tick ends
    /// with [`TickError::Node`](crate::TickError::Node) naming the child. Return Failure
    /// after calling it.
    ///
    /// # Panics
    /// If `i` is not below [`child_count`](Self::child_count).
    pub fn fail_child(&mut self, i: usize, message: impl Into<String>) {
        let child = self.t.bp.children(self.id)[i];
        self.t.fault_node(child, message.into());
    }

    /// Halts child `i` if it is Running and resets it to Idle.
    pub fn halt_child(&mut self, i: usize) {
        let child = self.t.bp.children(self.id)[i];
        self.t.halt_child(child);
    }

    /// Halts every Running child and resets all of them to Idle; call it when completing.
    pub fn reset_children(&mut self) {
        self.t.reset_children(self.id);
    }

    /// Resets to Idle every child that is Success or Failure once this node's own result is
    /// stored, as BehaviorTree.CPP's `DecoratorNode::executeTick` does after every
    /// decorator's `tick`: an observer sees this node's change before its child's return to
    /// Idle, and the child's `_skipIf`/`_successIf`/`_failureIf` are checked again on its
    /// next tick. No child is halted (none that completed is Running). Has no effect in
    /// [`CustomNode::halt`].
    pub fn reset_completed_children_after_tick(&mut self) {
        self.reset_completed = true;
    }

    /// Says that this node's own result changes only when its children's do: a tree may
    /// sleep while this node is ticked (see [`sleep`](crate::tree::sleep)). A node that
    /// says nothing keeps the tree awake.
    pub fn wakes_with_children(&mut self) {
        self.declared = true;
    }

    /// Says that this node's result may also change when the blackboard is written (it
    /// reads `key`); the sleeping tree wakes on any write.
    pub fn wake_on(&mut self, key: &str) {
        let _ = key;
        self.declared = true;
        self.t.waits.any = true;
    }

    /// Says that this node's result may also change at `at` on the tree's clock: a
    /// sleeping tree wakes then.
    pub fn sleep_until(&mut self, at: Duration) {
        self.declared = true;
        self.t.wake_at(crate::clock::duration_to_nanos(at));
    }

    /// Asks `tick_once` to tick the tree again at once (after yielding Running).
    pub fn request_wake_up(&mut self) {
        self.t.wake = Some(self.id);
    }

    /// The user's context.
    pub fn ctx(&mut self) -> &mut C {
        self.t.ctx
    }

    /// The tree's blackboard.
    pub fn blackboard(&mut self) -> &mut Blackboard {
        self.t.bb
    }

    /// The blackboard scope the node reads and writes (its subtree's).
    pub fn scope(&self) -> crate::ScopeId {
        self.t.bp.scope(self.id)
    }

    /// The node's ports and their bindings. They belong to the blueprint, so they may be
    /// held while the blackboard is borrowed.
    pub fn ports(&self) -> &'t [crate::Port] {
        let bp: &'t crate::Blueprint<C> = self.t.bp;
        bp.ports(self.id)
    }

    /// Reads input port `port`, as [`Handle::input`](crate::Handle::input) does: its literal
    /// text converted to `T`, or the blackboard entry it is bound to.
    pub fn input<T: FromPortStr + Any + Clone>(&self, port: &str) -> Result<T, PortError> {
        read_input(self.t.bb, self.t.bp, self.id, port)
    }

    /// The tree's clock reading.
    pub fn now(&self) -> Duration {
        self.t.clock.now()
    }

    /// Gives a reason for the Failure this node returns, and returns Failure, as
    /// [`Handle::fail_with`](crate::Handle::fail_with) does for a leaf.
    pub fn fail_with(&mut self, reason: crate::Reason) -> NodeStatus {
        self.t
            .note(self.id, crate::tree::failure::Note::Gave(reason));
        NodeStatus::Failure
    }

    /// Reports a runtime error: the tick ends with [`TickError::Node`](crate::TickError::Node)
    /// after the tree is halted. Return Failure after calling it.
    pub fn fail(&mut self, message: impl Into<String>) {
        let id = self.id;
        self.t.fault_node(id, message.into());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::*;
    use crate::{Arity, CustomSpec, Port};
    use alloc::boxed::Box;
    use std::sync::Mutex;

    /// What a [`Probe`] saw per call: the call, its previous status, its `limit` port.
    type Log = Arc<Mutex<Vec<(&'static str, NodeStatus, Option<u32>)>>>;

    /// A decorator that records the status it had before each call, and the `limit` port.
    struct Probe(Log);

    impl CustomNode<Lab> for Probe {
        fn tick(&mut self, node: &mut NodeCtx<'_, '_, Lab>) -> NodeStatus {
            let limit = node.input::<u32>("limit").ok();
            self.0
                .lock()
                .unwrap()
                .push(("tick", node.previous_status(), limit));
            let status = node.tick_child(0);
            if status.is_completed() {
                node.reset_children();
            }
            status
        }
        fn halt(&mut self, node: &mut NodeCtx<'_, '_, Lab>) {
            self.0
                .lock()
                .unwrap()
                .push(("halt", node.previous_status(), None));
        }
    }

    fn probe(log: &Log) -> CustomSpec<Lab> {
        let log = Arc::clone(log);
        CustomSpec::new(
            "Probe",
            Arity::One,
            Box::new(move || Box::new(Probe(Arc::clone(&log)))),
        )
    }

    fn seen(log: &Log) -> Vec<(&'static str, NodeStatus)> {
        log.lock().unwrap().drain(..).map(|e| (e.0, e.1)).collect()
    }

    #[test]
    fn a_custom_node_sees_its_status_from_before_the_tick() {
        use NodeStatus::{Failure as Fail, Idle, Running as Run};
        let log = Arc::new(Mutex::new(Vec::new()));
        // A run from Idle, a tick while Running, and after the root's reset a new run.
        let mut lab = Lab::new(&[&[R, S, R]]);
        let mut tree = lab.tree(|b| b.custom("p", probe(&log), |c| c.scripted(0)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        lab.halt(&mut tree);
        assert_eq!(
            seen(&log),
            [("tick", Idle), ("tick", Run), ("tick", Idle), ("halt", Run)]
        );
        // IfThenElse with two children leaves its failed condition un-reset: the next tick
        // finds the condition's Failure still stored.
        let mut lab = Lab::new(&[&[F], &[S]]);
        let mut tree = lab.tree(|b| {
            b.if_then_else("ite", |i| {
                i.custom("q", probe(&log), |c| c.check(0)).scripted(1)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(seen(&log), [("tick", Idle), ("tick", Fail)]);
    }

    #[test]
    fn a_custom_node_reads_its_ports() {
        let log = Arc::new(Mutex::new(Vec::new()));
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| {
            b.custom("p", probe(&log), |c| {
                c.ports([Port::entry("limit", "max")]).scripted(0)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        tree.blackboard_mut().set("max", 7_u32).unwrap();
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        let limits: Vec<Option<u32>> = log.lock().unwrap().iter().map(|e| e.2).collect();
        assert_eq!(limits, [None, Some(7)]);
    }

    /// A custom leaf that succeeds; with `mark`, a decorator that marks itself Running (as
    /// BehaviorTree.CPP's own decorators do) and passes its child's status.
    struct Plain {
        mark: bool,
    }

    impl CustomNode<Lab> for Plain {
        fn tick(&mut self, node: &mut NodeCtx<'_, '_, Lab>) -> NodeStatus {
            if !self.mark {
                return NodeStatus::Success;
            }
            node.set_running();
            let status = node.tick_child(0);
            if status.is_completed() {
                node.reset_children();
            }
            status
        }
    }

    fn plain(mark: bool) -> CustomSpec<Lab> {
        CustomSpec::new(
            "Plain",
            if mark { Arity::One } else { Arity::Leaf },
            Box::new(move || Box::new(Plain { mark })),
        )
    }

    /// Records every status change as (node, from, to).
    struct Changes(Arc<Mutex<Vec<(usize, NodeStatus, NodeStatus)>>>);

    impl crate::Observer for Changes {
        fn on_status_change(&mut self, c: crate::StatusChange) {
            self.0.lock().unwrap().push((c.node.index(), c.from, c.to));
        }
    }

    #[test]
    fn the_engine_does_not_mark_a_custom_node_running_before_its_tick() {
        use NodeStatus::{Idle, Running as Run, Success as Succ};
        let changes = Arc::new(Mutex::new(Vec::new()));
        // A custom leaf under a Sequence goes Idle → Success, as a BehaviorTree.CPP leaf.
        let mut lab = Lab::new(&[]);
        let mut tree = lab.tree(|b| b.sequence("s", |s| s.custom("leaf", plain(false), |c| c)));
        tree.set_observer(Changes(Arc::clone(&changes)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        let leaf: Vec<_> = changes
            .lock()
            .unwrap()
            .iter()
            .filter(|c| c.0 == 1)
            .copied()
            .collect();
        assert_eq!(leaf, [(1, Idle, Succ), (1, Succ, Idle)]);
        // A node that marks itself Running, as BehaviorTree.CPP's Loop or RecoveryNode do,
        // shows it before its child's changes.
        changes.lock().unwrap().clear();
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| b.custom("deco", plain(true), |c| c.scripted(0)));
        tree.set_observer(Changes(Arc::clone(&changes)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(
            *changes.lock().unwrap(),
            [
                (0, Idle, Run),
                (1, Idle, Succ),
                (1, Succ, Idle),
                (0, Run, Succ),
                (0, Succ, Idle)
            ]
        );
    }

    /// A decorator that passes its child's status and leaves the reset of a completed child
    /// to the engine, as BehaviorTree.CPP's `DecoratorNode::executeTick` does it.
    struct After;

    impl CustomNode<Lab> for After {
        fn tick(&mut self, node: &mut NodeCtx<'_, '_, Lab>) -> NodeStatus {
            let status = node.tick_child(0);
            node.reset_completed_children_after_tick();
            status
        }
    }

    fn after() -> CustomSpec<Lab> {
        CustomSpec::new("After", Arity::One, Box::new(|| Box::new(After)))
    }

    #[test]
    fn a_completed_child_is_reset_after_its_parents_status_is_stored() {
        use NodeStatus::{Failure as Fail, Idle, Running as Run, Success as Succ};
        let changes = Arc::new(Mutex::new(Vec::new()));
        let mut lab = Lab::new(&[&[R, S, F]]);
        let mut tree = lab.tree(|b| b.custom("deco", after(), |c| c.scripted(0)));
        tree.set_observer(Changes(Arc::clone(&changes)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(
            *changes.lock().unwrap(),
            [
                (1, Idle, Run),
                (0, Idle, Run),
                (1, Run, Succ),
                (0, Run, Succ),
                // The child is reset after its parent's change, not before.
                (1, Succ, Idle),
                (0, Succ, Idle),
                (1, Idle, Fail),
                (0, Idle, Fail),
                (1, Fail, Idle),
                (0, Fail, Idle),
            ]
        );
        assert_eq!(lab.ticks, [3]);
        assert_eq!(lab.halts, [0]);
        // Unobserved, the child is Idle after the tick all the same.
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("s", |s| {
                s.custom("deco", after(), |c| c.scripted(0)).scripted(0)
            })
        });
        assert_eq!(lab.tick_exactly_once(&mut tree), Ok(Status::Success));
        assert_eq!(tree.statuses(), [Idle, Idle, Idle, Idle]);
        assert_eq!(lab.ticks, [2]);
    }
}

//! Leaves: the nodes that do the work.
//!
//! | kind | in short |
//! |---|---|
//! | [`Condition`] / closure `Fn(&C) -> bool` or [of the handle](with_handle) | Success or Failure |
//! | [`Action`] / closure `Fn(&mut C) -> Status` or [of the handle](with_handle) | Success or Failure in one tick |
//! | [`StatefulAction`] | started, updated and halted over several ticks |
//! | [`AsyncAction`] / closure returning a future ([async_action]) | a future per run |
//! | [AlwaysSuccess / AlwaysFailure](always) | as their names |
//! | [Sleep](sleep) | Running until the duration has passed on the tree's clock |
//!
//! Conditions, actions and AlwaysSuccess / AlwaysFailure never run (they complete within the
//! tick) and have nothing per instance. StatefulAction, AsyncAction and Sleep run; per
//! instance, a StatefulAction has its object, an AsyncAction a future per run, a Sleep a state
//! slot.
//!
//! Stateless leaves belong to the blueprint and serve every instance; only stateful leaves
//! are created per instance. That keeps an instance of a large tree within a few kilobytes.

pub mod always;
pub mod async_action;
pub mod sleep;
pub mod with_handle;

pub use async_action::{ActionFuture, AsyncAction, HaltFuture};
pub use with_handle::{FnAction, FnCondition, Inputs, PortCondition};

use core::time::Duration;

use alloc::string::String;
use core::any::Any;

use crate::blackboard::{Blackboard, BlackboardError, ScopeId};
use crate::blueprint::{FromPortStr, Port, PortError, PortValue};
use crate::{Clock, NodeId, Status};

/// What a leaf sees while it runs: the user's context, the blackboard scope of its subtree,
/// the tree's clock and its own identity.
///
/// A handle is made for every call of a leaf, so it holds only what the engine has at hand
/// (references and the node's id); the node's scope, name and ports are looked up in the
/// blueprint when asked for, which most leaves never do.
pub struct Handle<'a, C> {
    pub(crate) ctx: &'a mut C,
    pub(crate) blackboard: &'a mut Blackboard,
    pub(crate) clock: &'a dyn Clock,
    pub(crate) node: NodeId,
    /// Where the node's scope, name and ports are, and who names it in an error.
    pub(crate) bp: &'a crate::Blueprint<C>,
    /// The pass's error and the tick's record of reasons.
    pub(crate) out: &'a mut crate::tree::failure::Outcome,
    /// What the nodes ticked in the pass wait on.
    pub(crate) waits: &'a mut crate::tree::sleep::Waits,
}

impl<'a, C> Handle<'a, C> {
    /// Says, when returning Running, that nothing changes for this action before `at` on
    /// the tree's clock: if every Running action of the tree waits, the tree sleeps and is
    /// not ticked until then (or until something else it waits on happens; see
    /// [`sleep`](crate::tree::sleep)).
    ///
    /// ```
    /// use core::time::Duration;
    /// use neurotree_core::{Blueprint, Handle, ManualClock, StatefulAction, Status, Tree};
    ///
    /// /// Cooks for two seconds, counting how often it is asked.
    /// struct Cook { done_at: Duration }
    /// impl StatefulAction<u32> for Cook {
    ///     fn on_start(&mut self, h: &mut Handle<'_, u32>) -> Status {
    ///         self.done_at = h.now() + Duration::from_secs(2);
    ///         self.on_running(h)
    ///     }
    ///     fn on_running(&mut self, h: &mut Handle<'_, u32>) -> Status {
    ///         *h.ctx_mut() += 1;
    ///         if h.now() >= self.done_at { return Status::Success; }
    ///         h.sleep_until(self.done_at);
    ///         Status::Running
    ///     }
    /// }
    /// let bp = Blueprint::<u32>::builder()
    ///     .stateful("cook", || Cook { done_at: Duration::ZERO })
    ///     .build_shared()
    ///     .unwrap();
    /// let clock = ManualClock::new();
    /// let mut tree = Tree::with_clock(bp, clock.clone());
    /// let mut asked = 0;
    /// for _ in 0..20 {
    ///     assert_eq!(tree.tick_once(&mut asked), Ok(Status::Running));
    ///     clock.advance(Duration::from_millis(100));
    /// }
    /// assert_eq!(tree.tick_once(&mut asked), Ok(Status::Success));
    /// assert_eq!(asked, 2); // at the start, and when the two seconds were up
    /// ```
    pub fn sleep_until(&mut self, at: Duration) {
        self.waits.until(at);
    }

    /// Says, when returning Running, that nothing changes for this action until the
    /// blackboard entry `key` is written: the sleeping tree wakes on a write (to any entry:
    /// the tree does not tell entries apart).
    ///
    /// A condition (or a sync action) says it too: its answer changes only when the
    /// blackboard is written, so a reactive node that re-checks it lets the tree sleep (see
    /// [`sleep`](crate::tree::sleep)).
    pub fn wake_on(&self, key: &str) {
        let _ = key;
        self.out.reads.on_event();
    }

    /// Says, when returning Running, that nothing changes for this action until the
    /// program wakes the tree through a [`WakeHandle`](crate::tree::WakeHandle) (an event, a
    /// message, another thread). A condition says it when its answer changes only then.
    pub fn wake_on_handle(&self) {
        self.out.reads.on_event();
    }

    /// The user's context.
    #[inline]
    pub fn ctx(&self) -> &C {
        self.ctx
    }

    /// The user's context, to change the world.
    #[inline]
    pub fn ctx_mut(&mut self) -> &mut C {
        self.ctx
    }

    /// The tree's blackboard (all scopes).
    pub fn blackboard(&self) -> &Blackboard {
        self.blackboard
    }

    /// The tree's blackboard, writable.
    pub fn blackboard_mut(&mut self) -> &mut Blackboard {
        self.blackboard
    }

    /// The scope this node reads and writes (its subtree's).
    pub fn scope(&self) -> ScopeId {
        self.bp.scope(self.node)
    }

    /// Reads `key` in this node's scope (`@key` reads the root scope).
    pub fn get<T: Any + Clone>(&self, key: &str) -> Result<T, BlackboardError> {
        self.blackboard.get_in(self.scope(), key)
    }

    /// Writes `key` in this node's scope, stamped with the clock's time.
    pub fn set<T: Any + Send + Sync>(
        &mut self,
        key: &str,
        value: T,
    ) -> Result<(), BlackboardError> {
        let now = self.clock.now();
        let scope = self.scope();
        self.blackboard.set_in(scope, key, value, now)
    }

    /// The tree's clock reading.
    pub fn now(&self) -> Duration {
        self.clock.now()
    }

    /// Reads input port `port`: its literal text converted to `T`, or the blackboard entry
    /// it is bound to (a text entry is converted too, as BehaviorTree.CPP does).
    ///
    /// A port declared of a type `T` is incompatible with is a
    /// [`PortError::TypeMismatch`] (see [`PortType`](crate::PortType)).
    pub fn input<T: FromPortStr + Any + Clone>(&self, port: &str) -> Result<T, PortError> {
        read_input(self.blackboard, self.bp, self.node, port)
    }

    /// Writes output port `port`: the blackboard entry it is bound to, stamped with the
    /// clock's time.
    ///
    /// A port declared of a type `T` is incompatible with is a
    /// [`PortError::TypeMismatch`] (see [`PortType`](crate::PortType)).
    pub fn output<T: Any + Send + Sync>(&mut self, port: &str, value: T) -> Result<(), PortError> {
        let bp = self.bp;
        let binding = find_port(bp.ports(self.node), port)?;
        if !binding.declared.writes_as::<T>() {
            return Err(type_mismatch::<T, C>(bp, self.node, binding, true));
        }
        let PortValue::Entry(key) = &binding.value else {
            return Err(PortError::NotAnEntry {
                port: String::from(port),
            });
        };
        let now = self.clock.now();
        self.blackboard
            .set_in(bp.scope(self.node), key, value, now)
            .map_err(|source| PortError::Blackboard {
                port: String::from(port),
                source,
            })
    }

    /// The node's ports and their bindings.
    pub fn ports(&self) -> &'a [Port] {
        self.bp.ports(self.node)
    }

    /// The node being ticked.
    pub fn node(&self) -> NodeId {
        self.node
    }

    /// The node's name.
    pub fn name(&self) -> &'a str {
        self.bp.name(self.node)
    }

    /// Gives a reason for the Failure this leaf returns, and returns Failure:
    /// `return h.fail_with(106, "blocked")`. The reason is not an error: the tick goes on as
    /// for any Failure, and [`Tree::last_failure`](crate::Tree::last_failure) tells it if
    /// this failure decided the root. A static message allocates nothing once the tree has
    /// room for it (see [`failure`](crate::tree::failure): the first makes room for 4 a
    /// tick).
    pub fn fail_with(&mut self, code: u32, message: &'static str) -> Status {
        self.fail_because(crate::Reason::new(code, message))
    }

    /// As [`fail_with`](Self::fail_with), with any [`Reason`](crate::Reason) (one made with
    /// [`Reason::owned`](crate::Reason::owned) carries text made at run time).
    pub fn fail_because(&mut self, reason: crate::Reason) -> Status {
        self.out
            .push(self.node, crate::tree::failure::Note::Gave(reason));
        Status::Failure
    }

    /// Reports a runtime error, as BehaviorTree.CPP's nodes throw one: the tick ends with
    /// [`TickError::Node`](crate::TickError::Node) (the first error of a tick wins) after the
    /// tree is halted. Return Failure after calling it.
    pub fn fail(&mut self, message: impl Into<String>) {
        let (bp, node) = (self.bp, self.node);
        self.out.fault(|| crate::TickError::Node {
            node,
            path: bp.path(node),
            message: message.into(),
        });
    }
}

/// The binding of port `port` among `ports`.
pub(crate) fn find_port<'p>(ports: &'p [Port], port: &str) -> Result<&'p Port, PortError> {
    ports
        .iter()
        .find(|p| p.name == port)
        .ok_or_else(|| PortError::NoSuchPort {
            port: String::from(port),
        })
}

/// The error of node `node` reading (or writing) `binding` as `T`.
#[cold]
#[inline(never)]
fn type_mismatch<T, C>(
    bp: &crate::Blueprint<C>,
    node: NodeId,
    binding: &Port,
    written: bool,
) -> PortError {
    PortError::TypeMismatch {
        node: bp.path(node),
        port: binding.name.clone(),
        declared: binding.declared.name(),
        requested: core::any::type_name::<T>(),
        written,
    }
}

/// Reads input port `port` of node `node`: its literal text converted to `T`, or the
/// blackboard entry it is bound to in the node's scope (a text entry is converted too, as
/// BehaviorTree.CPP does), once `T` is found compatible with the port's declared type.
/// Leaves, custom nodes and built-ins read ports through it.
pub(crate) fn read_input<T: FromPortStr + Any + Clone, C>(
    blackboard: &Blackboard,
    bp: &crate::Blueprint<C>,
    node: NodeId,
    port: &str,
) -> Result<T, PortError> {
    let scope = bp.scope(node);
    let binding = find_port(bp.ports(node), port)?;
    // The declaration is on the binding already found: no look-up of its own, and for an
    // untyped port one comparison.
    if !binding.declared.reads_as::<T>() {
        return Err(type_mismatch::<T, C>(bp, node, binding, false));
    }
    let convert = |text: &str| {
        T::from_port_str(text).map_err(|()| PortError::Convert {
            port: String::from(port),
            text: String::from(text),
            type_name: core::any::type_name::<T>(),
        })
    };
    match &binding.value {
        PortValue::Literal(text) => convert(text),
        PortValue::Entry(key) => {
            // Typed first, then text; probing with `get_any_in` builds no error (and so
            // allocates nothing) on the way.
            let Some(any) = blackboard.get_any_in(scope, key) else {
                let source = blackboard.get_ref_in::<T>(scope, key).err();
                return Err(PortError::Blackboard {
                    port: String::from(port),
                    source: source.unwrap_or(BlackboardError::NotFound {
                        key: String::from(key.as_str()),
                    }),
                });
            };
            if let Some(value) = any.downcast_ref::<T>() {
                return Ok(value.clone());
            }
            if let Some(text) = any.downcast_ref::<String>() {
                return convert(text);
            }
            if let Some(converted) = T::from_other(any) {
                return converted.map_err(|value| PortError::OutOfRange {
                    port: String::from(port),
                    value,
                    type_name: core::any::type_name::<T>(),
                });
            }
            Err(PortError::Blackboard {
                port: String::from(port),
                source: blackboard.get_ref_in::<T>(scope, key).err().unwrap_or(
                    BlackboardError::NotFound {
                        key: String::from(key.as_str()),
                    },
                ),
            })
        }
    }
}

/// A check of the world that never runs; one object serves every instance.
///
/// A condition without pre- or post-conditions is called by its parent's loop through a
/// plain function made for its type (the sealed supertrait, implemented for every
/// `Condition`), with no vtable. A panic in `check` ends the tick with
/// [`TickError::Panicked`](crate::TickError::Panicked) naming the node, as anywhere else;
/// without the `std` feature, where a panic cannot be caught, it aborts.
///
/// ```
/// use neurotree_core::{Blueprint, Condition, Handle};
///
/// struct Above(f32);
/// impl Condition<f32> for Above {
///     fn check(&self, h: &Handle<'_, f32>) -> bool { *h.ctx() > self.0 }
/// }
/// let bp = Blueprint::<f32>::builder().condition_node("charged", Above(20.0)).build();
/// assert!(bp.is_ok());
/// ```
pub trait Condition<C>: Send + Sync + crate::blueprint::call::sealed::ConditionEntry<C> {
    /// `true` for Success, `false` for Failure.
    fn check(&self, h: &Handle<'_, C>) -> bool;

    /// `true` if the answer depends on the blackboard and the node's ports alone (not the
    /// context, the clock, the world): a reactive node that re-checks it lets the tree
    /// sleep (see [`sleep`](crate::tree::sleep)). A condition that reads something else
    /// may still declare, in `check`, what wakes it ([`Handle::wake_on_handle`]).
    ///
    /// Asked once per node, when the blueprint is built (and when a node is ticked
    /// through the dispatcher): the answer must not change.
    fn reads_only_blackboard(&self) -> bool {
        false
    }
}

/// A synchronous action: it completes within the tick; one object serves every instance.
///
/// Success or Failure in one tick; returning Running is reported as a
/// [`TickError`](crate::TickError).
pub trait Action<C>: Send + Sync {
    /// Success or Failure; Running is a contract violation reported by the tick.
    fn tick(&self, h: &mut Handle<'_, C>) -> Status;

    /// `true` if the result depends on the blackboard and the node's ports alone, as for
    /// [`Condition::reads_only_blackboard`].
    fn reads_only_blackboard(&self) -> bool {
        false
    }
}

/// An action that runs over several ticks, with per-instance state: started once, updated on
/// every later tick while Running, told when it is halted.
///
/// `on_start` on the tick from Idle, `on_running` on later ticks, `on_halted` when halted
/// while Running; or, for a halt that takes ticks, `on_halt_requested` then `on_halting`
/// on later ticks until it is done (see [`slow_halt`](crate::tree::slow_halt)).
///
/// ```
/// use neurotree_core::{Handle, StatefulAction, Status};
///
/// /// Moves one step per tick until it has moved `n`.
/// struct Walk { n: u32, done: u32 }
/// impl StatefulAction<i32> for Walk {
///     fn on_start(&mut self, h: &mut Handle<'_, i32>) -> Status {
///         self.done = 0;
///         self.on_running(h)
///     }
///     fn on_running(&mut self, h: &mut Handle<'_, i32>) -> Status {
///         *h.ctx_mut() += 1;
///         self.done += 1;
///         if self.done == self.n { Status::Success } else { Status::Running }
///     }
///     fn on_halted(&mut self, _h: &mut Handle<'_, i32>) {}
/// }
/// ```
pub trait StatefulAction<C>: Send {
    /// Called on the tick that finds the node Idle.
    fn on_start(&mut self, h: &mut Handle<'_, C>) -> Status;
    /// Called on every later tick while the node is Running.
    fn on_running(&mut self, h: &mut Handle<'_, C>) -> Status;
    /// Called when the node is halted while Running; release what `on_start` took.
    fn on_halted(&mut self, _h: &mut Handle<'_, C>) {}

    /// Called instead of [`on_halted`](Self::on_halted) when the engine halts the node
    /// while Running. The default calls `on_halted` and answers
    /// [`HaltProgress::Done`]: the halt is over at once, as in BehaviorTree.CPP.
    ///
    /// An action whose halt takes time (an arm that decelerates, an action server that
    /// must acknowledge a cancel) answers [`HaltProgress::Halting`]: it is stored Idle,
    /// its parent does not start a conflicting branch, and it gets
    /// [`on_halting`](Self::on_halting) on later ticks until it answers `Done` (see
    /// [`tree::slow_halt`](crate::tree::slow_halt) for who waits, and how).
    fn on_halt_requested(&mut self, h: &mut Handle<'_, C>) -> HaltProgress {
        self.on_halted(h);
        HaltProgress::Done
    }

    /// Called once per tick of the node that waits for this halt, after
    /// [`on_halt_requested`](Self::on_halt_requested) answered `Halting`, until it
    /// answers [`HaltProgress::Done`]. Never called for an action that halts at once.
    fn on_halting(&mut self, _h: &mut Handle<'_, C>) -> HaltProgress {
        HaltProgress::Done
    }

    /// Opt-in: the state this object keeps between ticks, as bytes, for
    /// [`Tree::save_state`](crate::Tree::save_state); `None` (the default) means it cannot
    /// be saved, and saving a tree that holds it is an error naming the node.
    /// [`state::encode`](crate::state::encode) turns any `serde` value into such bytes; an
    /// action that keeps nothing returns `Some(Vec::new())`.
    fn save_state(&self) -> Option<alloc::vec::Vec<u8>> {
        None
    }

    /// Takes back what [`save_state`](Self::save_state) gave, into an object fresh from
    /// its factory; `false` if the bytes are not its state (the restore is then refused).
    fn restore_state(&mut self, state: &[u8]) -> bool {
        state.is_empty()
    }
}

/// How far a [`StatefulAction`]'s halt has got.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HaltProgress {
    /// The action has stopped; it may be started again.
    Done,
    /// The action is still stopping: call [`StatefulAction::on_halting`] on a later tick.
    Halting,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::*;

    /// Succeeds when the context is above its threshold; records what the handle showed.
    struct Above(u32);
    impl Condition<(u32, Vec<String>)> for Above {
        fn check(&self, h: &Handle<'_, (u32, Vec<String>)>) -> bool {
            h.ctx().0 > self.0
        }
    }

    struct Bump;
    impl Action<(u32, Vec<String>)> for Bump {
        fn tick(&self, h: &mut Handle<'_, (u32, Vec<String>)>) -> Status {
            let seen = format!("{} {} {:?}", h.node(), h.name(), h.now());
            let ctx = h.ctx_mut();
            ctx.0 += 10;
            ctx.1.push(seen);
            Status::Success
        }
    }

    #[test]
    fn trait_leaves_see_their_identity_and_the_clock() {
        let clock = ManualClock::new();
        let bp = Builder::<(u32, Vec<String>)>::new()
            .fallback("root", |f| {
                f.condition_node("high", Above(15))
                    .action_node("bump", Bump)
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, clock.clone());
        let mut ctx = (0, Vec::new());
        clock.advance(ms(7));
        assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
        assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
        // The condition held on the third tick, so the action ran twice.
        assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
        assert_eq!(ctx.0, 20);
        assert_eq!(ctx.1, ["#2 bump 7ms", "#2 bump 7ms"]);
    }

    /// Reads a port and its scope, to show what the handle of a directly called condition
    /// looks up when asked.
    struct Named;
    impl Condition<(u32, Vec<String>)> for Named {
        fn check(&self, h: &Handle<'_, (u32, Vec<String>)>) -> bool {
            h.input::<u32>("limit") == Ok(h.ctx().0) && h.name() == "named"
        }
    }

    /// Notes each node's own tick and each status change.
    #[derive(Clone, Default)]
    struct Seen(std::sync::Arc<std::sync::Mutex<Vec<String>>>);
    impl crate::Observer for Seen {
        fn on_node_tick(&mut self, node: NodeId) {
            self.0.lock().unwrap().push(format!("tick {node}"));
        }
        fn on_status_change(&mut self, c: crate::StatusChange) {
            let line = format!("{} {}->{}", c.node, c.from, c.to);
            self.0.lock().unwrap().push(line);
        }
    }

    #[test]
    fn a_condition_object_called_from_its_parent_is_ticked_and_seen_like_any_node() {
        let bp = Builder::<(u32, Vec<String>)>::new()
            .sequence("root", |s| {
                s.condition_node("high", Above(15))
                    .condition_node("named", Named)
                    .ports([Port::literal("limit", "20")])
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let seen = Seen::default();
        tree.set_observer(seen.clone());
        let mut ctx = (20, Vec::new());
        assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Success));
        ctx.0 = 10;
        assert_eq!(tree.tick_once(&mut ctx), Ok(Status::Failure));
        assert_eq!(
            *seen.0.lock().unwrap(),
            [
                "tick #0",
                "#0 IDLE->RUNNING",
                "tick #1",
                "#1 IDLE->SUCCESS",
                "tick #2",
                "#2 IDLE->SUCCESS",
                "#1 SUCCESS->IDLE",
                "#2 SUCCESS->IDLE",
                "#0 RUNNING->SUCCESS",
                "#0 SUCCESS->IDLE",
                "tick #0",
                "#0 IDLE->RUNNING",
                "tick #1",
                "#1 IDLE->FAILURE",
                "#1 FAILURE->IDLE",
                "#0 RUNNING->FAILURE",
                "#0 FAILURE->IDLE",
            ]
        );
    }

    #[test]
    fn closure_condition_and_action() {
        let mut lab = Lab::new(&[]);
        let mut tree = lab.tree(|b| {
            b.sequence("s", |s| {
                s.condition("no_ticks_yet", |l: &Lab| l.halts.is_empty())
                    .action("record", |l: &mut Lab| {
                        l.halts.push(9);
                        Status::Success
                    })
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.halts, [9]);
    }

    #[test]
    fn stateful_completed_and_unreset_repeats_its_result() {
        // IfThenElse with two children leaves a failed condition un-reset, as BT.CPP does;
        // a stateful condition then answers from its stored status without being called.
        let mut lab = Lab::new(&[&[F, S], &[S]]);
        let mut tree = lab.tree(|b| b.if_then_else("ite", |i| i.scripted(0).scripted(1)));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(lab.ticks, [1, 0]);
    }

    /// Reads `speed` (a literal) and `goal` (an entry), writes `reached` (an entry).
    struct MoveTo;
    impl Action<u32> for MoveTo {
        fn tick(&self, h: &mut Handle<'_, u32>) -> Status {
            let speed: f64 = h.input("speed").unwrap();
            let goal: Vec<i32> = h.input("goal").unwrap();
            *h.ctx_mut() = (speed * 10.0) as u32 + goal.len() as u32;
            h.output("reached", true).unwrap();
            // Errors name the port and say what is wrong.
            assert_eq!(
                h.input::<u8>("nope"),
                Err(PortError::NoSuchPort {
                    port: "nope".into()
                })
            );
            assert!(matches!(
                h.input::<u8>("speed"),
                Err(PortError::Convert { text, .. }) if text == "0.5"
            ));
            assert!(matches!(
                h.output("speed", 1_u8),
                Err(PortError::NotAnEntry { .. })
            ));
            Status::Success
        }
    }

    #[test]
    fn ports_read_literals_and_entries_and_write_entries() {
        use crate::Port;
        let bp = Builder::<u32>::new()
            .action_node("move", MoveTo)
            .ports([
                Port::literal("speed", "0.5"),
                Port::entry("goal", "target"),
                Port::entry("reached", "@done"),
            ])
            .build_shared()
            .unwrap();
        assert_eq!(bp.ports(NodeId(0)).len(), 3);
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        // A text entry converts on read, as BehaviorTree.CPP's string entries do.
        tree.blackboard_mut()
            .set("target", String::from("1;2;3"))
            .unwrap();
        let mut n = 0;
        assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
        assert_eq!(n, 8);
        assert_eq!(tree.blackboard().get::<bool>("done"), Ok(true));
    }

    /// What a [`Probe`] read and wrote, printed: `Ok(value)` or the error's message.
    type Log = Vec<String>;

    /// Reads and writes its ports as a test asks, and logs the results.
    struct Probe(fn(&mut Handle<'_, Log>) -> Log);
    impl Action<Log> for Probe {
        fn tick(&self, h: &mut Handle<'_, Log>) -> Status {
            let seen = (self.0)(h);
            h.ctx_mut().extend(seen);
            Status::Success
        }
    }

    fn show<T: core::fmt::Debug>(r: Result<T, PortError>) -> String {
        match r {
            Ok(v) => format!("Ok({v:?})"),
            Err(e) => e.to_string(),
        }
    }

    fn probe(ports: Vec<Port>, f: fn(&mut Handle<'_, Log>) -> Log) -> (Tree<Log>, Log) {
        let bp = Builder::<Log>::new()
            .sequence("root", |s| s.action_node("probe", Probe(f)).ports(ports))
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut log = Vec::new();
        assert_eq!(tree.tick_once(&mut log), Ok(Status::Success));
        (tree, log)
    }

    #[test]
    fn a_declared_port_is_read_as_a_compatible_type_only() {
        use crate::PortType;
        let u8_literal = Port::literal("n", "7").with_type(PortType::of::<u8>());
        let u8_entry = Port::entry("e", "count").with_type(PortType::of::<u8>());
        let (_, log) = probe(vec![u8_literal, u8_entry], |h| {
            h.blackboard_mut().set("count", 300_i64).unwrap();
            vec![
                show(h.input::<u8>("n")),
                show(h.input::<i64>("n")),
                show(h.input::<f32>("n")),
                show(h.input::<bool>("n")),
                show(h.input::<String>("n")),
                show(h.input::<Vec<u8>>("n")),
                show(h.input::<i64>("e")),
                // The type is compatible; the value is not: its own error.
                show(h.input::<u8>("e")),
            ]
        });
        assert_eq!(
            log,
            [
                "Ok(7)",
                "Ok(7)",
                "Ok(7.0)",
                // The declaration lets a number be read as bool; `7` is none.
                "port `n`: cannot read `7` as bool",
                "Ok(\"7\")",
                "node `root/probe`: port `n` is declared as u8; it cannot be read as alloc::vec::Vec<u8>",
                "Ok(300)",
                "port `e`: the entry's value 300 does not fit u8",
            ]
        );
        let (_, log) = probe(
            vec![Port::literal("n", "7").with_type(PortType::of::<u8>())],
            |h| match h.input::<Vec<u8>>("n") {
                Err(e) => vec![format!("{e:?}")],
                Ok(_) => vec![],
            },
        );
        assert_eq!(
            log,
            [format!(
                "{:?}",
                PortError::TypeMismatch {
                    node: "root/probe".into(),
                    port: "n".into(),
                    declared: "u8",
                    requested: "alloc::vec::Vec<u8>",
                    written: false,
                }
            )]
        );
    }

    #[test]
    fn text_and_other_declared_types_and_untyped_ports() {
        use crate::PortType;
        let ports = vec![
            Port::literal("text", "12").with_type(PortType::of::<String>()),
            Port::literal("list", "1;2").with_type(PortType::of::<Vec<i32>>()),
            Port::literal("free", "3"),
        ];
        let (_, log) = probe(ports, |h| {
            vec![
                show(h.input::<String>("text")),
                show(h.input::<u16>("text")),
                show(h.input::<Vec<i32>>("text")),
                show(h.input::<Vec<i32>>("list")),
                show(h.input::<Vec<i64>>("list")),
                show(h.input::<String>("list")),
                show(h.input::<u8>("free")),
                show(h.input::<String>("free")),
                show(h.input::<Vec<i64>>("free")),
            ]
        });
        assert_eq!(
            log,
            [
                "Ok(\"12\")",
                "Ok(12)",
                "node `root/probe`: port `text` is declared as alloc::string::String; it cannot be read as alloc::vec::Vec<i32>",
                "Ok([1, 2])",
                "node `root/probe`: port `list` is declared as alloc::vec::Vec<i32>; it cannot be read as alloc::vec::Vec<i64>",
                "node `root/probe`: port `list` is declared as alloc::vec::Vec<i32>; it cannot be read as alloc::string::String",
                "Ok(3)",
                "Ok(\"3\")",
                "Ok([3])",
            ]
        );
    }

    #[test]
    fn a_declared_output_is_written_as_a_compatible_type_only() {
        use crate::PortType;
        let ports = vec![
            Port::entry("count", "c").with_type(PortType::of::<u32>()),
            Port::entry("label", "l").with_type(PortType::of::<String>()),
            Port::entry("free", "f"),
        ];
        let (tree, log) = probe(ports, |h| {
            vec![
                show(h.output("label", 5_i32)),
                show(h.output("count", vec![1_u32])),
                show(h.output("label", String::from("five"))),
                show(h.output("count", 5_u32)),
                show(h.output("free", vec![1_u8])),
            ]
        });
        assert_eq!(
            log,
            [
                "node `root/probe`: port `label` is declared as alloc::string::String; it cannot be written as i32",
                "node `root/probe`: port `count` is declared as u32; it cannot be written as alloc::vec::Vec<u32>",
                "Ok(())",
                "Ok(())",
                "Ok(())",
            ]
        );
        let bb = tree.blackboard();
        assert_eq!(bb.get::<String>("l"), Ok("five".into()));
        assert_eq!(bb.get::<u32>("c"), Ok(5));
        assert_eq!(bb.get::<Vec<u8>>("f"), Ok(vec![1]));
    }

    #[test]
    fn port_type_compatibility() {
        use crate::PortType;
        let number = PortType::named("i32");
        assert!(number.reads_as::<u64>() && number.reads_as::<f32>() && number.reads_as::<bool>());
        assert!(number.reads_as::<String>() && !number.reads_as::<Vec<i32>>());
        assert!(number.writes_as::<i8>() && number.writes_as::<String>());
        assert!(!number.writes_as::<&'static str>());
        let text = PortType::named("String");
        assert!(text.reads_as::<String>() && text.reads_as::<f64>());
        assert!(text.writes_as::<String>() && !text.writes_as::<f64>());
        assert_eq!(PortType::named("Pose"), PortType::ANY);
        assert!(PortType::ANY.is_any() && !number.is_any());
        assert_eq!(
            (number.name(), PortType::of::<String>().name()),
            ("i32", "alloc::string::String")
        );
    }
}

//! The fluent half of the [`Builder`] for SubTree and the leaves of user code; each built-in
//! node's method is in the node's own module, beside its tick.

use alloc::boxed::Box;
use alloc::string::String;
use core::future::Future;

use super::Builder;
use crate::blueprint::{CustomSpec, NodeKind, Port, SubTreeScope};
use crate::nodes::leaf::async_action::AsyncFn;
use crate::nodes::leaf::{
    Action, AsyncAction, Condition, FnAction, FnCondition, Handle, StatefulAction,
};
use crate::Status;

/// SubTree and the leaves of user code.
impl<C> Builder<C> {
    /// A [SubTree](crate::nodes::decorator::subtree): its child sees its own blackboard scope.
    pub fn subtree(
        self,
        name: &str,
        scope: SubTreeScope,
        child: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::SubTree(Box::new(scope)), name, child)
    }
    /// A condition from a closure of the context.
    pub fn condition(self, name: &str, f: impl Fn(&C) -> bool + Send + Sync + 'static) -> Self {
        self.leaf(NodeKind::ConditionFn(Box::new(f)), name)
    }
    /// A condition from a [`Condition`] object.
    pub fn condition_node(self, name: &str, c: impl Condition<C> + 'static) -> Self {
        self.leaf(NodeKind::Condition(alloc::sync::Arc::new(c)), name)
    }
    /// A condition from a closure of the node's [`Handle`], with its `ports` bound: it reads
    /// them ([`Handle::input`]), the blackboard and the clock, as a registered condition does.
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Port, Status, Tree};
    ///
    /// struct Robot { battery: f64 }
    ///
    /// let blueprint = Blueprint::<Robot>::builder()
    ///     .condition_with("charged", [Port::literal("min", "20")], |h| {
    ///         h.input::<f64>("min").is_ok_and(|min| h.ctx().battery >= min)
    ///     })
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut Robot { battery: 35.0 }), Ok(Status::Success));
    /// assert_eq!(tree.tick_once(&mut Robot { battery: 5.0 }), Ok(Status::Failure));
    /// ```
    pub fn condition_with(
        self,
        name: &str,
        ports: impl IntoIterator<Item = Port>,
        f: impl Fn(&Handle<'_, C>) -> bool + Send + Sync + 'static,
    ) -> Self {
        self.condition_node(name, FnCondition(f)).ports(ports)
    }
    /// A sync action from a closure of the context.
    pub fn action(self, name: &str, f: impl Fn(&mut C) -> Status + Send + Sync + 'static) -> Self {
        self.leaf(NodeKind::ActionFn(Box::new(f)), name)
    }
    /// A sync action from a closure of the node's [`Handle`], with its `ports` bound: it
    /// reads its inputs ([`Handle::input`]) and writes its outputs ([`Handle::output`]), as
    /// a registered action does. A port is a literal ([`Port::literal`]) or a blackboard
    /// entry ([`Port::entry`]).
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Port, Status, Tree};
    ///
    /// struct Robot { at: String }
    ///
    /// let blueprint = Blueprint::<Robot>::builder()
    ///     .sequence("patrol", |s| {
    ///         s.action_with("go", [Port::literal("goal", "dock")], |h| {
    ///             let Ok(goal) = h.input::<String>("goal") else { return Status::Failure };
    ///             h.ctx_mut().at = goal;
    ///             Status::Success
    ///         })
    ///         .action_with("report", [Port::entry("where", "last_place")], |h| {
    ///             let at = h.ctx().at.clone();
    ///             h.output("where", at).is_ok().into()
    ///         })
    ///     })
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    /// let mut robot = Robot { at: String::new() };
    /// assert_eq!(tree.tick_once(&mut robot), Ok(Status::Success));
    /// assert_eq!(robot.at, "dock");
    /// assert_eq!(tree.blackboard().get::<String>("last_place").as_deref(), Ok("dock"));
    /// ```
    pub fn action_with(
        self,
        name: &str,
        ports: impl IntoIterator<Item = Port>,
        f: impl Fn(&mut Handle<'_, C>) -> Status + Send + Sync + 'static,
    ) -> Self {
        self.action_node(name, FnAction(f)).ports(ports)
    }
    /// A sync action from an [`Action`] object.
    pub fn action_node(self, name: &str, a: impl Action<C> + 'static) -> Self {
        self.leaf(NodeKind::Action(alloc::sync::Arc::new(a)), name)
    }
    /// A stateful action: `make` builds one object per tree instance.
    pub fn stateful<S, F>(self, name: &str, make: F) -> Self
    where
        S: StatefulAction<C> + 'static,
        F: Fn() -> S + Send + Sync + 'static,
    {
        let factory = move || -> Box<dyn StatefulAction<C>> { Box::new(make()) };
        self.leaf(NodeKind::Stateful(Box::new(factory)), name)
    }
    /// An [async action](crate::nodes::leaf::async_action): on each start, `start` reads
    /// what it needs from the handle and returns the future that does the work; the future
    /// is polled once per tick and dropped when the node is halted. Each start allocates
    /// once, to box the future.
    ///
    /// ```
    /// use neurotree_core::{Blueprint, ManualClock, Status, Tree};
    ///
    /// let blueprint = Blueprint::<u32>::builder()
    ///     .async_action("double", |h| {
    ///         let n = *h.ctx();
    ///         async move { if n * 2 > 5 { Status::Success } else { Status::Failure } }
    ///     })
    ///     .build_shared()
    ///     .unwrap();
    /// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut 3), Ok(Status::Success));
    /// ```
    pub fn async_action<F, Fut>(self, name: &str, start: F) -> Self
    where
        F: Fn(&mut Handle<'_, C>) -> Fut + Send + Sync + 'static,
        Fut: Future<Output = Status> + Send + 'static,
    {
        self.async_action_node(name, AsyncFn(start))
    }
    /// An async action from an [`AsyncAction`] object.
    pub fn async_action_node(self, name: &str, a: impl AsyncAction<C> + 'static) -> Self {
        self.leaf(NodeKind::Async(Box::new(a)), name)
    }
    /// A user-defined control or decorator.
    pub fn custom(
        self,
        name: &str,
        spec: CustomSpec<C>,
        children: impl FnOnce(Self) -> Self,
    ) -> Self {
        self.node(NodeKind::Custom(Box::new(spec)), name, children)
    }
}

/// What code that adds nodes of its own needs.
impl<C> Builder<C> {
    /// Records that the node added last is invalid, for `message`: how code that adds a
    /// node of its own (an extension of the builder) refuses what it was given, such as a
    /// script that does not parse. [`build`](Self::build) then fails with
    /// [`BuildErrorKind::Rejected`](crate::BuildErrorKind::Rejected) at that node's path (the first error recorded wins).
    ///
    /// ```
    /// use neurotree_core::{Blueprint, BuildErrorKind};
    ///
    /// let error = Blueprint::<()>::builder()
    ///     .sequence("root", |s| s.always_success("wait").reject("`-3 s` is not a duration"))
    ///     .build()
    ///     .unwrap_err();
    /// assert_eq!(error.path, "root/wait");
    /// assert!(matches!(error.kind, BuildErrorKind::Rejected { .. }));
    /// assert_eq!(error.to_string(), "root/wait: `-3 s` is not a duration");
    /// ```
    pub fn reject(mut self, message: impl Into<String>) -> Self {
        if self.s.ignored > 0 || self.s.error.is_some() {
            return self;
        }
        let last = self.s.defs.len().checked_sub(1).map(|last| last as u32);
        let message = message.into();
        self.s
            .fail(last, crate::BuildErrorKind::Rejected { message });
        self
    }
}

#[cfg(test)]
mod tests {
    use alloc::string::String;
    use alloc::vec::Vec;

    use crate::{Blueprint, BuildErrorKind, ManualClock, Port, PortError, Status, Tree};

    /// What the leaves saw and did.
    #[derive(Default)]
    struct World {
        checks: u32,
        steps: Vec<(String, i64)>,
    }

    #[test]
    fn closures_of_the_handle_read_and_write_their_own_ports() {
        let bp = Blueprint::<World>::builder()
            .sequence("root", |s| {
                s.condition_with("ready", [Port::entry("flag", "go")], |h| {
                    h.input::<bool>("flag").unwrap_or(false)
                })
                .action_with(
                    "step",
                    [Port::literal("to", "dock"), Port::entry("by", "stride")],
                    |h| {
                        let to = h.input::<String>("to");
                        let by = h.input::<i64>("by");
                        let (Ok(to), Ok(by)) = (to, by) else {
                            return Status::Failure;
                        };
                        h.ctx_mut().steps.push((to, by));
                        Status::Success
                    },
                )
                .action_with("echo", [Port::entry("out", "echoed")], |h| {
                    h.ctx_mut().checks += 1;
                    let n = h.ctx().steps.len() as i64;
                    h.output("out", n).is_ok().into()
                })
                .action_with("stray", [Port::literal("x", "1")], |h| {
                    // A port the node does not bind is an error, not another node's.
                    match h.input::<i64>("to") {
                        Err(PortError::NoSuchPort { .. }) => Status::Success,
                        _ => Status::Failure,
                    }
                })
            })
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        let mut world = World::default();
        // No `go` entry: the condition fails, and nothing after it is ticked.
        assert_eq!(tree.tick_once(&mut world), Ok(Status::Failure));
        assert_eq!((world.steps.len(), world.checks), (0, 0));
        tree.blackboard_mut().set("go", true).unwrap();
        tree.blackboard_mut().set("stride", 3i64).unwrap();
        assert_eq!(tree.tick_once(&mut world), Ok(Status::Success));
        tree.blackboard_mut().set("stride", 5i64).unwrap();
        assert_eq!(tree.tick_once(&mut world), Ok(Status::Success));
        assert_eq!(
            world.steps,
            [(String::from("dock"), 3), (String::from("dock"), 5)]
        );
        assert_eq!(world.checks, 2);
        assert_eq!(tree.blackboard().get::<i64>("echoed"), Ok(2));
        // The ports are the blueprint's, as an XML node's are.
        let step = tree.blueprint().find("root/step").unwrap();
        let names: Vec<&str> = tree
            .blueprint()
            .ports(step)
            .iter()
            .map(|p| p.name.as_str())
            .collect();
        assert_eq!(names, ["to", "by"]);
    }

    #[test]
    fn a_rejected_node_fails_the_build_at_its_path() {
        let e = Blueprint::<()>::builder()
            .sequence("root", |s| {
                s.always_success("a")
                    .reject("first")
                    .always_success("b")
                    .reject("second")
            })
            .build()
            .unwrap_err();
        assert_eq!(e.path, "root/a");
        assert_eq!(
            e.kind,
            BuildErrorKind::Rejected {
                message: String::from("first")
            }
        );
        let e = Blueprint::<()>::builder().reject("nothing yet").build();
        assert_eq!(e.unwrap_err().path, "");
    }
}

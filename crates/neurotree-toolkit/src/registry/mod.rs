//! The registry (BehaviorTree.CPP's factory): node types by name, with their ports.
//!
//! A BehaviorTree.CPP file names node types (`<MoveBase goal="{target}"/>`); the registry
//! says what each name is. It starts with every built-in node of the engine under its
//! BehaviorTree.CPP name, and the user adds leaves: a stateful action, an async action, a
//! sync action or a condition, each with the ports it reads and writes. Port declarations
//! let the loader reject an unknown attribute or a literal that does not convert, before
//! anything runs.
//!
//! Here: registration; [`ports`] declares ports; the built-in types come from the nodes'
//! declarations (`neurotree_core::nodes::BUILT_INS` and
//! [`STD_BUILT_INS`](crate::nodes::STD_BUILT_INS)); the engine makes a built-in's kind from
//! its ports (`NodeKind::from_declared`), and `builtins` reads them back for the writer;
//! `enums` holds the names scripts read as numbers; `suggest` finds what a misspelt name
//! meant; `aliases` lists the few names real files write that BehaviorTree.CPP does not
//! know (`inverter`, the v3 `SequenceStar`) and what they load as. Reading and writing a `TreeNodesModel` is the XML side's business
//! (`xml::model`), so that the registry does not depend on the loader that depends on it.

use std::collections::BTreeMap;
use std::future::Future;
use std::sync::Arc;

use crate::script::Enums;

use neurotree_core::nodes::leaf::{FnAction, FnCondition};
use neurotree_core::nodes::semantics::{Order, Semantics, Statuses};
use neurotree_core::state::StateCodecs;
use neurotree_core::{Category, Handle, NodeKind, StatefulAction, Status};

pub(crate) mod aliases;
mod builtins;
mod enums;
mod lookup;
pub mod ports;
mod shared_async;
use ports::check_port_names;
use shared_async::{SharedAsync, SharedAsyncAction};
pub(crate) mod suggest;
mod values;

pub(crate) use builtins::built_in_ports;
pub use ports::{PortDirection, PortSpec};

/// Makes the per-node part of a leaf from its port bindings (most leaves ignore them; a
/// Script node parses its `code` here, at load time) and the registry's enums (which its
/// scripts name).
pub(crate) type LeafMaker<C> = Arc<
    dyn Fn(&[neurotree_core::Port], &Arc<Enums>) -> Result<NodeKind<C>, MakerError> + Send + Sync,
>;

/// Why a leaf maker refused a node's ports: the loader reports it with its kind.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum MakerError {
    /// A port the node needs is not given.
    MissingPort(String),
    /// A value the node cannot use.
    BadValue(String),
    /// A script that does not parse.
    Script(String),
}

impl From<String> for MakerError {
    fn from(message: String) -> Self {
        MakerError::BadValue(message)
    }
}

impl MakerError {
    /// The loader's kind of error, and the message.
    pub(crate) fn into_parts(self) -> (crate::xml::LoadErrorKind, String) {
        match self {
            MakerError::MissingPort(m) => (crate::xml::LoadErrorKind::MissingPort, m),
            MakerError::BadValue(m) => (crate::xml::LoadErrorKind::BadValue, m),
            MakerError::Script(m) => (crate::xml::LoadErrorKind::Script, m),
        }
    }
}

/// How a registered type becomes a node.
pub(crate) enum Make<C> {
    /// An engine built-in, made from its ports by
    /// [`NodeKind::from_declared`](neurotree_core::NodeKind::from_declared).
    BuiltIn(&'static neurotree_core::nodes::NodeDecl),
    Leaf(LeafMaker<C>),
    /// A condition whose one object every node of the type calls: the loader opens it
    /// with [`Builder::open_shared_condition`](neurotree_core::Builder::open_shared_condition),
    /// so a blueprint holds it once however many nodes use it.
    Condition(Arc<dyn neurotree_core::Condition<C>>),
    /// Known only from a `TreeNodesModel`: enough to validate a tree, not to run it.
    Model,
}

/// A registered node type.
pub struct NodeType<C> {
    /// The XML name.
    pub name: String,
    /// Its family.
    pub category: Category,
    /// Its ports.
    pub ports: Vec<PortSpec>,
    /// What it does.
    pub description: String,
    pub(crate) make: Make<C>,
    /// Registered by [`Registry::new`], so not written into a `TreeNodesModel`.
    pub(crate) builtin: bool,
    /// What it can return and how it ticks its children, if declared.
    pub(crate) semantics: Option<Semantics>,
}

// By hand: a derive would ask the context `C` to be `Clone`, which only the makers' `Arc`s
// need to be.
impl<C> Clone for Make<C> {
    fn clone(&self) -> Self {
        match self {
            Make::BuiltIn(decl) => Make::BuiltIn(decl),
            Make::Leaf(make) => Make::Leaf(Arc::clone(make)),
            Make::Condition(condition) => Make::Condition(Arc::clone(condition)),
            Make::Model => Make::Model,
        }
    }
}

impl<C> Clone for NodeType<C> {
    fn clone(&self) -> Self {
        NodeType {
            name: self.name.clone(),
            category: self.category,
            ports: self.ports.clone(),
            description: self.description.clone(),
            make: self.make.clone(),
            builtin: self.builtin,
            semantics: self.semantics,
        }
    }
}

impl<C> NodeType<C> {
    /// A built-in type as its declaration describes it.
    pub(crate) fn declared(decl: &neurotree_core::NodeDecl, make: Make<C>) -> Self {
        NodeType {
            name: decl.name.to_string(),
            category: decl.category,
            ports: decl.ports.iter().map(PortSpec::from).collect(),
            description: decl.summary.to_string(),
            make,
            builtin: true,
            semantics: Some(decl.semantics),
        }
    }

    /// `true` for the types every registry starts with (the built-in nodes), which a
    /// `TreeNodesModel` does not list.
    pub fn is_builtin(&self) -> bool {
        self.builtin
    }

    /// `true` for a type known only from a `TreeNodesModel`: a tree using it validates,
    /// but does not run until an implementation is registered (or it is mocked).
    pub fn is_model_only(&self) -> bool {
        matches!(self.make, Make::Model)
    }

    /// The port named `name`.
    pub fn port(&self, name: &str) -> Option<&PortSpec> {
        self.ports.iter().find(|p| p.name == name)
    }

    /// What a node of this type can return and how it ticks its children: as declared (a
    /// built-in's declaration, [`Registry::declare_semantics`], a condition registered
    /// with [`Registry::register_condition`]); else SUCCESS or FAILURE for a type listed as
    /// a Condition (a condition does not run, by BehaviorTree.CPP's contract); else
    /// [`Semantics::ANY`]: anything, children in any order.
    pub fn semantics(&self) -> Semantics {
        match self.semantics {
            Some(declared) => declared,
            None if self.category == Category::Condition => {
                Semantics::new(Order::AllAtOnce, |_, _| Statuses::DONE)
            }
            None => Semantics::ANY,
        }
    }
}

/// Why a registration was refused.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// The name is taken.
    #[error("a node type named `{0}` is already registered; pick another name")]
    Duplicate(String),
    /// No node type has the name.
    #[error("no node type named `{0}` is registered; register it first")]
    Unknown(String),
    /// An enum name was defined again with another value.
    #[error("the enum name `{name}` is already {old}; it cannot also be {new}")]
    EnumRedefined {
        /// The name.
        name: String,
        /// Its value.
        old: i64,
        /// The value refused.
        new: i64,
    },
    /// A port name BehaviorTree.CPP's `CreatePort` refuses (it must start with a letter,
    /// not be `name`, `ID` or a reserved `_` attribute, and hold no space, `.`, `:` …).
    #[error("node type `{node}`: {reason}")]
    BadPortName {
        /// The node type being registered.
        node: String,
        /// The port refused.
        port: String,
        /// What is wrong with it.
        reason: String,
    },
}

neurotree_core::debug_shows_message!(enum RegistryError {
    Duplicate(source),
    Unknown(source),
    EnumRedefined { name, old, new },
    BadPortName { node, port, reason },
});

/// Adds the nodes of a subtree made in Rust below an open SubTree node.
pub(crate) type SubtreeMaker<C> =
    Arc<dyn Fn(neurotree_core::Builder<C>) -> neurotree_core::Builder<C> + Send + Sync>;

/// Node types by name: the built-ins, and the user's leaves; the subtrees made with the
/// builder; and the enum names that scripts and port values may use.
pub struct Registry<C> {
    pub(crate) types: BTreeMap<String, NodeType<C>>,
    /// Old names of registered types, each loading as the type with a warning
    /// ([`Registry::add_renamed`]).
    pub(crate) renamed: BTreeMap<String, aliases::Renamed>,
    subtrees: BTreeMap<String, SubtreeMaker<C>>,
    /// Shared with the script nodes made from this registry, which look names up at run time.
    enums: Arc<Enums>,
    /// The value types of the blackboards of the trees loaded with this registry.
    value_codecs: Arc<StateCodecs>,
    /// Refuse at load an entry written as one type and read as another
    /// ([`set_strict_types`](Registry::set_strict_types)).
    strict_types: bool,
}

/// A copy that goes its own way: types, enums and value types added to one are not added
/// to the other (the implementations themselves are shared). A test bench runs each
/// scenario on a copy, so that one scenario's enums and models do not leak into the next.
impl<C> Clone for Registry<C> {
    fn clone(&self) -> Self {
        Self {
            types: self.types.clone(),
            renamed: self.renamed.clone(),
            subtrees: self.subtrees.clone(),
            enums: Arc::clone(&self.enums),
            value_codecs: Arc::clone(&self.value_codecs),
            strict_types: self.strict_types,
        }
    }
}

impl<C: 'static> Default for Registry<C> {
    fn default() -> Self {
        Self::new()
    }
}

impl<C> Registry<C> {
    /// With `true`, the trees loaded with this registry are refused when an entry is
    /// written as one type and read through a port as another it cannot convert to (lint's
    /// NT0102 errors: a port writing a `Path` into `{p}`, another reading `{p}` as `f64`),
    /// at the reading port's line, as BehaviorTree.CPP refuses such a file when it
    /// creates the tree. Off by default: the file loads, and the read fails when it runs.
    pub fn set_strict_types(&mut self, strict: bool) {
        self.strict_types = strict;
    }

    /// Whether [`set_strict_types`](Self::set_strict_types) is on.
    pub fn strict_types(&self) -> bool {
        self.strict_types
    }
}

impl<C: 'static> Registry<C> {
    /// A registry holding every built-in node under its BehaviorTree.CPP name.
    pub fn new() -> Self {
        let mut r = Self {
            types: BTreeMap::new(),
            renamed: BTreeMap::new(),
            subtrees: BTreeMap::new(),
            enums: Arc::new(Enums::new()),
            value_codecs: Arc::new(StateCodecs::new()),
            strict_types: false,
        };
        for decl in neurotree_core::nodes::BUILT_INS {
            r.types.insert(
                decl.name.to_string(),
                NodeType::declared(decl, Make::BuiltIn(decl)),
            );
        }
        crate::nodes::script::register(&mut r);
        crate::nodes::loops::register(&mut r);
        crate::nodes::entry::register(&mut r);
        crate::nodes::switch::register(&mut r);
        crate::nodes::utility_selector::register(&mut r);
        crate::nodes::utility::register(&mut r);
        for t in r.types.values_mut() {
            t.builtin = true;
        }
        r
    }

    /// Registers a user control or decorator (a [`CustomNode`](neurotree_core::CustomNode)):
    /// `make` builds one object per tree instance; `arity` says how many children it takes.
    pub fn register_custom<F>(
        &mut self,
        name: &str,
        arity: neurotree_core::Arity,
        ports: Vec<PortSpec>,
        make: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn() -> Box<dyn neurotree_core::CustomNode<C>> + Send + Sync + 'static,
    {
        let category = match arity {
            neurotree_core::Arity::One => Category::Decorator,
            neurotree_core::Arity::Leaf => Category::Action,
            _ => Category::Control,
        };
        self.register_custom_as(name, category, arity, ports, make)
    }

    /// As [`register_custom`](Self::register_custom), listed under `category` in models,
    /// pictures and Groot2: a leaf that keeps state between ticks may be a Condition.
    pub fn register_custom_as<F>(
        &mut self,
        name: &str,
        category: Category,
        arity: neurotree_core::Arity,
        ports: Vec<PortSpec>,
        make: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn() -> Box<dyn neurotree_core::CustomNode<C>> + Send + Sync + 'static,
    {
        self.register_custom_shown_as(name, name, category, arity, ports, make)
    }

    /// As [`register_custom_as`](Self::register_custom_as), its nodes' type shown as
    /// `shown_as` in pictures (`neurotree show` draws a type it does not know as
    /// `unknown NAME`).
    pub fn register_custom_shown_as<F>(
        &mut self,
        name: &str,
        shown_as: &str,
        category: Category,
        arity: neurotree_core::Arity,
        ports: Vec<PortSpec>,
        make: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn() -> Box<dyn neurotree_core::CustomNode<C>> + Send + Sync + 'static,
    {
        let make = Arc::new(make);
        let type_name = shown_as.to_string();
        let leaf: LeafMaker<C> = Arc::new(move |_, _| {
            let make = Arc::clone(&make);
            Ok(NodeKind::Custom(Box::new(
                neurotree_core::CustomSpec::new(type_name.clone(), arity, Box::new(move || make()))
                    .in_category(category),
            )))
        });
        self.register_leaf(name, category, ports, leaf)
    }

    /// Registers a std built-in node as its declaration describes it, made by `make`.
    pub(crate) fn register_declared(
        &mut self,
        decl: &neurotree_core::NodeDecl,
        make: LeafMaker<C>,
    ) {
        // Each std node registers its own declaration once, in a new registry; the names
        // are distinct (`declarations_are_registered_once` in `nodes`).
        let fresh = !self.types.contains_key(decl.name);
        debug_assert!(fresh, "{} is registered twice", decl.name);
        self.types.insert(
            decl.name.to_string(),
            NodeType::declared(decl, Make::Leaf(make)),
        );
    }

    /// Registers a node type made from its port bindings at load time; refuses a taken name.
    pub(crate) fn register_leaf(
        &mut self,
        name: &str,
        category: Category,
        ports: Vec<PortSpec>,
        make: LeafMaker<C>,
    ) -> Result<(), RegistryError> {
        if self.types.contains_key(name) {
            return Err(RegistryError::Duplicate(name.to_string()));
        }
        check_port_names(name, &ports)?;
        let t = NodeType {
            name: name.to_string(),
            category,
            ports,
            description: String::new(),
            make: Make::Leaf(make),
            builtin: false,
            semantics: None,
        };
        self.types.insert(name.to_string(), t);
        Ok(())
    }

    /// Declares what nodes of the registered type `name` can return and how they tick their
    /// children, for `neurotree lint` and the other analyses: a control of your own that ticks
    /// child 0 now and then, then child 1 whose status it returns, is declared by
    ///
    /// ```
    /// use neurotree::nodes::semantics::{Order, Semantics, Statuses};
    /// # let mut registry = neurotree::Registry::<()>::new();
    /// # registry.register_custom("Refresh", neurotree::Arity::Range { min: 2, max: 2 },
    /// #     vec![], || -> Box<dyn neurotree::CustomNode<()>> { unimplemented!() }).unwrap();
    /// registry
    ///     .declare_semantics("Refresh", Semantics::new(Order::again(Statuses::ANY, Statuses::ANY),
    ///         |_, children| children[1].or(Statuses::RUNNING)))
    ///     .unwrap();
    /// ```
    ///
    /// The declaration must hold for every run (naming a status the node never returns is
    /// allowed, leaving out one it can return is not). Fails if no type is named `name`.
    pub fn declare_semantics(
        &mut self,
        name: &str,
        semantics: Semantics,
    ) -> Result<(), RegistryError> {
        let t = self
            .types
            .get_mut(name)
            .ok_or_else(|| RegistryError::Unknown(name.to_string()))?;
        t.semantics = Some(semantics);
        Ok(())
    }

    /// Registers a stateful action: `make` builds one object per tree instance.
    pub fn register_stateful<S, F>(
        &mut self,
        name: &str,
        ports: Vec<PortSpec>,
        make: F,
    ) -> Result<(), RegistryError>
    where
        S: StatefulAction<C> + 'static,
        F: Fn() -> S + Send + Sync + 'static,
    {
        self.register_stateful_as(name, Category::Action, ports, make)
    }

    /// As [`register_stateful`](Self::register_stateful), listed under `category`: a leaf
    /// that completes within its tick but remembers between ticks may be a Condition.
    pub fn register_stateful_as<S, F>(
        &mut self,
        name: &str,
        category: Category,
        ports: Vec<PortSpec>,
        make: F,
    ) -> Result<(), RegistryError>
    where
        S: StatefulAction<C> + 'static,
        F: Fn() -> S + Send + Sync + 'static,
    {
        let make = Arc::new(make);
        let leaf: LeafMaker<C> = Arc::new(move |_, _| {
            let make = Arc::clone(&make);
            Ok(NodeKind::Stateful(Box::new(
                move || -> Box<dyn StatefulAction<C>> { Box::new(make()) },
            )))
        });
        self.register_leaf(name, category, ports, leaf)
    }

    /// Registers an [async action](neurotree_core::nodes::leaf::async_action): on each start,
    /// `start` reads what it needs from the handle (its ports, the blackboard, the context)
    /// and returns the future that does the work, polled once per tick and dropped when the
    /// node is halted.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use neurotree::{ManualClock, PortSpec, Registry, Status, Tree, XmlLoader};
    ///
    /// let mut registry = Registry::<()>::new();
    /// registry
    ///     .register_async("CheckAltitude", vec![PortSpec::input::<f64>("min")], |h| {
    ///         let min: f64 = h.input("min").unwrap_or(f64::INFINITY);
    ///         async move { if 12.5 >= min { Status::Success } else { Status::Failure } }
    ///     })
    ///     .unwrap();
    /// let mut loader = XmlLoader::new(&registry);
    /// loader
    ///     .load_str(
    ///         r#"<root BTCPP_format="4"><BehaviorTree ID="main">
    ///              <CheckAltitude min="10"/>
    ///            </BehaviorTree></root>"#,
    ///         "main.xml",
    ///     )
    ///     .unwrap();
    /// let blueprint = Arc::new(loader.build_main().unwrap());
    /// let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    /// ```
    pub fn register_async<F, Fut>(
        &mut self,
        name: &str,
        ports: Vec<PortSpec>,
        start: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn(&mut Handle<'_, C>) -> Fut + Send + Sync + 'static,
        Fut: Future<Output = Status> + Send + 'static,
    {
        let start = Arc::new(start);
        let leaf: LeafMaker<C> =
            Arc::new(move |_, _| Ok(NodeKind::Async(Box::new(SharedAsync(Arc::clone(&start))))));
        self.register_leaf(name, Category::Action, ports, leaf)
    }

    /// Registers an [`AsyncAction`](neurotree_core::AsyncAction) object, shared by every
    /// node of the type: unlike [`register_async`](Self::register_async), which takes a
    /// closure, the object's own
    /// [`on_halt_requested`](neurotree_core::AsyncAction::on_halt_requested) runs, so a
    /// node loaded from XML may take ticks to halt (a server that must acknowledge a
    /// cancel).
    pub fn register_async_action<A>(
        &mut self,
        name: &str,
        ports: Vec<PortSpec>,
        action: A,
    ) -> Result<(), RegistryError>
    where
        A: neurotree_core::AsyncAction<C> + 'static,
    {
        let action = Arc::new(action);
        let leaf: LeafMaker<C> = Arc::new(move |_, _| {
            Ok(NodeKind::Async(Box::new(SharedAsyncAction(Arc::clone(
                &action,
            )))))
        });
        self.register_leaf(name, Category::Action, ports, leaf)
    }

    /// Registers a sync action: it completes within the tick.
    pub fn register_action<F>(
        &mut self,
        name: &str,
        ports: Vec<PortSpec>,
        f: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn(&mut Handle<'_, C>) -> Status + Send + Sync + 'static,
    {
        // One object shared by every node of this type: making a node allocates nothing.
        let action: Arc<dyn neurotree_core::Action<C>> = Arc::new(FnAction(f));
        let leaf: LeafMaker<C> = Arc::new(move |_, _| Ok(NodeKind::Action(Arc::clone(&action))));
        self.register_leaf(name, Category::Action, ports, leaf)
    }

    /// Registers a condition: Success or Failure, never Running.
    pub fn register_condition<F>(
        &mut self,
        name: &str,
        ports: Vec<PortSpec>,
        f: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn(&Handle<'_, C>) -> bool + Send + Sync + 'static,
    {
        // One object shared by every node of this type, and held once by each blueprint:
        // making a node allocates nothing and clones no `Arc`.
        if self.types.contains_key(name) {
            return Err(RegistryError::Duplicate(name.to_string()));
        }
        check_port_names(name, &ports)?;
        let t = NodeType {
            name: name.to_string(),
            category: Category::Condition,
            ports,
            description: String::new(),
            make: Make::Condition(Arc::new(FnCondition(f))),
            builtin: false,
            semantics: Some(Semantics::new(Order::AllAtOnce, |_, _| Statuses::DONE)),
        };
        self.types.insert(name.to_string(), t);
        Ok(())
    }

    /// Registers a condition of its ports and the blackboard alone (no context, no clock):
    /// a reactive node that re-checks it lets the tree sleep, waking when the blackboard is
    /// written (see the guide's sleeping chapter).
    ///
    /// ```
    /// use neurotree::{Inputs, PortSpec, Registry};
    ///
    /// let mut registry = Registry::<()>::new();
    /// registry
    ///     .register_port_condition("Hungry", vec![PortSpec::input::<u32>("food")], |i: &Inputs<'_, '_, ()>| {
    ///         i.input::<u32>("food").unwrap_or(0) < 3
    ///     })
    ///     .unwrap();
    /// ```
    pub fn register_port_condition<F>(
        &mut self,
        name: &str,
        ports: Vec<PortSpec>,
        f: F,
    ) -> Result<(), RegistryError>
    where
        F: Fn(&neurotree_core::nodes::leaf::Inputs<'_, '_, C>) -> bool + Send + Sync + 'static,
    {
        if self.types.contains_key(name) {
            return Err(RegistryError::Duplicate(name.to_string()));
        }
        check_port_names(name, &ports)?;
        let t = NodeType {
            name: name.to_string(),
            category: Category::Condition,
            ports,
            description: String::new(),
            make: Make::Condition(Arc::new(neurotree_core::nodes::leaf::PortCondition(f))),
            builtin: false,
            semantics: Some(Semantics::new(Order::AllAtOnce, |_, _| Statuses::DONE)),
        };
        self.types.insert(name.to_string(), t);
        Ok(())
    }

    /// Registers a subtree made with the builder under a tree ID, so that XML files can use
    /// it as `<SubTree ID="name"/>` (with remapping, like any subtree) without a
    /// `<BehaviorTree>` of that ID. `add` receives the builder with the SubTree node open and
    /// adds its one child. A tree loaded from XML with the same ID takes precedence.
    ///
    /// ```
    /// use neurotree::{ManualClock, Registry, Status, Tree, XmlLoader};
    ///
    /// let mut registry = Registry::<u32>::new();
    /// registry
    ///     .register_subtree("Count", |b| {
    ///         b.repeat("thrice", 3, |r| r.action("inc", |n: &mut u32| { *n += 1; Status::Success }))
    ///     })
    ///     .unwrap();
    /// let mut loader = XmlLoader::new(&registry);
    /// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
    ///     <Sequence><SubTree ID="Count"/><SubTree ID="Count" name="again"/></Sequence>
    ///   </BehaviorTree></root>"#, "main.xml").unwrap();
    /// let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    /// let mut n = 0;
    /// assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
    /// assert_eq!(n, 6);
    /// ```
    pub fn register_subtree<F>(&mut self, name: &str, add: F) -> Result<(), RegistryError>
    where
        F: Fn(neurotree_core::Builder<C>) -> neurotree_core::Builder<C> + Send + Sync + 'static,
    {
        if self.subtrees.contains_key(name) {
            return Err(RegistryError::Duplicate(name.to_string()));
        }
        self.subtrees.insert(name.to_string(), Arc::new(add));
        Ok(())
    }

    /// The subtree registered as `name`, if any.
    pub(crate) fn subtree(&self, name: &str) -> Option<&SubtreeMaker<C>> {
        self.subtrees.get(name)
    }

    /// The IDs of the subtrees made with the builder.
    pub fn subtree_ids(&self) -> impl Iterator<Item = &str> {
        self.subtrees.keys().map(String::as_str)
    }

    /// Adds a description to a registered type (shown in the `TreeNodesModel`).
    pub fn describe(&mut self, name: &str, description: &str) {
        if let Some(t) = self.types.get_mut(name) {
            t.description = description.to_string();
        }
    }

    /// Forgets type `name`, as a library of nodes that serves several releases keeps only
    /// one release's types; `false` if there was none.
    pub fn remove(&mut self, name: &str) -> bool {
        self.types.remove(name).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registering_a_name_twice_is_an_error() {
        let mut r = Registry::<()>::new();
        r.register_condition("IsOpen", vec![], |_| true).unwrap();
        assert_eq!(
            r.register_action("IsOpen", vec![], |_| Status::Success),
            Err(RegistryError::Duplicate("IsOpen".into()))
        );
        assert_eq!(
            r.register_condition("Sequence", vec![], |_| true),
            Err(RegistryError::Duplicate("Sequence".into()))
        );
    }
}

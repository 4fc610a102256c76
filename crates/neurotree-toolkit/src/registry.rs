//! The registry (BehaviorTree.CPP's factory): node types by name, with their ports.
//!
//! A BehaviorTree.CPP file names node types (`<MoveBase goal="{target}"/>`); the registry
//! says what each name is. It starts with every built-in node of the engine under its
//! BehaviorTree.CPP name, and the user adds leaves: a stateful action, an async action, a
//! sync action or a condition, each with the ports it reads and writes. Port declarations let the loader
//! reject an unknown attribute or a literal that does not convert, before anything runs.

use std::collections::BTreeMap;
use std::fmt;
use std::future::Future;
use std::sync::Arc;

use crate::script::Enums;
use crate::xml::escape;

use neurotree_core::{
    Category, FromPortStr, Handle, NodeKind, ParallelPolicy, StatefulAction, Status,
};

/// Which way a port carries data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortDirection {
    /// Read by the node.
    Input,
    /// Written by the node.
    Output,
    /// Both.
    InOut,
}

impl PortDirection {
    /// The element name BehaviorTree.CPP's `TreeNodesModel` uses.
    pub fn model_tag(self) -> &'static str {
        match self {
            PortDirection::Input => "input_port",
            PortDirection::Output => "output_port",
            PortDirection::InOut => "inout_port",
        }
    }
}

/// A declared port: name, direction, type, default and description.
#[derive(Clone)]
pub struct PortSpec {
    /// The attribute name.
    pub name: String,
    /// Which way it carries data.
    pub direction: PortDirection,
    /// The Rust type it converts to.
    pub type_name: &'static str,
    /// Text used when the attribute is absent.
    pub default: Option<String>,
    /// What it is for.
    pub description: String,
    /// `true` if a literal converts to the port's type.
    check: Option<fn(&str) -> bool>,
}

impl PortSpec {
    /// An input port of type `T`.
    pub fn input<T: FromPortStr + 'static>(name: &str) -> Self {
        Self::new::<T>(name, PortDirection::Input)
    }

    /// An output port of type `T`.
    pub fn output<T: 'static>(name: &str) -> Self {
        Self {
            name: name.to_string(),
            direction: PortDirection::Output,
            type_name: std::any::type_name::<T>(),
            default: None,
            description: String::new(),
            check: None,
        }
    }

    /// A port read and written, of type `T`.
    pub fn inout<T: FromPortStr + 'static>(name: &str) -> Self {
        Self::new::<T>(name, PortDirection::InOut)
    }

    fn new<T: FromPortStr + 'static>(name: &str, direction: PortDirection) -> Self {
        Self {
            name: name.to_string(),
            direction,
            type_name: std::any::type_name::<T>(),
            default: None,
            description: String::new(),
            check: Some(|text| T::from_port_str(text).is_ok()),
        }
    }

    /// With a default value (as text).
    pub fn default_value(mut self, text: &str) -> Self {
        self.default = Some(text.to_string());
        self
    }

    /// With a description.
    pub fn describe(mut self, text: &str) -> Self {
        self.description = text.to_string();
        self
    }

    /// `true` if `text` converts to the port's type (always for types without a check).
    pub fn accepts(&self, text: &str) -> bool {
        self.check.map_or(true, |check| check(text))
    }
}

impl fmt::Debug for PortSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PortSpec")
            .field("name", &self.name)
            .field("direction", &self.direction)
            .field("type_name", &self.type_name)
            .field("default", &self.default)
            .finish()
    }
}

/// The built-in nodes the loader knows how to build from their ports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BuiltIn {
    Sequence,
    SequenceWithMemory,
    ReactiveSequence,
    Fallback,
    ReactiveFallback,
    AsyncSequence,
    AsyncFallback,
    Parallel,
    ParallelAll,
    IfThenElse,
    WhileDoElse,
    TryCatch,
    Inverter,
    ForceSuccess,
    ForceFailure,
    Repeat,
    RetryUntilSuccessful,
    KeepRunningUntilFailure,
    Delay,
    Timeout,
    Cooldown,
    RunOnce,
    AlwaysSuccess,
    AlwaysFailure,
    Sleep,
}

/// Makes the per-node part of a leaf from its port bindings (most leaves ignore them; a
/// Script node parses its `code` here, at load time) and the registry's enums (which its
/// scripts name).
pub(crate) type LeafMaker<C> =
    Arc<dyn Fn(&[neurotree_core::Port], &Arc<Enums>) -> Result<NodeKind<C>, String> + Send + Sync>;

/// How a registered type becomes a node.
#[derive(Clone)]
pub(crate) enum Make<C> {
    BuiltIn(BuiltIn),
    Leaf(LeafMaker<C>),
    /// Known only from a `TreeNodesModel`: enough to validate a tree, not to run it.
    Model,
}

/// A registered node type.
#[derive(Clone)]
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
}

impl<C> NodeType<C> {
    /// The port named `name`.
    pub fn port(&self, name: &str) -> Option<&PortSpec> {
        self.ports.iter().find(|p| p.name == name)
    }
}

/// Why a registration was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RegistryError {
    /// The name is taken.
    #[error("a node type named `{0}` is already registered; pick another name")]
    Duplicate(String),
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
}

/// Adds the nodes of a subtree made in Rust below an open SubTree node.
pub(crate) type SubtreeMaker<C> =
    Arc<dyn Fn(neurotree_core::Builder<C>) -> neurotree_core::Builder<C> + Send + Sync>;

/// Node types by name: the built-ins, and the user's leaves; the subtrees made with the
/// builder; and the enum names that scripts and port values may use.
pub struct Registry<C> {
    types: BTreeMap<String, NodeType<C>>,
    subtrees: BTreeMap<String, SubtreeMaker<C>>,
    /// Shared with the script nodes made from this registry, which look names up at run time.
    enums: Arc<Enums>,
}

impl<C: 'static> Default for Registry<C> {
    fn default() -> Self {
        Self::new()
    }
}

impl<C: 'static> Registry<C> {
    /// A registry holding every built-in node under its BehaviorTree.CPP name.
    pub fn new() -> Self {
        let mut r = Self {
            types: BTreeMap::new(),
            subtrees: BTreeMap::new(),
            enums: Arc::new(Enums::new()),
        };
        for (name, category, built_in, ports) in built_ins() {
            let t = NodeType {
                name: name.to_string(),
                category,
                ports,
                description: String::new(),
                make: Make::BuiltIn(built_in),
                builtin: true,
            };
            r.types.insert(name.to_string(), t);
        }
        crate::nodes::script::register(&mut r);
        crate::nodes::loops::register(&mut r);
        crate::nodes::entry::register(&mut r);
        crate::nodes::switch::register(&mut r);
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
        let make = Arc::new(make);
        let type_name = name.to_string();
        let leaf: LeafMaker<C> = Arc::new(move |_, _| {
            let make = Arc::clone(&make);
            Ok(NodeKind::Custom(Box::new(neurotree_core::CustomSpec {
                type_name: type_name.clone(),
                arity,
                factory: Box::new(move || make()),
            })))
        });
        self.register_leaf(name, category, ports, leaf)
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
        let t = NodeType {
            name: name.to_string(),
            category,
            ports,
            description: String::new(),
            make: Make::Leaf(make),
            builtin: false,
        };
        self.types.insert(name.to_string(), t);
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
        let action: Arc<dyn neurotree_core::Action<C>> = Arc::new(SharedAction(f));
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
        // One object shared by every node of this type: making a node allocates nothing.
        let condition: Arc<dyn neurotree_core::Condition<C>> = Arc::new(SharedCondition(f));
        let leaf: LeafMaker<C> =
            Arc::new(move |_, _| Ok(NodeKind::Condition(Arc::clone(&condition))));
        self.register_leaf(name, Category::Condition, ports, leaf)
    }

    /// Declares the node types of a `TreeNodesModel` (the section Groot2 and Nav2 ship)
    /// that are not registered yet, with their ports. Such types let a tree be validated
    /// (see [`XmlLoader::validate`](crate::XmlLoader::validate)) but not run. Returns how
    /// many types were added.
    pub fn add_model_str(&mut self, text: &str, file: &str) -> Result<usize, crate::LoadError> {
        let doc = crate::xml::parse_model(text, file)?;
        let mut added = 0;
        for model in doc
            .root()
            .children()
            .filter(|c| c.tag() == "TreeNodesModel")
        {
            for node in model.children() {
                let category = match node.tag() {
                    "Action" => Category::Action,
                    "Condition" => Category::Condition,
                    "Control" => Category::Control,
                    "Decorator" => Category::Decorator,
                    "SubTree" => continue,
                    other => {
                        return Err(node.error(format!(
                            "unexpected <{other}> in <TreeNodesModel>; expected Action, Condition, Control, Decorator or SubTree"
                        )))
                    }
                };
                let Some(id) = node.attr("ID") else {
                    return Err(node.error(format!("<{}> in a model needs an ID", node.tag())));
                };
                if self.types.contains_key(id) {
                    continue;
                }
                let mut ports = Vec::new();
                for port in node.children() {
                    let direction = match port.tag() {
                        "input_port" => PortDirection::Input,
                        "output_port" => PortDirection::Output,
                        "inout_port" => PortDirection::InOut,
                        _ => continue,
                    };
                    let Some(name) = port.attr("name") else {
                        return Err(port.error("a port in a model needs a name"));
                    };
                    ports.push(PortSpec {
                        name: name.to_string(),
                        direction,
                        type_name: model_type_name(port.attr("type")),
                        default: port.attr("default").map(str::to_string),
                        description: port.text().to_string(),
                        check: model_type_check(port.attr("type")),
                    });
                }
                self.types.insert(
                    id.to_string(),
                    NodeType {
                        name: id.to_string(),
                        category,
                        ports,
                        description: String::new(),
                        make: Make::Model,
                        builtin: false,
                    },
                );
                added += 1;
            }
        }
        Ok(added)
    }

    /// The `TreeNodesModel` of the registered types that are not built in, as a BehaviorTree.CPP
    /// format-4 document: what Groot2 reads to know the user's nodes and their ports.
    pub fn tree_nodes_model(&self) -> String {
        let mut out = String::from("<root BTCPP_format=\"4\">\n");
        self.write_models(&mut out, false);
        out.push_str("</root>\n");
        out
    }

    /// Writes the `<TreeNodesModel>` element, indented one level, with the built-in types too
    /// when `builtins` is set.
    pub(crate) fn write_models(&self, out: &mut String, builtins: bool) {
        out.push_str("  <TreeNodesModel>\n");
        for t in self.types.values() {
            if t.builtin && !builtins {
                continue;
            }
            let tag = t.category.as_str();
            out.push_str(&format!("    <{tag} ID=\"{}\"", escape(&t.name)));
            if t.ports.is_empty() && t.description.is_empty() {
                out.push_str("/>\n");
                continue;
            }
            out.push_str(">\n");
            for p in &t.ports {
                out.push_str(&format!(
                    "      <{} name=\"{}\" type=\"{}\"",
                    p.direction.model_tag(),
                    escape(&p.name),
                    escape(p.type_name)
                ));
                if let Some(d) = &p.default {
                    out.push_str(&format!(" default=\"{}\"", escape(d)));
                }
                if p.description.is_empty() {
                    out.push_str("/>\n");
                } else {
                    out.push_str(&format!(
                        ">{}</{}>\n",
                        escape(&p.description),
                        p.direction.model_tag()
                    ));
                }
            }
            if !t.description.is_empty() {
                out.push_str(&format!(
                    "      <description>{}</description>\n",
                    escape(&t.description)
                ));
            }
            out.push_str(&format!("    </{tag}>\n"));
        }
        out.push_str("  </TreeNodesModel>\n");
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

    /// Defines the enum name `name` as `value`, as BehaviorTree.CPP's
    /// `registerScriptingEnum` does: scripts may write `state == DOCKING`, and a literal port
    /// value `DOCKING` reads as the number wherever the port wants a number. Trees loaded
    /// afterwards see it. Redefining a name with another value is an error.
    ///
    /// ```
    /// use neurotree::{Registry, XmlLoader, ManualClock, Status, Tree};
    ///
    /// let mut registry = Registry::<()>::new();
    /// registry.register_enums([("IDLE", 0), ("DOCKING", 2)]).unwrap();
    /// let mut loader = XmlLoader::new(&registry);
    /// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
    ///     <Sequence>
    ///       <Script code="state := DOCKING"/>
    ///       <ScriptCondition code="state == DOCKING &amp;&amp; state != IDLE"/>
    ///       <Repeat num_cycles="DOCKING"><AlwaysSuccess/></Repeat>
    ///     </Sequence>
    ///   </BehaviorTree></root>"#, "enums.xml").unwrap();
    /// let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    /// assert_eq!(tree.blackboard().get::<i64>("state"), Ok(2));
    /// ```
    pub fn register_enum(&mut self, name: &str, value: i64) -> Result<(), RegistryError> {
        match self.enums.get(name) {
            Some(old) if old != value => Err(RegistryError::EnumRedefined {
                name: name.to_string(),
                old,
                new: value,
            }),
            Some(_) => Ok(()),
            None => {
                Arc::make_mut(&mut self.enums).insert(name, value);
                Ok(())
            }
        }
    }

    /// Defines several enum names (see [`register_enum`](Self::register_enum)).
    pub fn register_enums<'n>(
        &mut self,
        values: impl IntoIterator<Item = (&'n str, i64)>,
    ) -> Result<(), RegistryError> {
        values
            .into_iter()
            .try_for_each(|(name, value)| self.register_enum(name, value))
    }

    /// The enum names defined so far.
    pub fn enums(&self) -> &Arc<Enums> {
        &self.enums
    }

    /// Adds a description to a registered type (shown in the `TreeNodesModel`).
    pub fn describe(&mut self, name: &str, description: &str) {
        if let Some(t) = self.types.get_mut(name) {
            t.description = description.to_string();
        }
    }

    /// The built-in type whose name is `name` but for letter case (`inverter`), if exactly
    /// one is. Files written for Nav2 use such spellings; BehaviorTree.CPP would refuse them,
    /// but what they mean is not in doubt.
    pub(crate) fn builtin_ignoring_case(&self, name: &str) -> Option<&NodeType<C>> {
        let mut found = self
            .types
            .values()
            .filter(|t| t.builtin && t.name.eq_ignore_ascii_case(name));
        match (found.next(), found.next()) {
            (Some(t), None) => Some(t),
            _ => None,
        }
    }

    /// The type registered as `name`.
    pub fn get(&self, name: &str) -> Option<&NodeType<C>> {
        self.types.get(name)
    }

    /// Every registered type, by name.
    pub fn types(&self) -> impl Iterator<Item = &NodeType<C>> {
        self.types.values()
    }

    /// The registered name closest to `name`, to suggest when `name` is unknown.
    pub fn closest(&self, name: &str) -> Option<&str> {
        self.types
            .keys()
            .map(|k| (strsim::damerau_levenshtein(name, k), k))
            .filter(|(d, k)| *d <= k.len().max(3) / 2)
            .min()
            .map(|(_, k)| k.as_str())
    }
}

/// The Rust type a model's type name converts to, for messages.
fn model_type_name(t: Option<&str>) -> &'static str {
    match t.map(str::trim) {
        Some("double" | "float") => "f64",
        Some("bool") => "bool",
        Some("int" | "int8" | "int16" | "int32" | "int64" | "long") => "i64",
        Some("unsigned int" | "unsigned" | "uint8" | "uint16" | "uint32" | "uint64" | "size_t") => {
            "u64"
        }
        Some("std::string" | "string" | "alloc::string::String") => "String",
        Some("f64" | "f32") => "f64",
        Some("i8" | "i16" | "i32" | "i64" | "isize") => "i64",
        Some("u8" | "u16" | "u32" | "u64" | "usize") => "u64",
        _ => "text",
    }
}

/// How a model's literal is checked: numbers and booleans are, other types are taken as given.
fn model_type_check(t: Option<&str>) -> Option<fn(&str) -> bool> {
    match model_type_name(t) {
        "f64" => Some(|s| f64::from_port_str(s).is_ok()),
        "bool" => Some(|s| bool::from_port_str(s).is_ok()),
        "i64" => Some(|s| i64::from_port_str(s).is_ok()),
        "u64" => Some(|s| u64::from_port_str(s).is_ok()),
        _ => None,
    }
}

struct SharedAction<F>(F);

impl<C, F> neurotree_core::Action<C> for SharedAction<F>
where
    F: Fn(&mut Handle<'_, C>) -> Status + Send + Sync,
{
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        (self.0)(h)
    }
}

struct SharedAsync<F>(Arc<F>);

impl<C, F, Fut> neurotree_core::AsyncAction<C> for SharedAsync<F>
where
    F: Fn(&mut Handle<'_, C>) -> Fut + Send + Sync,
    Fut: Future<Output = Status> + Send + 'static,
{
    fn start(&self, h: &mut Handle<'_, C>) -> neurotree_core::ActionFuture {
        Box::pin((self.0)(h))
    }
}

struct SharedCondition<F>(F);

impl<C, F> neurotree_core::Condition<C> for SharedCondition<F>
where
    F: Fn(&Handle<'_, C>) -> bool + Send + Sync,
{
    fn check(&self, h: &Handle<'_, C>) -> bool {
        (self.0)(h)
    }
}

/// The built-in nodes, their families and their ports, as BehaviorTree.CPP declares them.
fn built_ins() -> Vec<(&'static str, Category, BuiltIn, Vec<PortSpec>)> {
    use BuiltIn as B;
    use Category::{Action, Control, Decorator};
    let ms = |name: &str| vec![PortSpec::input::<u64>(name)];
    vec![
        ("Sequence", Control, B::Sequence, vec![]),
        ("SequenceWithMemory", Control, B::SequenceWithMemory, vec![]),
        ("ReactiveSequence", Control, B::ReactiveSequence, vec![]),
        ("Fallback", Control, B::Fallback, vec![]),
        ("ReactiveFallback", Control, B::ReactiveFallback, vec![]),
        ("AsyncSequence", Control, B::AsyncSequence, vec![]),
        ("AsyncFallback", Control, B::AsyncFallback, vec![]),
        (
            "Parallel",
            Control,
            B::Parallel,
            vec![
                PortSpec::input::<i32>("success_count").default_value("-1"),
                PortSpec::input::<i32>("failure_count").default_value("1"),
            ],
        ),
        (
            "ParallelAll",
            Control,
            B::ParallelAll,
            vec![PortSpec::input::<i32>("max_failures").default_value("1")],
        ),
        ("IfThenElse", Control, B::IfThenElse, vec![]),
        ("WhileDoElse", Control, B::WhileDoElse, vec![]),
        (
            "TryCatch",
            Control,
            B::TryCatch,
            vec![PortSpec::input::<bool>("catch_on_halt").default_value("false")],
        ),
        ("Inverter", Decorator, B::Inverter, vec![]),
        ("ForceSuccess", Decorator, B::ForceSuccess, vec![]),
        ("ForceFailure", Decorator, B::ForceFailure, vec![]),
        (
            "Repeat",
            Decorator,
            B::Repeat,
            vec![PortSpec::input::<i32>("num_cycles")],
        ),
        (
            "RetryUntilSuccessful",
            Decorator,
            B::RetryUntilSuccessful,
            vec![PortSpec::input::<i32>("num_attempts")],
        ),
        (
            "KeepRunningUntilFailure",
            Decorator,
            B::KeepRunningUntilFailure,
            vec![],
        ),
        ("Delay", Decorator, B::Delay, ms("delay_msec")),
        ("Timeout", Decorator, B::Timeout, ms("msec")),
        ("Cooldown", Decorator, B::Cooldown, ms("cooldown_msec")),
        (
            "RunOnce",
            Decorator,
            B::RunOnce,
            vec![PortSpec::input::<bool>("then_skip").default_value("true")],
        ),
        ("AlwaysSuccess", Action, B::AlwaysSuccess, vec![]),
        ("AlwaysFailure", Action, B::AlwaysFailure, vec![]),
        ("Sleep", Action, B::Sleep, ms("msec")),
    ]
}

/// The kind of a built-in node from its ports' values (already checked to convert).
pub(crate) fn built_in_kind<C>(
    b: BuiltIn,
    port: impl Fn(&str) -> Option<String>,
) -> Result<NodeKind<C>, String> {
    use std::time::Duration;
    fn num<T: FromPortStr>(name: &str, text: Option<String>) -> Result<T, String> {
        let text = text.ok_or_else(|| format!("missing port `{name}`"))?;
        T::from_port_str(&text).map_err(|()| format!("port `{name}`: cannot read `{text}`"))
    }
    let ms = |name: &str| num::<u64>(name, port(name)).map(Duration::from_millis);
    Ok(match b {
        BuiltIn::Sequence => NodeKind::Sequence,
        BuiltIn::SequenceWithMemory => NodeKind::SequenceWithMemory,
        BuiltIn::ReactiveSequence => NodeKind::ReactiveSequence,
        BuiltIn::Fallback => NodeKind::Fallback,
        BuiltIn::ReactiveFallback => NodeKind::ReactiveFallback,
        BuiltIn::AsyncSequence => NodeKind::AsyncSequence,
        BuiltIn::AsyncFallback => NodeKind::AsyncFallback,
        BuiltIn::Parallel => NodeKind::Parallel(ParallelPolicy::Thresholds {
            success: num("success_count", port("success_count"))?,
            failure: num("failure_count", port("failure_count"))?,
        }),
        BuiltIn::ParallelAll => NodeKind::ParallelAll {
            max_failures: num("max_failures", port("max_failures"))?,
        },
        BuiltIn::IfThenElse => NodeKind::IfThenElse,
        BuiltIn::WhileDoElse => NodeKind::WhileDoElse,
        BuiltIn::TryCatch => NodeKind::TryCatch {
            catch_on_halt: num("catch_on_halt", port("catch_on_halt"))?,
        },
        BuiltIn::Inverter => NodeKind::Inverter,
        BuiltIn::ForceSuccess => NodeKind::ForceSuccess,
        BuiltIn::ForceFailure => NodeKind::ForceFailure,
        BuiltIn::Repeat => NodeKind::Repeat {
            num_cycles: num("num_cycles", port("num_cycles"))?,
        },
        BuiltIn::RetryUntilSuccessful => NodeKind::RetryUntilSuccessful {
            num_attempts: num("num_attempts", port("num_attempts"))?,
        },
        BuiltIn::KeepRunningUntilFailure => NodeKind::KeepRunningUntilFailure,
        BuiltIn::Delay => NodeKind::Delay(ms("delay_msec")?),
        BuiltIn::Timeout => NodeKind::Timeout(ms("msec")?),
        BuiltIn::Cooldown => NodeKind::Cooldown(ms("cooldown_msec")?),
        BuiltIn::RunOnce => NodeKind::RunOnce {
            then_skip: num("then_skip", port("then_skip"))?,
        },
        BuiltIn::AlwaysSuccess => NodeKind::AlwaysSuccess,
        BuiltIn::AlwaysFailure => NodeKind::AlwaysFailure,
        BuiltIn::Sleep => NodeKind::Sleep(ms("msec")?),
    })
}

/// The ports a built-in kind was made from, as [`built_in_kind`] reads them back: what a
/// saved file writes for the node. `children` resolves the Parallel shorthands the builder
/// offers into BehaviorTree.CPP's thresholds.
pub(crate) fn built_in_ports<C>(
    kind: &NodeKind<C>,
    children: usize,
) -> Vec<(&'static str, String)> {
    let ms = |d: &std::time::Duration| d.as_millis().to_string();
    match kind {
        NodeKind::Parallel(policy) => {
            let n = children as i32;
            let (success, failure) = match *policy {
                ParallelPolicy::Thresholds { success, failure } => (success, failure),
                ParallelPolicy::RequireAll => (-1, 1),
                ParallelPolicy::RequireOne => (1, -1),
                ParallelPolicy::RequireCount(m) => (m as i32, n - m as i32 + 1),
            };
            vec![
                ("success_count", success.to_string()),
                ("failure_count", failure.to_string()),
            ]
        }
        NodeKind::ParallelAll { max_failures } => vec![("max_failures", max_failures.to_string())],
        NodeKind::TryCatch { catch_on_halt } => vec![("catch_on_halt", catch_on_halt.to_string())],
        NodeKind::Repeat { num_cycles } => vec![("num_cycles", num_cycles.to_string())],
        NodeKind::RetryUntilSuccessful { num_attempts } => {
            vec![("num_attempts", num_attempts.to_string())]
        }
        NodeKind::Delay(d) => vec![("delay_msec", ms(d))],
        NodeKind::Timeout(d) | NodeKind::Sleep(d) => vec![("msec", ms(d))],
        NodeKind::Cooldown(d) => vec![("cooldown_msec", ms(d))],
        NodeKind::RunOnce { then_skip } => vec![("then_skip", then_skip.to_string())],
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_ports_read_back_into_the_same_kind() {
        let r = Registry::<()>::new();
        for t in r.types() {
            let Make::BuiltIn(b) = t.make else { continue };
            // Every port at a value other than the smallest, so a swapped pair would show.
            let kind = built_in_kind::<()>(b, |p| {
                Some(match p {
                    "success_count" => "2".into(),
                    "failure_count" => "-1".into(),
                    "catch_on_halt" | "then_skip" => "true".into(),
                    _ => "7".into(),
                })
            })
            .unwrap();
            let ports = built_in_ports(&kind, 3);
            let again = built_in_kind::<()>(b, |p| {
                ports.iter().find(|(n, _)| *n == p).map(|(_, v)| v.clone())
            })
            .unwrap();
            assert_eq!(format!("{again:?}"), format!("{kind:?}"), "{}", t.name);
            assert_eq!(ports.len(), t.ports.len(), "{}", t.name);
        }
        let count = NodeKind::<()>::Parallel(ParallelPolicy::RequireCount(2));
        assert_eq!(
            built_in_ports(&count, 5),
            [("success_count", "2".into()), ("failure_count", "4".into())]
        );
    }

    #[test]
    fn built_ins_are_registered_with_their_ports() {
        let r = Registry::<()>::new();
        let repeat = r.get("Repeat").unwrap();
        assert_eq!(repeat.category, Category::Decorator);
        assert_eq!(repeat.ports[0].name, "num_cycles");
        assert!(repeat.ports[0].accepts("3"));
        assert!(!repeat.ports[0].accepts("three"));
        assert_eq!(r.get("Parallel").unwrap().ports.len(), 2);
        assert!(r.get("MoveBase").is_none());
    }

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

    #[test]
    fn the_model_lists_user_types_and_reads_back() {
        let mut r = Registry::<()>::new();
        r.register_action(
            "MoveTo",
            vec![
                PortSpec::input::<f64>("speed")
                    .default_value("0.5")
                    .describe("metres per second, < 2"),
                PortSpec::output::<String>("result"),
            ],
            |_| Status::Success,
        )
        .unwrap();
        r.register_condition("IsReady", vec![], |_| true).unwrap();
        r.describe("IsReady", "the robot can move");
        let model = r.tree_nodes_model();
        assert!(model.contains(r#"<Action ID="MoveTo">"#), "{model}");
        assert!(model.contains(
            r#"<input_port name="speed" type="f64" default="0.5">metres per second, &lt; 2</input_port>"#
        ), "{model}");
        assert!(model.contains(r#"<Condition ID="IsReady">"#), "{model}");
        assert!(!model.contains("Sequence"), "{model}");
        assert!(!model.contains("Script"), "{model}");
        let mut back = Registry::<()>::new();
        assert_eq!(back.add_model_str(&model, "model.xml").unwrap(), 2);
        let move_to = back.get("MoveTo").unwrap();
        assert_eq!(move_to.ports.len(), 2);
        assert_eq!(move_to.ports[0].default.as_deref(), Some("0.5"));
        assert!(!move_to.ports[0].accepts("fast"));
        assert_eq!(move_to.ports[1].direction, PortDirection::Output);
    }

    #[test]
    fn unknown_names_get_a_suggestion() {
        let r = Registry::<()>::new();
        assert_eq!(r.closest("Sequense"), Some("Sequence"));
        assert_eq!(r.closest("Inverted"), Some("Inverter"));
        assert_eq!(r.closest("qqqqqqqqqqqqqqq"), None);
    }

    #[test]
    fn built_in_kinds_read_their_ports() {
        let kind =
            built_in_kind::<()>(BuiltIn::Repeat, |p| (p == "num_cycles").then(|| "3".into()));
        assert!(matches!(kind, Ok(NodeKind::Repeat { num_cycles: 3 })));
        let missing = built_in_kind::<()>(BuiltIn::Timeout, |_| None);
        assert_eq!(missing.err().as_deref(), Some("missing port `msec`"));
    }
}

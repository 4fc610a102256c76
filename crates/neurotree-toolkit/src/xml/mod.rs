//! BehaviorTree.CPP XML (format 4): load the trees that Groot2 and ROS 2 Nav2 write.
//!
//! An [`XmlLoader`] reads one or more files (following `<include path>`), collects their
//! `<BehaviorTree ID>`s, and builds a [`Blueprint`] of one of them, expanding `<SubTree>`s
//! into blackboard scopes. Node names resolve through a [`Registry`]: the built-in nodes, and
//! the leaves the user registered with their ports. Everything is checked while building —
//! unknown nodes (with the closest registered name), unknown ports (with the valid ones),
//! literals that do not convert, child counts, subtree cycles, nesting depth — and every
//! error names the file, line and column: `path:line:col: error: message`.
//!
//! ```
//! use neurotree::xml::XmlLoader;
//! use neurotree::{ManualClock, Registry, Status, Tree};
//!
//! let mut registry = Registry::<u32>::new();
//! registry
//!     .register_action("Count", vec![], |h| { *h.ctx_mut() += 1; Status::Success })
//!     .unwrap();
//! let mut loader = XmlLoader::new(&registry);
//! loader.load_str(r#"
//!     <root BTCPP_format="4" main_tree_to_execute="Main">
//!       <BehaviorTree ID="Main">
//!         <Repeat num_cycles="3"><Count/></Repeat>
//!       </BehaviorTree>
//!     </root>"#, "inline.xml").unwrap();
//! let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
//! let mut n = 0;
//! assert_eq!(tree.tick_once(&mut n), Ok(Status::Success));
//! assert_eq!(n, 3);
//! ```

mod budget;
mod build;
pub(crate) use build::{binding, is_explicit};
mod error;
mod errors;
mod escape;
mod file;
mod include;
use include::joined;
mod mock;
mod model;
mod names;
mod reactive_check;
use reactive_check::check_reactive;
pub mod save;
mod source;
pub mod substitute;

pub use budget::TOO_MANY_NODES;
pub use error::{LoadError, LoadErrorKind, LoadWarning};
pub use errors::{LoadErrors, MAX_ERRORS};
pub use escape::escape;
pub use file::{read_file, DEFAULT_MAX_FILE_BYTES};
pub use mock::{parse_outcomes, MockOutput, Outcomes, OutputType};
pub(crate) use names::check_port_name;
pub use save::{write_xml, SaveOptions};
pub use substitute::{Substitute, Substitutions, TestNodeConfig};

/// The most nodes a tree built by an [`XmlLoader`] may have, its subtrees expanded, unless
/// [`XmlLoader::max_nodes`] says otherwise: far more than any real tree, and few enough
/// that a file whose subtrees use each other many times over is refused before it takes
/// gigabytes.
pub const DEFAULT_MAX_NODES: usize = 2_000_000;

/// Parses a file that holds a `TreeNodesModel` (for [`Registry::add_model_str`]).
pub(crate) fn parse_model(text: &str, file: &str) -> Result<Document, LoadError> {
    source::parse(text, file)
}

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};

use neurotree_core::Blueprint;

use crate::registry::Registry;
pub(crate) use source::{Document, Element};

use neurotree_core::nodes::control::reactive;

/// Where a loaded `<BehaviorTree>` is: its document and its element there.
#[derive(Clone, Copy, Debug)]
struct TreeAt {
    doc: usize,
    element: usize,
}

/// Loads BehaviorTree.CPP XML files and builds blueprints from their trees.
pub struct XmlLoader<'r, C> {
    registry: &'r Registry<C>,
    /// Every file loaded, kept whole: the trees point into them.
    docs: Vec<Document>,
    trees: BTreeMap<String, TreeAt>,
    main: Option<String>,
    base_dir: Option<PathBuf>,
    mock_unknown: bool,
    /// Files being loaded, to stop include cycles.
    loading: Vec<PathBuf>,
    /// The texts `<include>`s are served from instead of the file system, by path (see
    /// [`include_texts`](Self::include_texts)).
    include_texts: Option<BTreeMap<String, String>>,
    /// Trees loaded without an ID so far.
    unnamed_trees: usize,
    /// Node name (or type) → the outcomes of the mock that replaces it.
    mocks: BTreeMap<String, Outcomes>,
    /// BehaviorTree.CPP's substitution rules, applied after the mocks.
    substitutions: Substitutions,
    /// The most nodes a built tree may have, subtrees expanded.
    max_nodes: usize,
    /// The largest file read, in bytes.
    max_file_bytes: u64,
    /// How many nodes each loaded tree expands to, as far as worked out (see
    /// `budget.rs`); emptied when a file is loaded. Behind a lock because building
    /// borrows the loader shared, and the loader may be shared across threads.
    sizes: std::sync::Mutex<BTreeMap<String, u64>>,
    /// Whether a loaded tree holds a `<SubTree>`: until one does, a tree's size is its
    /// number of elements.
    subtrees: bool,
    /// What the files loaded so far should change, in load order.
    warnings: Vec<LoadWarning>,
    /// The ports the files' `TreeNodesModel`s declare for SubTrees, by tree ID: each
    /// port's name and default (`None`: mandatory), applied where a SubTree leaves one out.
    subtree_models: BTreeMap<String, Vec<(String, Option<String>)>>,
    /// What an unknown node type's error tells the reader to do.
    unknown_type_advice: std::borrow::Cow<'static, str>,
    /// Replaces the hooks of the nodes of each tree built ([`XmlLoader::wrap_hooks`]).
    wrap_hooks: Option<SharedHookWrapper<C>>,
}

/// What [`XmlLoader::wrap_hooks`] is given: called with each node of a tree being built and
/// the hooks the file gave it, it returns the hooks the node gets.
pub type SharedHookWrapper<C> = std::sync::Arc<
    dyn Fn(
            neurotree_core::NodeId,
            Option<Box<dyn neurotree_core::NodeHooks<C>>>,
        ) -> Option<Box<dyn neurotree_core::NodeHooks<C>>>
        + Send
        + Sync,
>;

impl<C> fmt::Debug for XmlLoader<'_, C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("XmlLoader")
            .field("trees", &self.trees.keys().collect::<Vec<_>>())
            .field("main", &self.main)
            .finish_non_exhaustive()
    }
}

impl<'r, C: 'static> XmlLoader<'r, C> {
    /// A loader resolving node names through `registry`.
    pub fn new(registry: &'r Registry<C>) -> Self {
        Self {
            registry,
            docs: Vec::new(),
            trees: BTreeMap::new(),
            main: None,
            base_dir: None,
            mock_unknown: false,
            loading: Vec::new(),
            include_texts: None,
            unnamed_trees: 0,
            mocks: BTreeMap::new(),
            substitutions: Substitutions::new(),
            max_nodes: DEFAULT_MAX_NODES,
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
            sizes: std::sync::Mutex::default(),
            subtrees: false,
            warnings: Vec::new(),
            subtree_models: BTreeMap::new(),
            unknown_type_advice: "register it in the Registry before loading".into(),
            wrap_hooks: None,
        }
    }

    /// Has `wrap` give the nodes of every tree built from now on their hooks (see
    /// [`Builder::wrap_hooks`](neurotree_core::Builder::wrap_hooks)): how faults are
    /// injected into chosen nodes ([`crate::fault`]).
    pub fn wrap_hooks(mut self, wrap: SharedHookWrapper<C>) -> Self {
        self.wrap_hooks = Some(wrap);
        self
    }

    /// What the error for an unknown node type advises, "register it in the Registry before
    /// loading" by default: a tool whose users cannot reach the registry says what they can
    /// do instead (the command line: `--model`, `--nav2`, `--mock`).
    pub fn unknown_type_advice(
        mut self,
        advice: impl Into<std::borrow::Cow<'static, str>>,
    ) -> Self {
        self.unknown_type_advice = advice.into();
        self
    }

    /// Sets the most nodes a tree built (or validated) may have once its subtrees are
    /// expanded, [`DEFAULT_MAX_NODES`] by default. A SubTree whose expansion would go past
    /// it is an error at that SubTree, found before anything of it is built.
    pub fn max_nodes(mut self, nodes: usize) -> Self {
        self.max_nodes = nodes;
        self
    }

    /// Sets the largest file (tree file or include) read, in bytes,
    /// [`DEFAULT_MAX_FILE_BYTES`] by default; a larger one is an error naming it.
    pub fn max_file_bytes(mut self, bytes: u64) -> Self {
        self.max_file_bytes = bytes;
        self
    }

    /// Confines `<include>`s to files under `dir`; an include that leaves it is an error.
    /// Without it, includes are confined to the directory of the first file loaded.
    pub fn base_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.base_dir = Some(dir.into());
        self
    }

    /// Turns every unregistered leaf into a mock that succeeds, for dry runs.
    pub fn mock_unknown(mut self, yes: bool) -> Self {
        self.mock_unknown = yes;
        self
    }

    /// Replaces every leaf (Action or Condition) whose `name` (or, without one, its type) is
    /// `name`, else whose type is `name`, by a leaf that returns `outcomes` one per tick (a
    /// `Vec<Status>`, or the runs [`parse_outcomes`] reads), then the last one forever, and
    /// writes the outcomes' outputs at every tick, for dry runs. A control or decorator of
    /// that name stays; if no leaf of the tree built is named so or of that type, building
    /// it fails ([`LoadErrorKind::MockNotLeaf`] if a control or decorator is,
    /// [`LoadErrorKind::UnmatchedMock`] if no node is).
    pub fn mock(mut self, name: &str, outcomes: impl Into<Outcomes>) -> Self {
        self.mocks.insert(name.to_string(), outcomes.into());
        self
    }

    /// Applies BehaviorTree.CPP's substitution rules when building (see
    /// [the rules](crate::xml::substitute)), after the ones given before. A node that a
    /// mock replaces is not substituted.
    ///
    /// ```
    /// use neurotree::xml::{Substitutions, XmlLoader};
    /// use neurotree::{ManualClock, Registry, Status, Tree};
    ///
    /// let rules = Substitutions::from_json(r#"{
    ///     "TestNodeConfigs": { "Done": { "return_status": "SUCCESS", "post_script": "n := 7" } },
    ///     "SubstitutionRules": { "Drive*": "Done" } }"#, "rules.json").unwrap();
    /// let registry = Registry::<()>::new();
    /// let mut loader = XmlLoader::new(&registry).substitute(rules);
    /// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
    ///     <DriveToDock/></BehaviorTree></root>"#, "main.xml").unwrap();
    /// let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    /// assert_eq!(tree.blackboard().get::<i64>("n"), Ok(7));
    /// ```
    pub fn substitute(mut self, rules: Substitutions) -> Self {
        self.substitutions.extend(rules);
        self
    }

    /// The warnings of the files loaded so far, in load order: each use of an alias
    /// (a deprecated or misspelt built-in name that loads as the one it stands for).
    pub fn warnings(&self) -> &[LoadWarning] {
        &self.warnings
    }

    /// The registry node names resolve through.
    pub(crate) fn registry(&self) -> &'r Registry<C> {
        self.registry
    }

    /// The IDs of the trees loaded so far.
    pub fn tree_ids(&self) -> impl Iterator<Item = &str> {
        self.trees.keys().map(String::as_str)
    }

    /// The tree to execute: the `main_tree_to_execute` of the first file loaded, or the only
    /// tree loaded.
    pub fn main_tree(&self) -> Option<&str> {
        match &self.main {
            Some(m) => Some(m),
            None if self.trees.len() == 1 => self.trees.keys().next().map(String::as_str),
            None => None,
        }
    }

    /// Serves `<include>`s from `texts`, by path, rather than from the file system: for
    /// trees kept where paths are not file paths (a game engine's assets). An include's
    /// path is joined to the directory of the file that includes it, with `.` and `..`
    /// resolved, as [`includes_of`](Self::includes_of) gives it; the base directory does
    /// not apply.
    pub fn include_texts(&mut self, texts: BTreeMap<String, String>) -> &mut Self {
        self.include_texts = Some(texts);
        self
    }

    /// The paths the `<include>`s of `text` name, `file` being its path: what to read for
    /// [`include_texts`](Self::include_texts) before loading `text`, and then what the
    /// included texts name in turn.
    pub fn includes_of(text: &str, file: &str) -> Result<Vec<String>, LoadError> {
        let doc = source::parse(text, file)?;
        let dir = Path::new(file).parent().unwrap_or(Path::new(""));
        let mut paths = Vec::new();
        for child in doc.root().children() {
            if child.tag() != "include" {
                continue;
            }
            let Some(path) = child.attr("path") else {
                return Err(child.error(LoadErrorKind::Include, "<include> needs a path attribute"));
            };
            paths.push(joined(dir, path));
        }
        Ok(paths)
    }

    /// Loads XML text; `file` names it in errors and anchors relative includes.
    pub fn load_str(&mut self, text: &str, file: &str) -> Result<(), LoadError> {
        let root = source::parse(text, file)?;
        let dir = Path::new(file).parent().map(Path::to_path_buf);
        self.take_root(root, dir.as_deref())
    }

    /// Loads an XML file and the files it includes. Only regular files are read (a FIFO or a
    /// device is an error naming it), up to [`max_file_bytes`](Self::max_file_bytes) each.
    pub fn load_file(&mut self, path: impl AsRef<Path>) -> Result<(), LoadError> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let canonical = path.canonicalize().map_err(|e| {
            LoadError::at_file(
                LoadErrorKind::Io,
                &shown,
                format!("cannot open the file: {e}"),
            )
        })?;
        if self.base_dir.is_none() {
            self.base_dir = canonical.parent().map(Path::to_path_buf);
        }
        if self.loading.contains(&canonical) {
            return Err(LoadError::at_file(
                LoadErrorKind::Include,
                &shown,
                "this file includes itself (through its includes); remove the cycle",
            ));
        }
        let text = file::read_file(&canonical, self.max_file_bytes).map_err(|mut e| {
            e.file.clone_from(&shown);
            e
        })?;
        self.loading.push(canonical.clone());
        let root = source::parse(&text, &shown);
        let result = root.and_then(|root| self.take_root(root, canonical.parent()));
        self.loading.pop();
        result
    }

    fn take_root(&mut self, doc: Document, dir: Option<&Path>) -> Result<(), LoadError> {
        // The trees this file brings change what the SubTrees of the others expand to.
        self.sizes
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clear();
        let at = self.docs.len();
        self.docs.push(doc);
        let trees = self.trees.len();
        let result = self.take_children(at, dir);
        // A document none of whose trees was kept is not needed (unless an include came
        // after it, which is kept with it).
        if result.is_err() && self.trees.len() == trees && self.docs.len() == at + 1 {
            self.docs.pop();
        }
        result
    }

    fn take_children(&mut self, at: usize, dir: Option<&Path>) -> Result<(), LoadError> {
        let root = self.docs[at].root();
        if root.tag() != "root" {
            return Err(root.error(
                LoadErrorKind::Structure,
                format!(
                "the document element is <{}>; a BehaviorTree.CPP file starts with <root BTCPP_format=\"4\">",
                root.tag()
            )));
        }
        if let Some(format) = root.attr("BTCPP_format")
            && format != "4"
            && format != "3"
        {
            return Err(root.error(
                LoadErrorKind::UnsupportedFormat,
                format!("BTCPP_format=\"{format}\" is not supported; use format 4"),
            ));
        }
        // BehaviorTree.CPP executes the main tree of the first document opened: a file
        // loaded or included later does not change it.
        if at == 0 {
            self.main = root.attr("main_tree_to_execute").map(String::from);
        }
        // By number: an include loads more documents into `docs` while these are walked.
        let children: Vec<usize> = root.children().map(|c| c.id()).collect();
        let siblings = children.len();
        for element in children {
            let child = self.docs[at].element(element);
            match child.tag() {
                "BehaviorTree" => {
                    // BehaviorTree.CPP names an unnamed tree `BehaviorTree_<n>`.
                    let id = match child.attr("ID") {
                        Some(id) => id.to_string(),
                        None => format!("BehaviorTree_{}", self.unnamed_trees),
                    };
                    if child.attr("ID").is_none() {
                        self.unnamed_trees += 1;
                    }
                    if self.trees.contains_key(&id) {
                        return Err(child.error(LoadErrorKind::DuplicateTree, format!(
                            "a tree with ID `{id}` is already loaded; tree IDs must be unique"
                        )));
                    }
                    if child.child_count() != 1 {
                        return Err(child.error(LoadErrorKind::Structure, format!(
                            "<BehaviorTree ID=\"{id}\"> must hold exactly one root node, found {}",
                            child.child_count()
                        )));
                    }
                    let (warnings, subtrees) = self.check_tree(child, siblings)?;
                    self.subtrees |= subtrees;
                    self.trees.insert(id, TreeAt { doc: at, element });
                    self.warnings.extend(warnings);
                }
                "include" => self.include(at, element, dir)?,
                // Models describe nodes for editors, and the registry is the loader's model
                // of nodes; but a model's SubTree ports are applied as BehaviorTree.CPP does.
                "TreeNodesModel" => self.read_subtree_models(at, element)?,
                other => {
                    return Err(child.error(LoadErrorKind::Structure, format!(
                        "unexpected <{other}> under <root>; expected <BehaviorTree>, <include> or <TreeNodesModel>"
                    )))
                }
            }
        }
        Ok(())
    }

    /// Refuses what BehaviorTree.CPP's `VerifyXML` refuses in the `<BehaviorTree>` `tree`
    /// (one of `siblings` elements under `<root>`): its ID, its SubTrees' IDs and the node
    /// type names it writes as elements, and a ReactiveSequence with several asynchronous
    /// children. Returns the warnings for the node types it names by an alias, in document
    /// order (one walk over the tree for both).
    fn check_tree(
        &self,
        tree: Element<'_>,
        siblings: usize,
    ) -> Result<(Vec<LoadWarning>, bool), LoadError> {
        let registered = |id: &str| self.registry.get(id).is_some();
        let mut subtrees = false;
        match tree.attr("ID") {
            // BehaviorTree.CPP names the only tree of a file; among others it must be named.
            None | Some("") if siblings > 1 => {
                return Err(tree.error(
                    LoadErrorKind::BadName,
                    "<BehaviorTree> needs an ID when <root> holds other elements \
                     (BehaviorTree.CPP refuses it); add ID=\"...\"",
                ))
            }
            None | Some("") => {}
            Some(id) => {
                names::check_model_name(id, "tree ID")
                    .map_err(|m| tree.error(LoadErrorKind::BadName, m))?;
                if registered(id) {
                    return Err(tree.error(
                        LoadErrorKind::BadName,
                        format!(
                            "tree ID `{id}` is the name of a registered node type, which \
                         BehaviorTree.CPP refuses; rename the tree"
                        ),
                    ));
                }
            }
        }
        let mut warnings = Vec::new();
        // Tags already found to be valid names of no alias: a tree writes few types many
        // times, and each check looks the name up and scans it.
        let mut plain: [&str; 8] = [""; 8];
        let mut next_plain = 0;
        let mut last_plain = "";
        for el in tree.descendants() {
            let tag = el.tag();
            // The type of the element before first: trees write runs of the same type.
            if build::same(last_plain, tag) || plain.contains(&tag) {
                last_plain = tag;
                if tag == reactive::REACTIVE_SEQUENCE.name {
                    check_reactive(el)?;
                }
                continue;
            }
            let explicit = build::is_explicit(tag);
            let type_name = if explicit {
                el.attr("ID").unwrap_or("")
            } else {
                tag
            };
            let aliased = match self.registry.alias(type_name) {
                Some((alias, _)) => {
                    warnings.push(el.warning(alias.warning()));
                    true
                }
                None => false,
            };
            if tag == "SubTree" {
                subtrees = true;
                // Without an ID the builder says so; an empty one is a name refused here.
                let Some(id) = el.attr("ID") else { continue };
                names::check_model_name(id, "SubTree ID")
                    .map_err(|m| el.error(LoadErrorKind::BadName, m))?;
                if registered(id) {
                    return Err(el.error(
                        LoadErrorKind::BadName,
                        format!(
                            "SubTree ID `{id}` is the name of a registered node type, which \
                         BehaviorTree.CPP refuses; rename the tree"
                        ),
                    ));
                }
            } else if !explicit {
                names::check_model_name(tag, "node type")
                    .map_err(|m| el.error(LoadErrorKind::BadName, m))?;
                if !aliased && !tag.is_empty() {
                    plain[next_plain % plain.len()] = tag;
                    next_plain += 1;
                }
            }
            if type_name == reactive::REACTIVE_SEQUENCE.name {
                check_reactive(el)?;
            }
        }
        Ok((warnings, subtrees))
    }

    /// Keeps the ports that the `<SubTree>` entries of model `element` declare.
    fn read_subtree_models(&mut self, doc: usize, element: usize) -> Result<(), LoadError> {
        let model = self.docs[doc].element(element);
        for sub in model.children().filter(|c| c.tag() == "SubTree") {
            let id = sub.attr("ID").ok_or_else(|| {
                sub.error(
                    LoadErrorKind::Structure,
                    "<SubTree> in a TreeNodesModel needs an ID",
                )
            })?;
            let mut ports = Vec::new();
            for p in sub.children().filter(|p| p.tag().ends_with("_port")) {
                let Some(name) = p.attr("name") else {
                    return Err(p.error(
                        LoadErrorKind::Structure,
                        format!("a port of SubTree `{id}` in a TreeNodesModel needs a name"),
                    ));
                };
                names::check_subtree_port_name(name).map_err(|m| {
                    p.error(LoadErrorKind::BadName, format!("SubTree `{id}` model: {m}"))
                })?;
                ports.push((name.to_string(), p.attr("default").map(String::from)));
            }
            self.subtree_models.insert(id.to_string(), ports);
        }
        Ok(())
    }

    /// The ports a model declares for the SubTree `id`, if one does.
    pub(crate) fn subtree_model(&self, id: &str) -> Option<&[(String, Option<String>)]> {
        self.subtree_models.get(id).map(Vec::as_slice)
    }

    /// Builds the tree named `id` (its subtrees expanded).
    pub fn build(&self, id: &str) -> Result<Blueprint<C>, LoadError> {
        let Some(tree) = self.tree(id) else {
            let known: Vec<&str> = self.tree_ids().collect();
            let meant = crate::registry::suggest::did_you_mean(id, known.iter().copied());
            return Err(LoadError::at_file(
                LoadErrorKind::UnknownTree,
                "",
                format!(
                    "no tree with ID `{id}`{meant}; loaded trees: {}",
                    known.join(", ")
                ),
            ));
        };
        let built = build::build(self, id, tree, false)?;
        self.strict_types(id)?;
        Ok(built)
    }

    /// With [`Registry::set_strict_types`](crate::Registry::set_strict_types), the first
    /// entry of tree `id` written as one type and read as another.
    fn strict_types(&self, id: &str) -> Result<(), LoadError> {
        match self.strict_type_errors(id).into_iter().next() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// As [`strict_types`](Self::strict_types), every such entry.
    pub(crate) fn strict_type_errors(&self, id: &str) -> Vec<LoadError> {
        if !self.registry.strict_types() {
            return Vec::new();
        }
        crate::lint::types::strict_errors(self, id)
    }

    /// Checks the tree named `id` as [`build`](Self::build) does, also accepting node types
    /// known only from a `TreeNodesModel` (which cannot run).
    pub fn validate(&self, id: &str) -> Result<(), LoadError> {
        let Some(tree) = self.tree(id) else {
            let known: Vec<&str> = self.tree_ids().collect();
            let meant = crate::registry::suggest::did_you_mean(id, known.iter().copied());
            return Err(LoadError::at_file(
                LoadErrorKind::UnknownTree,
                "",
                format!("no tree with ID `{id}`{meant}"),
            ));
        };
        build::build(self, id, tree, true)?;
        self.strict_types(id)
    }

    /// Checks the tree named `id` as [`validate`](Self::validate) does, but goes on past a
    /// node in error to report up to `limit` errors (at least one): the elements' errors in
    /// document order, then a child count or threshold the builder refused; empty if the tree
    /// is valid. A subtree's errors are reported with each tree that uses it.
    pub fn validate_all(&self, id: &str, limit: usize) -> Vec<LoadError> {
        let Some(tree) = self.tree(id) else {
            let known: Vec<&str> = self.tree_ids().collect();
            let meant = crate::registry::suggest::did_you_mean(id, known.iter().copied());
            return vec![LoadError::at_file(
                LoadErrorKind::UnknownTree,
                "",
                format!("no tree with ID `{id}`{meant}"),
            )];
        };
        let errors = build::validate_all(self, id, tree, limit);
        if errors.is_empty() {
            let mut strict = self.strict_type_errors(id);
            strict.truncate(limit.max(1));
            return strict;
        }
        errors
    }

    /// The IDs that the `<SubTree>`s of the loaded trees name.
    fn subtree_references(&self) -> BTreeSet<&str> {
        self.trees
            .values()
            .flat_map(|at| self.docs[at.doc].element(at.element).descendants())
            .filter(|el| el.tag() == "SubTree")
            .filter_map(|el| el.attr("ID"))
            .collect()
    }

    /// The loaded trees that no `<SubTree>` of a loaded tree names, in ID order: where a
    /// file without `main_tree_to_execute` can start, if there is exactly one.
    pub fn unreferenced_trees(&self) -> Vec<&str> {
        let used = self.subtree_references();
        self.tree_ids().filter(|id| !used.contains(id)).collect()
    }

    /// The tree IDs that a `<SubTree>` names but that are neither loaded nor registered as
    /// subtrees, in ID order: what the loaded files need from other files.
    pub fn unresolved_subtrees(&self) -> Vec<&str> {
        self.subtree_references()
            .into_iter()
            .filter(|id| !self.trees.contains_key(*id) && self.registry.subtree(id).is_none())
            .collect()
    }

    /// The `<BehaviorTree>` element of the tree named `id`.
    pub(crate) fn tree(&self, id: &str) -> Option<Element<'_>> {
        let at = self.trees.get(id)?;
        Some(self.docs[at.doc].element(at.element))
    }

    /// Builds the main tree (see [`main_tree`](Self::main_tree)).
    pub fn build_main(&self) -> Result<Blueprint<C>, LoadError> {
        let Some(main) = self.main_tree() else {
            // Several trees and none named the main one is a choice left to make.
            let kind = if self.trees.len() > 1 {
                LoadErrorKind::AmbiguousMainTree
            } else {
                LoadErrorKind::NoMainTree
            };
            return Err(LoadError::at_file(
                kind,
                "",
                "no main tree: set main_tree_to_execute on <root>, or name the tree to build",
            ));
        };
        let main = main.to_string();
        self.build(&main)
    }
}

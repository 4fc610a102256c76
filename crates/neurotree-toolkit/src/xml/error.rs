//! What loading a file or building a tree can go wrong with, and where.

/// A file that could not be loaded or a tree that could not be built, with its place.
///
/// Its [`kind`](Self::kind) says what went wrong in a way a program can act on; the
/// message says it to a person, and may be reworded.
///
/// It prints as `file:line:col: error: message`, or `file: error: message` for an error
/// about the file as a whole (it cannot be opened, is too large, has no such tree), which
/// has no place in it.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}{}: error: {message}", place(*line, *col))]
pub struct LoadError {
    /// The file (as given to the loader).
    pub file: String,
    /// 1-based line; 0 for an error about the file as a whole.
    pub line: u32,
    /// 1-based column; 0 for an error about the file as a whole.
    pub col: u32,
    /// What is wrong and what to do.
    pub message: String,
    kind: LoadErrorKind,
}

neurotree_core::debug_shows_message!(struct LoadError { file, line, col, message, kind });

impl LoadError {
    /// An error of `kind` at `line` and `col` (1-based) of `file`; for tools that report
    /// their own input files the way the loader reports tree files.
    pub fn new(
        kind: LoadErrorKind,
        file: impl Into<String>,
        line: u32,
        col: u32,
        message: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            line,
            col,
            message: message.into(),
            kind,
        }
    }

    /// An error of `kind` about `file` as a whole: no line, no column.
    pub fn at_file(kind: LoadErrorKind, file: &str, message: impl Into<String>) -> Self {
        Self::new(kind, file, 0, 0, message)
    }

    /// What went wrong, to branch on (the message is for people).
    pub fn kind(&self) -> LoadErrorKind {
        self.kind
    }
}

/// `:line:col` of a place in a file, or nothing for the file as a whole (line 0).
fn place(line: u32, col: u32) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}:{col}")
    }
}

/// What kind of mistake a [`LoadError`] reports.
///
/// New kinds may come as the loader checks more, so a `match` needs a wildcard arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LoadErrorKind {
    /// A file could not be opened or read, is not a regular file, or is not UTF-8 text.
    Io,
    /// A file or text is larger than the loader reads.
    TooLarge,
    /// The text is not well-formed XML.
    Syntax,
    /// The document is well-formed but not shaped as BehaviorTree.CPP expects: another
    /// document element, an unexpected element, an element without its `ID`, a
    /// `<BehaviorTree>` without exactly one root node, a malformed `TreeNodesModel`.
    Structure,
    /// `BTCPP_format` names a version other than 3 or 4.
    UnsupportedFormat,
    /// An `<include>` that cannot be followed: not found, outside the base directory,
    /// in text loaded without a file, or including itself.
    Include,
    /// A second tree with an ID already loaded.
    DuplicateTree,
    /// A node type that is not registered.
    UnknownNode,
    /// A node type that only a `TreeNodesModel` describes, built to run.
    ModelOnly,
    /// An attribute that is no port of the node.
    UnknownPort,
    /// A port the node needs that is neither given nor defaulted.
    MissingPort,
    /// A value that cannot be read as what it must be (a port's literal, a flag).
    BadValue,
    /// A script (a port's or a pre/post-condition's) that does not parse.
    Script,
    /// An attribute starting with `_` that BehaviorTree.CPP does not define.
    ReservedAttribute,
    /// A node with a number of children it does not take, or a threshold above it.
    ChildCount,
    /// A tree that contains itself through its `<SubTree>`s.
    SubtreeCycle,
    /// A tree ID (of a `<SubTree>`, or asked for) that is neither loaded nor registered.
    UnknownTree,
    /// No tree to start from: no `main_tree_to_execute` and no tree loaded.
    NoMainTree,
    /// No `main_tree_to_execute`, and several trees could be the main one.
    AmbiguousMainTree,
    /// A tree nested deeper than the depth limit.
    TooDeep,
    /// A tree with more nodes than the loader's limit, its subtrees expanded.
    TooManyNodes,
    /// A mock named after a control or decorator and no leaf: mocks replace only leaves.
    MockNotLeaf,
    /// A mock that no node of the tree built is named or of the type of.
    UnmatchedMock,
    /// A substitution rules file that cannot be read, or a rule that cannot be applied
    /// (it names neither a TestNodeConfig nor a registered node type).
    Substitution,
    /// A name BehaviorTree.CPP refuses: a tree or SubTree ID that is empty, reserved
    /// (`Root`), holds a forbidden character or is a registered node type's name; a node
    /// type written as an element with a forbidden character; a port name that is reserved,
    /// holds a forbidden character or does not start as BehaviorTree.CPP requires.
    BadName,
    /// Two SubTrees with the same `name` in one tree: their paths (which Groot2 and
    /// observers go by) would be the same.
    DuplicateSubTreePath,
    /// A ReactiveSequence with more than one asynchronous child (`AsyncSequence`), which
    /// BehaviorTree.CPP refuses when it loads the file.
    ReactiveAsync,
}

/// Something a file does that loads but should change, with its place: a deprecated or
/// misspelt node name that loads as the built-in it stands for.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}:{col}: warning: {message}")]
pub struct LoadWarning {
    /// The file (as given to the loader).
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// What to change.
    pub message: String,
}

neurotree_core::debug_shows_message!(struct LoadWarning { file, line, col, message });

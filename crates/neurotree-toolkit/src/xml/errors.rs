//! Every error of a tree at once: what [`Registry::load_str`](crate::Registry::load_str),
//! [`Registry::load_file`](crate::Registry::load_file) and the loader's
//! [`build_all_errors`](super::XmlLoader::build_all_errors) return, and what
//! `neurotree check` prints.

use std::fmt;

use neurotree_core::Blueprint;

use super::{build, LoadError, LoadErrorKind, XmlLoader};

/// The most errors gathered for one tree or file: past these, the rest are mostly
/// consequences of the first ones.
pub const MAX_ERRORS: usize = 20;

/// The errors of a file or a tree, each once, in the order the loader meets them (document
/// order, a subtree's where it is used, a child count the builder refuses last): never
/// empty.
///
/// Each [`LoadError`] has its [`kind`](LoadError::kind) and its place (file, line, column).
/// Printed, they are one per line, `file:line:col: error: message`, as `neurotree check`
/// prints them.
///
/// ```
/// use neurotree::prelude::*;
/// use neurotree::LoadErrorKind;
///
/// let registry = Registry::<()>::new();
/// let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
///   <Sequence>
///     <Nope/>
///     <Repeat num_cycles="many"><AlwaysSuccess/></Repeat>
///   </Sequence>
/// </BehaviorTree></root>"#;
/// let errors = registry.load_str(xml, "main.xml", ManualClock::new()).unwrap_err();
/// assert_eq!(errors.len(), 2);
/// let kinds: Vec<LoadErrorKind> = errors.iter().map(|e| e.kind()).collect();
/// assert_eq!(kinds, [LoadErrorKind::UnknownNode, LoadErrorKind::BadValue]);
/// assert_eq!((errors.first().line, errors.first().col), (3, 5));
/// assert_eq!(errors.to_string().lines().count(), 2);
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct LoadErrors {
    /// At least one.
    errors: Vec<LoadError>,
}

impl LoadErrors {
    /// `errors`, each once in the order met (a subtree used twice meets its errors twice);
    /// `None` if there are none.
    pub fn new(errors: impl IntoIterator<Item = LoadError>) -> Option<Self> {
        let errors = once_each(errors);
        (!errors.is_empty()).then_some(Self { errors })
    }

    /// The first error: there is always one.
    pub fn first(&self) -> &LoadError {
        &self.errors[0]
    }

    /// The kind of the first error.
    pub fn kind(&self) -> LoadErrorKind {
        self.first().kind()
    }

    /// How many errors there are (at least one).
    #[allow(clippy::len_without_is_empty)] // never empty
    pub fn len(&self) -> usize {
        self.errors.len()
    }

    /// The errors, in order.
    pub fn iter(&self) -> std::slice::Iter<'_, LoadError> {
        self.errors.iter()
    }

    /// The errors, in order.
    pub fn as_slice(&self) -> &[LoadError] {
        &self.errors
    }

    /// The errors, in order.
    pub fn into_vec(self) -> Vec<LoadError> {
        self.errors
    }
}

/// Building and checking with every error reported.
impl<C: 'static> XmlLoader<'_, C> {
    /// Builds the tree named `id` as [`build`](Self::build) does, but a tree that does not
    /// build gives all its errors (up to [`MAX_ERRORS`]), not only the first: the loader
    /// goes on past a node in error, with a stand-in in its place.
    pub fn build_all_errors(&self, id: &str) -> Result<Blueprint<C>, LoadErrors> {
        match self.tree(id) {
            Some(tree) => {
                let built = build::build_all(self, id, tree, MAX_ERRORS)?;
                match LoadErrors::new(self.strict_type_errors(id)) {
                    Some(errors) => Err(errors),
                    None => Ok(built),
                }
            }
            None => self.build(id).map_err(LoadErrors::from),
        }
    }

    /// Builds the main tree (see [`main_tree`](Self::main_tree)) as
    /// [`build_all_errors`](Self::build_all_errors) builds a tree.
    pub fn build_main_all_errors(&self) -> Result<Blueprint<C>, LoadErrors> {
        match self.main_tree() {
            Some(main) => self.build_all_errors(main),
            None => self.build_main().map_err(LoadErrors::from),
        }
    }

    /// Checks the trees named `ids` as [`validate_all`](Self::validate_all) checks one, in
    /// the order they were loaded: `Ok` if all are valid, else their errors, each once (a
    /// subtree's error is met by every tree that uses it), up to [`MAX_ERRORS`]. What
    /// `neurotree check` reports for a file.
    pub fn validate_trees<'a>(
        &self,
        ids: impl IntoIterator<Item = &'a str>,
    ) -> Result<(), LoadErrors> {
        let mut ids: Vec<&str> = ids.into_iter().collect();
        ids.sort_by_key(|id| self.trees.get(*id).map(|at| (at.doc, at.element)));
        let errors = ids.iter().flat_map(|id| self.validate_all(id, MAX_ERRORS));
        match LoadErrors::new(errors) {
            Some(mut errors) => {
                errors.errors.truncate(MAX_ERRORS);
                Err(errors)
            }
            None => Ok(()),
        }
    }
}

impl LoadErrors {
    /// `before`, then `last`, each once, at most `limit` of them (at least one).
    pub(super) fn ending_with(before: Vec<LoadError>, last: LoadError, limit: usize) -> Self {
        // Never empty: the first error is always kept.
        let mut errors = once_each(before.into_iter().chain([last]));
        errors.truncate(limit.max(1));
        Self { errors }
    }
}

/// `errors`, each once, in the order met.
fn once_each(errors: impl IntoIterator<Item = LoadError>) -> Vec<LoadError> {
    let mut kept: Vec<LoadError> = Vec::new();
    for e in errors {
        if !kept.contains(&e) {
            kept.push(e);
        }
    }
    kept
}

impl From<LoadError> for LoadErrors {
    fn from(error: LoadError) -> Self {
        Self {
            errors: vec![error],
        }
    }
}

impl IntoIterator for LoadErrors {
    type Item = LoadError;
    type IntoIter = std::vec::IntoIter<LoadError>;

    fn into_iter(self) -> Self::IntoIter {
        self.errors.into_iter()
    }
}

impl<'a> IntoIterator for &'a LoadErrors {
    type Item = &'a LoadError;
    type IntoIter = std::slice::Iter<'a, LoadError>;

    fn into_iter(self) -> Self::IntoIter {
        self.errors.iter()
    }
}

impl fmt::Display for LoadErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.errors.iter().enumerate() {
            if i > 0 {
                f.write_str("\n")?;
            }
            write!(f, "{e}")?;
        }
        Ok(())
    }
}

impl std::error::Error for LoadErrors {}

/// The lines `Display` prints, so that `?` in `main` shows them, then each error's kind.
impl fmt::Debug for LoadErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{self} (LoadErrors ")?;
        f.debug_list()
            .entries(self.errors.iter().map(LoadError::kind))
            .finish()?;
        f.write_str(")")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(line: u32, message: &str) -> LoadError {
        LoadError::new(LoadErrorKind::BadValue, "t.xml", line, 3, message)
    }

    #[test]
    fn each_error_is_kept_once_in_the_order_met() {
        let errors = LoadErrors::new([at(2, "a"), at(5, "b"), at(2, "a"), at(7, "c")]).unwrap();
        let lines: Vec<u32> = errors.iter().map(|e| e.line).collect();
        assert_eq!(lines, [2, 5, 7]);
        assert_eq!(errors.len(), 3);
        assert_eq!(errors.first().message, "a");
        assert_eq!(
            errors.to_string(),
            "t.xml:2:3: error: a\nt.xml:5:3: error: b\nt.xml:7:3: error: c"
        );
        let owned: Vec<LoadError> = errors.clone().into_iter().collect();
        assert_eq!(owned, errors.as_slice());
        assert!(LoadErrors::new([]).is_none());
        assert_eq!(LoadErrors::from(at(1, "x")).len(), 1);
    }

    #[test]
    fn debug_leads_with_the_lines_display_prints() {
        let errors = LoadErrors::new([at(2, "a"), at(5, "b")]).unwrap();
        assert_eq!(
            format!("{errors:?}"),
            "t.xml:2:3: error: a\nt.xml:5:3: error: b (LoadErrors [BadValue, BadValue])"
        );
        let one = at(4, "use a number");
        assert_eq!(
            format!("{one:?}"),
            "t.xml:4:3: error: use a number (LoadError { file: \"t.xml\", line: 4, col: 3, \
             message: \"use a number\", kind: BadValue })"
        );
    }

    #[test]
    fn the_trees_of_a_file_are_checked_in_document_order_and_a_shared_error_told_once() {
        let registry = crate::Registry::<()>::new();
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(
                r#"<root BTCPP_format="4">
  <BehaviorTree ID="Zeta">
    <Sequence><Nope/><SubTree ID="Shared"/></Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Alpha">
    <Sequence><SubTree ID="Shared"/><Inverter/></Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Shared">
    <Repeat num_cycles="x"><AlwaysSuccess/></Repeat>
  </BehaviorTree>
</root>"#,
                "two.xml",
            )
            .unwrap();
        let ids: Vec<String> = loader.tree_ids().map(String::from).collect();
        assert_eq!(ids, ["Alpha", "Shared", "Zeta"]);
        let errors = loader
            .validate_trees(ids.iter().map(String::as_str))
            .unwrap_err();
        let seen: Vec<(LoadErrorKind, u32, u32)> =
            errors.iter().map(|e| (e.kind(), e.line, e.col)).collect();
        assert_eq!(
            seen,
            [
                (LoadErrorKind::UnknownNode, 3, 15),
                (LoadErrorKind::BadValue, 9, 5),
                (LoadErrorKind::ChildCount, 6, 37),
            ]
        );
        assert_eq!(loader.validate_trees(["Shared"]).unwrap_err().len(), 1);
        // Building stops at nothing either: the main tree asked for has both of its own.
        let built = loader.build_all_errors("Zeta").unwrap_err();
        assert_eq!(built.len(), 2);
        assert_eq!(loader.build("Zeta").unwrap_err(), *built.first());
    }
}

//! Names BehaviorTree.CPP 4.10 does not know but real files write, each loaded as the
//! built-in it means, with a warning.
//!
//! BehaviorTree.CPP's node names are case-sensitive, and so are the registry's: `<inverter>`
//! is not `<Inverter>`. This small table is the exception, one row per name a real file
//! needs; it is not a case-insensitive match. A name the user registered wins over an alias.
//!
//! A library of nodes that renamed some (Nav2: `IsPathValid` became `ValidatePath`) tells
//! its registry the old names with [`Registry::add_renamed`]; they load the same way.

use super::{NodeType, Registry};

/// Why a name is an alias.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AliasKind {
    /// A misspelling that a real file carries, which BehaviorTree.CPP would refuse.
    Misspelt,
    /// BehaviorTree.CPP 3's name for a node that version 4 renamed.
    Deprecated,
}

/// A name that loads as a built-in of another name.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Alias {
    /// What the file writes.
    pub name: &'static str,
    /// The built-in it loads as.
    pub target: &'static str,
    pub kind: AliasKind,
}

/// The aliases, each with the file or version that needs it.
pub(crate) const ALIASES: [Alias; 2] = [
    // Nav2's docking application example (opennav_docking_bt, in the corpus as
    // corpus/nav2/opennav_docking_bt__application_example.xml) writes `<inverter>`.
    Alias {
        name: "inverter",
        target: neurotree_core::nodes::decorator::inverter::INVERTER.name,
        kind: AliasKind::Misspelt,
    },
    // BehaviorTree.CPP 3 called SequenceWithMemory `SequenceStar`; version 4 renamed it
    // (its v3-to-v4 converter rewrites the name), and 4.10 no longer knows the old one.
    Alias {
        name: "SequenceStar",
        target: neurotree_core::nodes::control::sequence::SEQUENCE_WITH_MEMORY.name,
        kind: AliasKind::Deprecated,
    },
];

impl Alias {
    /// The warning a file using the alias gets.
    pub(crate) fn warning(&self) -> String {
        let (name, target) = (self.name, self.target);
        match self.kind {
            AliasKind::Misspelt => format!(
                "`{name}` is not a BehaviorTree.CPP name (names are case-sensitive; it would refuse the file); it loads as `{target}`, write that"
            ),
            AliasKind::Deprecated => format!(
                "`{name}` is deprecated (BehaviorTree.CPP 3's name); it loads as `{target}`, write that"
            ),
        }
    }
}

/// An old name of a registered type: the type's name and the warning a file using it gets.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Renamed {
    pub target: String,
    pub warning: String,
}

/// An alias as the registry finds it: a row of the table, or an old name it was told.
pub(crate) enum AliasRef<'r> {
    Table(&'static Alias),
    Renamed(&'r Renamed),
}

impl AliasRef<'_> {
    /// The warning a file using the alias gets.
    pub(crate) fn warning(&self) -> String {
        match self {
            AliasRef::Table(alias) => alias.warning(),
            AliasRef::Renamed(renamed) => renamed.warning.clone(),
        }
    }
}

impl<C: 'static> Registry<C> {
    /// Whether a file may name `name`: a registered type, or an alias of one.
    pub fn knows(&self, name: &str) -> bool {
        self.types.contains_key(name) || self.alias(name).is_some()
    }

    /// Every alias a file may write (misspellings real files carry, BehaviorTree.CPP 3's
    /// names, [`add_renamed`](Self::add_renamed)'s old names), each with the type it loads
    /// as: an editor shows `<inverter>` as the decorator it is.
    ///
    /// ```
    /// let registry = neurotree_toolkit::Registry::<()>::new();
    /// let (_, target) = registry.aliases().find(|(name, _)| *name == "inverter").unwrap();
    /// assert_eq!(target.name, "Inverter");
    /// ```
    pub fn aliases(&self) -> impl Iterator<Item = (&str, &NodeType<C>)> {
        ALIASES
            .iter()
            .map(|a| a.name)
            .chain(self.renamed.keys().map(String::as_str))
            .filter_map(|name| Some((name, self.alias(name)?.1)))
    }

    /// The alias `name` is, with the type it loads as, unless `name` is registered itself.
    pub(crate) fn alias(&self, name: &str) -> Option<(AliasRef<'_>, &NodeType<C>)> {
        // The table first: it is asked about every element of every file loaded, and two
        // comparisons cost less than a search of the registry.
        let (alias, target) = match ALIASES.iter().find(|a| a.name == name) {
            Some(alias) => (AliasRef::Table(alias), alias.target),
            None => {
                let renamed = self.renamed.get(name)?;
                (AliasRef::Renamed(renamed), renamed.target.as_str())
            }
        };
        if self.types.contains_key(name) {
            return None;
        }
        Some((alias, self.types.get(target)?))
    }

    /// Lets files name registered type `new` by its old name `old`, as a library of nodes
    /// that renamed one keeps its older files loading: each use loads as `new`, with a
    /// warning that says `why` (the release that renamed it). Until `new` is registered,
    /// and whenever `old` is registered itself, `old` is no alias.
    ///
    /// ```
    /// use neurotree_toolkit::{Registry, XmlLoader};
    ///
    /// let mut registry = Registry::<()>::new();
    /// registry.add_renamed("Forever", "KeepRunningUntilFailure", "renamed in 2.0");
    /// let mut loader = XmlLoader::new(&registry);
    /// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="T">
    ///   <Forever><AlwaysFailure/></Forever></BehaviorTree></root>"#, "old.xml").unwrap();
    /// loader.build_main().unwrap();
    /// assert_eq!(
    ///     loader.warnings()[0].to_string(),
    ///     "old.xml:2:3: warning: `Forever` is `KeepRunningUntilFailure` now (renamed in 2.0); \
    ///      it loads as `KeepRunningUntilFailure`, write that"
    /// );
    /// ```
    pub fn add_renamed(&mut self, old: &str, new: &str, why: &str) {
        let warning = format!("`{old}` is `{new}` now ({why}); it loads as `{new}`, write that");
        self.renamed.insert(
            old.to_string(),
            Renamed {
                target: new.to_string(),
                warning,
            },
        );
    }
}

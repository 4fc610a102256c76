//! Names BehaviorTree.CPP 4.10 does not know but real files write, each loaded as the
//! built-in it means, with a warning.
//!
//! BehaviorTree.CPP's node names are case-sensitive, and so are the registry's: `<inverter>`
//! is not `<Inverter>`. This small table is the exception, one row per name a real file
//! needs; it is not a case-insensitive match. A name the user registered wins over an alias.

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

impl<C: 'static> Registry<C> {
    /// The alias `name` is, with the type it loads as, unless `name` is registered itself.
    pub(crate) fn alias(&self, name: &str) -> Option<(&'static Alias, &NodeType<C>)> {
        // The table first: it is asked about every element of every file loaded, and two
        // comparisons cost less than a search of the registry.
        let alias = ALIASES.iter().find(|a| a.name == name)?;
        if self.types.contains_key(name) {
            return None;
        }
        Some((alias, self.types.get(alias.target)?))
    }
}

//! What an unknown name probably meant: a node type, a port, a tree ID.

use super::aliases::ALIASES;
use super::Registry;

/// The name among `candidates` nearest to `name`, to suggest when `name` is unknown: one
/// that differs only in letter case, else the nearest in edits (Damerau-Levenshtein), if
/// it is within half the candidate's length.
pub(crate) fn nearest<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str> + Clone,
) -> Option<&'a str> {
    if let Some(k) = candidates
        .clone()
        .into_iter()
        .find(|k| k.eq_ignore_ascii_case(name))
    {
        return Some(k);
    }
    candidates
        .into_iter()
        .map(|k| (strsim::damerau_levenshtein(name, k), k))
        .filter(|(d, k)| *d <= k.len().max(3) / 2)
        .min()
        .map(|(_, k)| k)
}

/// ` (did you mean `NAME`?)` for the name among `candidates` nearest to `name`, or nothing.
pub(crate) fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str> + Clone,
) -> String {
    nearest(name, candidates).map_or_else(String::new, |n| format!(" (did you mean `{n}`?)"))
}

impl<C: 'static> Registry<C> {
    /// The registered name closest to `name`, to suggest when `name` is unknown: one that
    /// differs only in letter case (`INVERTER` → `Inverter`), else the nearest in edits. An
    /// alias close to it suggests the name it stands for (`SequenceStr` →
    /// `SequenceWithMemory`).
    pub fn closest(&self, name: &str) -> Option<&str> {
        if let Some(k) = self.types.keys().find(|k| k.eq_ignore_ascii_case(name)) {
            return Some(k);
        }
        let names = self.types.keys().map(|k| (k.as_str(), k.as_str()));
        let aliases = ALIASES.iter().map(|a| (a.name, a.target));
        names
            .chain(aliases)
            .map(|(k, meant)| (strsim::damerau_levenshtein(name, k), k, meant))
            .filter(|(d, k, _)| *d <= k.len().max(3) / 2)
            .min()
            .and_then(|(_, _, meant)| self.types.get_key_value(meant))
            .map(|(k, _)| k.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_names_get_a_suggestion() {
        let r = Registry::<()>::new();
        assert_eq!(r.closest("Sequense"), Some("Sequence"));
        assert_eq!(r.closest("Inverted"), Some("Inverter"));
        assert_eq!(r.closest("qqqqqqqqqqqqqqq"), None);
        // Through the alias `SequenceStar`, to the name it stands for.
        assert_eq!(r.closest("SequenceStr"), Some("SequenceWithMemory"));
        assert_eq!(r.closest("forceSuccess"), Some("ForceSuccess"));
        assert_eq!(r.closest("INVERTER"), Some("Inverter"));
    }

    #[test]
    fn a_mistyped_name_gets_the_nearest_one() {
        let ports = ["goal", "path", "planner_id", "use_start"];
        assert_eq!(nearest("planer_id", ports), Some("planner_id"));
        assert_eq!(nearest("GOAL", ports), Some("goal"));
        assert_eq!(nearest("velocity", ports), None);
        assert_eq!(
            did_you_mean("planer_id", ports),
            " (did you mean `planner_id`?)"
        );
        assert_eq!(did_you_mean("velocity", ports), "");
    }
}

//! What an unknown node name probably meant.

use super::{NodeType, Registry};

impl<C: 'static> Registry<C> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_names_get_a_suggestion() {
        let r = Registry::<()>::new();
        assert_eq!(r.closest("Sequense"), Some("Sequence"));
        assert_eq!(r.closest("Inverted"), Some("Inverter"));
        assert_eq!(r.closest("qqqqqqqqqqqqqqq"), None);
    }
}

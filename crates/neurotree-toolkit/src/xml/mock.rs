//! Mock nodes for dry runs: a node replaced by a leaf that plays a list of outcomes.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeKind, NodeStatus, Status};

/// Plays its outcomes in order, one per tick, then repeats the last one.
struct Mock {
    outcomes: Vec<Status>,
    next: usize,
}

impl<C> CustomNode<C> for Mock {
    fn tick(&mut self, _node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let at = self.next.min(self.outcomes.len().saturating_sub(1));
        self.next += 1;
        self.outcomes
            .get(at)
            .copied()
            .map_or(NodeStatus::Success, NodeStatus::from)
    }
}

/// A leaf kind playing `outcomes` (a fresh copy per tree instance).
pub(crate) fn mock_kind<C>(outcomes: &[Status]) -> NodeKind<C> {
    let outcomes = outcomes.to_vec();
    NodeKind::Custom(Box::new(CustomSpec {
        type_name: "Mock".into(),
        arity: Arity::Leaf,
        factory: Box::new(move || {
            Box::new(Mock {
                outcomes: outcomes.clone(),
                next: 0,
            })
        }),
    }))
}

/// Parses `SUCCESS,RUNNING*3,FAILURE`: a comma list of outcomes, each optionally `*k`.
pub fn parse_outcomes(text: &str) -> Result<Vec<Status>, String> {
    let mut out = Vec::new();
    for item in text.split(',') {
        let (word, times) = match item.split_once('*') {
            Some((w, k)) => (
                w.trim(),
                k.trim()
                    .parse::<usize>()
                    .map_err(|_| format!("`{item}`: the count after `*` must be a whole number"))?,
            ),
            None => (item.trim(), 1),
        };
        let status = word.parse::<Status>().map_err(|()| {
            format!("`{word}` is not an outcome; write SUCCESS, FAILURE or RUNNING")
        })?;
        out.extend(std::iter::repeat(status).take(times));
    }
    if out.is_empty() {
        return Err("a mock needs at least one outcome".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_parse_with_repeats() {
        assert_eq!(
            parse_outcomes("RUNNING*2,SUCCESS"),
            Ok(vec![Status::Running, Status::Running, Status::Success])
        );
        assert!(parse_outcomes("MAYBE").unwrap_err().contains("`MAYBE`"));
        assert!(parse_outcomes("SUCCESS*x").is_err());
        assert!(parse_outcomes("SUCCESS*0")
            .unwrap_err()
            .contains("at least one"));
    }
}

//! Mock nodes for dry runs: a node replaced by a leaf that plays a list of outcomes.
//!
//! The outcomes are kept as runs (an outcome and how many ticks it lasts) and played with
//! a cursor, so `RUNNING*4000000000` costs one run, not four billion entries.

use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeKind, NodeStatus, Status};

/// What a mock plays: runs of outcomes, each lasting a number of ticks, then the last
/// outcome forever. Made by [`parse_outcomes`], or from a list of outcomes one per tick.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Outcomes {
    /// `(outcome, ticks)`, every count at least 1.
    runs: Vec<(Status, u64)>,
}

impl Outcomes {
    /// The runs, in order: each outcome and the number of ticks it lasts.
    pub fn runs(&self) -> &[(Status, u64)] {
        &self.runs
    }

    /// Appends `count` ticks of `status` (nothing if `count` is 0).
    fn push(&mut self, status: Status, count: u64) {
        if count > 0 {
            self.runs.push((status, count));
        }
    }
}

impl From<Vec<Status>> for Outcomes {
    /// One tick per outcome, in order.
    fn from(outcomes: Vec<Status>) -> Self {
        let mut out = Outcomes::default();
        for status in outcomes {
            out.push(status, 1);
        }
        out
    }
}

/// Plays its runs in order, one tick at a time, then repeats the last outcome.
struct Mock {
    runs: Vec<(Status, u64)>,
    /// The run being played.
    run: usize,
    /// Ticks of that run played so far.
    played: u64,
}

impl<C> CustomNode<C> for Mock {
    // Its place in its outcomes: what a resumed run must go on from.
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.run, self.played)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        match neurotree_core::state::decode::<(usize, u64)>(state) {
            Some((run, played)) if run < self.runs.len().max(1) => {
                self.run = run;
                self.played = played;
                true
            }
            _ => false,
        }
    }

    fn tick(&mut self, _node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        let Some(&(status, count)) = self.runs.get(self.run) else {
            // No outcome at all (an empty list given to `XmlLoader::mock`).
            return NodeStatus::Success;
        };
        self.played += 1;
        // The last run is never left: its outcome repeats forever.
        if self.played >= count && self.run + 1 < self.runs.len() {
            self.run += 1;
            self.played = 0;
        }
        NodeStatus::from(status)
    }
}

/// A leaf kind playing `outcomes` (a fresh cursor per tree instance).
pub(crate) fn mock_kind<C>(outcomes: &Outcomes) -> NodeKind<C> {
    let runs = outcomes.runs.clone();
    NodeKind::Custom(Box::new(CustomSpec {
        type_name: "Mock".into(),
        arity: Arity::Leaf,
        factory: Box::new(move || {
            Box::new(Mock {
                runs: runs.clone(),
                run: 0,
                played: 0,
            })
        }),
    }))
}

/// Parses `SUCCESS,RUNNING*3,FAILURE`: a comma list of outcomes, each optionally `*k` with
/// `k` from 1 to `u64::MAX`.
pub fn parse_outcomes(text: &str) -> Result<Outcomes, String> {
    let mut out = Outcomes::default();
    for item in text.split(',') {
        let (word, times) = match item.split_once('*') {
            Some((w, k)) => (w.trim(), repeat_count(item, k.trim())?),
            None => (item.trim(), 1),
        };
        let status = word.parse::<Status>().map_err(|()| {
            format!("`{word}` is not an outcome; write SUCCESS, FAILURE or RUNNING")
        })?;
        out.push(status, times);
    }
    if out.runs.is_empty() {
        return Err("a mock needs at least one outcome".into());
    }
    Ok(out)
}

/// The `k` of `item` = `OUTCOME*k`.
fn repeat_count(item: &str, k: &str) -> Result<u64, String> {
    match k.parse::<u64>() {
        Ok(0) => Err(format!(
            "`{item}`: the count after `*` must be at least one"
        )),
        Ok(k) => Ok(k),
        Err(_) if !k.is_empty() && k.bytes().all(|c| c.is_ascii_digit()) => Err(format!(
            "`{item}`: the count after `*` must be at most {}",
            u64::MAX
        )),
        Err(_) => Err(format!(
            "`{item}`: the count after `*` must be a whole number"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree_core::{Blueprint, ManualClock, Tree};

    #[test]
    fn outcomes_parse_with_repeats() {
        assert_eq!(
            parse_outcomes("RUNNING*2,SUCCESS").map(|o| o.runs),
            Ok(vec![(Status::Running, 2), (Status::Success, 1)])
        );
        assert!(parse_outcomes("MAYBE").unwrap_err().contains("`MAYBE`"));
        assert!(parse_outcomes("SUCCESS*x").is_err());
        assert!(parse_outcomes("SUCCESS*0")
            .unwrap_err()
            .contains("at least one"));
    }

    /// A tree whose only node is a mock of `outcomes`, and the statuses of `ticks` ticks.
    fn play(outcomes: &Outcomes, ticks: usize) -> Vec<Status> {
        let bp = Blueprint::<()>::builder()
            .leaf(mock_kind(outcomes), "mock")
            .build_shared()
            .unwrap();
        let mut tree = Tree::with_clock(bp, ManualClock::new());
        (0..ticks)
            .map(|_| match tree.tick_exactly_once(&mut ()) {
                Ok(s) => s,
                Err(e) => panic!("a mock tick failed: {e}"),
            })
            .collect()
    }

    #[test]
    fn huge_counts_are_one_run_each_and_play_without_expanding() {
        use Status::*;
        let longest = parse_outcomes("RUNNING*18446744073709551615").unwrap();
        assert_eq!(longest.runs(), [(Running, u64::MAX)]);
        assert_eq!(play(&longest, 4), [Running; 4]);
        let long = parse_outcomes("RUNNING*4000000000,SUCCESS").unwrap();
        assert_eq!(long.runs(), [(Running, 4_000_000_000), (Success, 1)]);
        assert_eq!(play(&long, 3), [Running; 3]);
        let past = parse_outcomes("RUNNING*18446744073709551616").unwrap_err();
        assert_eq!(
            past,
            "`RUNNING*18446744073709551616`: the count after `*` must be at most 18446744073709551615"
        );
        assert_eq!(
            parse_outcomes("RUNNING*-1").unwrap_err(),
            "`RUNNING*-1`: the count after `*` must be a whole number"
        );
    }

    #[test]
    fn runs_play_in_order_then_the_last_outcome_repeats() {
        use Status::*;
        let outcomes = parse_outcomes("RUNNING*2,FAILURE,SUCCESS*2").unwrap();
        assert_eq!(
            play(&outcomes, 7),
            [Running, Running, Failure, Success, Success, Success, Success]
        );
        // A list given outcome by outcome plays the same.
        let listed = Outcomes::from(vec![Running, Running, Failure, Success, Success]);
        assert_eq!(play(&listed, 7), play(&outcomes, 7));
        assert_eq!(play(&Outcomes::default(), 2), [Success, Success]);
    }
}

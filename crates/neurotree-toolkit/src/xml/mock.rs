//! Mock nodes for dry runs: a node replaced by a leaf that plays a list of outcomes, and
//! writes outputs as it goes.
//!
//! The outcomes are kept as runs (an outcome and how many ticks it lasts) and played with
//! a cursor, so `RUNNING*4000000000` costs one run, not four billion entries.

use std::time::Duration;

use neurotree_core::{
    Arity, Blackboard, CustomNode, CustomSpec, NodeCtx, NodeKind, NodeStatus, Port, PortValue,
    ScopeId, Status,
};

use crate::script::Value;

/// What a mock plays: runs of outcomes, each lasting a number of ticks, then the last
/// outcome forever, and the outputs it writes at every tick. Made by [`parse_outcomes`],
/// or from a list of outcomes one per tick.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Outcomes {
    /// `(outcome, ticks)`, every count at least 1.
    runs: Vec<(Status, u64)>,
    /// Written at every tick, in order.
    outputs: Vec<MockOutput>,
}

/// A value a mock writes to one of its ports at every tick: `out=3` or `out:i32=3`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MockOutput {
    /// The port: the entry the node's attribute of that name binds (`out="{goal}"`), or,
    /// if the node has no such attribute, the entry named like the port.
    pub port: String,
    /// The type to store, if declared; otherwise the text is stored as a script literal
    /// would be (integer, else real, else `true`/`false`, else text), converted to the
    /// type of an entry that exists.
    pub declared: Option<OutputType>,
    /// The value, as written.
    pub text: String,
}

/// The types a mock's output may be declared as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputType {
    /// `i64` (also written `int`).
    I64,
    /// `i32`.
    I32,
    /// `u32`.
    U32,
    /// `u64`.
    U64,
    /// `f64` (also `double`, `real`).
    F64,
    /// `f32` (also `float`).
    F32,
    /// `bool`.
    Bool,
    /// `String` (also `string`, `str`).
    String,
}

impl OutputType {
    /// The type named `name`, as `--mock` and port models write it.
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "i64" | "int" | "int64_t" | "long" => OutputType::I64,
            "i32" | "int32_t" => OutputType::I32,
            "u32" | "uint32_t" | "unsigned" => OutputType::U32,
            "u64" | "uint64_t" => OutputType::U64,
            "f64" | "double" | "real" => OutputType::F64,
            "f32" | "float" => OutputType::F32,
            "bool" => OutputType::Bool,
            "string" | "String" | "str" | "std::string" => OutputType::String,
            _ => return None,
        })
    }

    /// Stores `text` read as this type at `key` from `scope`.
    fn store(
        self,
        bb: &mut Blackboard,
        scope: ScopeId,
        key: &str,
        text: &str,
        now: Duration,
    ) -> Result<(), String> {
        fn num<T: std::str::FromStr>(text: &str, ty: &str) -> Result<T, String> {
            text.trim()
                .parse()
                .map_err(|_| format!("cannot read `{text}` as {ty}"))
        }
        let stored = match self {
            OutputType::I64 => bb.set_in(scope, key, num::<i64>(text, "i64")?, now),
            OutputType::I32 => bb.set_in(scope, key, num::<i32>(text, "i32")?, now),
            OutputType::U32 => bb.set_in(scope, key, num::<u32>(text, "u32")?, now),
            OutputType::U64 => bb.set_in(scope, key, num::<u64>(text, "u64")?, now),
            OutputType::F64 => bb.set_in(scope, key, num::<f64>(text, "f64")?, now),
            OutputType::F32 => bb.set_in(scope, key, num::<f32>(text, "f32")?, now),
            OutputType::Bool => bb.set_in(scope, key, num::<bool>(text, "bool")?, now),
            OutputType::String => bb.set_in(scope, key, text.to_string(), now),
        };
        stored.map_err(|e| e.to_string())
    }

    /// Every type name [`parse`](Self::parse) reads, for messages.
    pub const NAMES: &'static str = "i64, i32, u32, u64, f64, f32, bool, string";
}

impl MockOutput {
    /// Writes the value to the port of the node being ticked.
    fn write<C>(&self, node: &mut NodeCtx<'_, '_, C>) -> Result<(), String> {
        let key = match node.ports().iter().find(|p| p.name == self.port) {
            Some(Port {
                value: PortValue::Entry(key),
                ..
            }) => key.clone(),
            Some(_) => {
                return Err(format!(
                    "the mock's output port `{}` is given a literal, not an entry like {{key}}",
                    self.port
                ))
            }
            None => self.port.clone(),
        };
        let (scope, now) = (node.scope(), node.now());
        let bb = node.blackboard();
        match self.declared {
            Some(ty) => ty.store(bb, scope, &key, &self.text, now),
            None => literal(&self.text)
                .store(bb, scope, &key, now)
                .map(drop)
                .map_err(|e| e.to_string()),
        }
    }
}

/// `text` as a script literal: integer, else real, else `true`/`false`, else text.
fn literal(text: &str) -> Value {
    if let Ok(i) = text.parse::<i64>() {
        Value::Int(i)
    } else if let Ok(f) = text.parse::<f64>() {
        Value::Real(f)
    } else if let Ok(b) = text.parse::<bool>() {
        Value::Bool(b)
    } else {
        Value::Str(text.to_string())
    }
}

impl Outcomes {
    /// The runs, in order: each outcome and the number of ticks it lasts.
    pub fn runs(&self) -> &[(Status, u64)] {
        &self.runs
    }

    /// The outputs written at every tick, in order.
    pub fn outputs(&self) -> &[MockOutput] {
        &self.outputs
    }

    /// Adds an output written at every tick (see [`MockOutput`]).
    pub fn with_output(mut self, output: MockOutput) -> Self {
        self.outputs.push(output);
        self
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
    outputs: Vec<MockOutput>,
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

    /// A mock given other outcomes than the saved one's (a fork of a run) plays on from the
    /// same place, as far as its outcomes go: past their end, from its last one.
    fn restore_state(&mut self, state: &[u8]) -> bool {
        let Some((run, played)) = neurotree_core::state::decode::<(usize, u64)>(state) else {
            return false;
        };
        let last = self.runs.len().saturating_sub(1);
        (self.run, self.played) = if run <= last {
            (run, played)
        } else {
            (last, 0)
        };
        true
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        for output in &self.outputs {
            if let Err(e) = output.write(node) {
                node.fail(format!("mock output `{}`: {e}", output.port));
                return NodeStatus::Failure;
            }
        }
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
    let outputs = outcomes.outputs.clone();
    NodeKind::Custom(Box::new(CustomSpec::new(
        "Mock",
        Arity::Leaf,
        Box::new(move || {
            Box::new(Mock {
                runs: runs.clone(),
                outputs: outputs.clone(),
                run: 0,
                played: 0,
            })
        }),
    )))
}

/// The ports a mock of `outcomes` writes, bound as the node's attributes `attr` bind them
/// (`{key}`, `{=}`, or a literal), or, without an attribute, to the entry of the same name.
pub(crate) fn output_ports(
    outcomes: &Outcomes,
    attr: impl Fn(&str) -> Option<PortValue>,
) -> Vec<Port> {
    outcomes
        .outputs
        .iter()
        .map(|o| Port {
            name: o.port.clone(),
            value: attr(&o.port).unwrap_or_else(|| PortValue::Entry(o.port.clone())),
            declared: neurotree_core::PortType::ANY,
        })
        .collect()
}

/// Parses `SUCCESS,RUNNING*3,FAILURE`: a comma list of outcomes, each optionally `*k` with
/// `k` from 1 to `u64::MAX`; then, after `;`, outputs to write at every tick:
/// `SUCCESS;pose=3;mode:string=dock` (`PORT=VALUE` or `PORT:TYPE=VALUE`, see
/// [`MockOutput`] and [`OutputType`]).
pub fn parse_outcomes(text: &str) -> Result<Outcomes, String> {
    let mut clauses = text.split(';');
    let mut out = parse_runs(clauses.next().unwrap_or(""))?;
    for clause in clauses.filter(|c| !c.trim().is_empty()) {
        let Some((port, value)) = clause.split_once('=') else {
            return Err(format!(
                "`{clause}` should be PORT=VALUE or PORT:TYPE=VALUE (an output to write)"
            ));
        };
        let (port, declared) = match port.split_once(':') {
            Some((port, ty)) => {
                let ty = OutputType::parse(ty.trim()).ok_or_else(|| {
                    format!(
                        "`{clause}`: unknown type `{}`; write one of {}",
                        ty.trim(),
                        OutputType::NAMES
                    )
                })?;
                (port, Some(ty))
            }
            None => (port, None),
        };
        let port = port.trim();
        if port.is_empty() {
            return Err(format!(
                "`{clause}`: the output needs a port name before `=`"
            ));
        }
        if let Some(ty) = declared {
            // Checked now, so a value that cannot be stored is a mistake in the command.
            let mut bb = Blackboard::new();
            ty.store(&mut bb, ScopeId::ROOT, port, value, Duration::ZERO)
                .map_err(|e| format!("`{clause}`: {e}"))?;
        }
        out.outputs.push(MockOutput {
            port: port.to_string(),
            declared,
            text: value.to_string(),
        });
    }
    Ok(out)
}

/// The outcomes before any `;`.
fn parse_runs(text: &str) -> Result<Outcomes, String> {
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
    fn outputs_parse_after_the_outcomes() {
        let o = parse_outcomes("SUCCESS*2,FAILURE;out=3;mode:string=dock").unwrap();
        assert_eq!(o.runs(), [(Status::Success, 2), (Status::Failure, 1)]);
        assert_eq!(o.outputs().len(), 2);
        assert_eq!(o.outputs()[0].declared, None);
        assert_eq!(o.outputs()[1].declared, Some(OutputType::String));
        assert_eq!(o.outputs()[1].text, "dock");
        assert!(parse_outcomes("SUCCESS;out")
            .unwrap_err()
            .contains("PORT=VALUE"));
        assert!(parse_outcomes("SUCCESS;out:pose=1")
            .unwrap_err()
            .contains("unknown type `pose`"));
        assert_eq!(
            parse_outcomes("SUCCESS;n:i32=x").unwrap_err(),
            "`n:i32=x`: cannot read `x` as i32"
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

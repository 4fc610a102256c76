//! A campaign file, as read: the tree, how variants are made, and each factor's values.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde_json::{json, Value};
use toml::Spanned;

/// The factors, in the order a grid varies them (the last fastest) and a sample draws them.
pub const FACTORS: [&str; 6] = [
    "goal",
    "seed",
    "heading",
    "battery",
    "no_obstacle",
    "faults",
];

/// The calls `faults = "each-single"` faults, when `[each_single]` does not say.
pub const DEFAULT_CALLS: u32 = 3;

/// The file as TOML gives it.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCampaign {
    pub name: Option<String>,
    #[allow(dead_code)]
    pub description: Option<String>,
    pub tree: Option<String>,
    pub seed: Option<u64>,
    pub grid: Option<Spanned<bool>>,
    pub sample: Option<Spanned<u64>>,
    pub max_ticks: Option<u32>,
    #[serde(default)]
    pub factors: BTreeMap<Spanned<String>, Spanned<RawFactor>>,
    pub each_single: Option<EachSingle>,
}

/// `[each_single]`: how far `faults = "each-single"` goes.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct EachSingle {
    pub calls: Option<u32>,
}

/// A factor's values as written.
#[derive(Deserialize, Debug)]
#[serde(untagged)]
pub(super) enum RawFactor {
    List(Vec<toml::Value>),
    Range {
        from: f64,
        to: f64,
        step: Option<f64>,
    },
    Uniform {
        uniform: [f64; 2],
    },
    Normal {
        normal: [f64; 2],
    },
    Word(String),
}

/// A factor's values: a list, or a distribution a sample draws from.
#[derive(Clone, Debug, PartialEq)]
pub enum Domain {
    /// These values.
    Values(Vec<Value>),
    /// Uniform between the two bounds.
    Uniform(f64, f64),
    /// Normal, of this mean and standard deviation.
    Normal(f64, f64),
    /// Every single fault of the tree's actions at every call up to this one, and none.
    EachSingle(u32),
}

/// The error for `text` of `file` at byte `at`: `file:line:col: error: message`.
pub(super) fn located(file: &Path, text: &str, at: Option<usize>, message: &str) -> String {
    let place = at
        .map(|at| {
            let before = &text[..at.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("{line}:{col}: ")
        })
        .unwrap_or_default();
    format!(
        "{}:{place}error: {message}; see `neurotree campaign run --help` for the campaign format",
        file.display()
    )
}

/// What [`super::Campaign::parse`] makes of the file's factors and settings.
pub(super) struct Parsed {
    pub name: String,
    pub tree: Option<PathBuf>,
    pub seed: u64,
    pub sample: Option<u64>,
    pub max_ticks: u32,
    pub factors: Vec<(String, Domain)>,
}

/// Reads the TOML, checking every factor's values; errors name line and column.
pub(super) fn parse(text: &str, file: &Path) -> Result<Parsed, String> {
    let raw: RawCampaign = toml::from_str(text)
        .map_err(|e| located(file, text, e.span().map(|s| s.start), e.message()))?;
    let at = |span: std::ops::Range<usize>, message: &str| {
        located(file, text, Some(span.start), message)
    };
    let grid = raw.grid.as_ref().is_some_and(|g| *g.get_ref());
    let sample = match (&raw.sample, grid) {
        (Some(s), true) => {
            return Err(at(
                s.span(),
                "`grid = true` and `sample` exclude each other: keep one",
            ))
        }
        (Some(s), false) if *s.get_ref() == 0 => {
            return Err(at(s.span(), "`sample` should be 1 or more"))
        }
        (Some(s), false) => Some(*s.get_ref()),
        (None, true) => None,
        (None, false) => {
            return Err(located(
                file,
                text,
                None,
                "say how variants are made: `grid = true` (every combination) or `sample = N`",
            ))
        }
    };
    let calls = raw
        .each_single
        .as_ref()
        .and_then(|e| e.calls)
        .unwrap_or(DEFAULT_CALLS);
    let mut factors = Vec::new();
    for name in FACTORS {
        let Some((key, spec)) = raw.factors.iter().find(|(k, _)| k.get_ref() == name) else {
            continue;
        };
        let domain = domain(name, spec.get_ref(), calls).map_err(|m| at(spec.span(), &m))?;
        if sample.is_none() && matches!(domain, Domain::Uniform(..) | Domain::Normal(..)) {
            return Err(at(
                key.span(),
                &format!(
                    "`{name}` is a distribution: a grid needs a list or a range; use `sample = N`"
                ),
            ));
        }
        factors.push((name.to_string(), domain));
    }
    if let Some((key, _)) = raw
        .factors
        .iter()
        .find(|(k, _)| !FACTORS.contains(&k.get_ref().as_str()))
    {
        return Err(at(
            key.span(),
            &format!(
                "unknown factor `{}`; the factors are {}",
                key.get_ref(),
                FACTORS.join(", ")
            ),
        ));
    }
    let name = raw.name.clone().unwrap_or_else(|| {
        file.file_stem()
            .map_or("campaign".into(), |s| s.to_string_lossy().into_owned())
    });
    Ok(Parsed {
        name,
        tree: raw.tree.as_ref().map(PathBuf::from),
        seed: raw.seed.unwrap_or(0),
        sample,
        max_ticks: raw.max_ticks.unwrap_or(3000),
        factors,
    })
}

/// The domain of factor `name` from what the file wrote, its values checked.
fn domain(name: &str, raw: &RawFactor, calls: u32) -> Result<Domain, String> {
    let numeric = matches!(name, "heading" | "battery");
    match raw {
        RawFactor::Word(word) if name == "faults" && word == "each-single" => {
            if calls == 0 {
                return Err("`[each_single] calls` should be 1 or more".into());
            }
            Ok(Domain::EachSingle(calls))
        }
        RawFactor::Word(word) if name == "faults" => Err(format!(
            "`{word}`: `faults` is \"each-single\" or a list of faults"
        )),
        RawFactor::Word(_) => Err(format!("`{name}` should be a list of values or a range")),
        RawFactor::List(values) => {
            if values.is_empty() {
                return Err(format!("`{name}` has no values"));
            }
            values
                .iter()
                .map(|v| value(name, v))
                .collect::<Result<_, _>>()
                .map(Domain::Values)
        }
        RawFactor::Range { from, to, step } => {
            let step = step.unwrap_or(1.0);
            if !(step > 0.0 && step.is_finite() && from.is_finite() && to.is_finite()) || to < from
            {
                return Err("a range goes `from` up `to` by a `step` above 0".into());
            }
            let count = ((to - from) / step + 1e-9).floor() as u64 + 1;
            if count > 1_000_000 {
                return Err(format!("the range has {count} values; at most 1000000"));
            }
            let values = (0..count).map(|i| from + i as f64 * step);
            match name {
                "seed" => values
                    .map(|v| {
                        (v >= 0.0 && v.fract() == 0.0)
                            .then(|| json!(v as u64))
                            .ok_or_else(|| {
                                "a seed range holds whole numbers of 0 or more".to_string()
                            })
                    })
                    .collect::<Result<_, _>>()
                    .map(Domain::Values),
                _ if numeric => values
                    .map(|v| number(name, round(v)))
                    .collect::<Result<_, _>>()
                    .map(Domain::Values),
                _ => Err(format!("`{name}` cannot be a range: list its values")),
            }
        }
        RawFactor::Uniform { uniform: [a, b] } if numeric && a <= b => {
            number(name, *a)?;
            number(name, *b)?;
            Ok(Domain::Uniform(*a, *b))
        }
        RawFactor::Normal { normal: [mean, sd] } if numeric && *sd >= 0.0 => {
            Ok(Domain::Normal(*mean, *sd))
        }
        RawFactor::Uniform { .. } | RawFactor::Normal { .. } if numeric => Err(
            "`uniform = [LOW, HIGH]` with LOW <= HIGH; `normal = [MEAN, SD]` with SD >= 0".into(),
        ),
        _ => Err(format!(
            "`{name}` cannot be drawn from a distribution: list its values"
        )),
    }
}

/// Three decimals: values a person reads back from the results.
pub(super) fn round(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// A numeric factor's value, checked.
fn number(name: &str, v: f64) -> Result<Value, String> {
    match name {
        "battery" if !(0.0..=100.0).contains(&v) => {
            Err(format!("a battery level is 0 to 100 percent, not {v}"))
        }
        _ if !v.is_finite() => Err(format!("`{name}` should be a finite number")),
        _ => Ok(json!(v)),
    }
}

/// One listed value of factor `name`, as the results store it.
fn value(name: &str, v: &toml::Value) -> Result<Value, String> {
    let float = v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
    match name {
        "goal" => {
            let pair: Option<(f64, f64)> = match v {
                toml::Value::String(s) => s
                    .split_once(',')
                    .and_then(|(x, y)| Some((x.trim().parse().ok()?, y.trim().parse().ok()?))),
                toml::Value::Array(a) if a.len() == 2 => {
                    let n =
                        |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
                    n(&a[0]).zip(n(&a[1]))
                }
                _ => None,
            };
            match pair {
                Some((x, y)) if x.is_finite() && y.is_finite() => Ok(json!([x, y])),
                _ => Err(format!("a goal is \"X,Y\" or [X, Y] in metres, not {v}")),
            }
        }
        "seed" => v
            .as_integer()
            .filter(|i| *i >= 0)
            .map(|i| json!(i))
            .ok_or_else(|| format!("a seed is a whole number of 0 or more, not {v}")),
        "heading" | "battery" => match float {
            Some(f) => number(name, f),
            None => Err(format!("`{name}` values are numbers, not {v}")),
        },
        "no_obstacle" => v
            .as_bool()
            .map(|b| json!(b))
            .ok_or_else(|| format!("`no_obstacle` values are true or false, not {v}")),
        _ => {
            let text = v
                .as_str()
                .ok_or_else(|| format!("a fault is written as a string, not {v}"))?;
            super::faults::Faults::parse(text)?;
            Ok(json!(text))
        }
    }
}

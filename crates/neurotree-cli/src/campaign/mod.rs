//! Robustness campaigns: one tree through many worlds and faults, each variant a
//! deterministic run of the demo's warehouse ([`crate::demo`]), every result a row of a
//! SQLite file ([`Results`]).
//!
//! A campaign file (TOML) names the tree (Nav2's navigator when it does not), how variants
//! are made, and the factors:
//!
//! ```toml
//! name = "goals and seeds"
//! tree = "my_navigator.xml"       # optional, relative to the file
//! seed = 7                         # draws of a sample (default 0)
//! grid = true                      # every combination; or `sample = 300`: 300 draws
//! max_ticks = 3000                 # a run still going then is RUNNING
//! [factors]
//! goal = ["36.5,1.5", [20.5, 6.5]] # a list of values
//! seed = { from = 0, to = 29 }     # a range, `step` 1 unless given
//! heading = { uniform = [-180, 180] }  # a distribution (sample only); also `normal = [M, SD]`
//! battery = [100, 50]
//! no_obstacle = [false, true]
//! faults = ["none", "ComputePathToPose=FAILURE@3#106", "FollowPath*2",
//!           "ClearEntireCostmap=RUNNING@1", "battery=10%@30s"]
//! # faults = "each-single": none, then every action node failing at every call up to 3
//! [each_single]
//! calls = 3
//! ```
//!
//! Variant `n` (from 1) of a grid is the `n`th combination, the last factor varying
//! fastest; of a sample, one draw of each factor from a generator seeded with the
//! campaign's seed and `n` alone. So a variant's run depends on the file and its number
//! only: the same on any machine, in any order, on any number of threads.
//!
//! ```
//! use neurotree_cli::campaign::Campaign;
//!
//! let campaign = Campaign::parse(
//!     "grid = true\n[factors]\nseed = [0, 1]\nno_obstacle = [true]\n",
//!     std::path::Path::new("two.toml"),
//! )
//! .unwrap();
//! assert_eq!(campaign.variants(), 2);
//! let row = campaign.run_variant(2);
//! assert_eq!(row.factors["seed"], 1);
//! assert_eq!(row.outcome, "SUCCESS");
//! assert_eq!(campaign.run_variant(2), row);
//! ```

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Duration;

use neurotree::observe::Coverage;
use neurotree::robotics::Pose2D;
use neurotree::Status;
use serde_json::{json, Map, Value};

use crate::demo::{DemoConfig, DemoRun, DemoSummary};

mod db;
mod faults;
mod file;
mod report;
mod scenario;

pub use db::{merge, Results};
pub use faults::Faults;
pub use file::{Domain, FACTORS};
pub use report::{report_json, report_markdown, report_svg};
pub use scenario::{variant_scenario, VariantScenario};

/// A campaign, read and checked.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// Its name (the file's stem unless it says).
    pub name: String,
    /// The file's text, which the results keep to replay a variant.
    pub text: String,
    /// Where the file is: a tree is relative to its folder.
    pub file: PathBuf,
    tree: Option<PathBuf>,
    seed: u64,
    sample: Option<u64>,
    max_ticks: u32,
    /// Each factor's values, in [`FACTORS`] order, "each-single" worked out.
    factors: Vec<(String, Vec<Value>, Domain)>,
}

/// How a variant went: one row of the results.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantRow {
    /// Its number, from 1.
    pub variant: u64,
    /// The value of each factor the file gives.
    pub factors: Value,
    /// SUCCESS, FAILURE, RUNNING (stopped at `max_ticks`), or `error: ...`.
    pub outcome: String,
    /// Ticks of the tree.
    pub ticks: u32,
    /// Simulated seconds.
    pub seconds: f64,
    /// Metres driven.
    pub distance: f64,
    /// Runs of the recovery branches.
    pub recoveries: u32,
    /// Why the root failed ([`crate::failure::failure_json`]), when it did.
    pub failure_chain: Option<Value>,
    /// The first nonzero Nav2 error code the tree holds at the end, by entry name.
    pub error_code: Option<u16>,
    /// Nodes the run reached.
    pub nodes_covered: u32,
}

impl Campaign {
    /// Reads the campaign file at `path`; errors read `file:line:col: error: ...`.
    pub fn load(path: &Path) -> Result<Campaign, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read the campaign: {e}", path.display()))?;
        Self::parse(&text, path)
    }

    /// Reads `text`, the campaign file `file`.
    pub fn parse(text: &str, file: &Path) -> Result<Campaign, String> {
        let parsed = file::parse(text, file)?;
        let mut campaign = Campaign {
            name: parsed.name,
            text: text.to_string(),
            file: file.to_path_buf(),
            tree: parsed.tree,
            seed: parsed.seed,
            sample: parsed.sample,
            max_ticks: parsed.max_ticks,
            factors: Vec::new(),
        };
        for (name, domain) in parsed.factors {
            let values = match &domain {
                Domain::Values(values) => values.clone(),
                Domain::EachSingle(calls) => campaign
                    .each_single(*calls)
                    .map_err(|e| file::located(file, text, None, &e))?,
                Domain::Uniform(..) | Domain::Normal(..) => Vec::new(),
            };
            campaign.factors.push((name, values, domain));
        }
        Ok(campaign)
    }

    /// The tree file, relative to the campaign's folder; `None` for Nav2's navigator.
    pub fn tree_path(&self) -> Option<PathBuf> {
        let dir = self.file.parent().unwrap_or(Path::new(""));
        self.tree.as_ref().map(|t| dir.join(t))
    }

    /// `none`, then every action node of the tree failing at each call from 1 to `calls`.
    fn each_single(&self, calls: u32) -> Result<Vec<Value>, String> {
        let demo = DemoRun::new(&self.config_base()).map_err(|e| e.to_string())?;
        let mut values = vec![json!("none")];
        let blueprint = std::sync::Arc::clone(demo.blueprint());
        for path in neurotree::fault::action_paths(&blueprint) {
            for call in 1..=calls {
                values.push(json!(format!("{path}=FAILURE@{call}")));
            }
        }
        Ok(values)
    }

    /// How many variants the campaign has.
    pub fn variants(&self) -> u64 {
        match self.sample {
            Some(n) => n,
            None => self
                .factors
                .iter()
                .map(|(_, values, _)| values.len() as u64)
                .product(),
        }
    }

    /// The factors of variant `n` (from 1), by name.
    pub fn factors_of(&self, n: u64) -> Map<String, Value> {
        let mut out = Map::new();
        match self.sample {
            None => {
                let mut rest = n.saturating_sub(1);
                let mut picks = Vec::new();
                for (_, values, _) in self.factors.iter().rev() {
                    let len = values.len() as u64;
                    picks.push((rest % len) as usize);
                    rest /= len;
                }
                picks.reverse();
                for ((name, values, _), pick) in self.factors.iter().zip(picks) {
                    out.insert(name.clone(), values[pick].clone());
                }
            }
            Some(_) => {
                // One generator per variant, seeded by the campaign and the number alone.
                let mut rng = fastrand::Rng::with_seed(
                    self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ n.rotate_left(32) ^ n,
                );
                for (name, values, domain) in &self.factors {
                    let value = match domain {
                        Domain::Uniform(a, b) => json!(file::round(a + (b - a) * rng.f64())),
                        Domain::Normal(mean, sd) => {
                            // Box-Muller; 1 - f64() is in (0, 1], so the logarithm is finite.
                            let (u, v) = (1.0 - rng.f64(), rng.f64());
                            let z = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
                            let drawn = mean + sd * z;
                            let drawn = if name == "battery" {
                                drawn.clamp(0.0, 100.0)
                            } else {
                                drawn
                            };
                            json!(file::round(drawn))
                        }
                        _ => values[rng.usize(..values.len())].clone(),
                    };
                    out.insert(name.clone(), value);
                }
            }
        }
        out
    }

    /// The run's configuration before any factor.
    fn config_base(&self) -> DemoConfig {
        DemoConfig {
            tree: self.tree_path(),
            max_ticks: self.max_ticks,
            ..DemoConfig::default()
        }
    }

    /// The run's configuration of variant `n`.
    pub fn config_of(&self, n: u64) -> Result<DemoConfig, String> {
        let mut config = self.config_base();
        for (name, value) in self.factors_of(n) {
            match name.as_str() {
                "goal" => {
                    let (x, y) = (value[0].as_f64(), value[1].as_f64());
                    let (Some(x), Some(y)) = (x, y) else {
                        return Err(format!("variant {n}: a goal is [X, Y], not {value}"));
                    };
                    config.goal = Pose2D::new(x, y, 0.0);
                }
                "seed" => config.seed = value.as_u64().unwrap_or_default(),
                "heading" => config.start_heading = value.as_f64().unwrap_or_default().to_radians(),
                "battery" => config.battery = value.as_f64().unwrap_or(100.0),
                "no_obstacle" => config.obstacle = !value.as_bool().unwrap_or(false),
                _ => Faults::parse(value.as_str().unwrap_or("none"))?.apply(&mut config),
            }
        }
        Ok(config)
    }

    /// Runs variant `n`: its row. A panic in the run is the row's outcome, not the
    /// caller's.
    pub fn run_variant(&self, n: u64) -> VariantRow {
        self.run_variant_watched(n, &mut |_| {})
    }

    /// [`run_variant`](Self::run_variant), with `watch` shown the run after each tick.
    ///
    /// A panic in the run (a `PANIC@K` fault) prints nothing: its message is the row's
    /// outcome. Panics elsewhere, and on other threads, print as before.
    pub fn run_variant_watched(&self, n: u64, watch: &mut dyn FnMut(&DemoRun)) -> VariantRow {
        quietly(|| self.run_variant_quietly(n, watch))
    }

    fn run_variant_quietly(&self, n: u64, watch: &mut dyn FnMut(&DemoRun)) -> VariantRow {
        let factors = Value::Object(self.factors_of(n));
        let errored = |message: String| VariantRow {
            variant: n,
            factors: factors.clone(),
            outcome: format!("error: {message}"),
            ticks: 0,
            seconds: 0.0,
            distance: 0.0,
            recoveries: 0,
            failure_chain: None,
            error_code: None,
            nodes_covered: 0,
        };
        let config = match self.config_of(n) {
            Ok(config) => config,
            Err(e) => return errored(e),
        };
        let ran = catch_unwind(AssertUnwindSafe(|| run(&config, watch)));
        match ran {
            Ok(Ok((summary, chain, covered))) => VariantRow {
                variant: n,
                factors: factors.clone(),
                outcome: outcome(&summary),
                ticks: summary.ticks,
                seconds: summary.time.as_secs_f64(),
                distance: file::round(summary.distance),
                recoveries: summary.recoveries,
                failure_chain: chain,
                error_code: summary.error_codes.first().map(|(_, code, _)| *code),
                nodes_covered: covered,
            },
            Ok(Err(e)) => errored(e),
            Err(panic) => {
                let message = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic".into());
                errored(format!("panicked: {message}"))
            }
        }
    }
}

thread_local! {
    /// Whether this thread runs a variant, whose panics are its row's outcome.
    static IN_VARIANT: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f` with the panics on this thread kept quiet: the panic hook (the one set before,
/// which prints the message) is not called for them. A campaign of ten thousand variants
/// with a `PANIC@K` fault would otherwise print a message per variant.
pub(crate) fn quietly<T>(f: impl FnOnce() -> T) -> T {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let before = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !IN_VARIANT.with(std::cell::Cell::get) {
                before(info);
            }
        }));
    });
    /// Restores the flag however `f` ends.
    struct Restore(bool);
    impl Drop for Restore {
        fn drop(&mut self) {
            IN_VARIANT.with(|v| v.set(self.0));
        }
    }
    let _restore = Restore(IN_VARIANT.with(|v| v.replace(true)));
    f()
}

/// The outcome a row stores.
fn outcome(summary: &DemoSummary) -> String {
    match (&summary.error, summary.outcome) {
        (Some(error), _) => format!("error: {error}"),
        (None, Status::Success) => "SUCCESS".into(),
        (None, Status::Failure) => "FAILURE".into(),
        (None, Status::Running) => "RUNNING".into(),
    }
}

/// Runs `config` to its end: the summary, the failure chain, the nodes reached.
fn run(
    config: &DemoConfig,
    watch: &mut dyn FnMut(&DemoRun),
) -> Result<(DemoSummary, Option<Value>, u32), String> {
    let mut demo = DemoRun::new(config).map_err(|e| e.to_string())?;
    let coverage = Coverage::new(demo.blueprint());
    demo.add_observer(Box::new(coverage.clone()));
    while !demo.is_over() {
        demo.tick();
        watch(&demo);
    }
    let summary = demo.summary();
    let chain = demo
        .tree_mut()
        .last_failure()
        .map(|f| crate::failure::failure_json(&f));
    let report = coverage.report(demo.blueprint());
    let covered = report.nodes().iter().filter(|n| n.reached).count() as u32;
    Ok((summary, chain, covered))
}

impl Campaign {
    /// The variants of `selected` that `results` does not hold yet; an error if it holds
    /// some and `resume` is false (a run never records a variant twice).
    pub fn todo(
        &self,
        results: &Results,
        selected: Vec<u64>,
        resume: bool,
    ) -> Result<(Vec<u64>, usize), String> {
        results.claim(self)?;
        let done = results.done()?;
        let already = selected.iter().filter(|v| done.contains(v)).count();
        if already > 0 && !resume {
            return Err(format!(
                "the results already hold {already} of these variants: `--resume` runs the \
                 missing ones, or give another results file"
            ));
        }
        Ok((
            selected.into_iter().filter(|v| !done.contains(v)).collect(),
            already,
        ))
    }

    /// Runs `variants` on `threads` threads (0: `RAYON_NUM_THREADS`, or every core),
    /// writing each row into `results` as it finishes, in the order they finish, and
    /// showing it to `on_row`. Stops at the first row the file refuses.
    pub fn run_into(
        &self,
        results: &Results,
        variants: &[u64],
        threads: usize,
        on_row: &mut dyn FnMut(&VariantRow),
    ) -> Result<(), String> {
        use rayon::prelude::*;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| format!("{threads} threads: {e}"))?;
        let (send, receive) = std::sync::mpsc::channel::<VariantRow>();
        let mut failed = None;
        std::thread::scope(|scope| {
            scope.spawn(move || {
                pool.install(|| {
                    variants.par_iter().for_each_with(send, |send, &v| {
                        // The receiver is gone only after a refused row: stop quietly.
                        let _ = send.send(self.run_variant(v));
                    });
                });
            });
            for row in receive {
                if let Err(e) = results.insert(&row) {
                    failed = Some(e);
                    break;
                }
                on_row(&row);
            }
        });
        failed.map_or(Ok(()), Err)
    }
}

/// The variants of `1..=total` after `limit`, of shard `index` of `shards` (from 1): every
/// `shards`th from the `index`th.
pub fn selection(total: u64, limit: Option<u64>, shard: Option<(u64, u64)>) -> Vec<u64> {
    let last = limit.map_or(total, |l| l.min(total));
    let (index, count) = shard.unwrap_or((1, 1));
    (1..=last)
        .filter(|v| (v - 1) % count == index - 1)
        .collect()
}

/// A simulated time, for messages.
pub fn seconds(d: Duration) -> String {
    format!("{:.1} s", d.as_secs_f64())
}

/// The factors of a row as `name=value` pairs, in the row's order.
pub fn describe(factors: &Value) -> String {
    factors
        .as_object()
        .map(|m| {
            m.iter()
                .map(|(k, v)| match v {
                    Value::String(s) => format!("{k}={s}"),
                    other => format!("{k}={other}"),
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_default()
}

/// Results grouped by a key, in key order: used by the report.
pub(crate) type Groups<'a> = BTreeMap<String, Vec<&'a VariantRow>>;

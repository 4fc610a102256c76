//! `neurotree campaign`: run a tree through the variants of a campaign file on every core,
//! each result a row of a SQLite file; report on the results, replay a variant, merge the
//! results of shards. The library's [`neurotree_cli::campaign`] does the work.

use std::io::{self, IsTerminal, Write};
use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};
use neurotree_cli::campaign::{self, Campaign, Results, VariantRow};

use crate::Outcome;

/// What `neurotree campaign run --help` says after the options: the campaign format.
const RUN_AFTER_HELP: &str = r#"A campaign is a TOML file:

  name = "goals and seeds"         # optional; default: the file's stem
  tree = "navigator.xml"           # optional, relative to the file; default: Nav2's navigator
  seed = 7                         # what a sample draws with (default 0)
  grid = true                      # every combination; or `sample = N`: N draws
  max_ticks = 3000                 # a run still going then is RUNNING
  [factors]
  goal = ["36.5,1.5", [20.5, 6.5]] # a list of values
  seed = { from = 0, to = 29 }     # a range (`step` 1 unless given)
  heading = { uniform = [-180, 180] }  # a distribution (sample only); also normal = [M, SD]
  battery = [100, 50]              # percent at the start
  no_obstacle = [false, true]
  faults = ["none", "ComputePathToPose=FAILURE@3#106", "FollowPath*2",
            "ClearEntireCostmap=RUNNING@1", "battery=10%@30s"]
  # faults = "each-single": none, then each action node failing on each call up to 3
  [each_single]
  calls = 3

A fault `PATH=STATUS@K#CODE` makes node PATH (a path, or every node of a name or type)
return STATUS (SUCCESS, FAILURE, or RUNNING: never answers) on its Kth call, writing CODE
to its error_code_id; `FollowPath*F` makes the controller F times slower; `battery=P%@Ss`
drops the battery to P percent at S simulated seconds. Join faults with ` + `.

Each variant is one run of the demo's warehouse, the same for the same file and number
on any machine, in any order, on any number of threads. Its row (table `variants`) is
written as it finishes: a stopped run keeps every finished row, and `--resume` runs the
missing ones.

Exit status:
  0  every variant selected ran (whatever its outcome)
  1  the campaign could not run: a bad file, a database error"#;

/// `neurotree campaign`'s subcommands.
#[derive(clap::Subcommand, Debug)]
pub enum CampaignCommand {
    /// Run the variants of a campaign file, each result a row of a SQLite file.
    Run(RunArgs),
    /// Summarise a results file: success rate overall and per factor value, failures
    /// grouped by why, slowest successes.
    Report(ReportArgs),
    /// Run one variant of a results file again and check it gives its row.
    Replay(ReplayArgs),
    /// Combine the results files of shards into one.
    Merge(MergeArgs),
}

/// What `neurotree campaign run` was asked to do.
#[derive(clap::Args, Debug)]
#[command(after_help = RUN_AFTER_HELP)]
pub struct RunArgs {
    /// The campaign file (TOML; see below).
    pub file: PathBuf,
    /// The results file (SQLite), created if missing.
    #[arg(long, value_name = "RESULTS.db")]
    pub db: PathBuf,
    /// Run only the campaign's first N variants.
    #[arg(long, value_name = "N")]
    pub limit: Option<u64>,
    /// Threads to run variants on (0: `RAYON_NUM_THREADS`, or every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Run the variants the results file does not hold yet.
    #[arg(long)]
    pub resume: bool,
    /// Run shard I of N (I from 1): every Nth variant from the Ith, after --limit.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    pub shard: Option<(u64, u64)>,
}

/// `I/N` with 1 <= I <= N.
fn parse_shard(text: &str) -> Result<(u64, u64), String> {
    let parsed = text
        .split_once('/')
        .and_then(|(i, n)| Some((i.trim().parse::<u64>().ok()?, n.trim().parse::<u64>().ok()?)));
    match parsed {
        Some((i, n)) if i >= 1 && i <= n => Ok((i, n)),
        _ => Err(format!(
            "`{text}` should be I/N with I from 1 to N, such as 1/4"
        )),
    }
}

/// What `neurotree campaign report` was asked to do.
#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// The results file.
    pub db: PathBuf,
    /// markdown, or json: one object with `success_rate` (0 to 1) and `variants`.
    #[arg(long, default_value = "markdown", value_parser = ["markdown", "json"])]
    pub format: String,
    /// Also draw the success rate per factor value as SVG into FILE.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
}

/// What `neurotree campaign replay` was asked to do.
#[derive(clap::Args, Debug)]
pub struct ReplayArgs {
    /// The results file.
    pub db: PathBuf,
    /// The variant's number.
    pub variant: u64,
    /// Print each tick: its number, the time, the root's status, what happened.
    #[arg(long)]
    pub trace: bool,
    /// Also write the variant as a scenario file that `neurotree test FILE` passes: its
    /// leaves mocks that play what they returned, its node faults, its outcome expected
    /// (Nav2's navigator, when the campaign runs it, is written beside it as STEM.xml).
    #[arg(long, value_name = "FILE", conflicts_with = "studio")]
    pub scenario: Option<PathBuf>,
    #[command(flatten)]
    pub studio: crate::studio::StudioFlags,
}

/// What `neurotree campaign merge` was asked to do.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// The results files of the shards.
    #[arg(required = true)]
    pub sources: Vec<PathBuf>,
    /// The results file to write (rows are added to what it holds).
    #[arg(short = 'o', long = "output", value_name = "ALL.db")]
    pub output: PathBuf,
}

/// Runs the subcommand.
pub fn execute(
    command: CampaignCommand,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Outcome> {
    let done = match command {
        CampaignCommand::Run(args) => run(&args, out, err)?,
        CampaignCommand::Report(args) => report(&args, out)?,
        CampaignCommand::Replay(args) => return replay(&args, out, err),
        CampaignCommand::Merge(args) => {
            let sources: Vec<&std::path::Path> = args.sources.iter().map(|p| p.as_path()).collect();
            campaign::merge(&sources, &args.output).map(|n| {
                let _ = writeln!(out, "{n} rows merged into {}", args.output.display());
            })
        }
    };
    match done {
        Ok(()) => Ok(Outcome::Done),
        Err(message) => {
            writeln!(err, "neurotree: {message}")?;
            Ok(Outcome::Refused)
        }
    }
}

fn run(
    args: &RunArgs,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Result<(), String>> {
    let campaign = match Campaign::load(&args.file) {
        Ok(c) => c,
        Err(e) => return Ok(Err(e)),
    };
    let results = match Results::open(&args.db).and_then(|r| r.claim(&campaign).map(|()| r)) {
        Ok(r) => r,
        Err(e) => return Ok(Err(e)),
    };
    let selected = campaign::selection(campaign.variants(), args.limit, args.shard);
    let (todo, already) = match campaign.todo(&results, selected, args.resume) {
        Ok(t) => t,
        Err(e) => return Ok(Err(format!("{}: {e}", args.db.display()))),
    };
    let progress = Progress::new(&campaign.name, todo.len() as u64);
    let (mut ran, mut succeeded) = (0u64, 0u64);
    let done = campaign.run_into(&results, &todo, args.threads, &mut |row| {
        ran += 1;
        succeeded += u64::from(row.outcome == "SUCCESS");
        progress.tick(ran, succeeded, err);
    });
    progress.finish();
    if let Err(e) = done {
        return Ok(Err(format!("{}: {e}", args.db.display())));
    }
    let rate = if ran > 0 {
        100.0 * succeeded as f64 / ran as f64
    } else {
        0.0
    };
    writeln!(
        out,
        "campaign {} ({} variants): {ran} run ({already} recorded before), {rate:.1} % \
         succeeded; results in {}",
        campaign.name,
        campaign.variants(),
        args.db.display()
    )?;
    Ok(Ok(()))
}

/// A bar on a terminal; plain lines, about twenty in all, otherwise.
struct Progress {
    bar: Option<ProgressBar>,
    name: String,
    total: u64,
}

impl Progress {
    fn new(name: &str, total: u64) -> Self {
        let bar = io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(total);
            bar.set_style(
                ProgressStyle::with_template(
                    "{prefix} [{bar:30}] {pos}/{len} variants, {msg}, {eta} left",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            bar.set_prefix(name.to_string());
            bar
        });
        Self {
            bar,
            name: name.to_string(),
            total,
        }
    }

    fn tick(&self, ran: u64, succeeded: u64, err: &mut impl Write) {
        let rate = 100.0 * succeeded as f64 / ran.max(1) as f64;
        match &self.bar {
            Some(bar) => {
                bar.set_position(ran);
                bar.set_message(format!("{rate:.1} % succeeded"));
            }
            None => {
                let every = (self.total / 20).max(1);
                if ran.is_multiple_of(every) || ran == self.total {
                    let _ = writeln!(
                        err,
                        "campaign {}: {ran}/{} variants, {rate:.1} % succeeded",
                        self.name, self.total
                    );
                }
            }
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }
}

fn report(args: &ReportArgs, out: &mut impl Write) -> io::Result<Result<(), String>> {
    let loaded = Results::open(&args.db).and_then(|r| {
        let name = r
            .campaign()?
            .and_then(|(text, file)| Campaign::parse(&text, std::path::Path::new(&file)).ok())
            .map_or_else(|| "campaign".to_string(), |c| c.name);
        Ok((name, r.rows()?))
    });
    let (name, rows) = match loaded {
        Ok(l) => l,
        Err(e) => return Ok(Err(e)),
    };
    if args.format == "json" {
        writeln!(out, "{}", campaign::report_json(&name, &rows))?;
    } else {
        write!(out, "{}", campaign::report_markdown(&name, &rows))?;
    }
    if let Some(svg) = &args.svg {
        if let Err(e) = std::fs::write(svg, campaign::report_svg(&name, &rows)) {
            return Ok(Err(format!("--svg {}: {e}", svg.display())));
        }
    }
    Ok(Ok(()))
}

fn replay(args: &ReplayArgs, out: &mut impl Write, err: &mut impl Write) -> io::Result<Outcome> {
    let refuse = |err: &mut dyn Write, message: String| {
        writeln!(err, "neurotree: {message}").map(|()| Outcome::Refused)
    };
    let loaded = Results::open(&args.db).and_then(|r| {
        let (text, file) = r
            .campaign()?
            .ok_or_else(|| format!("{}: holds no campaign", args.db.display()))?;
        let campaign = Campaign::parse(&text, std::path::Path::new(&file))?;
        let row = r.row(args.variant)?.ok_or_else(|| {
            format!(
                "{} holds no row of variant {} (the campaign has {} variants)",
                args.db.display(),
                args.variant,
                campaign.variants()
            )
        })?;
        Ok((campaign, row))
    });
    let (campaign, row) = match loaded {
        Ok(l) => l,
        Err(e) => return refuse(err, e),
    };
    writeln!(
        out,
        "variant {}: {}",
        row.variant,
        campaign::describe(&row.factors)
    )?;
    if args.studio.port.is_some() {
        return replay_in_studio(args, &campaign, &row, out, err);
    }
    let mut trace_out: Vec<String> = Vec::new();
    let again = campaign.run_variant_watched(args.variant, &mut |demo| {
        if args.trace {
            let s = demo.summary();
            let mut line = format!(
                "tick {} t={:.1} s {}",
                s.ticks,
                s.time.as_secs_f64(),
                s.outcome
            );
            for note in demo.notes() {
                line.push_str("; ");
                line.push_str(note);
            }
            trace_out.push(line);
        }
    });
    for line in trace_out {
        writeln!(out, "{line}")?;
    }
    print_row(out, &again)?;
    let same = again.outcome == row.outcome
        && again.ticks == row.ticks
        && again.failure_chain == row.failure_chain;
    if same {
        writeln!(out, "matches the recorded row")?;
    } else {
        writeln!(out, "differs from the recorded row:")?;
        print_row(out, &row)?;
        return Ok(Outcome::Refused);
    }
    match &args.scenario {
        None => Ok(Outcome::Done),
        Some(file) => match write_scenario(&campaign, &row, file) {
            Ok(()) => {
                writeln!(
                    out,
                    "scenario written to {}: `neurotree test {}` passes",
                    file.display(),
                    file.display()
                )?;
                Ok(Outcome::Done)
            }
            Err(e) => refuse(err, e),
        },
    }
}

/// Writes variant `row` of `campaign` as the scenario `file` (and Nav2's navigator beside
/// it when the campaign runs that), then runs it as `neurotree test` does: an error if it
/// does not pass.
fn write_scenario(campaign: &Campaign, row: &VariantRow, file: &Path) -> Result<(), String> {
    let shown = file.display();
    let dir = match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let tree_file = match campaign.tree_path() {
        Some(tree) => relative(&tree, &dir),
        None => {
            let stem = file
                .file_stem()
                .map_or_else(|| "variant".into(), |s| s.to_string_lossy().into_owned());
            let beside = dir.join(format!("{stem}.xml"));
            if beside == file {
                return Err(format!(
                    "--scenario {shown}: the navigator is written beside it as {stem}.xml; \
                     give the scenario another name (such as {stem}.toml)"
                ));
            }
            // A file of that name that is not the navigator is someone's own tree.
            if std::fs::read(&beside)
                .is_ok_and(|b| b != neurotree_cli::demo::NAVIGATE_TO_POSE_XML.as_bytes())
            {
                return Err(format!(
                    "--scenario {shown}: the navigator is written beside it as {stem}.xml, \
                     and {} is another file; give the scenario another name",
                    beside.display()
                ));
            }
            std::fs::write(&beside, neurotree_cli::demo::NAVIGATE_TO_POSE_XML)
                .map_err(|e| format!("{}: {e}", beside.display()))?;
            format!("{stem}.xml")
        }
    };
    let scenario = campaign::variant_scenario(campaign, row.variant, &tree_file)?;
    if scenario.outcome != row.outcome || scenario.ticks != row.ticks {
        return Err(format!(
            "variant {} ran to {} in {} ticks, not {} in {} as recorded",
            row.variant, scenario.outcome, scenario.ticks, row.outcome, row.ticks
        ));
    }
    std::fs::write(file, &scenario.toml).map_err(|e| format!("--scenario {shown}: {e}"))?;
    // As `neurotree test` runs it.
    let registry = crate::registry::with_nav2_controls::<()>(crate::registry::Nav2Args::default());
    let result =
        neurotree::scenario::ScenarioBench::with_registry(&registry, |_| ()).run_file(file);
    if result.passed() {
        Ok(())
    } else {
        Err(format!(
            "the scenario written to {shown} does not replay the variant:
{result}"
        ))
    }
}

/// `target` as a path from the folder `from` (`target` itself if either cannot be found).
fn relative(target: &Path, from: &Path) -> String {
    let (Ok(t), Ok(f)) = (std::fs::canonicalize(target), std::fs::canonicalize(from)) else {
        return target.display().to_string();
    };
    let common = t
        .components()
        .zip(f.components())
        .take_while(|(a, b)| a == b)
        .count();
    let mut path = PathBuf::new();
    for _ in f.components().skip(common) {
        path.push("..");
    }
    for c in t.components().skip(common) {
        path.push(c);
    }
    path.display().to_string()
}

fn print_row(out: &mut impl Write, row: &VariantRow) -> io::Result<()> {
    writeln!(out, "  outcome        {}", row.outcome)?;
    writeln!(out, "  ticks          {}", row.ticks)?;
    match &row.failure_chain {
        Some(chain) => writeln!(out, "  failure chain  {chain}"),
        None => writeln!(out, "  failure chain  none"),
    }
}

/// Replays the variant served to the studio: outcome and ticks are compared.
fn replay_in_studio(
    args: &ReplayArgs,
    campaign: &Campaign,
    row: &VariantRow,
    out: &mut impl Write,
    err: &mut impl Write,
) -> io::Result<Outcome> {
    let config = match campaign.config_of(args.variant) {
        Ok(c) => c,
        Err(e) => {
            writeln!(err, "neurotree: {e}")?;
            return Ok(Outcome::Refused);
        }
    };
    let files: Vec<PathBuf> = config.tree.iter().cloned().collect();
    let opts = neurotree_cli::demo::DemoOptions {
        config,
        speed: None,
        every: 10,
        frames_between: false,
        terminal: None,
    };
    let nav2 = crate::registry::Nav2Args {
        nav2: Some(neurotree::nav2::Nav2Release::Main),
    };
    let mut sink = io::sink();
    let summary = match crate::studio::Served::start(&args.studio, &files, nav2, err)? {
        Err(()) => return Ok(Outcome::Refused),
        Ok(None) => neurotree_cli::demo::run(&opts, &mut sink, err)?,
        Ok(Some(served)) => crate::studio::run_demo(served, &opts, &mut sink, err)?,
    };
    let Some(summary) = summary else {
        return Ok(Outcome::Refused);
    };
    let outcome = match (&summary.error, summary.outcome) {
        (Some(e), _) => format!("error: {e}"),
        (None, s) => s.to_string().to_uppercase(),
    };
    writeln!(out, "  outcome        {outcome}")?;
    writeln!(out, "  ticks          {}", summary.ticks)?;
    if outcome == row.outcome && summary.ticks == row.ticks {
        writeln!(out, "matches the recorded row")?;
        Ok(Outcome::Done)
    } else {
        writeln!(out, "differs from the recorded row")?;
        Ok(Outcome::Refused)
    }
}

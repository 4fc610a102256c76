//! `neurotree lint`: `check`, then the static analysis of [`neurotree::lint`] over the
//! trees that loaded.
//!
//! Each file is checked as `neurotree check` checks it (with the trees it uses from the
//! others); a file that does not load reports its errors as findings of rule NT0001, the
//! loader's warnings (deprecated names) as NT0002, and one that loads is linted. The
//! findings are printed as `file:line:col: severity[CODE]: message` (text), as one JSON
//! document, or as SARIF 2.1.0 for code review tools. The exit status is 1 when an error is
//! found, or a warning with `--deny warnings`.

use std::collections::BTreeSet;
use std::io::{self, Write};
use std::path::PathBuf;

use neurotree::lint::{self, Diagnostic, LintOptions, Rule, Severity, RULES};
use neurotree::{LoadError, LoadErrorKind, LoadWarning, Registry};
use serde_json::{json, Value};

use crate::check::{self, Checked};
use crate::files::LoadLimits;
use crate::Outcome;

mod sarif;

/// What `neurotree lint` was asked to do.
#[derive(clap::Args, Debug)]
pub struct LintArgs {
    /// The files to lint, each with the trees it uses from the others.
    #[arg(required_unless_present_any = ["list", "explain"])]
    pub files: Vec<PathBuf>,
    /// A file whose `TreeNodesModel` declares node types the files use (repeatable).
    #[arg(long = "model")]
    pub models: Vec<PathBuf>,
    #[command(flatten)]
    pub nav2: crate::registry::Nav2Args,
    /// Lint only this tree and the trees it uses.
    #[arg(long)]
    pub tree: Option<String>,
    /// text (`file:line:col: warning[NT0101]: ...`), json (one document) or sarif (2.1.0).
    #[arg(long, short = 'f', value_enum, default_value_t = LintFormat::Text)]
    pub format: LintFormat,
    /// `warnings`: a warning fails the run (exit 1) as an error does.
    #[arg(long, value_enum)]
    pub deny: Option<Deny>,
    /// An entry of the root blackboard the application writes before the first tick
    /// (repeatable); `--nav2` adds the ones Nav2's navigators write (goal, goals, ...).
    #[arg(long = "entry", value_name = "KEY")]
    pub entries: Vec<String>,
    /// List the rules: code, severity, name and what each finds.
    #[arg(long, exclusive = true)]
    pub list: bool,
    /// Explain one rule (`--explain NT0101`).
    #[arg(long, value_name = "CODE", exclusive = true)]
    pub explain: Option<String>,
    #[command(flatten)]
    pub limits: LoadLimits,
}

/// How the findings are printed.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum LintFormat {
    /// One line per finding, as compilers print them.
    Text,
    /// One JSON document: the findings and their counts.
    Json,
    /// SARIF 2.1.0, for code scanning and review tools.
    Sarif,
}

/// What `--deny` turns into a failure.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deny {
    /// Warnings fail the run as errors do.
    Warnings,
}

/// The rule of a file that does not load or validate: what `neurotree check` reports.
pub const LOAD_ERROR: Rule = Rule {
    code: "NT0001",
    name: "invalid-tree",
    severity: Severity::Error,
    summary: "the file does not load or a tree does not validate (what `neurotree check` reports)",
    explanation: "\
The loader refuses the file as BehaviorTree.CPP would: bad XML, an unknown node type or
port, a literal that does not convert, a missing child, a SubTree cycle. The message says
what to change; `neurotree check` reports the same errors. Node types of your own are
declared in a TreeNodesModel given with --model FILE.",
};

/// The rule of a loader's warning: a deprecated or misspelt node name.
pub const LOAD_WARNING: Rule = Rule {
    code: "NT0002",
    name: "deprecated-name",
    severity: Severity::Warning,
    summary: "a deprecated or misspelt node name that loads as the node it stands for",
    explanation: "\
The file names a node by an old or misspelt name (`RetryUntilSuccesful`, Nav2's renamed
`IsPathValid`) that the loader accepts as the node it stands for. Write the new name.",
};

/// Every rule: the loader's two, then the analysis's.
pub fn all_rules() -> impl Iterator<Item = &'static Rule> {
    [&LOAD_ERROR, &LOAD_WARNING].into_iter().chain(RULES)
}

/// The options the command line gives the analysis.
fn options(args: &LintArgs) -> LintOptions {
    let mut options = if args.nav2.nav2.is_some() {
        LintOptions::nav2()
    } else {
        LintOptions::default()
    };
    options.written.extend(args.entries.iter().cloned());
    options.tree = args.tree.clone();
    options
}

/// Lints the files and prints the findings: [`Outcome::Done`] when none is an error (or a
/// denied warning), else [`Outcome::Refused`].
pub fn execute(args: &LintArgs, out: &mut impl Write, err: &mut impl Write) -> io::Result<Outcome> {
    if args.list {
        for r in all_rules() {
            writeln!(
                out,
                "{}  {:<7}  {:<22}  {}",
                r.code, r.severity, r.name, r.summary
            )?;
        }
        return Ok(Outcome::Done);
    }
    if let Some(code) = &args.explain {
        return match all_rules().find(|r| r.code.eq_ignore_ascii_case(code)) {
            Some(r) => {
                writeln!(
                    out,
                    "{} {} ({}): {}\n\n{}",
                    r.code, r.name, r.severity, r.summary, r.explanation
                )?;
                Ok(Outcome::Done)
            }
            None => {
                writeln!(
                    err,
                    "error: no rule `{code}`; `neurotree lint --list` lists them"
                )?;
                Ok(Outcome::Refused)
            }
        };
    }
    let (found, hints) = match check::registry(&args.models, args.nav2, &args.files) {
        Err(refused) => (refused.iter().map(load_error).collect(), Vec::new()),
        Ok(registry) => lint_files(&registry, args, &options(args)),
    };
    print(&found, args.format, out)?;
    let failed = found.iter().any(|d| {
        d.severity == Severity::Error
            || (d.severity == Severity::Warning && args.deny == Some(Deny::Warnings))
    });
    if args.format == LintFormat::Text {
        for hint in hints {
            writeln!(err, "{hint}")?;
        }
        writeln!(err, "{}", summary(&found))?;
    }
    Ok(Outcome::from(!failed))
}

/// The findings of every file, each once, and the hints `neurotree check` would add.
fn lint_files(
    registry: &Registry<()>,
    args: &LintArgs,
    options: &LintOptions,
) -> (Vec<Diagnostic>, Vec<&'static str>) {
    let mut found = Vec::new();
    let mut hints = BTreeSet::new();
    for at in 0..args.files.len() {
        let checked = check::check_file(registry, &args.files, at, args.limits.max_nodes);
        if let Err(errors) = &checked.trees {
            for e in errors {
                match e.kind() {
                    LoadErrorKind::TooManyNodes => hints.insert(crate::files::MAX_NODES_HINT),
                    _ => false,
                };
            }
        }
        found.extend(findings(&checked, options));
    }
    let mut seen = BTreeSet::new();
    found.retain(|d| seen.insert(d.to_string()));
    (found, hints.into_iter().collect())
}

/// The findings of one checked file or text: its load errors and warnings, else the
/// analysis of its trees.
pub(crate) fn findings(checked: &Checked<'_>, options: &LintOptions) -> Vec<Diagnostic> {
    let mut found: Vec<Diagnostic> = checked.warnings.iter().map(load_warning).collect();
    match &checked.trees {
        Err(errors) => found.extend(errors.iter().map(load_error)),
        Ok(_) => found.extend(lint::lint(&checked.loader, options)),
    }
    found
}

/// A loader's error as a finding.
pub(crate) fn load_error(e: &LoadError) -> Diagnostic {
    Diagnostic {
        code: LOAD_ERROR.code,
        rule: LOAD_ERROR.name,
        severity: LOAD_ERROR.severity,
        message: e.message.clone(),
        file: e.file.clone(),
        line: e.line,
        col: e.col,
        tree: String::new(),
        path: String::new(),
    }
}

/// A loader's warning as a finding.
fn load_warning(w: &LoadWarning) -> Diagnostic {
    Diagnostic {
        code: LOAD_WARNING.code,
        rule: LOAD_WARNING.name,
        severity: LOAD_WARNING.severity,
        message: w.message.clone(),
        file: w.file.clone(),
        line: w.line,
        col: w.col,
        tree: String::new(),
        path: String::new(),
    }
}

/// `2 errors, 1 warning, 0 notes`.
pub(crate) fn summary(found: &[Diagnostic]) -> String {
    let count = |severity, one: &str, many: &str| {
        let n = found.iter().filter(|d| d.severity == severity).count();
        format!("{n} {}", if n == 1 { one } else { many })
    };
    format!(
        "{}, {}, {}",
        count(Severity::Error, "error", "errors"),
        count(Severity::Warning, "warning", "warnings"),
        count(Severity::Note, "note", "notes")
    )
}

/// The JSON document of `--format json`.
pub(crate) fn json_document(found: &[Diagnostic]) -> Value {
    let count = |severity| found.iter().filter(|d| d.severity == severity).count();
    json!({
        "diagnostics": found,
        "errors": count(Severity::Error),
        "warnings": count(Severity::Warning),
        "notes": count(Severity::Note),
    })
}

fn print(found: &[Diagnostic], format: LintFormat, out: &mut impl Write) -> io::Result<()> {
    match format {
        LintFormat::Text => {
            for d in found {
                writeln!(out, "{d}")?;
            }
            Ok(())
        }
        LintFormat::Json => writeln!(out, "{:#}", json_document(found)),
        LintFormat::Sarif => writeln!(out, "{:#}", sarif::document(found)),
    }
}

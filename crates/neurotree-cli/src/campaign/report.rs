//! What a campaign's results say: the success rate overall and for each factor's values,
//! the failures grouped by why the root failed, the slowest successes.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde_json::{json, Value};

use super::{describe, Groups, VariantRow};

/// The share of `rows` that succeeded, 0 to 1 (0 for none).
fn rate(rows: &[&VariantRow]) -> f64 {
    if rows.is_empty() {
        return 0.0;
    }
    rows.iter().filter(|r| r.outcome == "SUCCESS").count() as f64 / rows.len() as f64
}

/// The rows of each value of each factor, factors in the order the rows give them.
fn by_factor(rows: &[VariantRow]) -> Vec<(String, Groups<'_>)> {
    let mut out: Vec<(String, Groups<'_>)> = Vec::new();
    for row in rows {
        let Some(factors) = row.factors.as_object() else {
            continue;
        };
        for (name, value) in factors {
            let key = match value {
                Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            let at = match out.iter().position(|(n, _)| n == name) {
                Some(at) => at,
                None => {
                    out.push((name.clone(), BTreeMap::new()));
                    out.len() - 1
                }
            };
            out[at].1.entry(key).or_default().push(row);
        }
    }
    out
}

/// The failures by why: the failure chain, else the outcome (RUNNING, an error).
fn failures(rows: &[VariantRow]) -> Vec<(String, Vec<&VariantRow>)> {
    let mut groups: Groups<'_> = BTreeMap::new();
    for row in rows.iter().filter(|r| r.outcome != "SUCCESS") {
        let key = match &row.failure_chain {
            Some(chain) => chain_text(chain),
            None => row.outcome.clone(),
        };
        groups.entry(key).or_default().push(row);
    }
    let mut groups: Vec<_> = groups.into_iter().collect();
    groups.sort_by(|a, b| b.1.len().cmp(&a.1.len()).then(a.0.cmp(&b.0)));
    groups
}

/// A failure chain in one line: each link's path, and the reason of the last that gives one.
fn chain_text(chain: &Value) -> String {
    let Some(links) = chain.as_array() else {
        return chain.to_string();
    };
    let leaf = links.last().and_then(|l| l["path"].as_str()).unwrap_or("?");
    let reason = links
        .iter()
        .rev()
        .find_map(|l| l["reason"].as_str())
        .map(|r| format!(": {r}"))
        .unwrap_or_default();
    format!("{leaf}{reason}")
}

/// The slowest successes, slowest first: at most `n`.
fn slowest(rows: &[VariantRow], n: usize) -> Vec<&VariantRow> {
    let mut ok: Vec<&VariantRow> = rows.iter().filter(|r| r.outcome == "SUCCESS").collect();
    ok.sort_by(|a, b| {
        b.seconds
            .total_cmp(&a.seconds)
            .then(a.variant.cmp(&b.variant))
    });
    ok.truncate(n);
    ok
}

/// The report as one JSON object: `success_rate` (0 to 1), `variants`, `outcomes`,
/// `factors` (per factor, per value: variants and success rate), `failures` (grouped, each
/// with its count and a variant), `slowest`.
pub fn report_json(name: &str, rows: &[VariantRow]) -> Value {
    let all: Vec<&VariantRow> = rows.iter().collect();
    let mut outcomes = BTreeMap::<&str, usize>::new();
    for row in rows {
        let key = if row.outcome.starts_with("error") {
            "error"
        } else {
            row.outcome.as_str()
        };
        *outcomes.entry(key).or_default() += 1;
    }
    let factors: serde_json::Map<String, Value> = by_factor(rows)
        .into_iter()
        .map(|(name, groups)| {
            let values: Vec<Value> = groups
                .iter()
                .map(|(value, rows)| {
                    json!({"value": value, "variants": rows.len(), "success_rate": rate(rows)})
                })
                .collect();
            (name, json!(values))
        })
        .collect();
    let failures: Vec<Value> = failures(rows)
        .iter()
        .map(|(why, rows)| json!({"why": why, "count": rows.len(), "variant": rows[0].variant}))
        .collect();
    let slowest: Vec<Value> = slowest(rows, 5)
        .iter()
        .map(|r| json!({"variant": r.variant, "seconds": r.seconds, "factors": r.factors}))
        .collect();
    json!({
        "campaign": name,
        "variants": rows.len(),
        "success_rate": rate(&all),
        "outcomes": outcomes,
        "factors": factors,
        "failures": failures,
        "slowest": slowest,
    })
}

/// The report in markdown.
pub fn report_markdown(name: &str, rows: &[VariantRow]) -> String {
    let report = report_json(name, rows);
    let mut md = String::new();
    let pct = |v: &Value| format!("{:.1} %", v.as_f64().unwrap_or(0.0) * 100.0);
    let _ = writeln!(md, "# Campaign {name}\n");
    let _ = writeln!(
        md,
        "{} variants, {} succeeded.\n",
        rows.len(),
        pct(&report["success_rate"])
    );
    if let Some(outcomes) = report["outcomes"].as_object() {
        let list: Vec<String> = outcomes.iter().map(|(k, v)| format!("{k} {v}")).collect();
        let _ = writeln!(md, "Outcomes: {}.\n", list.join(", "));
    }
    if let Some(factors) = report["factors"].as_object() {
        for (factor, values) in factors {
            let _ = writeln!(
                md,
                "## {factor}\n\n| value | variants | success |\n|---|---:|---:|"
            );
            for v in values.as_array().into_iter().flatten() {
                let _ = writeln!(
                    md,
                    "| {} | {} | {} |",
                    v["value"].as_str().unwrap_or_default().replace('|', "\\|"),
                    v["variants"],
                    pct(&v["success_rate"])
                );
            }
            md.push('\n');
        }
    }
    let _ = writeln!(md, "## Failures\n");
    let failures = failures(rows);
    if failures.is_empty() {
        let _ = writeln!(md, "None.\n");
    } else {
        let _ = writeln!(md, "| why | count | a variant |\n|---|---:|---|");
        for (why, group) in &failures {
            let _ = writeln!(
                md,
                "| {} | {} | {} ({}) |",
                why.replace('|', "\\|"),
                group.len(),
                group[0].variant,
                describe(&group[0].factors).replace('|', "\\|")
            );
        }
        md.push('\n');
    }
    let _ = writeln!(md, "## Slowest successes\n");
    for row in slowest(rows, 5) {
        let _ = writeln!(
            md,
            "- variant {}: {:.1} s ({})",
            row.variant,
            row.seconds,
            describe(&row.factors)
        );
    }
    md
}

/// An SVG of the success rate of each value of each factor: one bar per value, grouped by
/// factor.
pub fn report_svg(name: &str, rows: &[VariantRow]) -> String {
    let factors = by_factor(rows);
    let bars: usize = factors.iter().map(|(_, g)| g.len() + 1).sum();
    let (row_h, label_w, bar_w) = (18usize, 360usize, 300usize);
    let height = 40 + bars * row_h;
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n\
         <text x=\"4\" y=\"20\" font-size=\"14\">{}: success rate per factor value</text>\n",
        label_w + bar_w + 70,
        esc(name)
    );
    let mut y = 40;
    for (factor, groups) in &factors {
        let _ = writeln!(
            svg,
            "<text x=\"4\" y=\"{}\" font-weight=\"bold\">{}</text>",
            y + 13,
            esc(factor)
        );
        y += row_h;
        for (value, group) in groups {
            let r = rate(group);
            let _ = writeln!(
                svg,
                "<text x=\"16\" y=\"{}\">{}</text><rect x=\"{label_w}\" y=\"{}\" width=\"{:.1}\" \
                 height=\"{}\" fill=\"#4a8\"/><text x=\"{}\" y=\"{}\">{:.0} % of {}</text>",
                y + 13,
                esc(&value.chars().take(56).collect::<String>()),
                y + 3,
                r * bar_w as f64,
                row_h - 6,
                label_w + bar_w + 4,
                y + 13,
                r * 100.0,
                group.len()
            );
            y += row_h;
        }
    }
    svg.push_str("</svg>\n");
    svg
}

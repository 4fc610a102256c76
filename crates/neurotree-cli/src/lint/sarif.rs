//! The findings as SARIF 2.1.0 (OASIS), the format code scanning and review tools read.

use neurotree::lint::{Diagnostic, Severity};
use serde_json::{json, Value};

/// SARIF's name for a severity.
fn level(severity: Severity) -> &'static str {
    match severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Note => "note",
    }
}

/// One SARIF log of one run of `neurotree lint`, with every rule and the findings.
pub fn document(found: &[Diagnostic]) -> Value {
    let rules: Vec<Value> = super::all_rules()
        .map(|r| {
            json!({
                "id": r.code,
                "name": r.name,
                "shortDescription": { "text": r.summary },
                "fullDescription": { "text": r.explanation },
                "defaultConfiguration": { "level": level(r.severity) },
            })
        })
        .collect();
    let results: Vec<Value> = found
        .iter()
        .map(|d| {
            let mut location = json!({
                "physicalLocation": {
                    "artifactLocation": { "uri": d.file.replace('\\', "/") },
                    "region": { "startLine": d.line, "startColumn": d.col },
                },
            });
            if !d.tree.is_empty() {
                let name = if d.path.is_empty() {
                    d.tree.clone()
                } else {
                    format!("{}/{}", d.tree, d.path)
                };
                location["logicalLocations"] = json!([{ "fullyQualifiedName": name }]);
            }
            json!({
                "ruleId": d.code,
                "level": level(d.severity),
                "message": { "text": d.message },
                "locations": [location],
            })
        })
        .collect();
    json!({
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [{
            "tool": { "driver": {
                "name": "neurotree",
                "version": env!("CARGO_PKG_VERSION"),
                "informationUri": "https://github.com/neurotree/neurotree",
                "rules": rules,
            }},
            "results": results,
        }],
    })
}

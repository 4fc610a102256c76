//! Why a run failed, as JSON: the one place the shape of a failure chain is written, for
//! `neurotree run`'s summary and the results of `neurotree campaign`.

use neurotree::{Failure, FailureLink, Reason};
use serde_json::{json, Value};

/// Why the root failed, as the summary of `neurotree run` carries it: one entry per link of
/// the chain, from the root down, with the node's own reason and code when it gave one
/// (code 0, "none", is left out) and, for a Fallback, every child it tried, each with its
/// own chain in the same form (its first entry is the child itself): the tree of the
/// tick's failures, down to each leaf.
///
/// ```json
/// [{"path":"Fallback","tried":[{"path":"Fallback/a","reason":"blocked","code":106,
///   "chain":[{"path":"Fallback/a","reason":"blocked","code":106,"tried":[]}]},
///  {"path":"Fallback/b","chain":[{"path":"Fallback/b","tried":[]}]}]},
///  {"path":"Fallback/b","tried":[]}]
/// ```
pub fn failure_json(failure: &Failure) -> Value {
    links_json(&failure.links)
}

fn links_json(links: &[FailureLink]) -> Value {
    fn with_reason(mut entry: Value, reason: Option<&Reason>) -> Value {
        if let Some(reason) = reason {
            entry["reason"] = json!(reason.message());
            if reason.code() != 0 {
                entry["code"] = json!(reason.code());
            }
        }
        entry
    }
    let links: Vec<Value> = links
        .iter()
        .map(|link| {
            let tried: Vec<Value> = link
                .tried
                .iter()
                .map(|t| {
                    let mut entry = with_reason(json!({ "path": t.path }), t.reason.as_ref());
                    entry["chain"] = links_json(&t.chain);
                    entry
                })
                .collect();
            let mut entry = with_reason(json!({ "path": link.path }), link.reason.as_ref());
            entry["tried"] = json!(tried);
            entry
        })
        .collect();
    json!(links)
}

//! Why a run failed, as JSON: the one place the shape of a failure chain is written, for
//! `neurotree run`'s summary and the results of `neurotree campaign`.

use neurotree::{Failure, Reason};
use serde_json::{json, Value};

/// Why the root failed, as the summary of `neurotree run` carries it: one entry per link of
/// the chain, from the root down, with the node's own reason and code when it gave one
/// (code 0, "none", is left out) and, for a Fallback, every child it tried.
///
/// ```json
/// [{"path":"Fallback","tried":[{"path":"Fallback/a","reason":"blocked","code":106},
///  {"path":"Fallback/b"}]},{"path":"Fallback/b","tried":[]}]
/// ```
pub fn failure_json(failure: &Failure) -> Value {
    fn with_reason(mut entry: Value, reason: Option<&Reason>) -> Value {
        if let Some(reason) = reason {
            entry["reason"] = json!(reason.message());
            if reason.code() != 0 {
                entry["code"] = json!(reason.code());
            }
        }
        entry
    }
    let links: Vec<Value> = failure
        .links
        .iter()
        .map(|link| {
            let tried: Vec<Value> = link
                .tried
                .iter()
                .map(|t| with_reason(json!({ "path": t.path }), t.reason.as_ref()))
                .collect();
            let mut entry = with_reason(json!({ "path": link.path }), link.reason.as_ref());
            entry["tried"] = json!(tried);
            entry
        })
        .collect();
    json!(links)
}

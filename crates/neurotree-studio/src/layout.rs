//! `POST /api/layout`: the boxes of a tree's nodes and where they go, computed by the
//! renderer of `neurotree show --format svg` (`neurotree_toolkit::render::plan`), so that
//! the page draws a tree where the picture does. The page sends the nodes it draws (those
//! of a file being edited, or of a watched run) and the layouts it wants: an orientation,
//! a level of detail and the nodes folded, several at once when it looks for the one that
//! fits.

use std::collections::BTreeMap;

use axum::http::StatusCode;
use axum::Json;
use neurotree_toolkit::render::plan::{
    plan_boxes, plan_layout, Detail, Orientation, PlanNode, PlannedBox, PlannedLayout,
};
use neurotree_toolkit::PortDirection;
use serde::{Deserialize, Serialize};

use crate::server::Refusal;

/// The most layouts one request may ask for: enough for every depth of a deep tree in
/// both orientations.
const MOST_LAYOUTS: usize = 128;

/// The most places one answer may hold, its layouts times its nodes: 128 layouts of a
/// tree of 16,384 nodes. Each place costs some eighty bytes of answer, so that without it
/// a body of a few megabytes of bare nodes, asked for 128 times, would be answered with
/// gigabytes.
const MOST_PLACES: usize = 1 << 21;

/// One node as the page sends it.
#[derive(Deserialize)]
pub(crate) struct NodeIn {
    name: String,
    #[serde(rename = "type", default)]
    type_name: Option<String>,
    #[serde(default)]
    category: Option<String>,
    /// `[name, text]` in the order the file writes them.
    #[serde(default)]
    ports: Vec<(String, String)>,
    /// `input`, `output` or `inout` by port name.
    #[serde(default)]
    directions: BTreeMap<String, String>,
    #[serde(default)]
    children: Vec<usize>,
}

/// One layout asked for.
#[derive(Deserialize)]
pub(crate) struct Wanted {
    /// `TB` (top-down) or `LR` (left to right).
    orientation: String,
    /// `full` or `compact`.
    detail: String,
    /// The indices of the folded nodes.
    #[serde(default)]
    folded: Vec<usize>,
}

#[derive(Deserialize)]
pub(crate) struct LayoutBody {
    nodes: Vec<NodeIn>,
    /// Whether to answer with the boxes too (the first request for a tree).
    #[serde(default)]
    boxes: bool,
    #[serde(default)]
    layouts: Vec<Wanted>,
}

#[derive(Serialize)]
pub(crate) struct LayoutAnswer {
    boxes: Option<Vec<PlannedBox>>,
    layouts: Vec<PlannedLayout>,
}

fn direction(word: &str) -> Option<PortDirection> {
    match word {
        "input" => Some(PortDirection::Input),
        "output" => Some(PortDirection::Output),
        "inout" => Some(PortDirection::InOut),
        _ => None,
    }
}

/// The answer to `body`, or why it is refused.
pub(crate) fn answer(body: LayoutBody) -> Result<LayoutAnswer, Refusal> {
    if body.layouts.len() > MOST_LAYOUTS {
        return Err(Refusal(
            StatusCode::BAD_REQUEST,
            format!(
                "{} layouts asked for at once; ask for at most {MOST_LAYOUTS}",
                body.layouts.len()
            ),
        ));
    }
    let places = body.layouts.len().saturating_mul(body.nodes.len());
    if places > MOST_PLACES {
        let most = (MOST_PLACES / body.nodes.len()).max(1);
        return Err(Refusal(
            StatusCode::BAD_REQUEST,
            format!(
                "{} layouts of {} nodes asked for at once; ask for at most {most} layouts of \
                 a tree this size a request",
                body.layouts.len(),
                body.nodes.len()
            ),
        ));
    }
    let nodes: Vec<PlanNode> = body
        .nodes
        .into_iter()
        .map(|n| PlanNode {
            type_name: n.type_name.unwrap_or_else(|| n.name.clone()),
            name: n.name,
            category: n.category.unwrap_or_default(),
            ports: n.ports,
            directions: n
                .directions
                .iter()
                .filter_map(|(port, word)| Some((port.clone(), direction(word)?)))
                .collect(),
            children: n.children,
        })
        .collect();
    let boxes = plan_boxes(&nodes);
    let mut layouts = Vec::with_capacity(body.layouts.len());
    for wanted in &body.layouts {
        let orientation = match wanted.orientation.as_str() {
            "TB" => Orientation::TopDown,
            "LR" => Orientation::LeftRight,
            other => return Err(refused("orientation", other, "TB or LR")),
        };
        let detail = match wanted.detail.as_str() {
            "full" => Detail::Full,
            "compact" => Detail::Compact,
            other => return Err(refused("detail", other, "full or compact")),
        };
        layouts.push(plan_layout(
            &nodes,
            &boxes,
            orientation,
            detail,
            &wanted.folded,
        ));
    }
    Ok(LayoutAnswer {
        boxes: body.boxes.then_some(boxes),
        layouts,
    })
}

fn refused(field: &str, value: &str, expected: &str) -> Refusal {
    Refusal(
        StatusCode::BAD_REQUEST,
        format!("{field} `{value}` is not known; give {expected}"),
    )
}

/// The handler: laid out off the async threads, a big tree taking a few milliseconds.
pub(crate) async fn layout(Json(body): Json<LayoutBody>) -> Result<Json<LayoutAnswer>, Refusal> {
    tokio::task::spawn_blocking(move || answer(body))
        .await
        .map_err(|e| Refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()))?
        .map(Json)
}

//! A tree as the page draws it (PROTOCOL.md, "TreeView"): from a blueprint the engine
//! built, or from the XML a BehaviorTree.CPP log carries.

use std::collections::HashMap;

use neurotree_core::{Blueprint, Category, NodeKind, NodeStatus};
use neurotree_toolkit::render;
use serde::Serialize;
use serde_json::{Map, Value};

/// The page's name of a category.
pub fn category_name(category: Category) -> &'static str {
    match category {
        Category::Control => "control",
        Category::Decorator => "decorator",
        Category::Condition => "condition",
        Category::Action => "action",
        Category::SubTree => "subtree",
    }
}

/// The page's name of a status.
pub fn status_name(status: NodeStatus) -> &'static str {
    match status {
        NodeStatus::Idle => "IDLE",
        NodeStatus::Running => "RUNNING",
        NodeStatus::Success => "SUCCESS",
        NodeStatus::Failure => "FAILURE",
        NodeStatus::Skipped => "SKIPPED",
    }
}

/// A status from its stored byte (as [`NodeStatus`] is `repr(u8)`); unknown bytes read as
/// Idle.
pub fn status_of_byte(byte: u8) -> NodeStatus {
    match byte {
        1 => NodeStatus::Running,
        2 => NodeStatus::Success,
        3 => NodeStatus::Failure,
        4 => NodeStatus::Skipped,
        _ => NodeStatus::Idle,
    }
}

/// A tree, subtrees expanded, nodes in pre-order.
#[derive(Clone, Debug, Serialize)]
pub struct TreeView {
    /// The tree's ID.
    pub root: String,
    /// Every node; `nodes[i].id == i`.
    pub nodes: Vec<NodeView>,
}

/// One node of a [`TreeView`].
#[derive(Clone, Debug, Serialize)]
pub struct NodeView {
    /// Its index.
    pub id: u32,
    /// Its parent's index.
    pub parent: Option<u32>,
    /// Its children's indices, in order.
    pub children: Vec<u32>,
    /// Its name.
    pub name: String,
    /// Its type.
    #[serde(rename = "type")]
    pub type_name: String,
    /// `control`, `decorator`, `condition`, `action` or `subtree`.
    pub category: &'static str,
    /// Names from the root down, joined by `/`.
    pub path: String,
    /// For a SubTree node, the tree it opens.
    pub subtree: Option<String>,
    /// Its ports as written.
    pub ports: Map<String, Value>,
    /// Which way each port its type declares carries data: `input`, `output` or `inout`.
    pub directions: Map<String, Value>,
}

impl TreeView {
    /// The tree `blueprint` holds, named `root`.
    pub fn of_blueprint<C>(blueprint: &Blueprint<C>, root: &str) -> Self {
        let paths = blueprint.paths();
        let nodes = blueprint
            .ids()
            .map(|id| {
                let kind = blueprint.kind(id);
                // As a file writes them, built-ins' parameters included: what the
                // nodes draw under their names, as `show --format svg` does.
                let ports: Map<String, Value> = render::node_ports(blueprint, id)
                    .into_iter()
                    .map(|(name, text)| (name, Value::String(text)))
                    .collect();
                let directions = ports
                    .keys()
                    .filter_map(|name| {
                        let direction = blueprint.port_direction(id, name)?;
                        Some((name.clone(), render::direction_name(direction).into()))
                    })
                    .collect();
                NodeView {
                    id: id.0,
                    parent: blueprint.parent(id).map(|p| p.0),
                    children: blueprint.children(id).iter().map(|c| c.0).collect(),
                    name: blueprint.name(id).to_string(),
                    type_name: blueprint.type_id(id).to_string(),
                    category: category_name(kind.category()),
                    path: paths[id.index()].clone(),
                    subtree: matches!(kind, NodeKind::SubTree(_))
                        .then(|| blueprint.type_id(id).to_string()),
                    ports,
                    directions,
                }
            })
            .collect();
        Self {
            root: root.to_string(),
            nodes,
        }
    }

    /// The tree of a BehaviorTree.CPP log's XML (`.btlog`, SQLite log): its main tree with
    /// every SubTree expanded from the `<BehaviorTree>` of the same `_fullpath` (else ID).
    /// Returns the view and, per node, its `_uid` (0 if it has none).
    pub fn of_log_xml(xml: &str) -> Result<(Self, Vec<u16>), String> {
        let options = crate::check::xml_options();
        let doc = roxmltree::Document::parse_with_options(xml, options)
            .map_err(|e| format!("the log's tree is not XML: {e}"))?;
        let root = doc.root_element();
        let trees: Vec<roxmltree::Node<'_, '_>> = root
            .children()
            .filter(|n| n.has_tag_name("BehaviorTree"))
            .collect();
        let main_id = root.attribute("main_tree_to_execute");
        let main = trees
            .iter()
            .find(|t| main_id.is_some() && t.attribute("ID") == main_id)
            .or_else(|| trees.first())
            .ok_or("the log's tree has no <BehaviorTree>")?;
        let mut categories: HashMap<&str, &'static str> = HashMap::new();
        if let Some(model) = root.children().find(|n| n.has_tag_name("TreeNodesModel")) {
            for m in model.children().filter(|n| n.is_element()) {
                let category = match m.tag_name().name() {
                    "Control" => "control",
                    "Decorator" => "decorator",
                    "Condition" => "condition",
                    "SubTree" => "subtree",
                    _ => "action",
                };
                if let Some(id) = m.attribute("ID") {
                    categories.insert(id, category);
                }
            }
        }
        let mut walk = LogWalk {
            trees: &trees,
            categories,
            view: TreeView {
                root: main.attribute("ID").unwrap_or("MainTree").to_string(),
                nodes: Vec::new(),
            },
            uids: Vec::new(),
            open: Vec::new(),
        };
        let first = main
            .children()
            .find(|n| n.is_element())
            .ok_or("the log's main tree is empty")?;
        walk.node(first, None, "")?;
        Ok((walk.view, walk.uids))
    }
}

/// The most nodes a log's tree may expand to: a log is read from a file the page chose.
const MAX_LOG_NODES: usize = 200_000;

struct LogWalk<'d, 'i> {
    trees: &'d [roxmltree::Node<'d, 'i>],
    categories: HashMap<&'d str, &'static str>,
    view: TreeView,
    uids: Vec<u16>,
    /// The `<BehaviorTree>`s being expanded, so a cycle is refused rather than followed.
    open: Vec<roxmltree::NodeId>,
}

impl<'d, 'i> LogWalk<'d, 'i> {
    fn node(
        &mut self,
        el: roxmltree::Node<'d, 'i>,
        parent: Option<u32>,
        parent_path: &str,
    ) -> Result<u32, String> {
        if self.view.nodes.len() >= MAX_LOG_NODES || self.open.len() > 256 {
            return Err("the log's tree is too large or too deep".into());
        }
        let tag = el.tag_name().name();
        let explicit = matches!(
            tag,
            "Action" | "Condition" | "Control" | "Decorator" | "SubTree"
        );
        let type_name = if explicit {
            el.attribute("ID").unwrap_or(tag)
        } else {
            tag
        };
        let name = el.attribute("name").unwrap_or(type_name);
        let path = if parent_path.is_empty() {
            name.to_string()
        } else {
            format!("{parent_path}/{name}")
        };
        let children: Vec<roxmltree::Node<'d, 'i>> =
            el.children().filter(|n| n.is_element()).collect();
        let is_subtree = tag == "SubTree";
        let category = if is_subtree {
            "subtree"
        } else if let Some(c) = self.categories.get(type_name) {
            c
        } else {
            match (tag, children.len()) {
                ("Condition", _) => "condition",
                ("Decorator", _) => "decorator",
                (_, 0) => "action",
                (_, 1) if tag == "Decorator" => "decorator",
                _ => "control",
            }
        };
        let ports = el
            .attributes()
            .filter(|a| !matches!(a.name(), "name" | "ID" | "_uid" | "_fullpath"))
            .map(|a| (a.name().to_string(), Value::String(a.value().to_string())))
            .collect();
        let id = self.view.nodes.len() as u32;
        self.view.nodes.push(NodeView {
            id,
            parent,
            children: Vec::new(),
            name: name.to_string(),
            type_name: type_name.to_string(),
            category,
            path: path.clone(),
            subtree: is_subtree.then(|| type_name.to_string()),
            ports,
            // A log's tree carries no declarations of its types' ports.
            directions: Map::new(),
        });
        self.uids.push(
            el.attribute("_uid")
                .and_then(|u| u.parse().ok())
                .unwrap_or(0),
        );
        let body: Vec<roxmltree::Node<'d, 'i>> = if is_subtree && children.is_empty() {
            let fullpath = el.attribute("_fullpath");
            let tree = self
                .trees
                .iter()
                .find(|t| fullpath.is_some() && t.attribute("_fullpath") == fullpath)
                .or_else(|| {
                    self.trees
                        .iter()
                        .find(|t| t.attribute("ID") == Some(type_name))
                });
            match tree {
                Some(t) if !self.open.contains(&t.id()) => {
                    self.open.push(t.id());
                    let first: Vec<_> = t.children().filter(|n| n.is_element()).take(1).collect();
                    first
                }
                _ => Vec::new(),
            }
        } else {
            children
        };
        let expanded = is_subtree && !body.is_empty() && el.children().all(|n| !n.is_element());
        for child in body {
            let c = self.node(child, Some(id), &path)?;
            self.view.nodes[id as usize].children.push(c);
        }
        if expanded {
            self.open.pop();
        }
        Ok(id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_tree_expands_its_subtrees_by_fullpath() {
        let xml = r#"<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <Sequence name="Sequence" _uid="1">
      <SubTree ID="Task" _fullpath="Sequence/A" name="A" _uid="2"/>
      <SubTree ID="Task" _fullpath="Sequence/B" name="B" _uid="4"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Task" _fullpath="Sequence/A"><Sleep _uid="3" msec="10"/></BehaviorTree>
  <BehaviorTree ID="Task" _fullpath="Sequence/B"><IsDone _uid="5"/></BehaviorTree>
  <TreeNodesModel><Condition ID="IsDone"/></TreeNodesModel>
</root>"#;
        let (view, uids) = TreeView::of_log_xml(xml).unwrap();
        let paths: Vec<&str> = view.nodes.iter().map(|n| n.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "Sequence",
                "Sequence/A",
                "Sequence/A/Sleep",
                "Sequence/B",
                "Sequence/B/IsDone"
            ]
        );
        assert_eq!(uids, [1, 2, 3, 4, 5]);
        assert_eq!(view.nodes[4].category, "condition");
        assert_eq!(view.nodes[1].category, "subtree");
        assert_eq!(view.nodes[0].children, [1, 3]);
        assert_eq!(view.nodes[2].ports["msec"], "10");
    }

    #[test]
    fn nav2s_runnable_conditions_are_conditions_in_the_watch_views_tree() {
        let xml = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <ReactiveFallback>
      <GoalUpdated/>
      <GlobalUpdatedGoal/>
      <RateController hz="1.0"><AlwaysSuccess/></RateController>
    </ReactiveFallback>
  </BehaviorTree>
</root>"#;
        let mut registry = neurotree_toolkit::Registry::<()>::new();
        neurotree_nav2::register_controls(&mut registry).unwrap();
        let mut loader = neurotree_toolkit::XmlLoader::new(&registry);
        loader.load_str(xml, "t.xml").unwrap();
        let view = TreeView::of_blueprint(&loader.build_main().unwrap(), "Main");
        let categories: Vec<&str> = view.nodes.iter().map(|n| n.category).collect();
        assert_eq!(
            categories,
            ["control", "condition", "condition", "decorator", "action"]
        );
    }

    #[test]
    fn a_blueprint_view_carries_the_ports_nodes_draw() {
        let xml = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence>
      <Repeat num_cycles="3"><Script code="x := 1"/></Repeat>
      <SubTree ID="Task" goal="{target}" speed="2"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Task"><Sleep msec="{goal}"/></BehaviorTree>
</root>"#;
        let registry = neurotree_toolkit::Registry::<()>::new();
        let mut loader = neurotree_toolkit::XmlLoader::new(&registry);
        loader.load_str(xml, "t.xml").unwrap();
        let view = TreeView::of_blueprint(&loader.build_main().unwrap(), "Main");
        let ports = |path: &str| {
            let node = view.nodes.iter().find(|n| n.path == path).unwrap();
            Value::Object(node.ports.clone())
        };
        // A built-in's parameter, which the engine keeps in the node's kind, is a port.
        assert_eq!(
            ports("Sequence/Repeat"),
            serde_json::json!({"num_cycles": "3"})
        );
        assert_eq!(
            ports("Sequence/Repeat/Script"),
            serde_json::json!({"code": "x := 1"})
        );
        assert_eq!(
            ports("Sequence/Task"),
            serde_json::json!({"goal": "{target}", "speed": "2"})
        );
        assert_eq!(
            ports("Sequence/Task/Sleep"),
            serde_json::json!({"msec": "{goal}"})
        );
        assert_eq!(ports("Sequence"), serde_json::json!({}));
    }

    #[test]
    fn a_subtree_that_opens_itself_is_not_followed_forever() {
        let xml = r#"<root main_tree_to_execute="T">
  <BehaviorTree ID="T"><SubTree ID="T" _uid="1"/></BehaviorTree>
</root>"#;
        let (view, _) = TreeView::of_log_xml(xml).unwrap();
        assert!(view.nodes.len() <= 258, "{}", view.nodes.len());
    }
}

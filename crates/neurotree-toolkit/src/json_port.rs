//! Port values written as JSON, as BehaviorTree.CPP reads a `json:` prefix.

use neurotree_core::FromPortStr;
use serde::de::DeserializeOwned;

/// A port value given as JSON text: `json:{"x": 1.0, "y": 2.0}` (BehaviorTree.CPP's form) or
/// the JSON alone. Any type that implements `serde::Deserialize` can be read this way, and a
/// literal is checked when the tree is loaded, like every other port type.
///
/// ```
/// use neurotree::{Json, PortSpec, Registry, Status, XmlLoader};
///
/// #[derive(serde::Deserialize, Clone, Debug, PartialEq)]
/// struct Goal { x: f64, y: f64 }
///
/// let mut registry = Registry::<Vec<Goal>>::new();
/// registry.register_action("GoTo", vec![PortSpec::input::<Json<Goal>>("goal")], |h| {
///     let Ok(Json(goal)) = h.input::<Json<Goal>>("goal") else { return Status::Failure };
///     h.ctx_mut().push(goal);
///     Status::Success
/// }).unwrap();
/// let mut loader = XmlLoader::new(&registry);
/// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
///     <GoTo goal='json:{"x": 1.5, "y": -2}'/>
///   </BehaviorTree></root>"#, "goal.xml").unwrap();
/// let mut tree = neurotree::Tree::with_clock(loader.build_main().unwrap().into(), neurotree::ManualClock::new());
/// let mut visited = Vec::new();
/// assert_eq!(tree.tick_once(&mut visited), Ok(Status::Success));
/// assert_eq!(visited, [Goal { x: 1.5, y: -2.0 }]);
///
/// // A literal that is not the type's JSON is refused when the file is loaded.
/// let mut bad = XmlLoader::new(&registry);
/// bad.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
///     <GoTo goal='json:{"x": "east"}'/>
///   </BehaviorTree></root>"#, "bad.xml").unwrap();
/// assert!(bad.build_main().unwrap_err().message.contains("cannot read"));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Json<T>(pub T);

impl<T: DeserializeOwned> FromPortStr for Json<T> {
    fn from_port_str(text: &str) -> Result<Self, ()> {
        let text = text.trim();
        let json = text.strip_prefix("json:").unwrap_or(text);
        serde_json::from_str(json).map(Json).map_err(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_with_and_without_the_prefix() {
        assert_eq!(
            Json::<Vec<i32>>::from_port_str("json:[1, 2]"),
            Ok(Json(vec![1, 2]))
        );
        assert_eq!(Json::<Vec<i32>>::from_port_str(" [3] "), Ok(Json(vec![3])));
        assert_eq!(Json::<f64>::from_port_str("json:2.5"), Ok(Json(2.5)));
        assert_eq!(Json::<Vec<i32>>::from_port_str("json:[1,"), Err(()));
        assert_eq!(Json::<bool>::from_port_str("json:3"), Err(()));
    }
}

//! The value types a registry's trees show, edit and save their blackboard values with.

use std::any::Any;
use std::sync::Arc;

use neurotree_core::state::StateCodecs;
use serde::de::DeserializeOwned;
use serde::Serialize;

use super::Registry;

impl<C: 'static> Registry<C> {
    /// Makes values of type `T` JSON wherever a blackboard of a tree this registry loads is
    /// shown or edited (the studio, `run`'s summary, the Groot2 monitor, traces), and lets
    /// them be saved with the tree's state. Register a type once, before loading.
    ///
    /// ```
    /// use neurotree::prelude::*;
    /// use neurotree::ScopeId;
    ///
    /// #[derive(Clone, serde::Serialize, serde::Deserialize)]
    /// struct Pose { x: f64, y: f64 }
    ///
    /// let mut registry = Registry::<()>::new();
    /// registry.register_value::<Pose>();
    /// let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#;
    /// let mut tree = registry.load_str(xml, "m.xml", ManualClock::new()).unwrap();
    /// tree.blackboard_mut().set("goal", Pose { x: 1.0, y: 2.0 }).unwrap();
    /// assert_eq!(
    ///     tree.blackboard().json_in(ScopeId::ROOT, "goal"),
    ///     Some(serde_json::json!({"x": 1.0, "y": 2.0}))
    /// );
    /// ```
    pub fn register_value<T>(&mut self)
    where
        T: Serialize + DeserializeOwned + Any + Send + Sync,
    {
        Arc::make_mut(&mut self.value_codecs).add::<T>();
    }

    /// The value codecs the trees loaded with this registry get
    /// ([`register_value`](Self::register_value)).
    pub fn value_codecs(&self) -> &Arc<StateCodecs> {
        &self.value_codecs
    }
}

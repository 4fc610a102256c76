//! Enum names, as BehaviorTree.CPP's `registerScriptingEnum` defines them: names that
//! scripts and number ports read as numbers.

use std::sync::Arc;

use super::{Registry, RegistryError};
use crate::script::Enums;

impl<C: 'static> Registry<C> {
    /// Defines the enum name `name` as `value`, as BehaviorTree.CPP's
    /// `registerScriptingEnum` does: scripts may write `state == DOCKING`, and a literal port
    /// value `DOCKING` reads as the number wherever the port wants a number. Trees loaded
    /// afterwards see it. Redefining a name with another value is an error.
    ///
    /// ```
    /// use neurotree::{Registry, XmlLoader, ManualClock, Status, Tree};
    ///
    /// let mut registry = Registry::<()>::new();
    /// registry.register_enums([("IDLE", 0), ("DOCKING", 2)]).unwrap();
    /// let mut loader = XmlLoader::new(&registry);
    /// loader.load_str(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
    ///     <Sequence>
    ///       <Script code="state := DOCKING"/>
    ///       <ScriptCondition code="state == DOCKING &amp;&amp; state != IDLE"/>
    ///       <Repeat num_cycles="DOCKING"><AlwaysSuccess/></Repeat>
    ///     </Sequence>
    ///   </BehaviorTree></root>"#, "enums.xml").unwrap();
    /// let mut tree = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    /// assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    /// assert_eq!(tree.blackboard().get::<i64>("state"), Ok(2));
    /// ```
    pub fn register_enum(&mut self, name: &str, value: i64) -> Result<(), RegistryError> {
        match self.enums.get(name) {
            Some(old) if old != value => Err(RegistryError::EnumRedefined {
                name: name.to_string(),
                old,
                new: value,
            }),
            Some(_) => Ok(()),
            None => {
                Arc::make_mut(&mut self.enums).insert(name, value);
                Ok(())
            }
        }
    }

    /// Defines several enum names (see [`register_enum`](Self::register_enum)).
    pub fn register_enums<'n>(
        &mut self,
        values: impl IntoIterator<Item = (&'n str, i64)>,
    ) -> Result<(), RegistryError> {
        values
            .into_iter()
            .try_for_each(|(name, value)| self.register_enum(name, value))
    }

    /// The enum names defined so far.
    pub fn enums(&self) -> &Arc<Enums> {
        &self.enums
    }
}

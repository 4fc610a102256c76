//! What a registry holds, read back: its types one by one and the ports' directions.

use super::{NodeType, Registry};

impl<C> Registry<C> {
    /// The type registered as `name`.
    pub fn get(&self, name: &str) -> Option<&NodeType<C>> {
        self.types.get(name)
    }

    /// Every registered type, by name.
    pub fn types(&self) -> impl Iterator<Item = &NodeType<C>> {
        self.types.values()
    }

    /// Which way each port of each registered type carries data, as the trees it loads
    /// carry it for their pictures to mark ([`Blueprint::port_direction`](neurotree_core::Blueprint::port_direction)).
    pub fn port_directions(&self) -> neurotree_core::PortDirections {
        let mut directions = neurotree_core::PortDirections::new();
        for node_type in self.types.values() {
            for port in &node_type.ports {
                directions.insert(&node_type.name, &port.name, port.direction);
            }
        }
        directions
    }
}

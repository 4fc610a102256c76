//! The blackboard a new instance of a blueprint starts with.

use core::time::Duration;

use crate::blackboard::Blackboard;
use crate::blueprint::Blueprint;

/// A blackboard with the scopes of `blueprint`'s SubTrees, their remaps and literal values,
/// and an entry declared for every key a port names, as BehaviorTree.CPP makes one.
pub(super) fn new_blackboard<C>(blueprint: &Blueprint<C>) -> Blackboard {
    let mut blackboard = Blackboard::new();
    if let Some(codecs) = &blueprint.value_codecs {
        blackboard.set_codecs(codecs.clone());
    }
    for (parent, scope) in blueprint.scopes.iter() {
        let id = blackboard.add_scope(*parent, scope.autoremap);
        for (child_key, parent_key) in &scope.remap {
            blackboard.remap(id, child_key, parent_key);
        }
        // The subtree's own entries: never written through autoremap into the parent.
        // Numbers typed as BehaviorTree.CPP 4.10 types them, so that scripts can
        // compute with them.
        for (child_key, text) in &scope.values {
            match crate::blueprint::Literal::parse(text) {
                crate::blueprint::Literal::Int(i) => {
                    blackboard.replace_own_in(id, child_key, i, Duration::ZERO)
                }
                crate::blueprint::Literal::Long(i) => {
                    blackboard.replace_own_in(id, child_key, i, Duration::ZERO)
                }
                crate::blueprint::Literal::Real(r) => {
                    blackboard.replace_own_in(id, child_key, r, Duration::ZERO)
                }
                crate::blueprint::Literal::Text(t) => {
                    blackboard.replace_own_in(id, child_key, t, Duration::ZERO)
                }
            }
        }
    }
    // As in BehaviorTree.CPP, every entry a port names exists from the start.
    for id in blueprint.ids() {
        for port in blueprint.ports(id) {
            if let crate::PortValue::Entry(key) = &port.value {
                blackboard.declare_in(blueprint.scope(id), key);
            }
        }
    }
    blackboard
}

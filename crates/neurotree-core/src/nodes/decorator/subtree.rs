//! SubTree: a child tree with its own blackboard scope.
//!
//! Own blackboard scope with remapping; passes the child's status.
//!
//! The scope is created with the tree instance from the blueprint's
//! [`SubTreeScope`](crate::SubTreeScope): remapped keys alias the parent's entries, and with
//! `autoremap` every key the child does not define resolves in the parent, except keys
//! starting with `_`. Keys starting with `@` always address the root scope. A literal port
//! value (`values`) is an entry of the child scope itself, even with `autoremap`: as
//! BehaviorTree.CPP, which turns autoremapping off while it sets them, it is never written
//! into the parent.

use crate::blueprint::NodeDef;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

#[inline(never)]
pub(crate) fn tick<C>(t: &mut Ticker<'_, C>, id: NodeId, def: &NodeDef<C>) -> NodeStatus {
    t.set_status(id, NodeStatus::Running);
    let child = t.child(def, 0);
    let status = t.tick(child);
    if status.is_completed() {
        t.halt_child(child);
    }
    status
}

#[cfg(test)]
mod tests {
    use crate::testing::*;
    use crate::{Action, Handle, SubTreeScope};

    struct Write(&'static str, i64);
    impl Action<Lab> for Write {
        fn tick(&self, h: &mut Handle<'_, Lab>) -> Status {
            h.set(self.0, self.1).is_ok().into()
        }
    }

    #[test]
    fn remapped_keys_write_the_parent() {
        let scope = SubTreeScope {
            remap: vec![("goal".into(), "target".into())],
            autoremap: false,
            values: vec![],
        };
        let mut lab = Lab::new(&[]);
        let mut tree = lab.tree(|b| {
            b.sequence("root", |s| {
                s.subtree("sub", scope, |t| {
                    t.sequence("inner", |i| {
                        i.action_node("w1", Write("goal", 7))
                            .action_node("w2", Write("local", 1))
                    })
                })
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(tree.blackboard().get::<i64>("target"), Ok(7));
        assert!(!tree.blackboard().contains("local"));
        let inner = tree.subtree_scope(NodeId(1)).unwrap();
        assert_eq!(tree.blackboard().get_in::<i64>(inner, "local"), Ok(1));
    }

    #[test]
    fn literal_values_seed_the_child_scope() {
        // Typed as BehaviorTree.CPP 4.10 types them: numbers as numbers, the rest as text.
        let scope = SubTreeScope {
            remap: vec![],
            autoremap: false,
            values: vec![
                ("speed".into(), "0.5".into()),
                ("laps".into(), "3".into()),
                ("name".into(), "kitchen".into()),
            ],
        };
        let lab = Lab::new(&[]);
        let tree = lab.tree(|b| b.subtree("sub", scope, |t| t.always_success("x")));
        let inner = tree.subtree_scope(NodeId(0)).unwrap();
        let bb = tree.blackboard();
        assert_eq!(bb.get_in::<f64>(inner, "speed"), Ok(0.5));
        assert_eq!(bb.get_in::<i32>(inner, "laps"), Ok(3));
        assert_eq!(
            bb.get_in::<String>(inner, "name"),
            Ok(String::from("kitchen"))
        );
        assert!(!bb.contains("speed"));
    }
}

//! The goals a Nav2 goal node last saw, and how it reads the current ones.
//!
//! GoalUpdated, GlobalUpdatedGoal and GoalUpdatedController all compare the `goal` and
//! `goals` they read now with the ones they remembered. Nav2 reads each with
//! `getInputOrBlackboard`: the port if it is given and readable, else the blackboard entry
//! named like the port; a value found nowhere leaves the reader's variable as it was. So
//! remembering a missing goal keeps the old one, and a missing current goal compares as the
//! empty one.

use std::any::{type_name, Any};
use std::borrow::Cow;

use neurotree_core::{Blackboard, FromPortStr, NodeCtx, Port, PortValue, ScopeId};

use crate::robotics::Pose2D;

/// The `goal` and `goals` a node saw last.
#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct SeenGoals {
    goal: Pose2D,
    goals: Vec<Pose2D>,
}

impl SeenGoals {
    /// Remembers the current goals; one that cannot be found keeps its remembered value.
    pub(crate) fn remember<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Result<(), String> {
        let (ports, scope) = (node.ports(), node.scope());
        let bb = &*node.blackboard();
        if let Some(goal) = read::<Pose2D>(bb, scope, ports, "goal")? {
            self.goal = *goal;
        }
        if let Some(goals) = read::<Vec<Pose2D>>(bb, scope, ports, "goals")? {
            self.goals.clone_from(&goals);
        }
        Ok(())
    }

    /// `true` if the current goals differ from the remembered ones, which they then replace.
    /// A goal that cannot be found is the empty one: the origin, or no goals.
    pub(crate) fn update<C>(&mut self, node: &mut NodeCtx<'_, '_, C>) -> Result<bool, String> {
        let (ports, scope) = (node.ports(), node.scope());
        let bb = &*node.blackboard();
        let goal = read::<Pose2D>(bb, scope, ports, "goal")?.map_or_else(Pose2D::default, |g| *g);
        let goals = read::<Vec<Pose2D>>(bb, scope, ports, "goals")?;
        let goals: &[Pose2D] = match &goals {
            Some(goals) => goals,
            None => &[],
        };
        if goal == self.goal && goals == self.goals.as_slice() {
            return Ok(false);
        }
        self.goal = goal;
        // Reuses the remembered vector's memory: no allocation unless the list grew.
        self.goals.clear();
        self.goals.extend_from_slice(goals);
        Ok(true)
    }
}

/// Entry `key` (no port) as a `T`, owned: see [`entry`].
pub(crate) fn entry_owned<C, T>(
    node: &mut NodeCtx<'_, '_, C>,
    key: &str,
) -> Result<Option<T>, String>
where
    T: FromPortStr + Any + Clone,
{
    let scope = node.scope();
    entry::<T>(node.blackboard(), scope, key, key).map(|v| v.map(Cow::into_owned))
}

/// The value of `port` as Nav2 reads it: the port's literal or entry if that gives a value,
/// else the entry named `port`. Borrowed from the blackboard where it can be, so that
/// comparing a list of goals allocates nothing. A value of another type is an error.
pub(crate) fn read<'b, T>(
    bb: &'b Blackboard,
    scope: ScopeId,
    ports: &[Port],
    port: &str,
) -> Result<Option<Cow<'b, T>>, String>
where
    T: FromPortStr + Any + Clone,
{
    match ports.iter().find(|p| p.name == port).map(|p| &p.value) {
        Some(PortValue::Literal(text)) => {
            if let Ok(value) = T::from_port_str(text) {
                return Ok(Some(Cow::Owned(value)));
            }
        }
        Some(PortValue::Entry(key)) => {
            if let Some(value) = entry(bb, scope, port, key)? {
                return Ok(Some(value));
            }
        }
        None => {}
    }
    entry(bb, scope, port, port)
}

/// Entry `key` as a `T`: the value itself, or text converted; `None` if it was never written.
pub(crate) fn entry<'b, T>(
    bb: &'b Blackboard,
    scope: ScopeId,
    port: &str,
    key: &str,
) -> Result<Option<Cow<'b, T>>, String>
where
    T: FromPortStr + Any + Clone,
{
    let Some(any) = bb.get_any_in(scope, key) else {
        return Ok(None);
    };
    if let Some(value) = any.downcast_ref::<T>() {
        return Ok(Some(Cow::Borrowed(value)));
    }
    match any.downcast_ref::<String>() {
        Some(text) => T::from_port_str(text)
            .map(|value| Some(Cow::Owned(value)))
            .map_err(|()| {
                format!(
                    "`{port}`: entry `{key}` holds `{text}`, which is not a {}",
                    type_name::<T>()
                )
            }),
        None => Err(format!(
            "`{port}`: entry `{key}` holds a {}, not a {}",
            bb.info_in(scope, key).map_or("value", |i| i.type_name),
            type_name::<T>()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ports(bindings: &[(&str, &str, bool)]) -> Vec<Port> {
        bindings
            .iter()
            .map(|&(name, text, entry)| {
                if entry {
                    Port::entry(name, text)
                } else {
                    Port::literal(name, text)
                }
            })
            .collect()
    }

    fn goal(bb: &Blackboard, ports: &[Port]) -> Result<Option<Pose2D>, String> {
        read::<Pose2D>(bb, ScopeId::ROOT, ports, "goal").map(|g| g.map(Cow::into_owned))
    }

    #[test]
    fn the_port_comes_first_then_the_entry_named_like_it() {
        let mut bb = Blackboard::new();
        bb.set("goal", Pose2D::new(1.0, 1.0, 0.0)).unwrap();
        bb.set("target", Pose2D::new(2.0, 2.0, 0.0)).unwrap();
        let a = Some(Pose2D::new(1.0, 1.0, 0.0));
        assert_eq!(goal(&bb, &[]), Ok(a));
        let bound = ports(&[("goal", "target", true)]);
        assert_eq!(goal(&bb, &bound), Ok(Some(Pose2D::new(2.0, 2.0, 0.0))));
        let literal = ports(&[("goal", "3;4", false)]);
        assert_eq!(goal(&bb, &literal), Ok(Some(Pose2D::new(3.0, 4.0, 0.0))));
        // A port whose entry was never written falls back to the `goal` entry.
        let unwritten = ports(&[("goal", "nowhere", true)]);
        assert_eq!(goal(&bb, &unwritten), Ok(a));
    }

    #[test]
    fn missing_is_none_text_converts_and_another_type_is_an_error() {
        let mut bb = Blackboard::new();
        assert_eq!(goal(&bb, &[]), Ok(None));
        bb.set("goal", String::from("5;6;0.5")).unwrap();
        assert_eq!(goal(&bb, &[]), Ok(Some(Pose2D::new(5.0, 6.0, 0.5))));
        bb.replace_in(
            ScopeId::ROOT,
            "goal",
            String::from("north"),
            Default::default(),
        );
        let err = goal(&bb, &[]).unwrap_err();
        assert!(err.contains("north"), "{err}");
        bb.replace_in(ScopeId::ROOT, "goal", 7_i32, Default::default());
        let err = goal(&bb, &[]).unwrap_err();
        assert!(err.contains("i32") && err.contains("Pose2D"), "{err}");
    }

    #[test]
    fn a_list_of_goals_is_borrowed_not_copied() {
        let mut bb = Blackboard::new();
        let list = vec![Pose2D::new(1.0, 0.0, 0.0), Pose2D::new(2.0, 0.0, 0.0)];
        bb.set("goals", list.clone()).unwrap();
        let read = read::<Vec<Pose2D>>(&bb, ScopeId::ROOT, &[], "goals").unwrap();
        assert!(matches!(read, Some(Cow::Borrowed(goals)) if *goals == list));
    }
}

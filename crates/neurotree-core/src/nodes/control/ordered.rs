//! The loop shared by Sequence and Fallback, which mirror each other: a Sequence moves on
//! while its children succeed and stops at the first failure, a Fallback moves on while they
//! fail and stops at the first success. See [`sequence`](super::sequence) and
//! [`fallback`](super::fallback) for the semantics.

use super::{pack, unpack};
use crate::blueprint::call::Args;
use crate::blueprint::{Child, Hot, NodeDef};
use crate::tree::calls;
use crate::tree::Ticker;
use crate::{NodeId, NodeStatus};

/// Which member of a family is ticking.
pub(crate) type Flavor = u8;
/// Sequence, Fallback.
pub(crate) const PLAIN: Flavor = 0;
/// SequenceWithMemory: a failure and a halt keep the cursor; yields.
pub(crate) const MEMORY: Flavor = 1;
/// AsyncSequence, AsyncFallback: yields after each child that completed from Idle.
pub(crate) const ASYNC: Flavor = 2;

/// Ticks a Sequence (`SEQUENCE`) or a Fallback (`!SEQUENCE`) of the given flavor; the
/// parameters are constants so that each node compiles to its own loop.
#[inline(never)]
pub(crate) fn tick<C, const SEQUENCE: bool, const FLAVOR: Flavor>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    if t.observed() {
        run::<C, SEQUENCE, FLAVOR, true>(t, id, def)
    } else if FLAVOR == PLAIN {
        run_quiet::<C, SEQUENCE>(t, id, def)
    } else {
        run::<C, SEQUENCE, FLAVOR, false>(t, id, def)
    }
}

#[inline(always)]
fn run<C, const SEQUENCE: bool, const FLAVOR: Flavor, const OBSERVED: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    // The outcome that moves the loop on, and the one that ends it.
    let (go_on, stop) = if SEQUENCE {
        (NodeStatus::Success, NodeStatus::Failure)
    } else {
        (NodeStatus::Failure, NodeStatus::Success)
    };
    let bp = t.bp;
    let children = bp.children_of(def);
    let hot = bp.hot_children_of(def);
    let slot = t.bp.slot(id);
    let n = children.len() as u32;
    let (mut cursor, mut skipped) = unpack(t.aux, slot, children.len());
    if !t.status(id).is_active() {
        skipped = 0;
    }
    t.set_status(id, NodeStatus::Running);
    while let Some(child) = hot.get(cursor as usize) {
        let prev = if FLAVOR == PLAIN {
            NodeStatus::Running
        } else {
            t.status(child.id)
        };
        // An if-chain rather than a match: the common case costs one predictable compare
        // instead of an indirect jump through a table.
        let status = t.tick_child::<OBSERVED>(child);
        if status == go_on {
            cursor += 1;
            if FLAVOR != PLAIN && prev == NodeStatus::Idle && cursor < n {
                t.wake = Some(id);
                pack(t.aux, slot, children.len(), cursor, skipped);
                return NodeStatus::Running;
            }
        } else if status == NodeStatus::Running {
            pack(t.aux, slot, children.len(), cursor, skipped);
            return NodeStatus::Running;
        } else if status == NodeStatus::Skipped {
            cursor += 1;
            skipped += 1;
        } else {
            // `stop` (Idle never leaves `Ticker::tick`).
            if FLAVOR == MEMORY {
                t.halt_children_from(def, cursor);
            } else {
                // Children past the cursor are Idle already.
                t.reset_completed(&children[..=cursor as usize]);
                cursor = 0;
            }
            pack(t.aux, slot, children.len(), cursor, skipped);
            if FLAVOR != PLAIN {
                // Ticked again, it would yield between its children.
                t.answers_otherwise_next(id);
            }
            return stop;
        }
    }
    if FLAVOR != PLAIN {
        t.answers_otherwise_next(id);
    }
    let all_skipped = skipped == n;
    t.reset_completed(children);
    pack(t.aux, slot, children.len(), 0, 0);
    if all_skipped {
        NodeStatus::Skipped
    } else {
        go_on
    }
}

/// Ticks a plain Sequence (`SEQUENCE`) or Fallback whose children are all conditions
/// called from the child list: closures (`CLOSURES`) or `Condition` objects. Such a node
/// completes in every tick, so with no observer its loop is the calls alone: no status is
/// stored for the children (see [`run_quiet`]), none for the node until it returns, and
/// its cursor stays at the start.
// Inlined into its one caller in optimised builds (a call less per guard, 5 % of
// tree1111's tick); kept apart without optimisation, where its frame would add to every
// level of a deep tree's recursion (`tests/depth.rs` ticks 400 levels on a 2 MB stack).
#[cfg_attr(debug_assertions, inline(never))]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn tick_guard<C, const SEQUENCE: bool, const CLOSURES: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    if t.observed() {
        return run::<C, SEQUENCE, PLAIN, true>(t, id, def);
    }
    let hot = t.bp.hot_children_of(def);
    guard::<C, SEQUENCE, CLOSURES>(t, id, hot, true)
}

/// A guard's loop with no observer (see [`tick_guard`]): the calls of its conditions
/// `calls` (at least one), in order, until one decides (see [`calls`]). Run by the guard's parent in its
/// own loop when the parent is a quiet Sequence or Fallback ([`run_quiet`]), as if the
/// guard were one condition: its status is stored only if the parent returns Running.
/// `tracked`: the guard is under a node that re-checks it, and asks after the calls of its
/// `Condition` objects whether one may read more than the blackboard (elsewhere no call
/// notes it, and nobody would ask).
#[inline(always)]
fn guard<C, const SEQUENCE: bool, const CLOSURES: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    calls: &[Child],
    tracked: bool,
) -> NodeStatus {
    let (go_on, stop) = if SEQUENCE {
        (NodeStatus::Success, NodeStatus::Failure)
    } else {
        (NodeStatus::Failure, NodeStatus::Success)
    };
    debug_assert!(!calls.is_empty());
    let decided = if CLOSURES {
        // Closures of the context: they may read anything.
        t.waits.opaque(id);
        let mut args = Args::new(&raw const *t.ctx);
        // SAFETY: a guard of closures' children are closure conditions of `C`
        // (`Child::new`), called with the context, which nothing else borrows meanwhile;
        // the answer that decided is asked about once.
        unsafe { calls::until::<_, SEQUENCE>(calls, &mut args) }
            .map(|(call, answer)| (call.id, unsafe { args.panicked(answer) }))
    } else {
        let mut args = Args::new(t.handle(id));
        // SAFETY: as above, for `Condition` objects of `C`, called with a handle to the
        // ticker's state that only they use.
        let decided = unsafe { calls::until::<_, SEQUENCE>(calls, &mut args) }
            .map(|(call, answer)| (call.id, unsafe { args.panicked(answer) }));
        if tracked && t.out.reads.take_opaque() {
            t.waits.opaque(id);
        }
        decided
    };
    match decided {
        None => {
            // A Fallback of conditions that all failed: each one is part of why.
            if !SEQUENCE {
                for call in calls {
                    t.mark_failed(call.id);
                }
            }
            go_on
        }
        Some((node, Some(payload))) => t.resume_panic(node, payload),
        Some((node, None)) => {
            if SEQUENCE {
                t.mark_failed(node);
            }
            stop
        }
    }
}

/// A plain Sequence or Fallback with no observer: the most common node, made cheap.
///
/// A condition child called straight from the child list (a closure, or a registered
/// condition), or a guard of such conditions whose loop runs here, gets no status stored
/// while the loop runs: if the node completes in this
/// call, it resets every child it ticked to Idle anyway, so no one could see the status.
/// Only when the node returns Running do the statuses of the conditions that moved it on
/// outlive the call; they are written then. The reset at completion so covers the children
/// ticked in earlier calls, and those ticked now only if one of them was no such condition.
#[inline(always)]
fn run_quiet<C, const SEQUENCE: bool>(
    t: &mut Ticker<'_, C>,
    id: NodeId,
    def: &NodeDef<C>,
) -> NodeStatus {
    let go_on = if SEQUENCE {
        NodeStatus::Success
    } else {
        NodeStatus::Failure
    };
    let bp = t.bp;
    let children = bp.children_of(def);
    let hot = bp.hot_children_of(def);
    let slot = bp.slot(id);
    let (start, mut skipped) = unpack(t.aux, slot, children.len());
    if !t.status(id).is_active() {
        skipped = 0;
    }
    *t.status_mut(id) = NodeStatus::Running;
    let start = (start as usize).min(hot.len());
    // Whether a child stored its own status (it was no condition called from the list).
    let mut stored = false;
    let mut rest = hot[start..].iter();
    let ended = loop {
        let Some(child) = rest.next() else {
            break None;
        };
        let status = match child.hot() {
            // Which node a panic came from is written only if one ends the call: a store
            // per condition would cost this loop a tenth of its time.
            Hot::Closure => NodeStatus::from(crate::Status::from(t.check(child, true, false))),
            Hot::Condition(tracked) => {
                NodeStatus::from(crate::Status::from(t.check(child, false, tracked)))
            }
            // A guard completes in this call, like a condition: its status, like theirs,
            // is stored only if this node returns Running.
            Hot::Guard(sequence, closures, tracked, range) => {
                let calls = bp.hot_range(range);
                match (sequence, closures) {
                    (true, true) => guard::<C, true, true>(t, child.id, calls, false),
                    (false, true) => guard::<C, false, true>(t, child.id, calls, false),
                    (true, false) => guard::<C, true, false>(t, child.id, calls, tracked),
                    (false, false) => guard::<C, false, false>(t, child.id, calls, tracked),
                }
            }
            Hot::Other => {
                stored = true;
                t.tick_child_stored(child)
            }
        };
        if status == go_on {
            continue;
        }
        if status == NodeStatus::Skipped {
            skipped += 1;
            continue;
        }
        // The child that failed a Sequence is marked for `Tree::last_failure`: its status
        // is stored only if this node returns Running.
        if status == NodeStatus::Failure {
            t.mark_failed(child.id);
        }
        break Some(status);
    };
    // The index just past the child the loop stopped at (or the end).
    let end = hot.len() - rest.len();
    // The children to reset if the node completes: those ticked in earlier calls, and those
    // ticked now if one of them stored its status.
    let ticked = if stored { end } else { start };
    match ended {
        None => {
            // A Fallback that failed: the conditions and guards it called in this run
            // failed (none of them can be skipped), and are marked now, once the node is
            // known to fail; the others marked themselves when they stored their status.
            if !SEQUENCE && skipped as usize != hot.len() {
                for child in &hot[start..end] {
                    if !matches!(child.hot(), Hot::Other) {
                        t.mark_failed(child.id);
                    }
                }
            }
            t.reset_completed(&children[..ticked]);
            pack(t.aux, slot, children.len(), 0, 0);
            if skipped as usize == hot.len() {
                NodeStatus::Skipped
            } else {
                go_on
            }
        }
        Some(NodeStatus::Running) => {
            let cursor = end - 1;
            for child in &hot[start..cursor] {
                if child.is_fast() {
                    *t.status_mut(child.id) = go_on;
                    // A Fallback's conditions that failed before its running child failed
                    // in this tick: marked, as storing their status marks them when the
                    // node is observed, for a later pass of the same tick to explain.
                    if !SEQUENCE {
                        t.mark_failed(child.id);
                    }
                }
            }
            pack(t.aux, slot, children.len(), cursor as u32, skipped);
            NodeStatus::Running
        }
        Some(stop) => {
            // Children past the one that stopped the node are Idle already.
            t.reset_completed(&children[..ticked]);
            pack(t.aux, slot, children.len(), 0, skipped);
            stop
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::*;
    use crate::Condition;
    use NodeStatus::{Failure as Fl, Idle as I, Running as Rn, Success as Sc};

    /// A registered-style condition object: called from the child list like a closure.
    struct Holds(bool);
    impl Condition<Lab> for Holds {
        fn check(&self, _h: &crate::Handle<'_, Lab>) -> bool {
            self.0
        }
    }

    /// Ids in builder order: 0 the control, then its children.
    fn statuses(tree: &Tree<Lab>) -> Vec<NodeStatus> {
        tree.statuses().to_vec()
    }

    #[test]
    fn a_node_of_more_children_than_a_narrow_slot_counts_resumes_at_its_cursor() {
        use crate::nodes::control::{ordered_slots, NARROW_CHILDREN};
        // Past 65,534 children the cursor takes a slot of its own: the Sequence resumes at
        // child 69,999, not at that index cut to 16 bits (4,463).
        let n = 70_000;
        assert_eq!(ordered_slots(n as u32), 2);
        assert_eq!(ordered_slots(NARROW_CHILDREN), 1);
        let mut lab = Lab::new(&[]);
        lab.scripts = vec![vec![S]; n];
        lab.scripts[n - 1] = vec![R, S];
        lab.ticks = vec![0; n];
        lab.halts = vec![0; n];
        lab.logs = vec![Vec::new(); n];
        let mut tree = lab.tree(|b| b.sequence("s", |s| (0..n).fold(s, |s, i| s.scripted(i))));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert!(lab.ticks[..n - 1].iter().all(|t| *t == 1));
        assert_eq!(lab.ticks[n - 1], 2);
    }

    #[test]
    fn a_narrow_slot_keeps_a_cursor_and_a_count_and_saves_them_as_before() {
        use crate::nodes::control::{pack, restored_ordered, saved_ordered, unpack};
        let mut aux = [0u32; 3];
        pack(&mut aux, 1, 65_534, 65_534, 17);
        assert_eq!(aux, [0, 65_534 | (17 << 16), 0]);
        assert_eq!(unpack(&aux, 1, 65_534), (65_534, 17));
        // A count past the children (which it is only compared with) stays past them.
        pack(&mut aux, 1, 9, 0, 70_000);
        assert_eq!(unpack(&aux, 1, 9), (0, 0xFFFF));
        // Wide: two slots.
        pack(&mut aux, 1, 70_000, 69_999, 70_000);
        assert_eq!(aux, [0, 69_999, 70_000]);
        assert_eq!(unpack(&aux, 1, 70_000), (69_999, 70_000));
        // Saved as a cursor and a count of 32 bits each, both ways, and a cursor past the
        // children is no state of the node.
        let value: u64 = 3 | (2 << 16);
        assert_eq!(saved_ordered(value, 5), 3 | (2 << 32));
        assert_eq!(restored_ordered(3 | (2 << 32), 5), Some(value));
        assert_eq!(restored_ordered(6, 5), None);
        assert_eq!(
            saved_ordered(69_999 | (7 << 32), 70_000),
            69_999 | (7 << 32)
        );
        assert_eq!(
            restored_ordered(69_999 | (7 << 32), 70_000),
            Some(69_999 | (7 << 32))
        );
    }

    #[test]
    fn conditions_before_a_running_child_keep_their_success_until_completion() {
        // A closure condition and a condition object move the Sequence on, the scripted
        // child runs: the two conditions hold Success between the ticks, not Idle.
        let mut lab = Lab::new(&[&[R, R, S], &[S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("seq", |s| {
                s.condition("c", |_: &Lab| true)
                    .condition_node("o", Holds(true))
                    .scripted(0)
                    .condition("d", |_: &Lab| true)
                    .scripted(1)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(statuses(&tree), [Rn, Sc, Sc, Rn, I, I]);
        // Resumed at the running child: the conditions are not asked again.
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(statuses(&tree), [Rn, Sc, Sc, Rn, I, I]);
        assert_eq!(lab.ticks, [2, 0]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(lab.ticks, [3, 1]);
        assert_eq!(statuses(&tree), [I, I, I, I, I, I]);
    }

    #[test]
    fn a_fallback_resets_conditions_ticked_in_earlier_calls_when_it_fails() {
        let mut lab = Lab::new(&[&[R, F]]);
        let mut tree = lab.tree(|b| {
            b.fallback("fb", |f| {
                f.condition("c", |_: &Lab| false)
                    .scripted(0)
                    .condition_node("o", Holds(false))
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        assert_eq!(statuses(&tree), [Rn, Fl, Rn, I]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(statuses(&tree), [I, I, I, I]);
        assert_eq!(lab.ticks, [2]);
    }

    #[test]
    fn a_sequence_of_conditions_only_leaves_every_child_idle() {
        let mut lab = Lab::new(&[]);
        let mut tree = lab.tree(|b| {
            b.sequence("seq", |s| {
                s.condition("c", |_: &Lab| true)
                    .condition_node("o", Holds(true))
                    .condition("d", |_: &Lab| false)
                    .condition("e", |_: &Lab| true)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Failure));
        assert_eq!(statuses(&tree), [I, I, I, I, I]);
    }

    #[test]
    fn guards_of_conditions_decide_and_hold_their_result_while_the_parent_runs() {
        // Ids: 0 seq, 1 closures (2 a, 3 b), 4 objects (5 o, 6 p), 7 scripted.
        let mut lab = Lab::new(&[&[R, S]]);
        let mut tree = lab.tree(|b| {
            b.sequence("seq", |s| {
                s.sequence("closures", |g| {
                    g.condition("a", |_: &Lab| true)
                        .condition("b", |_: &Lab| true)
                })
                .fallback("objects", |g| {
                    g.condition_node("o", Holds(false))
                        .condition_node("p", Holds(true))
                })
                .scripted(0)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Running));
        // The guards hold their Success while their parent runs; their conditions, never
        // stored, are Idle.
        assert_eq!(statuses(&tree), [Rn, Sc, I, I, Sc, I, I, Rn]);
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(statuses(&tree), [I; 8]);
        assert_eq!(lab.ticks, [2]);
    }

    #[test]
    fn a_failing_guard_stops_its_parent_at_the_first_deciding_condition() {
        let asked = Arc::new(core::sync::atomic::AtomicU32::new(0));
        let counted = |holds: bool| {
            let asked = Arc::clone(&asked);
            move |_: &Lab| {
                asked.fetch_add(1, core::sync::atomic::Ordering::Relaxed);
                holds
            }
        };
        let mut lab = Lab::new(&[&[S]]);
        let mut tree = lab.tree(|b| {
            b.fallback("fb", |f| {
                f.sequence("guard", |g| {
                    g.condition("yes", counted(true))
                        .condition("no", counted(false))
                        .condition("unasked", counted(true))
                })
                .scripted(0)
            })
        });
        assert_eq!(lab.tick(&mut tree), Ok(Status::Success));
        assert_eq!(asked.load(core::sync::atomic::Ordering::Relaxed), 2);
        assert_eq!(lab.ticks, [1]);
        assert_eq!(statuses(&tree), [I; 6]);
    }

    #[test]
    fn observed_and_quiet_loops_agree() {
        // The same tree with a recording observer attached ticks the stored loop; both end
        // every tick with the same statuses.
        let make = |lab: &Lab| {
            lab.tree(|b| {
                b.sequence("seq", |s| {
                    s.condition("c", |_: &Lab| true)
                        .fallback("fb", |f| f.condition_node("o", Holds(false)).scripted(0))
                        .fallback("guard", |g| {
                            g.condition_node("x", Holds(false))
                                .condition_node("y", Holds(true))
                        })
                        .sequence("closures", |g| {
                            g.condition("e", |_: &Lab| true)
                                .condition("f", |_: &Lab| true)
                        })
                        .condition("d", |_: &Lab| true)
                })
            })
        };
        let script: &[&[Status]] = &[&[R, R, S]];
        let (mut quiet_lab, mut observed_lab) = (Lab::new(script), Lab::new(script));
        let mut quiet = make(&quiet_lab);
        let mut observed = make(&observed_lab);
        observed.set_observer(Vec::<alloc::boxed::Box<dyn crate::Observer>>::new());
        for _ in 0..3 {
            let q = quiet_lab.tick(&mut quiet);
            assert_eq!(q, observed_lab.tick(&mut observed));
            assert_eq!(statuses(&quiet), statuses(&observed));
        }
        assert_eq!(quiet_lab.ticks, [3]);
    }
}

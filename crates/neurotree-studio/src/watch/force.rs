//! Results forced by hand: a page makes a node return SUCCESS, FAILURE or RUNNING at its
//! next tick (once) or at every tick until the force is cleared, in place of its own tick
//! (PROTOCOL.md, "Forced results").
//!
//! The forces ride on [`neurotree_toolkit::fault`]'s hooks: the tree is built with
//! [`live_wrapper`](neurotree_toolkit::fault::live_wrapper) over the hub, which answers from
//! its table here. A once-force remembers the tick it applied at: when a page goes back
//! before that tick and the run forks there, the force is due again.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

use neurotree_core::{NodeId, Status};
use neurotree_toolkit::fault::{parse_status, status_name, LiveFaults};
use serde_json::{json, Value};

use super::hub::Hub;

/// One node's force, as set by a page.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Force {
    node: u32,
    status: Status,
    /// At every tick until cleared, else once.
    until_cleared: bool,
    /// The tick a once-force applied at; `None` while it is due.
    applied: Option<u64>,
}

/// A force that applied: what the run's log says of it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Forced {
    /// The tick it applied in (the watch's count, as pages show it).
    pub tick: u64,
    /// The node's path.
    pub node: String,
    /// What the node returned.
    pub status: Status,
    /// A force that stands until cleared, else one that applied once.
    pub until_cleared: bool,
}

impl Forced {
    /// `{"tick":T,"node":PATH,"status":S,"until":"once"|"cleared"}`.
    pub fn json(&self) -> Value {
        json!({
            "tick": self.tick,
            "node": self.node,
            "status": status_name(self.status),
            "until": until(self.until_cleared),
        })
    }
}

fn until(cleared: bool) -> &'static str {
    if cleared {
        "cleared"
    } else {
        "once"
    }
}

/// The most applications kept for the run to read: a force until cleared applies at every
/// tick, and a program that never reads them ([`crate::Watch::forced`]) must not grow
/// without end; past it, the oldest are forgotten.
const MOST_LOGGED: usize = 4096;

/// A node Running under a forced RUNNING, from the tick it was forced to the tick it was
/// halted: kept after it ends, so that a run gone back to inside it finds the node hanging
/// again, and forgotten when the run goes back to before it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Hang {
    node: u32,
    from: u64,
    until: Option<u64>,
}

#[derive(Default)]
struct Table {
    forces: Vec<Force>,
    /// In the order they began; the last [`MOST_LOGGED`] that ended, and those under way.
    hangs: Vec<Hang>,
    /// Applied since the run last read them ([`crate::Watch::forced`]), the last
    /// [`MOST_LOGGED`] of them.
    log: VecDeque<Forced>,
}

/// The forces of the run watched, read by the nodes' hooks at each tick.
#[derive(Default)]
pub(crate) struct Forces {
    table: Mutex<Table>,
    /// Whether any force is set: the hooks of a tree without one read no lock.
    any: AtomicBool,
    /// Whether any node hangs: the hooks of a running node read no lock otherwise.
    any_hanging: AtomicBool,
    /// Bumped when the list pages are shown changes.
    version: AtomicU64,
    /// The hooks that apply forces were handed out ([`crate::Studio::force_hooks`]): a
    /// run that builds its tree without them cannot be forced, and pages are told so.
    hooked: AtomicBool,
}

impl Forces {
    fn lock(&self) -> MutexGuard<'_, Table> {
        self.table.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn changed(&self, table: &Table) {
        self.any.store(!table.forces.is_empty(), Ordering::Release);
        self.version.fetch_add(1, Ordering::AcqRel);
    }

    /// The hooks were handed out to build a tree with.
    pub fn hand_out(&self) {
        self.hooked.store(true, Ordering::Release);
    }

    /// Whether a tree may have been built with the hooks.
    pub fn hooked(&self) -> bool {
        self.hooked.load(Ordering::Acquire)
    }

    /// A count that grows each time the list pages are shown changes: a page is sent the
    /// list again only when it grew.
    pub fn version(&self) -> u64 {
        self.version.load(Ordering::Acquire)
    }

    /// The forces as pages list them: `[{node, status, until, applied}]`.
    pub fn list(&self) -> Value {
        let table = self.lock();
        Value::Array(
            table
                .forces
                .iter()
                .map(|f| {
                    json!({
                        "node": f.node,
                        "status": status_name(f.status),
                        "until": until(f.until_cleared),
                        "applied": f.applied,
                    })
                })
                .collect(),
        )
    }

    /// Sets (or, with `None`, clears) the force of `node`, replacing the one it had.
    fn set(&self, node: u32, force: Option<(Status, bool)>) {
        let mut table = self.lock();
        table.forces.retain(|f| f.node != node);
        if let Some((status, until_cleared)) = force {
            table.forces.push(Force {
                node,
                status,
                until_cleared,
                applied: None,
            });
        }
        self.changed(&table);
    }

    /// Another tree is watched: its nodes are not those the forces named.
    pub fn clear(&self) {
        let mut table = self.lock();
        table.forces.clear();
        table.log.clear();
        table.hangs.clear();
        self.any_hanging.store(false, Ordering::Release);
        self.changed(&table);
    }

    /// The run forked at tick `tick`: the once-forces that applied after it are due again.
    pub fn fork(&self, tick: u64) {
        let mut table = self.lock();
        let mut any = false;
        for force in &mut table.forces {
            if force.applied.is_some_and(|t| t > tick) {
                force.applied = None;
                any = true;
            }
        }
        table.log.retain(|f| f.tick <= tick);
        // A hang begun after the tick gone back to is undone; one ended after it is
        // under way again.
        table.hangs.retain(|h| h.from <= tick);
        for hang in &mut table.hangs {
            if hang.until.is_some_and(|t| t > tick) {
                hang.until = None;
            }
        }
        self.hung(&table);
        if any {
            self.changed(&table);
        }
    }

    /// Whether `node` hangs now under a forced RUNNING.
    fn hanging(&self, node: u32) -> bool {
        self.any_hanging.load(Ordering::Acquire)
            && self
                .lock()
                .hangs
                .iter()
                .any(|h| h.node == node && h.until.is_none())
    }

    /// `node` began (at tick `tick`) or stopped hanging.
    fn set_hanging(&self, node: u32, tick: u64, hanging: bool) {
        let mut table = self.lock();
        let open = table
            .hangs
            .iter()
            .position(|h| h.node == node && h.until.is_none());
        match (open, hanging) {
            (None, true) => table.hangs.push(Hang {
                node,
                from: tick,
                until: None,
            }),
            (Some(at), false) => {
                table.hangs[at].until = Some(tick);
                let ended = table.hangs.iter().filter(|h| h.until.is_some()).count();
                if ended > MOST_LOGGED {
                    let oldest = table.hangs.iter().position(|h| h.until.is_some());
                    if let Some(oldest) = oldest {
                        table.hangs.remove(oldest);
                    }
                }
            }
            _ => {}
        }
        self.hung(&table);
    }

    fn hung(&self, table: &Table) {
        let any = table.hangs.iter().any(|h| h.until.is_none());
        self.any_hanging.store(any, Ordering::Release);
    }

    /// The forces that applied since the last call (the last [`MOST_LOGGED`] of them).
    pub fn take_log(&self) -> Vec<Forced> {
        Vec::from(std::mem::take(&mut self.lock().log))
    }

    /// The status `node` returns at tick `tick`, if a force applies; logs it.
    fn apply(&self, node: u32, path: String, tick: u64) -> Option<Status> {
        let mut table = self.lock();
        let force = table.forces.iter_mut().find(|f| f.node == node)?;
        if !force.until_cleared {
            if force.applied.is_some() {
                return None;
            }
            force.applied = Some(tick);
        }
        let forced = Forced {
            tick,
            node: path,
            status: force.status,
            until_cleared: force.until_cleared,
        };
        let once = !forced.until_cleared;
        if table.log.len() == MOST_LOGGED {
            table.log.pop_front();
        }
        table.log.push_back(forced.clone());
        if once {
            // The list shows where it applied.
            self.changed(&table);
        }
        Some(forced.status)
    }
}

impl LiveFaults for Hub {
    fn forced(&self, node: NodeId) -> Option<Status> {
        if !self.forces.any.load(Ordering::Acquire) {
            return None;
        }
        let (tick, path) = {
            let inner = self.lock();
            let run = inner.run.as_ref()?;
            (
                run.cell.tick.load(Ordering::Acquire),
                run.paths.get(node.index())?.clone(),
            )
        };
        let status = self.forces.apply(node.0, path, tick);
        if status.is_some() {
            self.bump();
        }
        status
    }

    fn hanging(&self, node: NodeId) -> bool {
        self.forces.hanging(node.0)
    }

    fn set_hanging(&self, node: NodeId, hanging: bool) {
        let tick = self
            .lock()
            .run
            .as_ref()
            .map_or(0, |run| run.cell.tick.load(Ordering::Acquire));
        self.forces.set_hanging(node.0, tick, hanging);
    }
}

impl Hub {
    /// A page forced a node's result (`status`: SUCCESS, FAILURE, RUNNING or `off`;
    /// `until`: `once` or `cleared`); the reason it was refused, if it was.
    pub fn force(&self, node: u64, status: &str, until: Option<&str>) -> Result<(), String> {
        if !self.forces.hooked() {
            return Err(
                "this run's tree was built without the studio's force hooks \
                        (Studio::force_hooks): its results cannot be forced"
                    .into(),
            );
        }
        // Held until the force is set: an attach of another tree, which clears the forces,
        // waits for it, so that a force checked against one tree never lands on the next.
        let hub = self.lock();
        let len = hub.run.as_ref().map_or(0, |r| r.paths.len());
        let Some(id) = super::node_in(node, len) else {
            return Err(format!("no node {node} in the tree watched"));
        };
        let force = if status == "off" {
            None
        } else {
            let status = parse_status(status).ok_or_else(|| {
                format!("a force is SUCCESS, FAILURE, RUNNING or `off`, not `{status}`")
            })?;
            let until_cleared = match until.unwrap_or("once") {
                "once" => false,
                "cleared" => true,
                other => {
                    return Err(format!(
                        "a force holds `once` or until `cleared`, not `{other}`"
                    ))
                }
            };
            Some((status, until_cleared))
        };
        #[cfg(test)]
        tests::between_check_and_set();
        self.forces.set(id.0, force);
        drop(hub);
        self.bump();
        Ok(())
    }
}

#[cfg(test)]
impl Forces {
    /// The nodes with a force set.
    fn nodes(&self) -> Vec<u32> {
        self.lock().forces.iter().map(|f| f.node).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_once_force_applies_once_and_again_after_a_fork_before_it() {
        let forces = Forces::default();
        forces.set(2, Some((Status::Failure, false)));
        assert_eq!(forces.apply(1, "a".into(), 5), None);
        assert_eq!(forces.apply(2, "b".into(), 5), Some(Status::Failure));
        assert_eq!(forces.apply(2, "b".into(), 6), None);
        forces.fork(5);
        assert_eq!(forces.apply(2, "b".into(), 6), None, "applied at 5, kept");
        forces.fork(4);
        assert_eq!(forces.apply(2, "b".into(), 5), Some(Status::Failure));
        let log = forces.take_log();
        assert_eq!(
            log.iter().map(|f| f.tick).collect::<Vec<_>>(),
            vec![5],
            "the fork forgot the first application: {log:?}"
        );
        assert_eq!(
            log[0].json(),
            json!({"tick": 5, "node": "b", "status": "FAILURE", "until": "once"})
        );
    }

    #[test]
    fn a_force_until_cleared_applies_at_every_tick_until_cleared() {
        let forces = Forces::default();
        forces.set(0, Some((Status::Running, true)));
        for tick in 1..4 {
            assert_eq!(forces.apply(0, "r".into(), tick), Some(Status::Running));
        }
        forces.set(0, None);
        assert_eq!(forces.apply(0, "r".into(), 4), None);
        assert!(!forces.any.load(Ordering::Acquire));
        assert_eq!(forces.take_log().len(), 3);
    }

    #[test]
    fn a_run_that_never_reads_its_forces_keeps_the_last_few_thousand() {
        let forces = Forces::default();
        forces.set(0, Some((Status::Failure, true)));
        let ticks = MOST_LOGGED as u64 + 10;
        for tick in 1..=ticks {
            assert_eq!(forces.apply(0, "r".into(), tick), Some(Status::Failure));
        }
        let log = forces.take_log();
        assert_eq!(log.len(), MOST_LOGGED);
        assert_eq!(log[0].tick, 11, "the oldest forgotten first");
        assert_eq!(log[MOST_LOGGED - 1].tick, ticks);
        assert!(forces.take_log().is_empty());
    }

    std::thread_local! {
        /// Run by [`Hub::force`] between its check of the node and the force's setting.
        static BETWEEN: std::cell::Cell<Option<Box<dyn FnOnce()>>> =
            const { std::cell::Cell::new(None) };
    }

    /// Called by [`Hub::force`] between its check and its setting.
    pub(super) fn between_check_and_set() {
        if let Some(f) = BETWEEN.take() {
            f();
        }
    }

    /// A page forces node 40 of a 60-node tree while another thread attaches a tree of
    /// 2 nodes, just after the check that node 40 exists: the force lands on the tree it
    /// was checked against, and the attach clears it, rather than the force standing on a
    /// node the tree watched lacks.
    #[test]
    fn a_force_checked_against_one_tree_never_lands_on_the_next() {
        use neurotree_core::{Blueprint, ManualClock, Tree};
        use std::sync::{mpsc, Arc};
        let tree = |leaves: usize| {
            let blueprint = Blueprint::<()>::builder()
                .sequence("s", |mut s| {
                    for i in 0..leaves {
                        s = s.always_success(&format!("leaf{i}"));
                    }
                    s
                })
                .build_shared()
                .unwrap();
            Tree::with_clock(blueprint, ManualClock::new())
        };
        let (small, large) = (tree(1), tree(59));
        let hub = Hub::new();
        hub.forces.hand_out();
        let _watched = hub.attach(&large, "t");
        let (attached, done) = mpsc::channel();
        let attacher = Arc::clone(&hub);
        BETWEEN.set(Some(Box::new(move || {
            std::thread::spawn(move || {
                drop(attacher.attach(&small, "t"));
                attached.send(()).unwrap();
            });
            // Time for the attach to end, unless the force holds it back.
            std::thread::sleep(std::time::Duration::from_millis(250));
        })));
        hub.force(40, "FAILURE", Some("cleared")).unwrap();
        done.recv().unwrap();
        let len = hub.lock().run.as_ref().map_or(0, |r| r.paths.len());
        assert_eq!(len, 2, "the small tree is watched");
        assert_eq!(
            hub.forces.nodes(),
            Vec::<u32>::new(),
            "no force on a node it lacks"
        );
    }

    #[test]
    fn a_hang_is_undone_by_going_back_before_it_and_resumed_by_going_back_inside_it() {
        let forces = Forces::default();
        forces.set_hanging(3, 10, true);
        assert!(forces.hanging(3) && !forces.hanging(4));
        forces.set_hanging(3, 14, false);
        assert!(!forces.hanging(3));
        forces.fork(12);
        assert!(forces.hanging(3), "hanging at tick 12, halted at 14");
        forces.fork(9);
        assert!(!forces.hanging(3), "not yet forced at tick 9");
        forces.set_hanging(3, 11, true);
        forces.clear();
        assert!(!forces.hanging(3), "another tree watched");
    }
}

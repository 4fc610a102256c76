//! A small patrol whose every tick is scripted, for the observer tests: it runs, succeeds,
//! fails, is halted and skips a node.
//!
//! ```text
//! patrol (ReactiveSequence)        ids
//! ├── battery_ok (Condition)        1   reads World::battery_ok
//! └── route (Sequence)              2
//!     ├── once (RunOnce, skip)      3   after its first run: Skipped
//!     │   └── wave (Action)         4
//!     ├── move (StatefulAction)     5   Running for two ticks, then Success
//!     └── scan (Action)             6
//! ```
//!
//! [`run`] ticks it five times, the clock 100 ms further each time, with the battery
//! low on tick 2 only:
//! 1. battery ok: wave succeeds, move starts (Running);
//! 2. battery low: battery_ok fails, move is halted, patrol fails;
//! 3. battery ok: once is skipped, move starts again;
//! 4. move still Running: nothing changes;
//! 5. move succeeds, scan succeeds, patrol succeeds.

use std::sync::Arc;
use std::time::Duration;

use neurotree::{Blueprint, Handle, ManualClock, StatefulAction, Status, Tree};

/// The patrol's world.
#[derive(Default)]
pub struct World {
    pub battery_ok: bool,
    pub halts: u32,
}

/// Running on the tick it starts and the next, Success on the third.
struct Move {
    ticks: u32,
}

impl StatefulAction<World> for Move {
    fn on_start(&mut self, _h: &mut Handle<'_, World>) -> Status {
        self.ticks = 1;
        Status::Running
    }
    fn on_running(&mut self, _h: &mut Handle<'_, World>) -> Status {
        self.ticks += 1;
        if self.ticks == 3 {
            Status::Success
        } else {
            Status::Running
        }
    }
    fn on_halted(&mut self, h: &mut Handle<'_, World>) {
        h.ctx_mut().halts += 1;
    }
}

/// The patrol blueprint.
pub fn blueprint() -> Arc<Blueprint<World>> {
    Blueprint::<World>::builder()
        .reactive_sequence("patrol", |p| {
            p.condition("battery_ok", |w: &World| w.battery_ok)
                .sequence("route", |r| {
                    r.run_once("once", true, |o| {
                        o.action("wave", |_: &mut World| Status::Success)
                    })
                    .stateful("move", || Move { ticks: 0 })
                    .action("scan", |_: &mut World| Status::Success)
                })
        })
        .build_shared()
        .expect("the patrol is a valid tree")
}

/// A fresh patrol on a manual clock at zero.
pub fn start() -> (Tree<World>, ManualClock) {
    let clock = ManualClock::new();
    (Tree::with_clock(blueprint(), clock.clone()), clock)
}

/// Ticks the patrol five times as the module docs say (asserting what the root returns)
/// and returns the world.
pub fn run(tree: &mut Tree<World>, clock: &ManualClock) -> World {
    let mut world = World::default();
    let expected = [
        Status::Running,
        Status::Failure,
        Status::Running,
        Status::Running,
        Status::Success,
    ];
    for (tick, expected) in expected.into_iter().enumerate() {
        clock.advance(Duration::from_millis(100));
        world.battery_ok = tick != 1;
        assert_eq!(
            tree.tick_once(&mut world),
            Ok(expected),
            "tick {}",
            tick + 1
        );
    }
    assert_eq!(world.halts, 1);
    world
}

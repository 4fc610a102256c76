//! Needs: a villager chooses between eating, sleeping and working by how much each is
//! needed, with a [UtilitySelector](neurotree::nodes::utility_selector).
//!
//! ```text
//! day (ReactiveSequence)            sense every tick, then choose
//! ├── sense (Action)                hunger and fatigue into the blackboard
//! └── choose (UtilitySelector, hysteresis)
//!     ├── Utility score="hunger"    eat (StatefulAction)
//!     ├── Utility score="fatigue"   sleep (StatefulAction)
//!     └── Utility score="0.5"       work (StatefulAction)
//! ```
//!
//! Work makes the villager hungry and tired; eating and sleeping bring the needs down
//! until they are met. The selector ticks the activity with the highest score; the
//! hysteresis keeps a running activity until another beats it by more than that, so the
//! villager does not drop its work the moment hunger edges past it.
//!
//! Run it with `cargo run -p neurotree --example needs [hysteresis]` (0.1 by default).

use std::sync::Arc;

use neurotree::prelude::*;
use neurotree::{Action, Handle, StatefulAction, UtilityBuilder};

/// One villager's needs, 0 (met) to 1 (urgent), and what it did on each tick.
#[derive(Debug, Default)]
pub struct Villager {
    pub hunger: f64,
    pub fatigue: f64,
    pub coins: u32,
    pub did: Vec<&'static str>,
}

/// Writes the needs into the blackboard, where the scores read them.
struct Sense;

impl Action<Villager> for Sense {
    fn tick(&self, h: &mut Handle<'_, Villager>) -> Status {
        let (hunger, fatigue) = (h.ctx().hunger, h.ctx().fatigue);
        let bb = h.blackboard_mut();
        let written = bb.set("hunger", hunger).and(bb.set("fatigue", fatigue));
        Status::from(written.is_ok())
    }
}

/// One of the three activities, a step per tick.
#[derive(Clone, Copy)]
enum Activity {
    Eat,
    Sleep,
    Work,
}

impl Activity {
    fn step(self, v: &mut Villager) -> Status {
        match self {
            Activity::Eat => {
                v.did.push("eat");
                v.hunger = (v.hunger - 0.15).max(0.0);
                Status::from(v.hunger <= 0.05).or_running()
            }
            Activity::Sleep => {
                v.did.push("sleep");
                v.fatigue = (v.fatigue - 0.08).max(0.0);
                Status::from(v.fatigue <= 0.05).or_running()
            }
            Activity::Work => {
                v.did.push("work");
                v.coins += 1;
                v.hunger = (v.hunger + 0.03).min(1.0);
                v.fatigue = (v.fatigue + 0.02).min(1.0);
                Status::Running
            }
        }
    }
}

/// Success stays Success; Failure (need not met yet) becomes Running.
trait OrRunning {
    fn or_running(self) -> Status;
}

impl OrRunning for Status {
    fn or_running(self) -> Status {
        if self == Status::Success {
            Status::Success
        } else {
            Status::Running
        }
    }
}

impl StatefulAction<Villager> for Activity {
    fn on_start(&mut self, h: &mut Handle<'_, Villager>) -> Status {
        self.step(h.ctx_mut())
    }
    fn on_running(&mut self, h: &mut Handle<'_, Villager>) -> Status {
        self.step(h.ctx_mut())
    }
}

/// The villager's day, choosing with `hysteresis`.
pub fn needs_tree(hysteresis: f64) -> Arc<Blueprint<Villager>> {
    Blueprint::<Villager>::builder()
        .reactive_sequence("day", |d| {
            d.action_node("sense", Sense)
                .utility_selector("choose", hysteresis, |c| {
                    c.utility("eat", "hunger", |u| u.stateful("Eat", || Activity::Eat))
                        .utility("sleep", "fatigue", |u| {
                            u.stateful("Sleep", || Activity::Sleep)
                        })
                        .utility("work", "0.5", |u| u.stateful("Work", || Activity::Work))
                })
        })
        .build_shared()
        .expect("the needs tree is valid")
}

/// Runs a villager for `ticks` ticks and returns it, with what it did on each tick.
pub fn run(hysteresis: f64, ticks: usize) -> Result<Villager, TickError> {
    let mut tree = Tree::with_clock(needs_tree(hysteresis), ManualClock::new());
    let mut v = Villager {
        hunger: 0.3,
        fatigue: 0.2,
        ..Villager::default()
    };
    for _ in 0..ticks {
        tree.tick_once(&mut v)?;
    }
    Ok(v)
}

/// How many times the activity changed.
pub fn switches(did: &[&str]) -> usize {
    did.windows(2).filter(|w| w[0] != w[1]).count()
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let hysteresis = std::env::args()
        .nth(1)
        .map(|a| a.parse::<f64>())
        .transpose()?
        .unwrap_or(0.1);
    let v = run(hysteresis, 200)?;
    let count = |what: &str| v.did.iter().filter(|d| **d == what).count();
    println!(
        "200 ticks with hysteresis {hysteresis}: ate {}, slept {}, worked {} ({} coins); {} switches",
        count("eat"),
        count("sleep"),
        count("work"),
        v.coins,
        switches(&v.did)
    );
    let mut runs: Vec<(&str, usize)> = Vec::new();
    for d in &v.did {
        match runs.last_mut() {
            Some((what, n)) if what == d => *n += 1,
            _ => runs.push((d, 1)),
        }
    }
    let line: Vec<String> = runs.iter().map(|(w, n)| format!("{w}×{n}")).collect();
    println!("{}", line.join(" "));
    Ok(())
}

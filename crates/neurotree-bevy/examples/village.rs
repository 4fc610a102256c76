//! Villagers in Bevy choosing between eating, sleeping and working by their needs, with a
//! UtilitySelector (the Bevy side of the workspace's `examples/needs.rs`), headless.
//!
//! Each villager's needs are a component; its tree senses them into its blackboard every
//! tick, and a `UtilitySelector` runs the activity whose score is highest (`hunger`,
//! `fatigue`, and 0.5 for work), keeping the running one until another beats it by 0.1.
//! Villagers start with different needs, so the village is busy with all three at once.
//!
//! `cargo run --release -p neurotree-bevy --example village -- --agents N --frames F` prints,
//! every tenth of the run, how many villagers eat, sleep and work.

use std::sync::Arc;

use bevy_app::App;
use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryItem;
use neurotree::prelude::*;
use neurotree::{Action, Handle, StatefulAction, UtilityBuilder};
use neurotree_bevy::{AgentContext, AgentCrowd, NeuroTreePlugin, TreeAgent};

/// A villager's needs, 0 (met) to 1 (urgent).
#[derive(Component, Clone, Copy, PartialEq)]
struct Needs {
    hunger: f64,
    fatigue: f64,
}

/// What a villager does.
#[derive(Component, Clone, Copy, PartialEq, Eq, Debug, Default)]
enum Doing {
    #[default]
    Nothing,
    Eat,
    Sleep,
    Work,
}

/// What a villager's leaves see and change.
struct Villager {
    needs: Needs,
    doing: Doing,
}

impl AgentContext for Villager {
    type Components = (&'static mut Needs, &'static mut Doing);
    type Shared = ();

    fn load(&mut self, (needs, _): &QueryItem<'_, '_, Self::Components>, _: &()) {
        self.needs = **needs;
    }

    fn store(&self, (needs, doing): &mut QueryItem<'_, '_, Self::Components>) {
        needs.set_if_neq(self.needs);
        doing.set_if_neq(self.doing);
    }
}

/// Writes the needs into the blackboard, where the scores read them.
struct Sense;

impl Action<Villager> for Sense {
    fn tick(&self, h: &mut Handle<'_, Villager>) -> Status {
        let Needs { hunger, fatigue } = h.ctx().needs;
        let bb = h.blackboard_mut();
        Status::from(
            bb.set("hunger", hunger)
                .and(bb.set("fatigue", fatigue))
                .is_ok(),
        )
    }
}

/// An activity, a step per tick: eating and sleeping until the need is met, working on.
#[derive(Clone, Copy)]
struct Activity(Doing);

impl Activity {
    fn step(self, v: &mut Villager) -> Status {
        v.doing = self.0;
        let n = &mut v.needs;
        let met = match self.0 {
            Doing::Eat => {
                n.hunger = (n.hunger - 0.15).max(0.0);
                n.hunger <= 0.05
            }
            Doing::Sleep => {
                n.fatigue = (n.fatigue - 0.08).max(0.0);
                n.fatigue <= 0.05
            }
            Doing::Work | Doing::Nothing => {
                n.hunger = (n.hunger + 0.03).min(1.0);
                n.fatigue = (n.fatigue + 0.02).min(1.0);
                false
            }
        };
        if met {
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

fn needs_tree() -> Arc<Blueprint<Villager>> {
    Blueprint::<Villager>::builder()
        .reactive_sequence("day", |d| {
            d.action_node("sense", Sense)
                .utility_selector("choose", 0.1, |c| {
                    c.utility("eat", "hunger", |u| {
                        u.stateful("Eat", || Activity(Doing::Eat))
                    })
                    .utility("sleep", "fatigue", |u| {
                        u.stateful("Sleep", || Activity(Doing::Sleep))
                    })
                    .utility("work", "0.5", |u| {
                        u.stateful("Work", || Activity(Doing::Work))
                    })
                })
        })
        .build_shared()
        .expect("the needs tree is valid")
}

fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let agents = arg("--agents", 1000);
    let frames = arg("--frames", 300);
    let tree = needs_tree();
    let mut app = App::new();
    app.add_plugins(NeuroTreePlugin::new(Registry::<Villager>::new()));
    for i in 0..agents {
        // Needs spread over the village, so that all three activities go on at once.
        let needs = Needs {
            hunger: (i % 7) as f64 / 7.0,
            fatigue: (i % 5) as f64 / 5.0,
        };
        let villager = Villager {
            needs,
            doing: Doing::Nothing,
        };
        app.world_mut().spawn((
            needs,
            Doing::Nothing,
            TreeAgent::new(Arc::clone(&tree), villager),
        ));
    }
    app.world_mut()
        .resource_mut::<AgentCrowd<Villager>>()
        .set_report_finished(false);
    app.finish();
    app.cleanup();
    let every = (frames / 10).max(1);
    for frame in 0..frames {
        app.update();
        if (frame + 1) % every == 0 {
            let world = app.world_mut();
            let mut count = [0usize; 4];
            for doing in world.query::<&Doing>().iter(world) {
                count[*doing as usize] += 1;
            }
            println!(
                "frame {:>4}: {} eat, {} sleep, {} work",
                frame + 1,
                count[Doing::Eat as usize],
                count[Doing::Sleep as usize],
                count[Doing::Work as usize]
            );
        }
    }
}

//! Villagers in Bevy choosing between eating, sleeping and working by their needs, with a
//! UtilitySelector (the Bevy side of the workspace's `examples/needs.rs`), headless.
//!
//! Each villager's needs are a component; its tree senses them into its blackboard through
//! a `Service` (at the start of the day's choice and every 500 ms while an activity runs),
//! and a `UtilitySelector` runs the activity whose score is highest (`hunger`, `fatigue`,
//! and 0.5 for work), keeping the running one until another beats it by 0.1. Activities
//! know when they end and say so: a villager's tree sleeps between the sensings.
//! Villagers start with different needs, so the village is busy with all three at once.
//!
//! `cargo run --release -p neurotree-bevy --example village -- --agents N --frames F` prints,
//! every tenth of the run, how many villagers eat, sleep and work and how many trees were
//! ticked, and at the end the villagers ticked per frame; `--reactive` senses through a
//! ReactiveSequence instead, which keeps every tree awake, to compare.
//!
//! `--studio PORT` (0: a free port) serves the studio on the villagers instead, and runs in
//! real time until it is killed: it prints `studio: http://127.0.0.1:PORT/`, whose page
//! lists the villagers by entity and watches the first (click another to watch it).

use std::sync::Arc;
use std::time::Duration;

use bevy_app::App;
use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryItem;
use neurotree::prelude::*;
use neurotree::{Action, Handle, StatefulAction, UtilityBuilder};
use neurotree_bevy::{
    AgentContext, AgentCrowd, AwakeAgents, NeuroTreePlugin, TreeAgent, TreeStudio,
};

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

/// How fast an activity changes a need, per second.
const EAT_PER_S: f64 = 0.9;
const SLEEP_PER_S: f64 = 0.5;
/// A work shift, and what it costs.
const SHIFT: Duration = Duration::from_secs(2);
const SHIFT_HUNGER: f64 = 0.3;
const SHIFT_FATIGUE: f64 = 0.2;

/// An activity on the tree's clock: eating and sleeping until the need is met, working a
/// shift. It knows when it will be done, and says so: the villager's tree sleeps until then.
#[derive(Clone, Copy)]
struct Activity {
    doing: Doing,
    done_at: Duration,
}

impl Activity {
    fn new(doing: Doing) -> Self {
        Self {
            doing,
            done_at: Duration::ZERO,
        }
    }

    /// How long the activity takes from needs `n`.
    fn lasts(self, n: Needs) -> Duration {
        let secs = |need: f64, rate: f64| Duration::from_secs_f64((need - 0.05).max(0.0) / rate);
        match self.doing {
            Doing::Eat => secs(n.hunger, EAT_PER_S),
            Doing::Sleep => secs(n.fatigue, SLEEP_PER_S),
            Doing::Work | Doing::Nothing => SHIFT,
        }
    }

    fn finish(self, n: &mut Needs) {
        match self.doing {
            Doing::Eat => n.hunger = n.hunger.min(0.05),
            Doing::Sleep => n.fatigue = n.fatigue.min(0.05),
            Doing::Work | Doing::Nothing => {
                n.hunger = (n.hunger + SHIFT_HUNGER).min(1.0);
                n.fatigue = (n.fatigue + SHIFT_FATIGUE).min(1.0);
            }
        }
    }
}

impl StatefulAction<Villager> for Activity {
    fn on_start(&mut self, h: &mut Handle<'_, Villager>) -> Status {
        h.ctx_mut().doing = self.doing;
        self.done_at = h.now() + self.lasts(h.ctx().needs);
        self.on_running(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Villager>) -> Status {
        if h.now() >= self.done_at {
            let mut needs = h.ctx().needs;
            self.finish(&mut needs);
            h.ctx_mut().needs = needs;
            return Status::Success;
        }
        h.sleep_until(self.done_at);
        Status::Running
    }
}

/// The choice between the activities, by the scores the sensing wrote.
fn choose(c: neurotree::Builder<Villager>) -> neurotree::Builder<Villager> {
    c.utility_selector("choose", 0.1, |c| {
        c.utility("eat", "hunger", |u| {
            u.stateful("Eat", || Activity::new(Doing::Eat))
        })
        .utility("sleep", "fatigue", |u| {
            u.stateful("Sleep", || Activity::new(Doing::Sleep))
        })
        .utility("work", "0.5", |u| {
            u.stateful("Work", || Activity::new(Doing::Work))
        })
    })
}

/// The villager's day. With `service`, the needs are sensed through a Service every 500 ms
/// while an activity runs, and the tree sleeps in between; without, through a
/// ReactiveSequence that re-senses every frame, which keeps every villager awake (`Sense`
/// reads the context).
fn needs_tree(service: bool) -> Arc<Blueprint<Villager>> {
    let b = Blueprint::<Villager>::builder();
    let b = if service {
        b.service("day", Duration::from_millis(500), |d| {
            choose(d.action_node("sense", Sense))
        })
    } else {
        b.reactive_sequence("day", |d| choose(d.action_node("sense", Sense)))
    };
    b.build_shared().expect("the needs tree is valid")
}

fn arg(name: &str) -> Option<usize> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
}

fn main() {
    let agents = arg("--agents").unwrap_or(1000);
    let frames = arg("--frames").unwrap_or(300);
    let studio = arg("--studio").and_then(|p| u16::try_from(p).ok());
    let service = !std::env::args().any(|a| a == "--reactive");
    let tree = needs_tree(service);
    let mut app = App::new();
    let plugin = NeuroTreePlugin::new(Registry::<Villager>::new());
    match studio {
        // In real time: the trees' clock follows Bevy's virtual time.
        Some(port) => app
            .add_plugins(bevy_time::TimePlugin)
            .add_plugins(plugin.with_studio(port, "village")),
        None => app.add_plugins(plugin),
    };
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
    if studio.is_some() {
        watched(app);
    }
    let every = (frames / 10).max(1);
    let mut ticked = 0;
    for frame in 0..frames {
        app.update();
        ticked += app
            .world()
            .resource::<AgentCrowd<Villager>>()
            .last_frame()
            .ticked;
        if (frame + 1) % every == 0 {
            let world = app.world_mut();
            let mut count = [0usize; 4];
            for doing in world.query::<&Doing>().iter(world) {
                count[*doing as usize] += 1;
            }
            let awake = world.resource::<AwakeAgents>();
            println!(
                "frame {:>4}: {} eat, {} sleep, {} work; {} ticked, {} asleep",
                frame + 1,
                count[Doing::Eat as usize],
                count[Doing::Sleep as usize],
                count[Doing::Work as usize],
                awake.ticked,
                awake.asleep,
            );
        }
    }
    println!(
        "{} villagers, {} frames ({}): {:.1} ticked per frame",
        agents,
        frames,
        if service {
            "Service"
        } else {
            "ReactiveSequence"
        },
        ticked as f64 / frames.max(1) as f64
    );
}

/// Runs the village at 60 frames a second until the process is killed, its studio's address
/// printed after the first frame (which chose the villager the page opens on).
fn watched(mut app: App) -> ! {
    app.update();
    match app.world().get_resource::<TreeStudio<Villager>>() {
        Some(studio) => println!("studio: {}", studio.url()),
        None => {
            eprintln!("village: the studio did not start");
            std::process::exit(1);
        }
    }
    let frame = Duration::from_secs(1) / 60;
    loop {
        let started = std::time::Instant::now();
        app.update();
        if let Some(rest) = frame.checked_sub(started.elapsed()) {
            std::thread::sleep(rest);
        }
    }
}

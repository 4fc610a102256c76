//! bevy_behave's chase scenario in NeuroTree, headless, for the side-by-side benchmark
//! (`crates/neurotree-bench/compare/bevy.sh`): enemies wait until the player is within
//! their vision, chase it until they catch it or lose it, nap 5 s after a catch, forever
//! (`assets/chase.xml`). The player circles the field, which grows with the number of
//! enemies so that the share of them chasing stays the same: `--spacing S` units of side
//! per square root of an enemy (40 by default; 1 keeps many enemies busy).
//!
//! `cargo run --release -p neurotree-bevy --example chase -- --agents N --frames F` prints
//! one line: `{"lib":"neurotree","lod":false,"sleep":true,"agents":N,"frames":F,"ms_per_frame":…,"ms_steady":…,"chase":…,"awake_per_frame":…}`,
//! the mean time of a frame, and of the frames of the second half; `chase` being the
//! agent-frames spent moving towards the player, `awake_per_frame` the enemies ticked per
//! frame on average.
//!
//! A waiting enemy's tree sleeps until the player could first be in sight (see
//! `WaitUntilPlayerIsNear`), and a napping one until its nap ends; with `--no-sleep`
//! waiting enemies look every frame, as bevy_behave's do (naps still sleep).
//!
//! With `--lod`, an enemy farther from the player than its vision and 30 units ticks every
//! 8th frame: the player moves under 27 units in 8 frames, so no enemy sees it later than
//! it would have; only a nap far from the player may end up to 7 frames late.
//!
//! `--threads N` runs the frames on N threads (every core by default); `--summaries on`
//! or `off` turns the agents' inspector summaries on or off (`AgentCrowd::set_summaries`).

use std::sync::Arc;
use std::time::Instant;

use bevy_app::App;
use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryItem;
use neurotree::prelude::*;
use neurotree::{Handle, StatefulAction};
use neurotree_bevy::{AgentContext, AgentCrowd, NeuroTreePlugin, TreeAgent};

const ENEMY_SPEED: f32 = 100.0;
const PLAYER_SPEED: f32 = 200.0;
const FRAME: f32 = 1.0 / 60.0;

#[derive(Component, Clone, Copy, PartialEq)]
struct Pos(f32, f32);

#[derive(Component)]
struct VisionRadius(f32);

/// Frames this enemy spent chasing.
#[derive(Component, Default, PartialEq)]
struct Chased(u32);

#[derive(Resource, Clone, Copy)]
struct Player(Pos);

/// What an enemy's leaves see and change.
struct Enemy {
    pos: Pos,
    vision: f32,
    player: Pos,
    chased: u32,
}

impl AgentContext for Enemy {
    type Components = (&'static mut Pos, &'static VisionRadius, &'static mut Chased);
    type Shared = Res<'static, Player>;

    fn load(
        &mut self,
        (pos, vision, _): &QueryItem<'_, '_, Self::Components>,
        player: &Res<'_, Player>,
    ) {
        self.pos = **pos;
        self.vision = vision.0;
        self.player = player.0;
    }

    /// Writes only what changed, so that Bevy's change detection sees only the enemies
    /// that moved, and a waiting enemy's components are left untouched.
    fn store(&self, (pos, _, chased): &mut QueryItem<'_, '_, Self::Components>) {
        pos.set_if_neq(self.pos);
        chased.set_if_neq(Chased(self.chased));
    }
}

fn distance(a: Pos, b: Pos) -> f32 {
    ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt()
}

/// Waits until the player is within vision. The player cannot come closer than
/// `PLAYER_SPEED` allows, so the enemy says when it could first see it, and its tree
/// sleeps until then (a frame early, against rounding): it sees the player in the same
/// frame as if it looked every frame.
struct WaitUntilPlayerIsNear;

impl StatefulAction<Enemy> for WaitUntilPlayerIsNear {
    fn on_start(&mut self, h: &mut Handle<'_, Enemy>) -> Status {
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Enemy>) -> Status {
        let e = h.ctx();
        let gap = distance(e.pos, e.player) - e.vision;
        if gap < 0.0 {
            return Status::Success;
        }
        if !NO_SLEEP.load(std::sync::atomic::Ordering::Relaxed) {
            let safe = (gap / PLAYER_SPEED - 2.0 * FRAME).max(0.0);
            let at = h.now() + std::time::Duration::from_secs_f32(safe);
            h.sleep_until(at);
        }
        Status::Running
    }
}

/// `--no-sleep`: waiting enemies look every frame, as bevy_behave's do.
static NO_SLEEP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

struct MoveTowardsPlayer;

impl StatefulAction<Enemy> for MoveTowardsPlayer {
    fn on_start(&mut self, h: &mut Handle<'_, Enemy>) -> Status {
        self.on_running(h)
    }

    fn on_running(&mut self, h: &mut Handle<'_, Enemy>) -> Status {
        let e = h.ctx_mut();
        let d = distance(e.pos, e.player);
        if d > 0.0 {
            let step = ENEMY_SPEED * FRAME / d;
            e.pos.0 += (e.player.0 - e.pos.0) * step;
            e.pos.1 += (e.player.1 - e.pos.1) * step;
        }
        e.chased += 1;
        let d = distance(e.pos, e.player);
        if d < 10.0 {
            Status::Success
        } else if d > e.vision {
            Status::Failure
        } else {
            Status::Running
        }
    }
}

/// The same pseudo-random sequence as bevy_behave's side: a 64-bit LCG.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let agents = arg("--agents", 10_000);
    let frames = arg("--frames", 100);
    let lod = std::env::args().any(|a| a == "--lod");
    let no_sleep = std::env::args().any(|a| a == "--no-sleep");
    NO_SLEEP.store(no_sleep, std::sync::atomic::Ordering::Relaxed);
    // Units of field per square root of an agent: 40 leaves most enemies out of sight; 1
    // puts many within sight, chasing, catching and napping in turn.
    let spacing = arg("--spacing", 40) as f32;
    let side = (agents as f32).sqrt() * spacing;

    let mut registry = Registry::<Enemy>::new();
    registry.register_stateful("WaitUntilPlayerIsNear", vec![], || WaitUntilPlayerIsNear)?;
    registry.register_stateful("MoveTowardsPlayer", vec![], || MoveTowardsPlayer)?;
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(include_str!("../assets/chase.xml"), "assets/chase.xml")?;
    let tree = Arc::new(loader.build_main()?);

    let mut app = App::new();
    let player = Player(Pos(side / 2.0 + side / 3.0, side / 2.0));
    // `--threads N`: the threads the frames run on (every core without it).
    app.add_plugins(NeuroTreePlugin::new(registry).with_threads(arg("--threads", 0))?)
        .insert_resource(player);
    // `--summaries on|off`: the per-frame pass bringing the agents' inspector summaries
    // up (by default, on in debug builds only).
    if let Some(on) = std::env::args().skip_while(|a| a != "--summaries").nth(1) {
        app.world_mut()
            .resource_mut::<AgentCrowd<Enemy>>()
            .set_summaries(on == "on");
    }
    let mut rng = Lcg(22);
    for _ in 0..agents {
        let (x, y) = (rng.next() * side, rng.next() * side);
        let vision = rng.next() * 150.0 + 150.0;
        let enemy = Enemy {
            pos: Pos(x, y),
            vision,
            player: player.0,
            chased: 0,
        };
        app.world_mut().spawn((
            Pos(x, y),
            VisionRadius(vision),
            Chased::default(),
            TreeAgent::new(Arc::clone(&tree), enemy),
        ));
    }
    app.add_systems(
        bevy_app::Update,
        (move |mut player: ResMut<Player>, mut t: Local<u32>| {
            *t += 1;
            let radius = side / 3.0;
            let angle = *t as f32 * FRAME * PLAYER_SPEED / radius;
            player.0 = Pos(
                side / 2.0 + radius * angle.cos(),
                side / 2.0 + radius * angle.sin(),
            );
        })
        .before(neurotree_bevy::TreeSystems::Tick),
    );
    {
        let mut crowd = app.world_mut().resource_mut::<AgentCrowd<Enemy>>();
        crowd.set_report_finished(false);
        if lod {
            crowd.crowd_mut().set_level_of_detail(|e: &Enemy| {
                if distance(e.pos, e.player) > e.vision + 30.0 {
                    8
                } else {
                    1
                }
            });
        }
    }
    app.finish();
    app.cleanup();
    // The first frame puts every agent in the crowd; it is not timed.
    app.update();
    let mut times = Vec::with_capacity(frames);
    let mut awake = 0u64;
    for frame in 0..frames {
        let t = Instant::now();
        app.update();
        times.push(t.elapsed().as_secs_f64() * 1e3);
        awake += app
            .world()
            .resource::<AgentCrowd<Enemy>>()
            .last_frame()
            .ticked;
        if frame < 3 || frame + 1 == frames {
            eprintln!("frame {frame}: {:.2} ms", times[frame]);
        }
    }
    let ms = times.iter().sum::<f64>() / frames.max(1) as f64;
    // The second half of the frames, once the trees have started.
    let half = &times[frames / 2..];
    let steady = half.iter().sum::<f64>() / half.len().max(1) as f64;
    let world = app.world_mut();
    let chase: u64 = world
        .query::<&Chased>()
        .iter(world)
        .map(|c| u64::from(c.0))
        .sum();
    let sleep = !no_sleep;
    let awake = awake as f64 / frames.max(1) as f64;
    println!(
        "{{\"lib\":\"neurotree\",\"lod\":{lod},\"sleep\":{sleep},\"agents\":{agents},\"frames\":{frames},\"ms_per_frame\":{ms:.3},\"ms_steady\":{steady:.3},\"chase\":{chase},\"awake_per_frame\":{awake:.1}}}"
    );
    Ok(())
}

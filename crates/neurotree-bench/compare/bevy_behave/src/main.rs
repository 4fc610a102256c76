//! The chase scenario of bevy_behave's own `chase` example, headless: enemies wait until
//! the player is within their vision, chase it until they catch it (Success) or lose it
//! (Failure), nap 5 s after a catch, forever. The player circles the field. The field
//! grows with the number of enemies, so that the share of them chasing stays the same:
//! `--spacing S` units of side per square root of an enemy (40 by default; 1 keeps many
//! enemies busy).
//!
//! `cargo run --release -- --agents N --frames F` prints one line:
//! `{"lib":"bevy_behave","agents":N,"frames":F,"ms_per_frame":…,"ms_steady":…,"chase":…}`:
//! the mean time of a frame, and of the frames of the second half; `chase`
//! being the agent-frames spent moving towards the player. The same scenario in NeuroTree
//! is `cargo run --release -p neurotree-bevy --example chase`.

use std::time::{Duration, Instant};

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_behave::prelude::*;

const ENEMY_SPEED: f32 = 100.0;
const PLAYER_SPEED: f32 = 200.0;
const FRAME: f32 = 1.0 / 60.0;

#[derive(Component)]
struct Enemy;

#[derive(Component)]
struct Player;

#[derive(Component, Clone, Copy)]
struct Pos(f32, f32);

#[derive(Component)]
struct VisionRadius(f32);

#[derive(Resource)]
struct Field {
    side: f32,
}

#[derive(Resource, Default)]
struct ChaseFrames(u64);

#[derive(Component, Clone)]
struct WaitUntilPlayerIsNear {
    player: Entity,
}

#[derive(Component, Clone)]
struct MoveTowardsPlayer {
    player: Entity,
    speed: f32,
}

/// The same pseudo-random sequence as NeuroTree's side: a 64-bit LCG.
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

fn distance(a: Pos, b: Pos) -> f32 {
    ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt()
}

fn wait_system(
    q: Query<(&WaitUntilPlayerIsNear, &BehaveCtx)>,
    enemies: Query<(&Pos, &VisionRadius), (With<Enemy>, Without<Player>)>,
    players: Query<&Pos, (With<Player>, Without<Enemy>)>,
    mut commands: Commands,
) {
    for (wait, ctx) in &q {
        let player = players.get(wait.player).unwrap();
        let (enemy, vision) = enemies.get(ctx.target_entity()).unwrap();
        if distance(*enemy, *player) < vision.0 {
            commands.trigger(ctx.success());
        }
    }
}

fn move_system(
    q: Query<(&MoveTowardsPlayer, &BehaveCtx)>,
    mut enemies: Query<(&mut Pos, &VisionRadius), (With<Enemy>, Without<Player>)>,
    players: Query<&Pos, (With<Player>, Without<Enemy>)>,
    mut chase: ResMut<ChaseFrames>,
    mut commands: Commands,
    time: Res<Time>,
) {
    for (chasing, ctx) in &q {
        let player = *players.get(chasing.player).unwrap();
        let (mut enemy, vision) = enemies.get_mut(ctx.target_entity()).unwrap();
        let d = distance(*enemy, player);
        if d > 0.0 {
            let step = chasing.speed * time.delta_secs() / d;
            enemy.0 += (player.0 - enemy.0) * step;
            enemy.1 += (player.1 - enemy.1) * step;
        }
        chase.0 += 1;
        let d = distance(*enemy, player);
        if d < 10.0 {
            commands.trigger(ctx.success());
        } else if d > vision.0 {
            commands.trigger(ctx.failure());
        }
    }
}

fn player_system(mut players: Query<&mut Pos, With<Player>>, field: Res<Field>, time: Res<Time>) {
    let radius = field.side / 3.0;
    let angle = time.elapsed_secs() * PLAYER_SPEED / radius;
    for mut p in &mut players {
        *p = Pos(
            field.side / 2.0 + radius * angle.cos(),
            field.side / 2.0 + radius * angle.sin(),
        );
    }
}

fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(|v| v.parse().expect("a number"))
        .unwrap_or(default)
}

fn main() {
    let agents = arg("--agents", 10_000);
    let frames = arg("--frames", 100);
    // Units of field per square root of an agent: 40 leaves most enemies out of sight; 1
    // puts many within sight, chasing, catching and napping in turn.
    let spacing = arg("--spacing", 40) as f32;
    let side = (agents as f32).sqrt() * spacing;

    let mut app = App::new();
    app.add_plugins(MinimalPlugins)
        .add_plugins(BehavePlugin::default())
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
            FRAME,
        )))
        .insert_resource(Field { side })
        .init_resource::<ChaseFrames>()
        .add_systems(Update, (player_system, wait_system, move_system).chain());

    let world = app.world_mut();
    let player = world
        .spawn((Player, Pos(side / 2.0 + side / 3.0, side / 2.0)))
        .id();
    let tree = behave! {
        Behave::Forever => {
            Behave::Sequence => {
                Behave::spawn_named("Wait until player is near", WaitUntilPlayerIsNear { player }),
                Behave::spawn_named(
                    "Move towards player while in range",
                    MoveTowardsPlayer { player, speed: ENEMY_SPEED }
                ),
                Behave::Wait(5.0),
            }
        }
    };
    let mut rng = Lcg(22);
    for _ in 0..agents {
        let (x, y) = (rng.next() * side, rng.next() * side);
        let vision = rng.next() * 150.0 + 150.0;
        world
            .spawn((Enemy, VisionRadius(vision), Pos(x, y)))
            .with_child(BehaveTree::new(tree.clone()));
    }
    app.finish();
    app.cleanup();
    // The first frame starts every tree; it is not timed.
    app.update();
    let mut times = Vec::with_capacity(frames);
    for frame in 0..frames {
        let t = Instant::now();
        app.update();
        times.push(t.elapsed().as_secs_f64() * 1e3);
        if frame < 3 || frame + 1 == frames {
            eprintln!("frame {frame}: {:.2} ms", times[frame]);
        }
    }
    let ms = times.iter().sum::<f64>() / frames.max(1) as f64;
    // The second half of the frames, once the trees have started.
    let half = &times[frames / 2..];
    let steady = half.iter().sum::<f64>() / half.len().max(1) as f64;
    let chase = app.world().resource::<ChaseFrames>().0;
    println!(
        "{{\"lib\":\"bevy_behave\",\"agents\":{agents},\"frames\":{frames},\"ms_per_frame\":{ms:.3},\"ms_steady\":{steady:.3},\"chase\":{chase}}}"
    );
}

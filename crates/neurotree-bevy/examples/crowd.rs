//! A crowd of game agents in Bevy, headless: each patrols around its home, chases the
//! target when it sees it, flees when hurt (the target hits back), regroups when far
//! from home, and rests while the target is far away, all from one tree file,
//! `assets/crowd.xml`, loaded as a Bevy asset. Agents far from the target think every 4th
//! frame (a level-of-detail hook); a resting agent's tree sleeps until the target could
//! have come near, so it is not ticked at all meanwhile.
//!
//! `cargo run --release -p neurotree-bevy --example crowd -- --agents N --frames F` prints
//! frame times, how many agents were awake, and what the agents did; its last line is
//! `{"agents":N,"frames":F,"ms_per_frame":…,"awake_per_frame":…,"patrol":…,"chase":…,"flee":…,"regroup":…,"rest":…}`,
//! the agents ticked per frame on average and the agent-frames spent in each behaviour.

use std::io::Write;
use std::time::Instant;

use bevy_app::{App, TaskPoolPlugin, Update};
use bevy_asset::{AssetPlugin, AssetServer, Handle, LoadState};
use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryItem;
use neurotree::prelude::*;
use neurotree_bevy::{
    AgentContext, AgentCrowd, NeuroTreePlugin, TreeAgent, TreeAsset, TreeSystems,
};

/// Units between homes on the field's grid.
const SPACING: f32 = 10.0;
const VISION: f32 = 25.0;
/// Beyond this distance from the target, an agent thinks every 4th frame.
const NEAR: f32 = 100.0;
/// The most the target moves in a frame (its Lissajous curve's top speed is under 2.44).
const TARGET_STEP: f32 = 2.5;
/// The trees' clock moves 1/60 s per frame (the plugin's default step).
const FRAME_SECS: f32 = 1.0 / 60.0;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pos(f32, f32);

impl Pos {
    fn distance(self, o: Pos) -> f32 {
        ((self.0 - o.0).powi(2) + (self.1 - o.1).powi(2)).sqrt()
    }

    /// `self` moved `step` towards `to` (away from it if `step` is negative).
    fn toward(self, to: Pos, step: f32) -> Pos {
        let d = self.distance(to);
        if d <= f32::EPSILON {
            return self;
        }
        let k = (step / d).min(1.0);
        Pos(self.0 + (to.0 - self.0) * k, self.1 + (to.1 - self.1) * k)
    }
}

/// What an agent did in its last tick.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Doing {
    #[default]
    Patrol,
    Chase,
    Flee,
    Regroup,
    Rest,
}

#[derive(Component, Clone, Copy)]
pub struct Position(Pos);

#[derive(Component, Clone, Copy)]
pub struct Home(Pos);

#[derive(Component, Clone, Copy)]
pub struct Health(f32);

/// Where the target is: one for all agents.
#[derive(Resource, Clone, Copy)]
pub struct Target(Pos);

/// What an agent's leaves see and change.
#[derive(Default)]
pub struct Agent {
    pos: Pos,
    home: Pos,
    health: f32,
    target: Pos,
    doing: Doing,
}

impl AgentContext for Agent {
    type Components = (
        &'static mut Position,
        &'static Home,
        &'static mut Health,
        &'static mut Doing,
    );
    type Shared = Res<'static, Target>;

    fn load(
        &mut self,
        (pos, home, health, _): &QueryItem<'_, '_, Self::Components>,
        target: &Res<'_, Target>,
    ) {
        self.pos = pos.0;
        self.home = home.0;
        self.health = health.0;
        self.target = target.0;
    }

    fn store(&self, (pos, _, health, doing): &mut QueryItem<'_, '_, Self::Components>) {
        pos.0 = self.pos;
        health.0 = self.health;
        **doing = self.doing;
    }
}

/// Rests while the target is farther than `within`: Running, its tree asleep until the
/// target could have come that near (it moves at most [`TARGET_STEP`] a frame; two frames
/// early, against rounding); then Failure, so that the agent patrols.
struct Rest;

impl Rest {
    fn check(h: &mut neurotree::Handle<'_, Agent>) -> Status {
        let within = h.input::<f64>("within").unwrap_or(0.0) as f32;
        let a = h.ctx_mut();
        let gap = a.pos.distance(a.target) - within;
        if gap <= 0.0 {
            return Status::Failure;
        }
        a.doing = Doing::Rest;
        let frames = (gap / TARGET_STEP - 2.0).max(0.0);
        let at = h.now() + std::time::Duration::from_secs_f32(frames * FRAME_SECS);
        h.sleep_until(at);
        Status::Running
    }
}

impl neurotree::StatefulAction<Agent> for Rest {
    fn on_start(&mut self, h: &mut neurotree::Handle<'_, Agent>) -> Status {
        Self::check(h)
    }
    fn on_running(&mut self, h: &mut neurotree::Handle<'_, Agent>) -> Status {
        Self::check(h)
    }
}

/// The leaves `assets/crowd.xml` names.
pub fn registry() -> Result<Registry<Agent>, RegistryError> {
    let mut r = Registry::<Agent>::new();
    r.register_condition("IsHurt", vec![PortSpec::input::<f64>("below")], |h| {
        let below = h.input::<f64>("below").unwrap_or(0.0) as f32;
        h.ctx().health < below
    })?;
    r.register_condition("CanSeeTarget", vec![], |h| {
        let a = h.ctx();
        a.pos.distance(a.target) < VISION
    })?;
    r.register_condition("FarFromHome", vec![PortSpec::input::<f64>("beyond")], |h| {
        let beyond = h.input::<f64>("beyond").unwrap_or(0.0) as f32;
        let a = h.ctx();
        a.pos.distance(a.home) > beyond
    })?;
    r.register_action("Flee", vec![], |h| {
        let a = h.ctx_mut();
        a.pos = a.pos.toward(a.target, -1.5);
        a.health = (a.health + 0.5).min(100.0);
        a.doing = Doing::Flee;
        Status::Success
    })?;
    r.register_action("Chase", vec![], |h| {
        let a = h.ctx_mut();
        a.pos = a.pos.toward(a.target, 1.2);
        // The target hits back at close range.
        if a.pos.distance(a.target) < 6.0 {
            a.health -= 25.0;
        }
        a.doing = Doing::Chase;
        Status::Success
    })?;
    r.register_action("Regroup", vec![], |h| {
        let a = h.ctx_mut();
        a.pos = a.pos.toward(a.home, 1.0);
        a.doing = Doing::Regroup;
        Status::Success
    })?;
    r.register_stateful("Rest", vec![PortSpec::input::<f64>("within")], || Rest)?;
    r.register_action("Patrol", vec![], |h| {
        let a = h.ctx_mut();
        // A point a little further round a circle of 8 units about home.
        let angle = (a.pos.1 - a.home.1).atan2(a.pos.0 - a.home.0) + 0.1;
        let next = Pos(a.home.0 + 8.0 * angle.cos(), a.home.1 + 8.0 * angle.sin());
        a.pos = a.pos.toward(next, 1.0);
        a.doing = Doing::Patrol;
        Status::Success
    })?;
    Ok(r)
}

/// Agent-frames per behaviour, counted once the crowd has joined.
#[derive(Resource, Default, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tally {
    pub counting: bool,
    pub patrol: u64,
    pub chase: u64,
    pub flee: u64,
    pub regroup: u64,
    pub rest: u64,
    /// Agents ticked, summed over the frames counted.
    pub awake: u64,
}

fn tally(agents: Query<&Doing>, mut tally: ResMut<Tally>) {
    if !tally.counting {
        return;
    }
    for doing in &agents {
        match doing {
            Doing::Patrol => tally.patrol += 1,
            Doing::Chase => tally.chase += 1,
            Doing::Flee => tally.flee += 1,
            Doing::Regroup => tally.regroup += 1,
            Doing::Rest => tally.rest += 1,
        }
    }
}

/// The target crosses the field on a Lissajous curve.
fn move_target(mut target: ResMut<Target>, field: Res<Field>, mut t: Local<u32>) {
    *t += 1;
    let (c, r) = (field.side / 2.0, field.side * 0.45);
    let s = *t as f32 * 1.5 / field.side;
    target.0 = Pos(c + r * (3.0 * s).sin(), c + r * (2.0 * s).sin());
}

#[derive(Resource)]
struct Field {
    side: f32,
}

/// Runs `agents` agents for `frames` frames, writing progress lines to `out`, and returns
/// the tally and the mean time of a frame in milliseconds.
pub fn run(
    agents: usize,
    frames: usize,
    out: &mut dyn Write,
) -> Result<(Tally, f64), Box<dyn std::error::Error>> {
    let per_row = (agents as f32).sqrt().ceil().max(1.0) as usize;
    let side = per_row as f32 * SPACING;
    let mut app = App::new();
    app.add_plugins((
        TaskPoolPlugin::default(),
        AssetPlugin {
            file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/assets").to_string(),
            ..AssetPlugin::default()
        },
    ))
    // `--threads N` for the threads the frames run on; every core by default.
    .add_plugins(NeuroTreePlugin::new(registry()?).with_threads(arg("--threads", 0)?)?)
    .insert_resource(Field { side })
    .insert_resource(Target(Pos(side / 2.0, side / 2.0)))
    .init_resource::<Tally>()
    .add_systems(Update, move_target.before(TreeSystems::Tick))
    .add_systems(Update, tally.after(TreeSystems::Tick));
    {
        let mut crowd = app.world_mut().resource_mut::<AgentCrowd<Agent>>();
        // Every root returns Success every frame: no message for each.
        crowd.set_report_finished(false);
        crowd.crowd_mut().set_level_of_detail(|a: &Agent| {
            if a.pos.distance(a.target) > NEAR {
                4
            } else {
                1
            }
        });
    }
    let tree: Handle<TreeAsset<Agent>> = app.world().resource::<AssetServer>().load("crowd.xml");
    loop {
        app.update();
        match app.world().resource::<AssetServer>().load_state(&tree) {
            LoadState::Loaded => break,
            LoadState::Failed(e) => return Err(e.into()),
            _ => std::thread::sleep(std::time::Duration::from_millis(1)),
        }
    }
    for i in 0..agents {
        let home = Pos(
            (i % per_row) as f32 * SPACING + SPACING / 2.0,
            (i / per_row) as f32 * SPACING + SPACING / 2.0,
        );
        app.world_mut().spawn((
            Position(home),
            Home(home),
            Health(100.0),
            Doing::Patrol,
            TreeAgent::from_asset(tree.clone(), Agent::default()),
        ));
    }
    // Agents join the crowd in this frame; it is neither timed nor counted.
    let t = Instant::now();
    app.update();
    writeln!(
        out,
        "joined {agents} agents in {:.1} ms",
        t.elapsed().as_secs_f64() * 1e3
    )?;
    app.world_mut().resource_mut::<Tally>().counting = true;
    let every = (frames / 10).max(1);
    let start = Instant::now();
    for frame in 0..frames {
        let t = Instant::now();
        app.update();
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let last = app.world().resource::<AgentCrowd<Agent>>().last_frame();
        app.world_mut().resource_mut::<Tally>().awake += last.ticked;
        if (frame + 1) % every == 0 || frame + 1 == frames {
            let d = *app.world().resource::<Tally>();
            writeln!(
                out,
                "frame {:>5}: {ms:>8.2} ms, {} awake, {} asleep; so far patrol {} chase {} flee {} regroup {} rest {}",
                frame + 1,
                last.ticked,
                last.asleep,
                d.patrol,
                d.chase,
                d.flee,
                d.regroup,
                d.rest
            )?;
        }
    }
    let ms = start.elapsed().as_secs_f64() * 1e3 / frames.max(1) as f64;
    Ok((*app.world().resource::<Tally>(), ms))
}

/// The last line the example prints.
pub fn summary(agents: usize, frames: usize, tally: Tally, ms: f64) -> String {
    let awake = tally.awake as f64 / frames.max(1) as f64;
    format!(
        "{{\"agents\":{agents},\"frames\":{frames},\"ms_per_frame\":{ms:.3},\"awake_per_frame\":{awake:.1},\"patrol\":{},\"chase\":{},\"flee\":{},\"regroup\":{},\"rest\":{}}}",
        tally.patrol, tally.chase, tally.flee, tally.regroup, tally.rest
    )
}

fn arg(name: &str, default: usize) -> Result<usize, String> {
    let args: Vec<String> = std::env::args().collect();
    match args.iter().position(|a| a == name) {
        None => Ok(default),
        Some(i) => args
            .get(i + 1)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| format!("{name} takes a number")),
    }
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let agents = arg("--agents", 10_000)?;
    let frames = arg("--frames", 600)?;
    let mut stdout = std::io::stdout();
    let (tally, ms) = run(agents, frames, &mut stdout)?;
    println!("{}", summary(agents, frames, tally, ms));
    Ok(())
}

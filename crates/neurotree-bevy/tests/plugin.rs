//! The plugin in an app: ticks with intervals, leaves over components, messages and
//! observers, tree assets loaded and reloaded, agents removed.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use bevy_app::{App, TaskPoolPlugin, Update};
use bevy_asset::{AssetPlugin, AssetServer, Handle, LoadState};
use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryItem;
use neurotree::prelude::*;
use neurotree::{FailureLink, Handle as NodeHandle, StatefulAction};
use neurotree_bevy::{
    AgentContext, AgentCrowd, FailureReason, NeuroTreePlugin, TreeAgent, TreeAsset, TreeFailed,
    TreeFinished, TreeReloaded, TreeSystems,
};

/// A hang catch: far longer than a load or a reload takes on a loaded machine.
const HANG: std::time::Duration = std::time::Duration::from_secs(180);

/// What a guard's sensors say; the trees only read it.
#[derive(Component)]
struct Hp(i32);

/// Raised for every guard at once.
#[derive(Resource)]
struct Alarm(bool);

/// What a guard's tree did, written back by the plugin.
#[derive(Component, Clone, Copy, Default, Debug, PartialEq)]
struct Counts {
    ticks: u32,
    steps: u32,
    started: u32,
    fleeing: bool,
}

/// The context the leaves see: a copy of `Hp` and `Counts`, and the halts counted apart
/// (a removed agent's context is gone with it).
#[derive(Default)]
struct Guard {
    hp: i32,
    alarm: bool,
    counts: Counts,
    halts: Arc<AtomicU32>,
}

impl AgentContext for Guard {
    type Components = (&'static Hp, &'static mut Counts);
    type Shared = Option<Res<'static, Alarm>>;

    fn load(
        &mut self,
        (hp, counts): &QueryItem<'_, '_, Self::Components>,
        alarm: &Option<Res<'_, Alarm>>,
    ) {
        self.hp = hp.0;
        self.alarm = alarm.as_ref().is_some_and(|a| a.0);
        self.counts = **counts;
    }

    fn store(&self, (_, counts): &mut QueryItem<'_, '_, Self::Components>) {
        **counts = self.counts;
    }
}

/// Runs until halted, counting its starts in the context and its halts apart.
struct Hold;

impl StatefulAction<Guard> for Hold {
    fn on_start(&mut self, h: &mut NodeHandle<'_, Guard>) -> Status {
        h.ctx_mut().counts.started += 1;
        Status::Running
    }

    fn on_running(&mut self, _h: &mut NodeHandle<'_, Guard>) -> Status {
        Status::Running
    }

    fn on_halted(&mut self, h: &mut NodeHandle<'_, Guard>) {
        h.ctx().halts.fetch_add(1, Ordering::SeqCst);
    }
}

fn registry() -> Registry<Guard> {
    let mut r = Registry::<Guard>::new();
    r.register_action("Tick", vec![], |h| {
        h.ctx_mut().counts.ticks += 1;
        Status::Success
    })
    .unwrap();
    r.register_action("Step", vec![], |h| {
        h.ctx_mut().counts.steps += 1;
        Status::Success
    })
    .unwrap();
    r.register_condition("Hurt", vec![], |h| h.ctx().hp < 50)
        .unwrap();
    r.register_condition("Alarmed", vec![], |h| h.ctx().alarm)
        .unwrap();
    // A sync action may not return Running: its tick ends with an error.
    r.register_action("Broken", vec![], |_| Status::Running)
        .unwrap();
    r.register_action("Flee", vec![], |h| {
        h.ctx_mut().counts.fleeing = true;
        Status::Success
    })
    .unwrap();
    r.register_action("Patrol", vec![], |h| {
        h.ctx_mut().counts.fleeing = false;
        Status::Success
    })
    .unwrap();
    r.register_action("NoPath", vec![], |h| h.fail_with(7, "no path"))
        .unwrap();
    r.register_stateful("Hold", vec![PortSpec::input::<i32>("speed")], || Hold)
        .unwrap();
    r.register_stateful("WaitForHp", vec![], || WaitForHp)
        .unwrap();
    r
}

/// Counts its ticks; Success once the guard's `Hp` is 0, else Running, asleep until the
/// program wakes the tree (the plugin, when `Hp` changes or a `Poke` names the guard).
struct WaitForHp;

impl WaitForHp {
    fn check(h: &mut NodeHandle<'_, Guard>) -> Status {
        h.ctx_mut().counts.ticks += 1;
        if h.ctx().hp <= 0 {
            return Status::Success;
        }
        h.wake_on_handle();
        Status::Running
    }
}

impl StatefulAction<Guard> for WaitForHp {
    fn on_start(&mut self, h: &mut NodeHandle<'_, Guard>) -> Status {
        Self::check(h)
    }

    fn on_running(&mut self, h: &mut NodeHandle<'_, Guard>) -> Status {
        Self::check(h)
    }
}

/// Wakes the guard it names.
#[derive(Message, Clone, Copy)]
struct Poke(Entity);

fn blueprint(xml: &str) -> Arc<Blueprint<Guard>> {
    let registry = registry();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(xml, "test.xml").unwrap();
    Arc::new(loader.build_main().unwrap())
}

fn tree(body: &str) -> String {
    format!(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">{body}</BehaviorTree></root>"#)
}

fn app() -> App {
    let mut app = App::new();
    app.add_plugins(NeuroTreePlugin::new(registry()).with_threads(2).unwrap());
    app
}

fn counts(app: &App, entity: Entity) -> &Counts {
    app.world().get::<Counts>(entity).unwrap()
}

fn spawn(app: &mut App, agent: TreeAgent<Guard>, hp: i32) -> Entity {
    app.world_mut()
        .spawn((Hp(hp), Counts::default(), agent))
        .id()
}

#[test]
fn agents_are_ticked_once_per_frame_or_every_nth_frame_with_an_interval() {
    let mut app = app();
    let bp = blueprint(&tree("<Tick/>"));
    let every: Vec<Entity> = [1, 2, 3, 8]
        .into_iter()
        .map(|n| {
            let agent = TreeAgent::new(Arc::clone(&bp), Guard::default()).with_interval(n);
            spawn(&mut app, agent, 100)
        })
        .collect();
    for _ in 0..24 {
        app.update();
    }
    let ticks: Vec<u32> = every.iter().map(|&e| counts(&app, e).ticks).collect();
    assert_eq!(ticks, [24, 12, 8, 3]);
    let mut crowd = app.world_mut().resource_mut::<AgentCrowd<Guard>>();
    assert_eq!(crowd.crowd_mut().len(), 4);
    assert_eq!(crowd.crowd_mut().frames(), 24);
}

#[test]
fn a_budget_spreads_the_agents_ticks_over_frames_oldest_first() {
    let mut app = app();
    let bp = blueprint(&tree("<Tick/>"));
    let nodes = bp.len() as u64;
    let agents: Vec<Entity> = (0..10)
        .map(|_| {
            spawn(
                &mut app,
                TreeAgent::new(Arc::clone(&bp), Guard::default()),
                100,
            )
        })
        .collect();
    let budget = 4 * nodes;
    app.world_mut()
        .resource_mut::<AgentCrowd<Guard>>()
        .crowd_mut()
        .set_budget(Some(budget));
    for _ in 0..5 {
        app.update();
        let last = app.world().resource::<AgentCrowd<Guard>>().last_frame();
        assert_eq!((last.ticked, last.visits), (4, budget));
    }
    // The 20 ticks are written back, and spread: every agent had its turn.
    let ticks: Vec<u32> = agents.iter().map(|&e| counts(&app, e).ticks).collect();
    assert_eq!(ticks.iter().sum::<u32>(), 20, "{ticks:?}");
    assert!(ticks.iter().all(|&t| (1..=3).contains(&t)), "{ticks:?}");
    let last = app.world().resource::<AgentCrowd<Guard>>().last_frame();
    assert_eq!(last.behind.overdue, 6);
}

#[test]
fn an_agent_without_its_contexts_components_is_not_ticked() {
    let mut app = app();
    let bp = blueprint(&tree("<Tick/>"));
    let whole = spawn(
        &mut app,
        TreeAgent::new(Arc::clone(&bp), Guard::default()),
        100,
    );
    // No `Counts`: the context cannot be loaded.
    let partial = app
        .world_mut()
        .spawn((Hp(100), TreeAgent::new(bp, Guard::default())))
        .id();
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(counts(&app, whole).ticks, 3);
    app.world_mut()
        .resource_scope(|world, mut crowd: Mut<AgentCrowd<Guard>>| {
            assert_eq!(crowd.last_frame().ticked, 1);
            let agent = world.get::<TreeAgent<Guard>>(partial).unwrap();
            let member = crowd.member(agent).expect("it joined the crowd");
            assert_eq!(member.context().counts.ticks, 0);
            assert_eq!(member.status(), neurotree::crowd::FrameStatus::NotDue);
        });
}

#[test]
fn leaves_read_and_write_the_agents_components() {
    let mut app = app();
    let bp = blueprint(&tree(
        "<ReactiveFallback><Sequence><Hurt/><Flee/></Sequence><Patrol/></ReactiveFallback>",
    ));
    let hurt = spawn(
        &mut app,
        TreeAgent::new(Arc::clone(&bp), Guard::default()),
        10,
    );
    let well = spawn(&mut app, TreeAgent::new(bp, Guard::default()), 90);
    app.update();
    assert!(counts(&app, hurt).fleeing);
    assert!(!counts(&app, well).fleeing);
    // The world changes between frames; the next frame's tick sees it.
    app.world_mut().get_mut::<Hp>(hurt).unwrap().0 = 80;
    app.world_mut().get_mut::<Hp>(well).unwrap().0 = 20;
    app.update();
    assert!(!counts(&app, hurt).fleeing);
    assert!(counts(&app, well).fleeing);
}

#[test]
fn contexts_read_what_all_agents_share() {
    let mut app = app();
    let bp = blueprint(&tree(
        "<Fallback><Sequence><Alarmed/><Flee/></Sequence><Patrol/></Fallback>",
    ));
    let guards: Vec<Entity> = (0..3)
        .map(|_| {
            spawn(
                &mut app,
                TreeAgent::new(Arc::clone(&bp), Guard::default()),
                100,
            )
        })
        .collect();
    app.update();
    assert!(guards.iter().all(|&g| !counts(&app, g).fleeing));
    app.insert_resource(Alarm(true));
    app.update();
    assert!(guards.iter().all(|&g| counts(&app, g).fleeing));
}

/// What the test's systems and observers saw.
#[derive(Resource, Default)]
struct Seen {
    finished: Vec<TreeFinished>,
    failed: Vec<(Entity, String, String)>,
    on_entity: u32,
}

fn record_finished(mut messages: MessageReader<TreeFinished>, mut seen: ResMut<Seen>) {
    seen.finished.extend(messages.read().copied());
}

#[test]
fn results_are_messages_and_failures_reach_observers_with_their_reason() {
    let mut app = app();
    app.init_resource::<Seen>()
        .add_systems(Update, record_finished.after(TreeSystems::Tick))
        .add_observer(|failed: On<TreeFailed>, mut seen: ResMut<Seen>| {
            let seen_as = match &failed.reason {
                FailureReason::Failed(failure) => {
                    let leaf: &FailureLink = failure.leaf();
                    let reason = failure.reason().map(ToString::to_string);
                    (failed.entity, leaf.path.clone(), reason.unwrap_or_default())
                }
                FailureReason::Error(error) => (failed.entity, "error".into(), error.to_string()),
            };
            seen.failed.push(seen_as);
        });
    let ok = spawn(
        &mut app,
        TreeAgent::new(blueprint(&tree("<Step/>")), Guard::default()),
        100,
    );
    let stuck = blueprint(&tree(
        r#"<Sequence name="go"><Step/><NoPath name="plan"/></Sequence>"#,
    ));
    let failing = spawn(&mut app, TreeAgent::new(stuck, Guard::default()), 100);
    let running = spawn(
        &mut app,
        TreeAgent::new(blueprint(&tree(r#"<Hold speed="1"/>"#)), Guard::default()),
        100,
    );
    let broken = spawn(
        &mut app,
        TreeAgent::new(blueprint(&tree("<Broken/>")), Guard::default()),
        100,
    );
    app.world_mut()
        .entity_mut(failing)
        .observe(|_: On<TreeFailed>, mut seen: ResMut<Seen>| seen.on_entity += 1);
    for _ in 0..3 {
        app.update();
    }
    let seen = app.world().resource::<Seen>();
    let of = |e: Entity| {
        seen.finished
            .iter()
            .filter(|f| f.entity == e)
            .map(|f| f.status)
            .collect::<Vec<_>>()
    };
    assert_eq!(of(ok), [Status::Success; 3]);
    assert_eq!(of(failing), [Status::Failure; 3]);
    assert_eq!(of(running), []);
    assert_eq!(of(broken), []);
    let failure = (
        failing,
        "go/plan".to_string(),
        "no path (error 7)".to_string(),
    );
    let of = |e: Entity| seen.failed.iter().filter(|f| f.0 == e).collect::<Vec<_>>();
    assert_eq!(of(failing), [&failure; 3]);
    // An error is no Failure message, but it reaches the observers with the error.
    let errors = of(broken);
    assert_eq!(errors.len(), 3);
    assert_eq!(errors[0].1, "error");
    assert!(errors[0].2.starts_with("Broken (#0)"), "{}", errors[0].2);
    assert_eq!(seen.failed.len(), 6);
    assert_eq!(seen.on_entity, 3);
}

#[test]
fn removing_or_despawning_an_agent_halts_its_running_action_once() {
    let mut app = app();
    let bp = blueprint(&tree(r#"<Hold speed="1"/>"#));
    let halts: Vec<Arc<AtomicU32>> = (0..3).map(|_| Arc::default()).collect();
    let agents: Vec<Entity> = halts
        .iter()
        .map(|h| {
            let guard = Guard {
                halts: Arc::clone(h),
                ..Guard::default()
            };
            spawn(&mut app, TreeAgent::new(Arc::clone(&bp), guard), 100)
        })
        .collect();
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(counts(&app, agents[0]).started, 1);
    app.world_mut().despawn(agents[0]);
    app.world_mut()
        .entity_mut(agents[1])
        .remove::<TreeAgent<Guard>>();
    for _ in 0..3 {
        app.update();
    }
    let halted: Vec<u32> = halts.iter().map(|h| h.load(Ordering::SeqCst)).collect();
    assert_eq!(halted, [1, 1, 0]);
    let mut crowd = app.world_mut().resource_mut::<AgentCrowd<Guard>>();
    assert_eq!(crowd.crowd_mut().len(), 1);
    // The agent whose component went keeps its last written components and is ticked no more.
    assert_eq!(counts(&app, agents[1]).started, 1);
}

#[test]
fn replacing_an_agents_tree_halts_the_old_one_once_and_runs_the_new_one() {
    let mut app = app();
    let hold = blueprint(&tree(r#"<Hold speed="1"/>"#));
    let halts = Arc::new(AtomicU32::new(0));
    let guard = Guard {
        halts: Arc::clone(&halts),
        ..Guard::default()
    };
    let agent = spawn(&mut app, TreeAgent::new(hold, guard), 100);
    app.update();
    let step = blueprint(&tree("<Step/>"));
    app.world_mut()
        .entity_mut(agent)
        .insert(TreeAgent::new(step, Guard::default()));
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(halts.load(Ordering::SeqCst), 1);
    let mut crowd = app.world_mut().resource_mut::<AgentCrowd<Guard>>();
    assert_eq!(crowd.crowd_mut().len(), 1);
    // The new tree's context starts from the components, as the old one's did.
    assert_eq!(counts(&app, agent).steps, 3);
}

/// A directory of its own under the system's temporary one, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn asset_app(dir: &TempDir) -> App {
    let mut app = App::new();
    app.add_plugins((
        TaskPoolPlugin::default(),
        AssetPlugin {
            file_path: dir.0.display().to_string(),
            ..AssetPlugin::default()
        },
    ));
    app.add_plugins(NeuroTreePlugin::new(registry()));
    app
}

/// Updates until the asset has loaded or failed.
fn wait_for(app: &mut App, handle: &Handle<TreeAsset<Guard>>) -> LoadState {
    let deadline = std::time::Instant::now() + HANG;
    while std::time::Instant::now() < deadline {
        app.update();
        let state = app.world().resource::<AssetServer>().load_state(handle);
        if !matches!(state, LoadState::Loading | LoadState::NotLoaded) {
            return state;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    panic!("the asset neither loaded nor failed");
}

#[derive(Resource, Default)]
struct Reloads(Vec<TreeReloaded>);

#[test]
fn a_tree_file_loads_as_an_asset_and_reloads_keeping_the_state_of_unchanged_nodes() {
    let dir = TempDir::new("neurotree-bevy-reload");
    let v1 =
        tree(r#"<SequenceWithMemory name="work"><Step/><Hold speed="1"/></SequenceWithMemory>"#);
    std::fs::write(dir.0.join("guard.xml"), &v1).unwrap();
    let mut app = asset_app(&dir);
    app.init_resource::<Reloads>().add_systems(
        Update,
        (|mut m: MessageReader<TreeReloaded>, mut r: ResMut<Reloads>| {
            r.0.extend(m.read().copied())
        })
        .after(TreeSystems::Tick),
    );
    let handle: Handle<TreeAsset<Guard>> = app.world().resource::<AssetServer>().load("guard.xml");
    let halts = Arc::new(AtomicU32::new(0));
    let guard = Guard {
        halts: Arc::clone(&halts),
        ..Guard::default()
    };
    let agent = spawn(&mut app, TreeAgent::from_asset(handle.clone(), guard), 100);
    assert!(matches!(wait_for(&mut app, &handle), LoadState::Loaded));
    // The frames that waited for the file did not tick the agent.
    let start = counts(&app, agent).ticks;
    let frames = |app: &mut App, n| {
        for _ in 0..n {
            app.update();
        }
    };
    frames(&mut app, 3);
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 1)
    );
    assert_eq!(start, 0);

    // Hold's port changes: Hold restarts, the sequence and Step keep their state, so Step
    // does not run again.
    let v2 =
        tree(r#"<SequenceWithMemory name="work"><Step/><Hold speed="2"/></SequenceWithMemory>"#);
    std::fs::write(dir.0.join("guard.xml"), &v2).unwrap();
    app.world().resource::<AssetServer>().reload("guard.xml");
    let deadline = std::time::Instant::now() + HANG;
    while std::time::Instant::now() < deadline {
        app.update();
        if !app.world().resource::<Reloads>().0.is_empty() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let reloads = &app.world().resource::<Reloads>().0;
    assert_eq!(reloads.len(), 1);
    assert_eq!(reloads[0].entity, agent);
    let report = reloads[0].report;
    assert_eq!((report.kept, report.restarted, report.halted), (2, 1, 1));
    frames(&mut app, 2);
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 2)
    );
    assert_eq!(halts.load(Ordering::SeqCst), 1);

    // A change made in `Assets` reloads too: back to v1.
    let id = handle.id();
    app.world_mut()
        .resource_mut::<bevy_asset::Assets<TreeAsset<Guard>>>()
        .insert(id, TreeAsset::new(blueprint(&v1)))
        .unwrap();
    // `Assets` tells of the change at the end of the frame; the next frame reloads.
    frames(&mut app, 2);
    assert_eq!(app.world().resource::<Reloads>().0.len(), 2);
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 3)
    );
    assert_eq!(halts.load(Ordering::SeqCst), 2);
}

#[test]
fn a_bad_tree_file_fails_to_load_naming_its_line_and_column() {
    let dir = TempDir::new("neurotree-bevy-bad");
    std::fs::write(
        dir.0.join("bad.xml"),
        "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"Main\">\n    <Sequence>\n      <Nope/>\n      <Nada/>\n    </Sequence>\n  </BehaviorTree>\n</root>\n",
    )
    .unwrap();
    let mut app = asset_app(&dir);
    let handle: Handle<TreeAsset<Guard>> = app.world().resource::<AssetServer>().load("bad.xml");
    let agent = spawn(
        &mut app,
        TreeAgent::from_asset(handle.clone(), Guard::default()),
        100,
    );
    let LoadState::Failed(error) = wait_for(&mut app, &handle) else {
        panic!("a tree with an unknown node loaded");
    };
    let printed = error.to_string();
    // Every error, one per line, as `neurotree check` prints them.
    let errors: Vec<&str> = printed
        .lines()
        .filter(|l| l.contains(": error: "))
        .collect();
    assert_eq!(errors.len(), 2, "{printed}");
    assert!(
        errors[0].contains(": bad.xml:4:7: error: unknown node type `Nope`"),
        "{printed}"
    );
    assert!(
        errors[1].starts_with("bad.xml:5:7: error: unknown node type `Nada`"),
        "{printed}"
    );
    // The agent waits for a tree; it is never ticked.
    app.update();
    let agent = app.world().get::<TreeAgent<Guard>>(agent).unwrap();
    assert_eq!(agent.member(), None);
}

/// A tree file that includes `parts/hold.xml` (relative to its own directory, `trees/`),
/// which includes `speed.xml` beside it.
fn write_including_tree(dir: &TempDir, speed: i32) {
    std::fs::create_dir_all(dir.0.join("trees/parts")).unwrap();
    let main = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <include path="./parts/hold.xml"/>
  <BehaviorTree ID="Main">
    <SequenceWithMemory><Step/><SubTree ID="Holding"/></SequenceWithMemory>
  </BehaviorTree>
</root>"#;
    let hold = r#"<root BTCPP_format="4">
  <include path="speed.xml"/>
  <BehaviorTree ID="Holding"><SubTree ID="Speed"/></BehaviorTree>
</root>"#;
    let speed = format!(
        r#"<root BTCPP_format="4"><BehaviorTree ID="Speed"><Hold speed="{speed}"/></BehaviorTree></root>"#
    );
    std::fs::write(dir.0.join("trees/guard.xml"), main).unwrap();
    std::fs::write(dir.0.join("trees/parts/hold.xml"), hold).unwrap();
    std::fs::write(dir.0.join("trees/parts/speed.xml"), speed).unwrap();
}

#[test]
fn a_tree_file_loads_the_files_it_includes_relative_to_itself() {
    let dir = TempDir::new("neurotree-bevy-include");
    write_including_tree(&dir, 1);
    let mut app = asset_app(&dir);
    let server = app.world().resource::<AssetServer>().clone();
    let handle: Handle<TreeAsset<Guard>> = server.load("trees/guard.xml");
    let agent = spawn(
        &mut app,
        TreeAgent::from_asset(handle.clone(), Guard::default()),
        100,
    );
    assert!(matches!(wait_for(&mut app, &handle), LoadState::Loaded));
    app.update();
    app.update();
    // Step, then the included Hold, started once and running.
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 1)
    );
    // An include that names no file fails the tree, naming the include.
    std::fs::remove_file(dir.0.join("trees/parts/speed.xml")).unwrap();
    let broken: Handle<TreeAsset<Guard>> = server.load("trees/parts/hold.xml");
    let LoadState::Failed(error) = wait_for(&mut app, &broken) else {
        panic!("a tree whose include is missing loaded");
    };
    let printed = error.to_string();
    assert!(
        printed.contains("trees/parts/speed.xml: cannot read the included file"),
        "{printed}"
    );
}

/// With the watcher, a change to an included file reloads the tree that includes it.
#[cfg(feature = "file_watcher")]
#[test]
fn an_included_file_edited_on_disk_reloads_the_tree_that_includes_it() {
    let dir = TempDir::new("neurotree-bevy-watch-include");
    write_including_tree(&dir, 1);
    let mut app = asset_app(&dir);
    app.init_resource::<Reloads>().add_systems(
        Update,
        (|mut m: MessageReader<TreeReloaded>, mut r: ResMut<Reloads>| {
            r.0.extend(m.read().copied())
        })
        .after(TreeSystems::Tick),
    );
    let handle: Handle<TreeAsset<Guard>> = app
        .world()
        .resource::<AssetServer>()
        .load("trees/guard.xml");
    let agent = spawn(
        &mut app,
        TreeAgent::from_asset(handle.clone(), Guard::default()),
        100,
    );
    assert!(matches!(wait_for(&mut app, &handle), LoadState::Loaded));
    app.update();
    app.update();
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 1)
    );
    // Two levels down: guard.xml includes hold.xml, which includes speed.xml.
    let speed = r#"<root BTCPP_format="4"><BehaviorTree ID="Speed"><Hold speed="2"/></BehaviorTree></root>"#;
    std::fs::write(dir.0.join("trees/parts/speed.xml"), speed).unwrap();
    let deadline = std::time::Instant::now() + HANG;
    while std::time::Instant::now() < deadline {
        app.update();
        if !app.world().resource::<Reloads>().0.is_empty() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let reloads = &app.world().resource::<Reloads>().0;
    assert_eq!(
        reloads.len(),
        1,
        "the change to the included file reloaded nothing"
    );
    assert_eq!(reloads[0].entity, agent);
    assert_eq!(reloads[0].report.halted, 1);
    app.update();
    // The Hold restarted with its new speed; the Step before it kept its state.
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 2)
    );
}

/// With bevy_asset's watcher, a file edited on disk reloads the agents running it. The
/// watcher reports on its own thread after a debounce, so the frames are run until it has.
#[cfg(feature = "file_watcher")]
#[test]
fn a_tree_file_edited_on_disk_is_reloaded_keeping_state() {
    let dir = TempDir::new("neurotree-bevy-watch");
    let v1 = tree(r#"<SequenceWithMemory><Step/><Hold speed="1"/></SequenceWithMemory>"#);
    std::fs::write(dir.0.join("guard.xml"), &v1).unwrap();
    let mut app = asset_app(&dir);
    app.init_resource::<Reloads>().add_systems(
        Update,
        (|mut m: MessageReader<TreeReloaded>, mut r: ResMut<Reloads>| {
            r.0.extend(m.read().copied())
        })
        .after(TreeSystems::Tick),
    );
    let handle: Handle<TreeAsset<Guard>> = app.world().resource::<AssetServer>().load("guard.xml");
    let agent = spawn(
        &mut app,
        TreeAgent::from_asset(handle.clone(), Guard::default()),
        100,
    );
    assert!(matches!(wait_for(&mut app, &handle), LoadState::Loaded));
    app.update();
    app.update();
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 1)
    );
    let v2 = tree(r#"<SequenceWithMemory><Step/><Hold speed="2"/></SequenceWithMemory>"#);
    std::fs::write(dir.0.join("guard.xml"), &v2).unwrap();
    let deadline = std::time::Instant::now() + HANG;
    while std::time::Instant::now() < deadline {
        app.update();
        if !app.world().resource::<Reloads>().0.is_empty() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let reloads = &app.world().resource::<Reloads>().0;
    assert_eq!(reloads.len(), 1, "the watcher did not report the change");
    assert_eq!((reloads[0].report.kept, reloads[0].report.halted), (2, 1));
    app.update();
    assert_eq!(
        (counts(&app, agent).steps, counts(&app, agent).started),
        (1, 2)
    );
}

#[test]
fn sleeping_agents_wake_only_when_their_component_changes_or_a_message_names_them() {
    let mut app = App::new();
    app.add_plugins(
        NeuroTreePlugin::new(registry())
            .with_threads(2)
            .unwrap()
            .wake_on_change::<Hp>()
            .wake_on_message::<Poke>(|poke| poke.0),
    );
    let bp = blueprint(&tree("<WaitForHp/>"));
    let guards: Vec<Entity> = (0..20)
        .map(|_| {
            spawn(
                &mut app,
                TreeAgent::new(Arc::clone(&bp), Guard::default()),
                100,
            )
        })
        .collect();
    let ticks = |app: &App| -> Vec<u32> { guards.iter().map(|&g| counts(app, g).ticks).collect() };
    let last = |app: &mut App| {
        let report = app.world().resource::<AgentCrowd<Guard>>().last_frame();
        (report.ticked, report.asleep)
    };
    let mut expected = vec![1; 20];
    app.update();
    assert_eq!(last(&mut app), (20, 0));
    for _ in 0..4 {
        app.update();
        assert_eq!(last(&mut app), (0, 20));
    }
    assert_eq!(ticks(&app), expected);

    // A change to one guard's Hp wakes that guard alone: still unhurt enough to wait, it
    // is Running again, and asleep from the next frame.
    app.world_mut().get_mut::<Hp>(guards[3]).unwrap().0 = 60;
    app.update();
    expected[3] += 1;
    assert_eq!(ticks(&app), expected);
    assert_eq!(last(&mut app), (1, 19));
    app.update();
    assert_eq!(last(&mut app), (0, 20));

    // A message naming a guard wakes it alone.
    app.world_mut().write_message(Poke(guards[7]));
    app.update();
    expected[7] += 1;
    assert_eq!(ticks(&app), expected);
    app.update();
    assert_eq!(ticks(&app), expected);

    // A guard whose Hp drops to 0 succeeds; its tree, finished, is ticked every frame
    // from then on, as any tree that does not wait.
    app.world_mut().get_mut::<Hp>(guards[11]).unwrap().0 = 0;
    app.update();
    app.update();
    app.update();
    expected[11] += 3;
    assert_eq!(ticks(&app), expected);
    assert_eq!(last(&mut app), (1, 19));

    // Without the wakes, a change wakes no one.
    let mut plain = App::new();
    plain.add_plugins(NeuroTreePlugin::new(registry()).with_threads(2).unwrap());
    let guard = spawn(
        &mut plain,
        TreeAgent::new(Arc::clone(&bp), Guard::default()),
        100,
    );
    plain.update();
    plain.world_mut().get_mut::<Hp>(guard).unwrap().0 = 0;
    plain.update();
    assert_eq!(counts(&plain, guard).ticks, 1);
}

/// An app with Bevy's `TimePlugin`, each update 100 ms of real time.
fn timed_app() -> App {
    use bevy_time::{TimePlugin, TimeUpdateStrategy};
    let mut app = App::new();
    app.add_plugins(TimePlugin)
        .insert_resource(TimeUpdateStrategy::ManualDuration(
            std::time::Duration::from_millis(100),
        ))
        .add_plugins(NeuroTreePlugin::new(registry()).with_threads(2).unwrap());
    app
}

/// The trees' clock: what the virtual time was at the last frame.
fn virtual_now(app: &App) -> (std::time::Duration, std::time::Duration) {
    use bevy_time::{Time, Virtual};
    let time = app.world().resource::<Time<Virtual>>().elapsed();
    let clock = app.world().resource::<AgentCrowd<Guard>>().clock().now();
    (clock, time)
}

#[test]
fn the_trees_clock_follows_the_virtual_time_and_stops_while_it_is_paused() {
    use bevy_time::{Time, Virtual};
    let mut app = timed_app();
    let bp = blueprint(&tree("<Tick/>"));
    let agent = spawn(&mut app, TreeAgent::new(bp, Guard::default()), 100);
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(counts(&app, agent).ticks, 3);
    let (clock, time) = virtual_now(&app);
    assert_eq!(clock, time);
    assert!(time > std::time::Duration::ZERO);
    // Paused: no frame, no tick, the clock stands.
    app.world_mut().resource_mut::<Time<Virtual>>().pause();
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(counts(&app, agent).ticks, 3);
    assert_eq!(virtual_now(&app).0, clock);
    // Slowed to half speed: a frame moves the clock half of the real 100 ms.
    {
        let mut time = app.world_mut().resource_mut::<Time<Virtual>>();
        time.unpause();
        time.set_relative_speed(0.5);
    }
    app.update();
    app.update();
    assert_eq!(counts(&app, agent).ticks, 5);
    let (later, time) = virtual_now(&app);
    assert_eq!(later, time);
    assert_eq!(later - clock, std::time::Duration::from_millis(100));
}

#[test]
fn awake_agents_are_counted_by_reason_in_a_resource() {
    use neurotree_bevy::AwakeAgents;
    let mut app = app();
    let holds = blueprint(&tree("<Hold/>"));
    let ticks = blueprint(&tree("<Tick/>"));
    for _ in 0..3 {
        spawn(
            &mut app,
            TreeAgent::new(Arc::clone(&holds), Guard::default()),
            100,
        );
    }
    spawn(&mut app, TreeAgent::new(ticks, Guard::default()), 100);
    app.update();
    app.update();
    let awake = app.world().resource::<AwakeAgents>().clone();
    assert_eq!((awake.ticked, awake.asleep, awake.awake), (4, 0, 4));
    // `Hold` runs and declares no wait; `Tick`'s tree completes every frame.
    assert_eq!(
        awake.by_reason,
        [
            ("not_running".to_string(), 1),
            ("undeclared_leaf".to_string(), 3)
        ]
    );
}

/// A field of a reflected struct, by name, as `T`.
fn field<'a, T: bevy_reflect::Reflect>(value: &'a dyn bevy_reflect::Reflect, name: &str) -> &'a T {
    use bevy_reflect::structs::Struct;
    use bevy_reflect::ReflectRef;
    let ReflectRef::Struct(s) = value.reflect_ref() else {
        panic!("{} is not a struct", value.reflect_type_path());
    };
    let field = Struct::field(s, name).unwrap_or_else(|| panic!("no field {name}"));
    field
        .try_downcast_ref::<T>()
        .unwrap_or_else(|| panic!("{name} is not a {}", std::any::type_name::<T>()))
}

#[test]
fn agents_and_the_awake_counts_show_through_reflection() {
    use bevy_ecs::reflect::{AppTypeRegistry, ReflectComponent, ReflectResource};
    use neurotree_bevy::AgentSummary;
    let mut app = app();
    let holds = spawn(
        &mut app,
        TreeAgent::new(
            blueprint(&tree(r#"<Sequence name="watch"><Hold/></Sequence>"#)),
            Guard::default(),
        ),
        100,
    );
    let waits = spawn(
        &mut app,
        TreeAgent::new(blueprint(&tree("<WaitForHp/>")), Guard::default()),
        100,
    );
    let ends = spawn(
        &mut app,
        TreeAgent::new(blueprint(&tree("<Tick/>")), Guard::default()),
        100,
    );
    // On by default in debug builds only.
    app.world_mut()
        .resource_mut::<AgentCrowd<Guard>>()
        .set_summaries(true);
    app.update();
    app.update();
    let registry = app.world().resource::<AppTypeRegistry>().clone();
    let registry = registry.read();
    assert!(
        registry
            .get_type_data::<ReflectComponent>(std::any::TypeId::of::<TreeAgent<Guard>>())
            .is_some(),
        "TreeAgent<Guard> is registered as a reflected component"
    );
    let summaries = registry
        .get_type_data::<ReflectComponent>(std::any::TypeId::of::<AgentSummary>())
        .expect("AgentSummary is registered as a reflected component");
    let summary = |entity: Entity| {
        let reflected = summaries
            .reflect(app.world().entity(entity))
            .expect("an agent brings its summary along");
        (
            field::<String>(reflected, "tree").clone(),
            *field::<&'static str>(reflected, "status"),
            *field::<bool>(reflected, "asleep"),
            *field::<&'static str>(reflected, "awake_reason"),
            field::<String>(reflected, "why_awake").clone(),
        )
    };
    let (tree, status, asleep, reason, why) = summary(holds);
    assert_eq!(
        (status, asleep, reason),
        ("running", false, "undeclared_leaf")
    );
    assert!(why.contains("Hold"), "{why}");
    assert_eq!(tree, "watch");
    // Asleep since its first frame: the second did not tick it.
    assert_eq!(
        summary(waits),
        ("WaitForHp".into(), "asleep", true, "", String::new())
    );
    assert_eq!(counts(&app, waits).ticks, 1);
    let (_, status, asleep, reason, _) = summary(ends);
    assert_eq!((status, asleep, reason), ("success", false, "not_running"));
    drop(registry);

    // Woken with its `Hp` at 0, it completes, and its summary says so.
    app.world_mut().get_mut::<Hp>(waits).unwrap().0 = 0;
    app.world_mut()
        .resource_scope(|world, mut crowd: Mut<AgentCrowd<Guard>>| {
            let agent = world.get::<TreeAgent<Guard>>(waits).unwrap();
            crowd.member_mut(agent).unwrap().wake();
        });
    app.update();
    let summary = app.world().get::<AgentSummary>(waits).unwrap();
    assert_eq!(
        (summary.status, summary.asleep, summary.awake_reason),
        ("success", false, "not_running")
    );
    assert!(
        summary.why_awake.contains("WaitForHp"),
        "{}",
        summary.why_awake
    );
    let registry = app.world().resource::<AppTypeRegistry>().clone();
    let registry = registry.read();

    // A resource is reflected as the component of its entity.
    use neurotree_bevy::AwakeAgents;
    let awake = std::any::TypeId::of::<AwakeAgents>();
    assert!(registry.get_type_data::<ReflectResource>(awake).is_some());
    let resource = app.world().resource_entity::<AwakeAgents>().unwrap();
    let counted = registry
        .get_type_data::<ReflectComponent>(awake)
        .unwrap()
        .reflect(app.world().entity(resource))
        .unwrap();
    assert_eq!(*field::<u64>(counted, "ticked"), 3);
    assert_eq!(*field::<u64>(counted, "asleep"), 0);
    assert_eq!(*field::<u64>(counted, "awake"), 3);
}

#[test]
fn frames_run_on_every_core_by_default_or_on_the_threads_chosen() {
    let cores = std::thread::available_parallelism().unwrap().get();
    let mut by_default = App::new();
    by_default.add_plugins(NeuroTreePlugin::new(registry()));
    let bp = blueprint(&tree("<Tick/>"));
    let agents: Vec<Entity> = (0..300)
        .map(|_| {
            spawn(
                &mut by_default,
                TreeAgent::new(Arc::clone(&bp), Guard::default()),
                100,
            )
        })
        .collect();
    by_default.update();
    by_default.update();
    assert!(agents.iter().all(|&e| counts(&by_default, e).ticks == 2));
    let crowd = by_default.world().resource::<AgentCrowd<Guard>>();
    assert_eq!(crowd.threads(), cores);

    let mut chosen = App::new();
    chosen.add_plugins(NeuroTreePlugin::new(registry()).with_threads(1).unwrap());
    assert_eq!(chosen.world().resource::<AgentCrowd<Guard>>().threads(), 1);

    // On Bevy's compute pool, the trees get the threads `TaskPoolPlugin` gives it.
    let mut compute = App::new();
    compute.add_plugins((
        neurotree_bevy::task_pools(0),
        NeuroTreePlugin::new(registry()).on_compute_pool(),
    ));
    let threads = bevy_tasks::ComputeTaskPool::get().thread_num();
    assert_eq!(
        compute.world().resource::<AgentCrowd<Guard>>().threads(),
        threads
    );
    let agent = spawn(&mut compute, TreeAgent::new(bp, Guard::default()), 100);
    compute.update();
    assert_eq!(counts(&compute, agent).ticks, 1);
}

//! One agent of a crowd watched in a real browser: a person finds the crowd's agents in
//! the list, searches them, clicks one and sees its statuses at once (a sleeping one too,
//! and why it sleeps), edits its blackboard, and stops it at a breakpoint while the rest of
//! the crowd runs on, or, with the toggle, the whole crowd with it.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use neurotree::crowd::{Crowd, MemberId};
use neurotree::crowd_studio::watched_frame;
use neurotree_studio::Studio;
use neurotree_toolkit::{ManualClock, NodeStatus, Tree, XmlLoader};

use super::{browser_slot, css_path, registry, serve, workspace, Browser, NEEDS};

/// Sleeps for a minute: its agent is asleep after its first tick.
const RESTING: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Resting">
  <BehaviorTree ID="Resting">
    <Sequence name="night">
      <Sleep name="nap" msec="60000"/>
    </Sequence>
  </BehaviorTree>
</root>
"#;

/// Agents 0 to 19 choose by their scores (agent i's need `i % 3` is the highest), 20 to
/// 29 nap.
const AGENTS: usize = 30;

fn agent_tree(i: usize, clock: &ManualClock) -> Tree<()> {
    let registry = registry();
    let mut loader = XmlLoader::new(&registry);
    let (xml, name) = if i < 20 {
        (NEEDS, "needs.xml")
    } else {
        (RESTING, "resting.xml")
    };
    loader.load_str(xml, name).expect("the tree loads");
    let mut tree = Tree::with_clock(
        Arc::new(loader.build_main().expect("the tree builds")),
        clock.clone(),
    );
    if i < 20 {
        for (k, key) in ["a", "b", "c"].into_iter().enumerate() {
            let score = if k == i % 3 { 5.0 } else { 1.0 };
            tree.blackboard_mut().set(key, score).unwrap();
        }
    }
    tree
}

/// A crowd run frame by frame on a thread of its own, watched, until dropped.
struct CrowdRun {
    crowd: Arc<Mutex<Crowd<()>>>,
    ids: Vec<MemberId>,
    /// Frames run, and frames the page stood the whole crowd still for.
    ran: Arc<AtomicU64>,
    skipped: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl CrowdRun {
    fn start(studio: &Studio) -> CrowdRun {
        let clock = ManualClock::new();
        let mut crowd = Crowd::new(clock.clone()).with_threads(1).unwrap();
        let ids = (0..AGENTS)
            .map(|i| crowd.add_tree(agent_tree(i, &clock), ()))
            .collect();
        let crowd = Arc::new(Mutex::new(crowd));
        let mut watch = studio.watch_crowd("village");
        let (ran, skipped, stop) = Default::default();
        let (crowd2, ran2, skipped2, stop2): (_, Arc<AtomicU64>, Arc<AtomicU64>, Arc<AtomicBool>) = (
            Arc::clone(&crowd),
            Arc::clone(&ran),
            Arc::clone(&skipped),
            Arc::clone(&stop),
        );
        let thread = std::thread::spawn(move || {
            while !stop2.load(Ordering::Relaxed) {
                let mut crowd = crowd2.lock().unwrap();
                match watched_frame(&mut crowd, &mut watch) {
                    Some(_) => ran2.fetch_add(1, Ordering::Relaxed),
                    None => skipped2.fetch_add(1, Ordering::Relaxed),
                };
                drop(crowd);
                clock.advance(Duration::from_millis(20));
                // The pace of a game, so that the page is not flooded.
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        CrowdRun {
            crowd,
            ids,
            ran,
            skipped,
            stop,
            thread: Some(thread),
        }
    }

    /// Agent `i`'s entry `key`.
    fn entry(&self, i: usize, key: &str) -> f64 {
        let crowd = self.crowd.lock().unwrap();
        let m = crowd.get(self.ids[i]).unwrap();
        m.tree().blackboard().get::<f64>(key).unwrap()
    }

    /// Agent `i`'s node statuses.
    fn statuses(&self, i: usize) -> Vec<NodeStatus> {
        let crowd = self.crowd.lock().unwrap();
        crowd.get(self.ids[i]).unwrap().tree().statuses().to_vec()
    }

    fn held(&self, i: usize) -> bool {
        self.crowd.lock().unwrap().is_held(self.ids[i])
    }
}

impl Drop for CrowdRun {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The agent ids the list shows.
async fn listed(b: &Browser) -> Vec<String> {
    let v = b
        .js("return [...document.querySelectorAll('#watch-view [data-agent]')].map(e => e.dataset.agent);")
        .await;
    serde_json::from_value(v).unwrap()
}

/// Waits until the page watches agent `id`: its value and its text.
async fn until_watching(b: &Browser, id: &str) {
    b.until(
        &format!("agent {id} watched"),
        &format!(
            "(() => {{ const w = document.querySelector('[data-watched-agent]');
                 return w && w.value === '{id}' && w.textContent === '{id}'; }})()"
        ),
    )
    .await;
}

/// Serves a crowd of [`AGENTS`] running in the studio and opens the address it prints, until
/// every agent is listed: the folder, the studio and the run, to drop in the reverse order.
async fn open_crowd(b: &Browser) -> (tempfile::TempDir, Studio, CrowdRun) {
    let dir = workspace();
    let studio = serve(dir.path());
    let run = CrowdRun::start(&studio);
    b.goto(&studio.url()).await;
    b.until(
        "the agents listed",
        &format!("document.querySelectorAll('#watch-view [data-agent]').length === {AGENTS}"),
    )
    .await;
    (dir, studio, run)
}

/// The status the page shows on the node at `path`.
async fn shown(b: &Browser, path: &str) -> Option<String> {
    b.attr(&format!("#watch-view {}", css_path(path)), "data-status")
        .await
}

#[tokio::test(flavor = "multi_thread")]
async fn a_crowds_agents_are_listed_searched_and_each_watched_at_once() {
    let _slot = browser_slot().await;
    let Some(b) = Browser::start().await else {
        return;
    };
    // The address the program prints opens the watch view on the first agent.
    let (_dir, _studio, run) = open_crowd(&b).await;
    until_watching(&b, "0").await;
    let all = listed(&b).await;
    assert_eq!(all, (0..AGENTS).map(|i| i.to_string()).collect::<Vec<_>>());
    // Agent 0 eats.
    b.until(
        "agent 0 eating",
        &format!(
            "document.querySelector('#watch-view {}').dataset.status === 'RUNNING'",
            css_path("choose/eat/eating").replace('"', "\\\"")
        ),
    )
    .await;

    // Typing in the search keeps the agents whose id holds it.
    b.click("[data-agent-search]").await;
    b.element("[data-agent-search]")
        .await
        .send_keys("2")
        .await
        .unwrap();
    b.until(
        "the list searched",
        "document.querySelectorAll('#watch-view [data-agent]').length === 12",
    )
    .await;
    let found = listed(&b).await;
    let expected: Vec<String> = (0..AGENTS)
        .filter(|i| i.to_string().contains('2'))
        .map(|i| i.to_string())
        .collect();
    assert_eq!(found, expected);

    // A napping agent: shown at once as its tree stands, asleep.
    b.click("[data-agent='25']").await;
    until_watching(&b, "25").await;
    b.until(
        "the nap shown running",
        &format!(
            "document.querySelector('#watch-view {}')?.dataset.status === 'RUNNING'",
            css_path("night/nap").replace('"', "\\\"")
        ),
    )
    .await;
    assert_eq!(run.statuses(25)[1], NodeStatus::Running);
    let why = b
        .until(
            "why it is awake, or that it sleeps",
            "document.querySelector('[data-why-awake]').textContent === 'asleep' && 'asleep'",
        )
        .await;
    assert_eq!(why, "asleep");

    // Agent 12 (12 % 3 == 0) eats; agent 2 works: each shown as it runs.
    b.click("[data-agent='2']").await;
    until_watching(&b, "2").await;
    b.until(
        "agent 2 working",
        &format!(
            "document.querySelector('#watch-view {}')?.dataset.status === 'RUNNING'",
            css_path("choose/work/working").replace('"', "\\\"")
        ),
    )
    .await;
    assert_eq!(
        shown(&b, "choose/eat/eating").await.as_deref(),
        Some("IDLE")
    );
    b.until(
        "why agent 2 is awake",
        "document.querySelector('[data-why-awake]').textContent.startsWith('awake: ')",
    )
    .await;
    // Its scores, as its UtilitySelector gave them.
    b.until(
        "agent 2's scores on their nodes",
        &format!(
            "document.querySelector('#watch-view {}')?.dataset.score === '5'",
            css_path("choose/work").replace('"', "\\\"")
        ),
    )
    .await;
    drop(run);
    b.close().await;
}

#[tokio::test(flavor = "multi_thread")]
async fn an_edit_a_pause_and_a_breakpoint_touch_the_agent_watched_alone_or_the_whole_crowd() {
    let _slot = browser_slot().await;
    let Some(b) = Browser::start().await else {
        return;
    };
    let (_dir, _studio, run) = open_crowd(&b).await;
    b.click("[data-agent='4']").await;
    until_watching(&b, "4").await;

    // Agent 4's `a` edited: it alone changes.
    let field = "#watch-view input[data-entry=a][data-scope='0']";
    b.until(
        "agent 4's blackboard shown",
        &format!("document.querySelector(\"{field}\")?.value === '1'"),
    )
    .await;
    // The field stays where it is while the run ticks and the panels above it (why the
    // agent is awake, what runs, the last failure) change: a click aimed at it lands on it.
    let top = format!("document.querySelector(\"{field}\").getBoundingClientRect().top");
    let first = b.js(&format!("return {top}")).await;
    for _ in 0..10 {
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
        let now = b.js(&format!("return {top}")).await;
        assert_eq!(now, first, "the field moved");
    }
    b.type_into(field, "\u{e009}a\u{e009}9\u{e007}").await;
    b.until(
        "the edit shown",
        "studio.views.watch.state.blackboards[0].entries.find(e => e.key === 'a').value === 9",
    )
    .await;
    assert_eq!(run.entry(4, "a"), 9.0);
    for i in (0..20).filter(|&i| i != 4) {
        let want = if i % 3 == 0 { 5.0 } else { 1.0 };
        assert_eq!(run.entry(i, "a"), want, "agent {i}");
    }

    // A breakpoint before `eating`, which agent 4 now chooses: it stops there, alone.
    let eating = css_path("choose/eat/eating");
    b.click(&format!("#watch-view {eating}")).await;
    b.element("select[data-breakpoint-select]")
        .await
        .select_by_value("before")
        .await
        .unwrap();
    b.until(
        "paused at the breakpoint",
        "document.querySelector('[data-run-state]').dataset.runState === 'paused'",
    )
    .await;
    b.until(
        "held, and told so",
        "document.querySelector('[data-why-awake]').textContent.startsWith('held')",
    )
    .await;
    assert!(run.held(4));
    // The rest runs on: frames go by while it is held.
    let ran = run.ran.load(Ordering::Relaxed);
    wait_for(|| run.ran.load(Ordering::Relaxed) >= ran + 10).await;
    assert!(run.held(4), "held while the others ran");
    assert_eq!(run.skipped.load(Ordering::Relaxed), 0);

    // With the toggle, the whole crowd stands still with it.
    b.click("[data-agent-together]").await;
    wait_for(|| run.skipped.load(Ordering::Relaxed) >= 5).await;
    let ran = run.ran.load(Ordering::Relaxed);
    let skipped = run.skipped.load(Ordering::Relaxed);
    wait_for(|| run.skipped.load(Ordering::Relaxed) >= skipped + 10).await;
    assert_eq!(
        run.ran.load(Ordering::Relaxed),
        ran,
        "no frame while all stand still"
    );
    assert!(!run.held(4), "the crowd stands still, not the agent alone");

    // The breakpoint off and continued: every agent goes on.
    b.click(&format!("#watch-view {eating}")).await;
    b.element("select[data-breakpoint-select]")
        .await
        .select_by_value("off")
        .await
        .unwrap();
    b.click("[data-action=continue]").await;
    b.until(
        "the page told the run goes on",
        "document.querySelector('[data-run-state]').dataset.runState !== 'paused'",
    )
    .await;
    wait_for(|| run.ran.load(Ordering::Relaxed) >= ran + 10).await;
    assert!(!run.held(4));
    drop(run);
    b.close().await;
}

/// Waits until `done`, failing only after minutes: a catch for a crowd that hangs, far
/// longer than any wait on a loaded machine.
async fn wait_for(done: impl Fn() -> bool) {
    let deadline = std::time::Instant::now() + Duration::from_secs(180);
    while !done() {
        assert!(
            std::time::Instant::now() < deadline,
            "timed out waiting for the crowd"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

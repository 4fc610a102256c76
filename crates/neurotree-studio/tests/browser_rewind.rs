//! Rewind and the scene panel in a real browser (Debian's `chromium` through
//! `chromedriver`): a person pauses a watched run, clicks back and forward through the
//! ticks it kept and sees the tick, the statuses, the blackboard and the robot of each;
//! edits the blackboard at a past tick and steps, which forks the run there; and finds the
//! back button disabled, with the reason in its title, where the run cannot go back.
//!
//! Without a browser the tests print a note and pass, unless `NEUROTREE_REQUIRE_BROWSER=1`
//! (see `common/browser.rs`).

use crate::driver as browser;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use browser::Browser;
use neurotree_studio::{Studio, StudioOptions, World};
use neurotree_toolkit::scene::{Scene, Style};
use neurotree_toolkit::state::{decode, encode};
use neurotree_toolkit::{Handle, Registry, StatefulAction, Status, Tree, XmlLoader};
use serde_json::Value;

// One browser at a time, with the other browser tests: each is a few processes on a small
// machine.
use crate::browser_slot;

/// Counts its ticks in `n` and walks: `walk` is RUNNING for two ticks and SUCCESS on the
/// third, so at tick t it shows SUCCESS exactly when t is a multiple of 3.
pub(crate) const PATROL: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Patrol">
  <BehaviorTree ID="Patrol">
    <ReactiveSequence name="patrol">
      <Script name="count" code="n += 1"/>
      <Walk name="walk"/>
    </ReactiveSequence>
  </BehaviorTree>
</root>
"#;

/// Runs for two ticks, then succeeds; its state is saved with the tree's.
pub(crate) struct Walk {
    pub(crate) left: u32,
}

impl StatefulAction<()> for Walk {
    fn on_start(&mut self, h: &mut Handle<'_, ()>) -> Status {
        self.left = 2;
        self.on_running(h)
    }
    fn on_running(&mut self, _: &mut Handle<'_, ()>) -> Status {
        if self.left == 0 {
            return Status::Success;
        }
        self.left -= 1;
        Status::Running
    }
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(encode(&self.left))
    }
    fn restore_state(&mut self, state: &[u8]) -> bool {
        decode(state).map(|left| self.left = left).is_some()
    }
}

/// The robot: one metre along x a tick, drawn as a circle (`robot`) on its track.
struct Track {
    x: f64,
}

impl World<()> for Track {
    type Saved = f64;
    fn save(&self, _: &Tree<()>) -> Result<f64, String> {
        Ok(self.x)
    }
    fn restore(&mut self, saved: &f64) {
        self.x = *saved;
    }
    fn scene(&self, _: &Tree<()>) -> Option<Scene> {
        let mut scene = Scene::new([0.0, -2.0], [100.0, 2.0]);
        scene.polyline(
            "track",
            vec![[0.0, 0.0], [100.0, 0.0]],
            Style::stroke("#888", 0.1),
        );
        scene.circle("robot", [self.x, 0.0], 0.8, Style::fill("#1c7ed6"));
        Some(scene)
    }
}

fn registry() -> Registry<()> {
    let mut registry = Registry::new();
    registry
        .register_stateful("Walk", vec![], || Walk { left: 0 })
        .expect("Walk is free");
    registry
        .register_async("Forever", vec![], |_| std::future::pending::<Status>())
        .expect("Forever is free");
    registry
}

fn load(xml: &str) -> Tree<()> {
    load_hooked(xml, None)
}

/// The tree of `xml`, built with `hooks` (the studio's force hooks, say) when given.
pub(crate) fn load_hooked(
    xml: &str,
    hooks: Option<neurotree_toolkit::xml::SharedHookWrapper<()>>,
) -> Tree<()> {
    let registry = registry();
    let mut loader = XmlLoader::new(&registry);
    if let Some(hooks) = hooks {
        loader = loader.wrap_hooks(hooks);
    }
    loader.load_str(xml, "patrol.xml").expect("the tree loads");
    let mut tree = Tree::new(Arc::new(loader.build_main().expect("the tree builds")));
    tree.blackboard_mut().set("n", 0i64).expect("n is free");
    tree
}

pub(crate) fn serve(root: &std::path::Path) -> Studio {
    let options = StudioOptions {
        root: root.to_path_buf(),
        ..StudioOptions::default()
    };
    Studio::serve(options, registry).expect("the studio serves")
}

/// A watched run on a thread of its own, a tick every `pace`, the robot moving a metre a
/// tick; the ticks it forked at, as the watch returned them.
pub(crate) struct Run {
    stop: Arc<AtomicBool>,
    pub(crate) forks: Arc<Mutex<Vec<u64>>>,
    thread: Option<JoinHandle<()>>,
}

impl Run {
    pub(crate) fn start(studio: &Studio, mut tree: Tree<()>, pace: Duration) -> Run {
        let mut watch = studio.watch(&mut tree, "patrol.xml").rewind_window(50);
        let stop = Arc::new(AtomicBool::new(false));
        let forks = Arc::new(Mutex::new(Vec::new()));
        let (stop2, forks2) = (Arc::clone(&stop), Arc::clone(&forks));
        let thread = std::thread::spawn(move || {
            let mut track = Track { x: 0.0 };
            while !stop2.load(Ordering::Relaxed) {
                if let Some(to) = watch.between_ticks_with(&mut tree, &mut track) {
                    forks2.lock().expect("not poisoned").push(to);
                }
                tree.tick_once(&mut ()).expect("the tree ticks");
                track.x += 1.0;
                std::thread::sleep(pace);
            }
        });
        Run {
            stop,
            forks,
            thread: Some(thread),
        }
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        // A run a page still holds goes on once the page leaves: joined only if it ends.
        if let Some(t) = self.thread.take() {
            let deadline = std::time::Instant::now() + Duration::from_secs(2);
            while !t.is_finished() && std::time::Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(10));
            }
            if t.is_finished() {
                let _ = t.join();
            }
        }
    }
}

/// What the page shows: the tick, `walk`'s status, the field of `n`, the robot's x, and
/// the back button's state and title.
async fn shown(b: &Browser) -> Value {
    b.js(
        "const v = document.querySelector('#watch-view');
         const back = v.querySelector('[data-action=back]');
         return {
           tick: Number(v.querySelector('[data-tick]').dataset.tick),
           walk: v.querySelector('[data-node-path=\"patrol/walk\"]').dataset.status,
           n: v.querySelector('input[data-entry=n]')?.value,
           robot: Number(v.querySelector('[data-scene] [data-scene-item=robot]')?.getAttribute('cx')),
           back: back.disabled, title: back.title,
         };",
    )
    .await
}

/// Waits until the page shows tick `tick`, and returns what it shows then.
async fn at_tick(b: &Browser, tick: u64) -> Value {
    b.until(
        &format!("tick {tick} shown"),
        &format!(
            "Number(document.querySelector('#watch-view [data-tick]').dataset.tick) === {tick}"
        ),
    )
    .await;
    // The panels follow the tick within a frame.
    tokio::time::sleep(Duration::from_millis(150)).await;
    shown(b).await
}

fn walk_at(tick: u64) -> &'static str {
    if tick.is_multiple_of(3) {
        "SUCCESS"
    } else {
        "RUNNING"
    }
}

#[tokio::test(flavor = "multi_thread")]
async fn back_and_forward_show_each_kept_tick_and_a_step_from_the_past_forks_the_run() {
    let _slot = browser_slot().await;
    let Some(b) = Browser::start().await else {
        return;
    };
    let dir = tempfile::tempdir().expect("a folder");
    let studio = serve(dir.path());
    let run = Run::start(&studio, load(PATROL), Duration::from_millis(30));
    b.goto(&format!("{}#view=watch", studio.url())).await;
    b.until(
        "a few ticks",
        "Number(document.querySelector('#watch-view [data-tick]').dataset.tick) > 6",
    )
    .await;
    let running = shown(&b).await;
    assert_eq!(running["back"], true, "{running}");
    assert_eq!(running["title"], "pause the run to go back");
    assert_eq!(b.count("[data-scene] [data-scene-item=track]").await, 1);

    b.click("#watch-view [data-action=pause]").await;
    b.until(
        "paused",
        "document.querySelector('#watch-view [data-run-state]').dataset.runState === 'paused' && !document.querySelector('#watch-view [data-action=back]').disabled",
    )
    .await;
    let p = b.shown_tick().await;
    let now = at_tick(&b, p).await;
    assert_eq!(
        (
            now["n"].as_str(),
            now["robot"].as_f64(),
            now["walk"].as_str()
        ),
        (
            Some(p.to_string().as_str()),
            Some(p as f64),
            Some(walk_at(p))
        ),
        "{now}"
    );

    // Back two ticks, one by one: each shows its own tick, statuses, blackboard and robot.
    for back in 1..=2 {
        b.click("#watch-view [data-action=back]").await;
        let t = p - back;
        let then = at_tick(&b, t).await;
        assert_eq!(then["walk"], walk_at(t), "tick {t}: {then}");
        assert_eq!(then["n"], t.to_string(), "tick {t}: {then}");
        assert_eq!(then["robot"], t as f64, "tick {t}: {then}");
    }
    assert_eq!(
        b.attr("#watch-view", "data-at").await.as_deref(),
        Some((p - 2).to_string().as_str())
    );
    let state = b
        .js("return document.querySelector('#watch-view [data-run-state]').textContent;")
        .await;
    assert!(
        state
            .as_str()
            .unwrap()
            .starts_with(&format!("back at tick {}", p - 2)),
        "{state}"
    );
    b.click("#watch-view [data-action=forward]").await;
    let fork = p - 1;
    let then = at_tick(&b, fork).await;
    assert_eq!(then["n"], fork.to_string(), "{then}");
    assert_eq!(then["robot"].as_f64(), Some(fork as f64), "{then}");

    // An edit at the past tick, then a step: the run goes on from there with the edit.
    let field = "#watch-view input[data-entry=n][data-scope='0']";
    b.click(field).await;
    b.element(field)
        .await
        .send_keys("\u{e009}a\u{e009}100\u{e007}")
        .await
        .expect("typing");
    b.until(
        "the edit applied",
        "studio.views.watch.state.blackboards[0].entries.find(e => e.key === 'n').value === 100",
    )
    .await;
    b.click("#watch-view [data-action=step]").await;
    let forked = at_tick(&b, p).await;
    assert_eq!(forked["n"], "101", "{forked}");
    assert_eq!(forked["robot"], p as f64, "{forked}");
    assert_eq!(forked["walk"], walk_at(p), "{forked}");
    assert_eq!(*run.forks.lock().expect("not poisoned"), vec![fork]);
    // Nothing after the fork is kept: forward is disabled at its newest tick.
    b.until(
        "forward disabled at the newest tick",
        "document.querySelector('#watch-view [data-action=forward]').disabled",
    )
    .await;
    let title = b.attr("#watch-view [data-action=forward]", "title").await;
    assert_eq!(title, Some(format!("tick {p} is the latest")));
    drop(run);
    b.close().await;
}

#[tokio::test(flavor = "multi_thread")]
async fn where_the_tree_cannot_be_saved_back_is_disabled_and_says_why() {
    let _slot = browser_slot().await;
    let Some(b) = Browser::start().await else {
        return;
    };
    let dir = tempfile::tempdir().expect("a folder");
    let studio = serve(dir.path());
    let tree = load(&PATROL.replace("<Walk name=\"walk\"/>", "<Forever name=\"walk\"/>"));
    let run = Run::start(&studio, tree, Duration::from_millis(30));
    b.goto(&format!("{}#view=watch", studio.url())).await;
    b.until(
        "a few ticks",
        "Number(document.querySelector('#watch-view [data-tick]').dataset.tick) > 3",
    )
    .await;
    b.click("#watch-view [data-action=pause]").await;
    b.until(
        "paused",
        "document.querySelector('#watch-view [data-run-state]').dataset.runState === 'paused'",
    )
    .await;
    let title = b
        .until(
            "the reason in the back button's title",
            "document.querySelector('#watch-view [data-action=back]').disabled && document.querySelector('#watch-view [data-action=back]').title.startsWith('cannot go back') && document.querySelector('#watch-view [data-action=back]').title",
        )
        .await;
    let title = title.as_str().expect("a title");
    assert!(title.contains("walk") && title.contains("async"), "{title}");
    drop(run);
    b.close().await;
}

//! Watching a run through the WebSocket, as a page does: the whole tree first, then only
//! changes; pause, step and continue; breakpoints; blackboard edits between ticks; and a
//! run that goes on whatever the pages do.

use crate::common;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use common::{get, Page};
use neurotree_studio::{Studio, StudioOptions};
use neurotree_toolkit::{ManualClock, Registry, Tree, XmlLoader};
use serde_json::{json, Value};

/// Node ids: 0 `root`, 1 the Script, 2 `done`.
const TREE: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Sequence name="root">
      <Script code="count += 1"/>
      <AlwaysSuccess name="done"/>
    </Sequence>
  </BehaviorTree>
</root>"#;

/// A run ticking every 5 ms until stopped, watched by a studio; `ticks` counts the ticks
/// it made.
struct Run {
    studio: Studio,
    ticks: Arc<AtomicU64>,
    count: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    thread: Option<thread::JoinHandle<()>>,
}

/// A studio serving an empty temporary folder (kept as long as the studio is).
fn studio() -> (Studio, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let options = StudioOptions {
        root: dir.path().to_path_buf(),
        ..StudioOptions::default()
    };
    (Studio::serve(options, Registry::new).unwrap(), dir)
}

/// The blueprint of `xml`, with the built-in nodes only.
fn blueprint(xml: &str) -> Arc<neurotree_toolkit::Blueprint<()>> {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(xml, "main.xml").unwrap();
    Arc::new(loader.build_main().unwrap())
}

impl Run {
    fn start() -> Run {
        let (studio, dir) = studio();
        let clock = ManualClock::new();
        let mut tree = Tree::with_clock(blueprint(TREE), clock.clone());
        tree.blackboard_mut().set("count", 0i64).unwrap();
        let mut watch = studio.watch(&mut tree, "main.xml");
        let ticks = Arc::new(AtomicU64::new(0));
        let count = Arc::new(AtomicU64::new(0));
        let stop = Arc::new(AtomicBool::new(false));
        let (t, c, s) = (Arc::clone(&ticks), Arc::clone(&count), Arc::clone(&stop));
        let thread = thread::spawn(move || {
            while !s.load(Ordering::Acquire) {
                watch.between_ticks(&mut tree);
                clock.advance(Duration::from_millis(100));
                tree.tick_once(&mut ()).unwrap();
                t.fetch_add(1, Ordering::AcqRel);
                c.store(
                    tree.blackboard().get::<u64>("count").unwrap(),
                    Ordering::Release,
                );
                thread::sleep(Duration::from_millis(5));
            }
            drop(dir);
        });
        Run {
            studio,
            ticks,
            count,
            stop,
            thread: Some(thread),
        }
    }

    fn ticks(&self) -> u64 {
        self.ticks.load(Ordering::Acquire)
    }

    /// Waits until the run has made more than `n` ticks.
    fn wait_past(&self, n: u64) {
        let until = Instant::now() + Duration::from_secs(20);
        while self.ticks() <= n {
            assert!(
                Instant::now() < until,
                "the run stands still at {}",
                self.ticks()
            );
            thread::sleep(Duration::from_millis(5));
        }
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The node paths of a `hello`'s tree, in id order.
fn paths_of(hello: &Value) -> Vec<&str> {
    hello["tree"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["path"].as_str().unwrap())
        .collect()
}

fn root_count(m: &Value) -> Option<i64> {
    m["scopes"][0]["entries"]
        .as_array()?
        .iter()
        .find(|e| e["key"] == "count")?["value"]
        .as_i64()
}

#[test]
fn a_page_gets_the_whole_tree_then_changes() {
    let run = Run::start();
    run.wait_past(2);
    let mut page = Page::connect(run.studio.addr());
    let hello = page.expect("hello");
    let paths = paths_of(&hello);
    assert_eq!(paths, ["root", "root/Script", "root/done"]);
    assert_eq!(hello["tree"]["nodes"][0]["category"], "control");
    assert_eq!(hello["statuses"].as_array().unwrap().len(), 3);
    assert!(hello["tick"].as_u64().unwrap() >= 2);
    // Later messages carry the tick and what changed; ticks only grow.
    let first = page.expect("tick")["tick"].as_u64().unwrap();
    let later = page.expect_where("tick", |m| m["tick"].as_u64().unwrap() > first + 3);
    assert!(later["changes"].is_array());
    assert_eq!(get(run.studio.addr(), "/api/stats").json()["pages"], 1);
}

#[test]
fn pause_holds_the_run_and_each_step_is_one_tick() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    page.send(r#"{"type":"pause"}"#);
    let paused = page.expect("paused");
    assert_eq!(paused["paused"]["why"], "pause");
    // "paused" is sent from inside the held run, so nothing ticks until a page says so:
    // each step below is exactly one more tick, which a run that went on would break.
    let at = run.ticks();
    for n in 1..=3 {
        page.send(r#"{"type":"step"}"#);
        let stepped = page.expect_where("paused", |m| m["paused"]["why"] == "step");
        assert_eq!(run.ticks(), at + n, "step {n}");
        assert_eq!(stepped["tick"].as_u64().unwrap(), at + n);
    }
    page.send(r#"{"type":"continue"}"#);
    page.expect("resumed");
    run.wait_past(at + 5);
}

#[test]
fn a_breakpoint_stops_before_its_node_and_on_its_status() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    page.send(r#"{"type":"breakpoint","node":2,"when":"before"}"#);
    let set = page.expect("breakpoints");
    assert_eq!(set["breakpoints"], json!([{"node": 2, "when": "before"}]));
    let hit = page.expect("paused");
    assert_eq!(
        hit["paused"],
        json!({"why": "breakpoint", "node": 2, "status": null})
    );
    // Held inside the tick: the continue below moves it on by exactly one.
    let at = run.ticks();
    // On to the same breakpoint in the next tick.
    page.send(r#"{"type":"continue"}"#);
    page.expect("resumed");
    page.expect("paused");
    assert_eq!(run.ticks(), at + 1);
    // A breakpoint on a result instead.
    page.send(r#"{"type":"breakpoint","node":2,"when":"SUCCESS"}"#);
    page.send(r#"{"type":"continue"}"#);
    let hit = page.expect_where("paused", |m| m["paused"]["status"] == "SUCCESS");
    assert_eq!(hit["paused"]["node"], 2);
    page.send(r#"{"type":"breakpoint","node":2,"when":"off"}"#);
    page.send(r#"{"type":"continue"}"#);
    page.expect("resumed");
    run.wait_past(at + 10);
    // A node the tree does not have.
    page.send(r#"{"type":"breakpoint","node":99,"when":"before"}"#);
    assert!(page.expect("refused")["why"]
        .as_str()
        .unwrap()
        .contains("99"));
}

#[test]
fn a_blackboard_edit_lands_between_ticks() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    page.send(r#"{"type":"pause"}"#);
    page.expect("paused");
    page.send(r#"{"type":"set","scope":0,"key":"count","value":100}"#);
    let shown = page.expect_where("blackboards", |m| root_count(m) == Some(100));
    assert_eq!(shown["scopes"][0]["path"], "");
    page.send(r#"{"type":"step"}"#);
    page.expect_where("paused", |m| m["paused"]["why"] == "step");
    // The Script counted on from the edited value.
    assert_eq!(run.count.load(Ordering::Acquire), 101);
}

#[test]
fn an_edit_that_does_not_fit_is_refused_with_why_until_one_applies() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    assert_eq!(page.expect("hello")["edits"], json!([]));
    page.send(r#"{"type":"pause"}"#);
    page.expect("paused");
    // An object for a whole number, then text that is not one: each refused at the entry,
    // which keeps its value.
    page.send(r#"{"type":"set","scope":0,"key":"count","value":{"deep":1}}"#);
    let refused = page.expect("edits")["refused"].clone();
    assert_eq!(refused[0]["scope"], 0);
    assert_eq!(refused[0]["key"], "count");
    let why = refused[0]["why"].as_str().unwrap();
    assert!(why.starts_with("`count` holds a `i64`"), "{why}");
    page.send(r#"{"type":"set","scope":0,"key":"count","value":"many"}"#);
    let refused = page.expect("edits")["refused"].clone();
    assert_eq!(refused.as_array().unwrap().len(), 1, "{refused}");
    assert!(refused[0]["why"]
        .as_str()
        .unwrap()
        .contains("`many` is not one"));
    // A page that comes now is told the refusal standing.
    let mut late = Page::connect(run.studio.addr());
    assert_eq!(late.expect("hello")["edits"], refused);
    late.close();
    // An edit that fits applies and clears it.
    page.send(r#"{"type":"set","scope":0,"key":"count","value":"7"}"#);
    assert_eq!(page.expect("edits")["refused"], json!([]));
    page.expect_where("blackboards", |m| root_count(m) == Some(7));
    page.send(r#"{"type":"step"}"#);
    page.expect_where("paused", |m| m["paused"]["why"] == "step");
    assert_eq!(run.count.load(Ordering::Acquire), 8);
}

#[test]
fn bad_messages_are_refused_and_counted_and_the_page_stays() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    for bad in [
        "not json",
        r#"{"type":"explode"}"#,
        r#"{"type":"set","scope":0,"key":"","value":1}"#,
        &format!(r#"{{"type":"pause","pad":"{}"}}"#, "x".repeat(70_000)),
    ] {
        page.send(bad);
        page.expect("refused");
    }
    // A flood: past 100 a second the rest are refused without an answer each.
    for _ in 0..300 {
        page.send(r#"{"type":"continue"}"#);
    }
    // The server reads them after they were sent: its count is waited for.
    let until = Instant::now() + Duration::from_secs(180);
    let refused = loop {
        let refused = get(run.studio.addr(), "/api/stats").json()["refused"]
            .as_u64()
            .unwrap();
        if refused >= 4 + 150 || Instant::now() > until {
            break refused;
        }
        thread::sleep(Duration::from_millis(20));
    };
    assert!(refused >= 4 + 150, "{refused}");
    // The limit counts a second of wall time; past it the page is heard again.
    thread::sleep(Duration::from_millis(1100));
    // Still attached, and heard.
    page.send(r#"{"type":"pause"}"#);
    page.expect("paused");
    let at = run.ticks();
    page.send(r#"{"type":"step"}"#);
    page.expect_where("paused", |m| m["paused"]["why"] == "step");
    assert_eq!(run.ticks(), at + 1, "held, then one step");
}

#[test]
fn the_run_goes_on_when_its_last_page_leaves_and_a_new_page_gets_it_whole() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    page.send(r#"{"type":"pause"}"#);
    page.expect("paused");
    let at = run.ticks();
    page.close();
    // Nobody is left to continue it: the run goes on by itself.
    run.wait_past(at + 5);
    let mut again = Page::connect(run.studio.addr());
    let hello = again.expect("hello");
    assert!(hello["tick"].as_u64().unwrap() > at);
    assert_eq!(hello["paused"], Value::Null);
    assert_eq!(hello["statuses"].as_array().unwrap().len(), 3);
    // The blackboards as of the latest tick a page could have seen (none was attached).
    assert!(hello["blackboards"].is_array());
}

#[test]
fn with_no_page_attached_breakpoints_never_hold_the_run() {
    let run = Run::start();
    {
        let mut page = Page::connect(run.studio.addr());
        page.expect("hello");
        page.send(r#"{"type":"breakpoint","node":1,"when":"before"}"#);
        page.expect("paused");
        page.close();
    }
    let at = run.ticks();
    run.wait_past(at + 20);
}

#[test]
fn a_reloaded_tree_reaches_the_pages_whole_with_its_breakpoints() {
    let (studio, _dir) = studio();
    let mut tree = Tree::new(blueprint(TREE));
    tree.blackboard_mut().set("count", 0i64).unwrap();
    let mut watch = studio.watch(&mut tree, "main.xml");
    let mut page = Page::connect(studio.addr());
    assert_eq!(
        page.expect("hello")["tree"]["nodes"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    page.send(r#"{"type":"breakpoint","node":2,"when":"SUCCESS"}"#);
    page.expect("breakpoints");

    // A node is added before `done`, which moves from id 2 to id 3.
    let v2 = TREE.replace(
        r#"<AlwaysSuccess name="done"/>"#,
        r#"<AlwaysSuccess name="extra"/><AlwaysSuccess name="done"/>"#,
    );
    tree.reload(blueprint(&v2), &mut ()).unwrap();
    watch.reattach(&tree, "main.xml");
    let hello = page.expect("hello");
    let paths = paths_of(&hello);
    assert_eq!(paths, ["root", "root/Script", "root/extra", "root/done"]);
    assert_eq!(
        hello["breakpoints"],
        json!([{"node": 3, "when": "SUCCESS"}])
    );

    // The observer set before the reload follows the new tree: the breakpoint holds the
    // tick at `done`'s success, in a thread of its own.
    let ticking = thread::spawn(move || {
        watch.between_ticks(&mut tree);
        tree.tick_once(&mut ()).unwrap()
    });
    let hit = page.expect("paused");
    assert_eq!(
        hit["paused"],
        json!({"why": "breakpoint", "node": 3, "status": "SUCCESS"})
    );
    page.send(r#"{"type":"continue"}"#);
    assert_eq!(ticking.join().unwrap(), neurotree_toolkit::Status::Success);
}

#[test]
fn a_step_from_a_breakpoint_is_one_tick_too() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    page.send(r#"{"type":"breakpoint","node":2,"when":"before"}"#);
    let hit = page.expect("paused");
    let at = hit["tick"].as_u64().unwrap();
    // Held inside tick `at`: the run finished the ticks before it.
    assert_eq!(run.ticks(), at - 1);
    for n in 1..=3 {
        page.send(r#"{"type":"step"}"#);
        // The step finishes the tick, ticks the next, and meets the breakpoint in it.
        let again = page.expect("paused");
        assert_eq!(again["paused"]["why"], "breakpoint");
        assert_eq!(again["tick"].as_u64().unwrap(), at + n, "step {n}");
        assert_eq!(run.ticks(), at + n - 1);
    }
    // Without the breakpoint, a step from it stops after the next tick.
    page.send(r#"{"type":"breakpoint","node":2,"when":"off"}"#);
    page.send(r#"{"type":"step"}"#);
    let stepped = page.expect_where("paused", |m| m["paused"]["why"] == "step");
    assert_eq!(stepped["tick"].as_u64().unwrap(), at + 4);
    assert_eq!(run.ticks(), at + 4);
}

#[test]
fn nodes_reset_within_a_tick_show_how_they_ended() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    page.expect("hello");
    page.send(r#"{"type":"pause"}"#);
    page.expect("paused");
    let mut again = Page::connect(run.studio.addr());
    let hello = again.expect("hello");
    // Each tick the Sequence runs both children to success and resets them to Idle; the
    // page is shown how each ended, not the Idle they were reset to.
    page.send(r#"{"type":"step"}"#);
    page.expect_where("paused", |m| m["paused"]["why"] == "step");
    let shown = again.expect("tick");
    let all: Vec<Value> = hello["statuses"].as_array().unwrap().clone();
    let mut statuses = all;
    for change in shown["changes"].as_array().unwrap() {
        statuses[change[0].as_u64().unwrap() as usize] = change[1].clone();
    }
    assert_eq!(
        statuses,
        [json!("SUCCESS"), json!("SUCCESS"), json!("SUCCESS")]
    );
}

#[test]
fn a_page_that_acknowledges_is_never_sent_more_than_two_ticks_ahead() {
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    let hello = page.expect("hello");
    page.send(&format!(r#"{{"type":"ack","tick":{}}}"#, hello["tick"]));
    // The run ticks every 5 ms; unacknowledged, the page gets two ticks and no more.
    let until = Instant::now() + Duration::from_millis(400);
    let mut ticks = Vec::new();
    while Instant::now() < until {
        if let Some(m) = page.next(Duration::from_millis(50)) {
            if m["type"] == "tick" {
                ticks.push(m["tick"].as_u64().unwrap());
            }
        }
    }
    assert_eq!(ticks.len(), 2, "{ticks:?}");
    // One acknowledgement lets one more go, with every change since: the newest tick.
    let before = run.ticks();
    page.send(&format!(r#"{{"type":"ack","tick":{}}}"#, ticks[0]));
    let next = page.expect("tick")["tick"].as_u64().unwrap();
    assert!(
        next > ticks[1] && next >= before,
        "{next} after {ticks:?}, run at {before}"
    );
    // Paused, no more ticks are sent: past those in flight, an acknowledgement nobody
    // awaits is refused.
    page.send(r#"{"type":"pause"}"#);
    page.expect("paused");
    for _ in 0..3 {
        page.send(r#"{"type":"ack","tick":1}"#);
    }
    assert!(page.expect("refused")["why"]
        .as_str()
        .unwrap()
        .contains("ack"));
}

#[test]
fn the_last_failure_reaches_each_leaf_that_decided_it() {
    // A Fallback of two Sequences whose first conditions fail; no node gives a reason.
    const TWO_WAYS: &str = r#"<root BTCPP_format="4">
  <BehaviorTree ID="Main">
    <Fallback name="choose">
      <Sequence name="dock"><AlwaysFailure name="low"/><AlwaysSuccess/></Sequence>
      <Sequence name="patrol"><AlwaysFailure name="charged"/><AlwaysSuccess/></Sequence>
    </Fallback>
  </BehaviorTree>
</root>"#;
    let (studio, dir) = studio();
    let mut tree = Tree::with_clock(blueprint(TWO_WAYS), ManualClock::new());
    let mut watch = studio.watch(&mut tree, "main.xml");
    let stop = Arc::new(AtomicBool::new(false));
    let s = Arc::clone(&stop);
    let thread = thread::spawn(move || {
        while !s.load(Ordering::Acquire) {
            watch.between_ticks(&mut tree);
            assert!(tree.tick_once(&mut ()).is_ok());
            thread::sleep(Duration::from_millis(5));
        }
        drop(dir);
    });
    let mut page = Page::connect(studio.addr());
    page.expect("hello");
    let failure = page.expect_where("failure", |m| !m["failure"].is_null())["failure"].clone();
    stop.store(true, Ordering::Release);
    thread.join().unwrap();
    assert_eq!(failure["path"], "choose/patrol/charged");
    // Every node of the failure is marked on the page: both Sequences and both leaves.
    assert_eq!(failure["nodes"], json!([0, 1, 2, 4, 5]));
    assert_eq!(
        failure["chain"],
        "choose\n  tried choose/dock: no reason given\n    choose/dock/low\n  \
         tried choose/patrol: no reason given\n  choose/patrol\n    choose/patrol/charged"
    );
}

#[test]
fn a_run_built_without_the_force_hooks_refuses_a_force_and_says_so() {
    // `Run::start` builds its tree as most programs do: without `Studio::force_hooks`.
    let run = Run::start();
    let mut page = Page::connect(run.studio.addr());
    let hello = page.expect("hello");
    assert_eq!(hello["forcing"], false, "{hello}");
    assert_eq!(hello["forces"], json!([]));
    page.send(r#"{"type":"force","node":2,"status":"FAILURE"}"#);
    let why = page.expect("refused")["why"].as_str().unwrap().to_string();
    assert!(why.contains("without the studio's force hooks"), "{why}");
}

#[test]
fn a_force_is_checked_before_it_is_listed() {
    let (studio, _dir) = studio();
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).wrap_hooks(studio.force_hooks(None));
    loader.load_str(TREE, "main.xml").unwrap();
    let mut tree = Tree::new(Arc::new(loader.build_main().unwrap()));
    let _watch = studio.watch(&mut tree, "main.xml");
    let mut page = Page::connect(studio.addr());
    assert_eq!(page.expect("hello")["forcing"], true);
    for (message, refusal) in [
        (
            r#"{"type":"force","node":99,"status":"FAILURE"}"#,
            "no node 99",
        ),
        (
            r#"{"type":"force","node":1,"status":"MAYBE"}"#,
            "not `MAYBE`",
        ),
        (
            r#"{"type":"force","node":1,"status":"SUCCESS","until":"later"}"#,
            "not `later`",
        ),
    ] {
        page.send(message);
        let why = page.expect("refused")["why"].as_str().unwrap().to_string();
        assert!(why.contains(refusal), "{message}: {why}");
    }
    page.send(r#"{"type":"force","node":1,"status":"RUNNING","until":"cleared"}"#);
    assert_eq!(
        page.expect("forces")["forces"],
        json!([{"node": 1, "status": "RUNNING", "until": "cleared", "applied": null}])
    );
    page.send(r#"{"type":"force","node":1,"status":"off"}"#);
    assert_eq!(page.expect("forces")["forces"], json!([]));
}

#[test]
fn a_scene_shown_by_hand_stays_through_the_ticks() {
    use neurotree_toolkit::scene::{Scene, Style};

    let (studio, dir) = studio();
    let mut tree = Tree::with_clock(blueprint(TREE), ManualClock::new());
    tree.blackboard_mut().set("count", 0i64).unwrap();
    let mut watch = studio.watch(&mut tree, "main.xml");
    let stop = Arc::new(AtomicBool::new(false));
    let running = Arc::clone(&stop);
    let thread = thread::spawn(move || {
        let mut scene = Scene::new([0.0, 0.0], [4.0, 4.0]);
        scene.circle("robot", [1.0, 1.0], 0.5, Style::fill("#36c"));
        while !running.load(Ordering::Acquire) {
            watch.between_ticks(&mut tree);
            watch.show_scene(Some(&scene));
            tree.tick_once(&mut ()).unwrap();
            thread::sleep(Duration::from_millis(2));
        }
    });
    let mut page = Page::connect(studio.addr());
    let hello = page.expect("hello");
    let mut shown = !hello["scene"].is_null();
    let first = hello["tick"].as_u64().unwrap();
    // A run without a world shows what it was last told: the scene never blanks between
    // ticks, which a page would draw as the panel closing and opening again.
    let mut last = first;
    let until = Instant::now() + Duration::from_secs(180);
    while last < first + 60 {
        assert!(
            Instant::now() < until,
            "the run stands still at tick {last}"
        );
        let Some(m) = page.next(Duration::from_millis(200)) else {
            continue;
        };
        match m["type"].as_str() {
            Some("scene") => {
                assert!(!m["scene"].is_null(), "the scene blanked at {m}");
                shown = true;
            }
            Some("tick") => last = m["tick"].as_u64().unwrap(),
            _ => {}
        }
    }
    assert!(shown, "the scene was never shown");
    stop.store(true, Ordering::Release);
    thread.join().unwrap();
    drop(dir);
}

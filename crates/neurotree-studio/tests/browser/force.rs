//! Results forced by hand in the watch view, in a real browser: a person pauses a run,
//! opens a node's menu, forces its next result once or until cleared, steps and sees the
//! node return it, finds the force listed and drawn on the node, clears it, and goes back
//! before a forced tick to see it forced again when the run forks there.

use std::time::Duration;

use super::driver::Browser;
use super::{browser_slot, css_path};
use crate::browser_rewind::{load_hooked, serve, Run, PATROL};

const WALK: &str = "patrol/walk";

/// Steps once from tick `from` and waits for the next tick; `walk`'s status then.
async fn step(b: &Browser, from: u64) -> String {
    b.click("#watch-view [data-action=step]").await;
    b.until(
        &format!("tick {} shown, paused", from + 1),
        &format!(
            "Number(document.querySelector('#watch-view [data-tick]').dataset.tick) === {} \
             && document.querySelector('#watch-view [data-run-state]').dataset.runState === 'paused'",
            from + 1
        ),
    )
    .await;
    walk_status(b).await
}

async fn walk_status(b: &Browser) -> String {
    b.attr(&format!("#watch-view {}", css_path(WALK)), "data-status")
        .await
        .unwrap_or_default()
}

/// The forces listed: `[status, until, applied]` of each.
async fn listed(b: &Browser) -> Vec<(String, String, Option<u64>)> {
    let v = b
        .js("return [...document.querySelectorAll('#watch-view [data-force-list] li[data-force-node]')]
               .map(li => [li.dataset.status, li.dataset.until, li.dataset.applied ?? null]);")
        .await;
    v.as_array()
        .expect("a list")
        .iter()
        .map(|f| {
            (
                f[0].as_str().unwrap_or_default().to_string(),
                f[1].as_str().unwrap_or_default().to_string(),
                f[2].as_str().and_then(|t| t.parse().ok()),
            )
        })
        .collect()
}

/// Waits until the list of forces is `want`.
async fn until_listed(b: &Browser, what: &str, want: &[(&str, &str, Option<u64>)]) {
    let want: Vec<(String, String, Option<u64>)> = want
        .iter()
        .map(|(s, u, a)| (s.to_string(), u.to_string(), *a))
        .collect();
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    loop {
        let now = listed(b).await;
        if now == want {
            return;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "{what}: listed {now:?}, not {want:?}"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

async fn force(b: &Browser, status: &str, until: &str) {
    b.click(&format!("#watch-view {}", css_path(WALK))).await;
    b.click(&format!(
        "#watch-view [data-force-menu] [data-action=force][data-status={status}][data-until={until}]"
    ))
    .await;
}

async fn drawn(b: &Browser) -> Option<String> {
    b.attr(&format!("#watch-view {}", css_path(WALK)), "data-forced")
        .await
}

#[tokio::test(flavor = "multi_thread")]
async fn a_forced_result_applies_is_listed_and_cleared_and_applies_again_after_going_back() {
    let _slot = browser_slot().await;
    let Some(b) = Browser::start().await else {
        return;
    };
    let dir = tempfile::tempdir().expect("a folder");
    let studio = serve(dir.path());
    let tree = load_hooked(PATROL, Some(studio.force_hooks(None)));
    let run = Run::start(&studio, tree, Duration::from_millis(30));
    b.goto(&format!("{}#view=watch", studio.url())).await;
    b.until(
        "a few ticks",
        "Number(document.querySelector('#watch-view [data-tick]').dataset.tick) > 4",
    )
    .await;
    b.click("#watch-view [data-action=pause]").await;
    b.until(
        "paused",
        "document.querySelector('#watch-view [data-run-state]').dataset.runState === 'paused'",
    )
    .await;
    let mut tick = b.shown_tick().await;
    // Walk as it goes: from a fresh start it runs, whatever the tick.
    while walk_status(&b).await != "SUCCESS" {
        assert_eq!(walk_status(&b).await, "RUNNING");
        tick += 1;
        step(&b, tick - 1).await;
    }
    assert_eq!(listed(&b).await, vec![]);

    // FAILURE once: listed and drawn while due, returned at the next tick, then listed
    // with the tick it applied at and no longer drawn.
    force(&b, "FAILURE", "once").await;
    until_listed(&b, "the force set", &[("FAILURE", "once", None)]).await;
    assert_eq!(drawn(&b).await.as_deref(), Some("FAILURE once"));
    tick += 1;
    assert_eq!(step(&b, tick - 1).await, "FAILURE");
    until_listed(&b, "the force applied", &[("FAILURE", "once", Some(tick))]).await;
    assert_eq!(drawn(&b).await, None);
    // Once only: the next tick walks afresh.
    tick += 1;
    assert_eq!(step(&b, tick - 1).await, "RUNNING");
    b.click("#watch-view [data-force-list] [data-action=unforce]")
        .await;
    until_listed(&b, "the force cleared", &[]).await;

    // FAILURE until cleared: every tick, even of a walk under way, until cleared.
    force(&b, "FAILURE", "cleared").await;
    until_listed(&b, "the standing force", &[("FAILURE", "cleared", None)]).await;
    assert_eq!(drawn(&b).await.as_deref(), Some("FAILURE cleared"));
    for _ in 0..3 {
        tick += 1;
        assert_eq!(step(&b, tick - 1).await, "FAILURE", "tick {tick}");
    }
    until_listed(&b, "still standing", &[("FAILURE", "cleared", None)]).await;
    b.click("#watch-view [data-force-menu] [data-action=unforce]")
        .await;
    until_listed(&b, "the standing force cleared", &[]).await;
    assert_eq!(drawn(&b).await, None);
    tick += 1;
    assert_eq!(step(&b, tick - 1).await, "RUNNING");

    // Once, applied at tick q; back before it and a step: forced again at q.
    force(&b, "FAILURE", "once").await;
    until_listed(&b, "the force set again", &[("FAILURE", "once", None)]).await;
    let q = tick + 1;
    assert_eq!(step(&b, tick).await, "FAILURE");
    until_listed(&b, "applied at q", &[("FAILURE", "once", Some(q))]).await;
    b.click("#watch-view [data-action=back]").await;
    b.until(
        "back at the tick before",
        &format!("document.querySelector('#watch-view').dataset.at === '{tick}'"),
    )
    .await;
    b.until(
        "walk as it was before the force",
        &format!(
            "document.querySelector('#watch-view {}').dataset.status === 'RUNNING'",
            css_path(WALK).replace('"', "\\\"")
        ),
    )
    .await;
    assert_eq!(step(&b, tick).await, "FAILURE", "forced again at {q}");
    until_listed(&b, "applied again at q", &[("FAILURE", "once", Some(q))]).await;
    assert_eq!(*run.forks.lock().expect("not poisoned"), vec![tick]);
    drop(run);
    b.close().await;
}

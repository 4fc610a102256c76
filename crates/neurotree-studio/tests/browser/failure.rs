//! The watch view's "Last failure" as a person reads it: a Fallback whose two branches each
//! fail at their first condition shows the root and both tried branches down to each
//! failing leaf, and marks exactly those nodes on the drawing.

use std::time::Duration;

use serde_json::{json, Value};

use super::{browser_slot, load, serve, workspace, Browser, Run};

/// Both branches fail at their condition, so neither action is ever ticked.
const TWO_TRIES: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Dock">
  <BehaviorTree ID="Dock">
    <Fallback name="root">
      <Sequence name="first">
        <AlwaysFailure name="low_battery"/>
        <AlwaysSuccess name="charge"/>
      </Sequence>
      <Sequence name="second">
        <AlwaysFailure name="blocked"/>
        <AlwaysSuccess name="drive"/>
      </Sequence>
    </Fallback>
  </BehaviorTree>
</root>
"#;

#[tokio::test(flavor = "multi_thread")]
async fn the_last_failure_shows_every_branch_a_fallback_tried_down_to_its_leaf() {
    let _slot = browser_slot().await;
    let Some(b) = Browser::start().await else {
        return;
    };
    let dir = workspace();
    std::fs::write(dir.path().join("dock.xml"), TWO_TRIES).expect("dock written");
    let studio = serve(dir.path());
    let run = Run::start(
        &studio,
        load(TWO_TRIES, "dock.xml"),
        "dock.xml",
        Duration::from_millis(40),
    );
    b.goto(&format!("{}#view=watch", studio.url())).await;
    b.until(
        "a tick shown",
        "Number(document.querySelector('[data-tick]').dataset.tick) >= 1",
    )
    .await;
    b.until(
        "the failure shown",
        "!document.querySelector('#watch-view [data-failure] .hint')",
    )
    .await;

    let text = b
        .js("return document.querySelector('#watch-view [data-failure]').textContent;")
        .await;
    let text = text.as_str().expect("the section's text");
    for name in ["root", "first", "low_battery", "second", "blocked"] {
        assert!(
            text.contains(name),
            "\"Last failure\" names {name}: {text:?}"
        );
    }
    for never in ["charge", "drive"] {
        assert!(
            !text.contains(never),
            "\"Last failure\" leaves out {never}, never ticked: {text:?}"
        );
    }

    let failed: Value = b
        .js("return [...document.querySelectorAll('#watch-view [data-failed]')].map(e => e.dataset.nodePath).sort();")
        .await;
    assert_eq!(
        failed,
        json!([
            "root",
            "root/first",
            "root/first/low_battery",
            "root/second",
            "root/second/blocked"
        ]),
        "exactly the failure tree's nodes are marked"
    );
    // The failure path drawn over the tree: one line down to each of the four nodes below
    // the root, none to the actions.
    let lines = b
        .js("return (document.querySelector('#watch-view path.edges.failed').getAttribute('d').match(/M/g) || []).length;")
        .await;
    assert_eq!(lines, json!(4), "the failure path's lines");
    drop(run);
    b.close().await;
}

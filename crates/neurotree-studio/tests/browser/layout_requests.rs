//! The layout is asked of the server without blocking the page: no synchronous request, the
//! page drawing frames while an answer is awaited, what was asked of the drawing meanwhile
//! done once the tree is drawn, and an answer to a tree replaced since dropped.

use serde_json::{json, Value};

use super::canvas::{open_in_editor, sized_browser};
use super::{browser_slot, css_path, serve, workspace, Browser, NAV2_TREE};

/// The editor's drawing, in a script.
const DRAWING: &str = "document.querySelector('#edit-view .tree-drawing').treeDrawing";

/// Records every synchronous request the page opens (`window.syncOpened`), and holds each
/// layout request until the test lets it go (`window.held`, in the order asked: calling
/// one sends it); then gives the nodes of the drawn tree, as `setTree` takes them.
async fn hold_layouts(b: &Browser) {
    b.js("window.syncOpened = [];
          const open = XMLHttpRequest.prototype.open;
          XMLHttpRequest.prototype.open = function (method, url, async) {
            if (async === false) window.syncOpened.push(String(url));
            return open.apply(this, arguments);
          };
          window.held = [];
          const send = window.fetch;
          window.fetch = (url, options) => String(url).includes('/api/layout')
            ? new Promise((answer) => window.held.push(() => answer(send(url, options))))
            : send(url, options);")
        .await;
}

/// A script giving the drawn tree's nodes renamed: each name ends with `suffix`, each path
/// starts with `prefix`.
fn renamed(prefix: &str, suffix: &str) -> String {
    format!(
        "{DRAWING}.nodes.map((n) => ({{ name: n.name + '{suffix}', type: n.type,
           category: n.category, path: '{prefix}' + n.path, ports: n.ports,
           directions: n.directions, children: n.children.slice() }}))"
    )
}

/// The paths of the nodes drawn.
async fn drawn_paths(b: &Browser) -> Value {
    b.js(
        "return Array.from(document.querySelectorAll('#edit-view g.node[data-node-path]'),
                             (g) => g.dataset.nodePath);",
    )
    .await
}

#[tokio::test(flavor = "multi_thread")]
async fn the_page_draws_frames_while_a_layout_is_awaited_and_then_does_what_was_asked() {
    let _slot = browser_slot().await;
    let Some(b) = sized_browser().await else {
        return;
    };
    let dir = workspace();
    let studio = serve(dir.path());
    open_in_editor(&b, &studio.url(), NAV2_TREE).await;
    let before = drawn_paths(&b).await;
    hold_layouts(&b).await;
    // A new tree, selected, marked and coloured at once, as the views do after `setTree`.
    b.js(&format!(
        "const d = {DRAWING};
         window.newTree = d.setTree({}, {{ keepView: true }});
         d.select(3);
         d.mark(5, 'data-error', 'refused');
         d.setStatus(0, 'RUNNING');
         window.framesDrawn = 0;
         const count = () => {{ window.framesDrawn += 1; requestAnimationFrame(count); }};
         requestAnimationFrame(count);",
        renamed("new:", "")
    ))
    .await;
    // The answer is held: the page goes on drawing frames, and shows the tree it had.
    b.until(
        "frames drawn while the layout is held",
        "window.framesDrawn >= 3",
    )
    .await;
    assert_eq!(b.js("return window.held.length;").await, json!(1));
    assert_eq!(drawn_paths(&b).await, before);
    assert_eq!(
        b.count("#edit-view g.node.selected, #edit-view g.node[data-error]")
            .await,
        0
    );

    b.js("window.held.shift()(); return window.newTree;").await;
    let paths = drawn_paths(&b).await;
    let paths = paths.as_array().unwrap();
    assert_eq!(paths.len(), before.as_array().unwrap().len());
    assert!(paths
        .iter()
        .all(|p| p.as_str().unwrap().starts_with("new:")));
    // What was asked while the layout was awaited is done on the tree drawn.
    let node = |i: usize| css_path(paths[i].as_str().unwrap());
    let selected = format!(
        "return document.querySelector('{}').classList.contains('selected');",
        node(3).replace('\'', "\\'")
    );
    assert_eq!(b.js(&selected).await, json!(true));
    assert_eq!(b.attr(&node(5), "data-error").await, Some("refused".into()));
    assert_eq!(
        b.attr(&node(0), "data-status").await,
        Some("RUNNING".into())
    );
    // Turning, folding and fitting ask the server too, never synchronously.
    b.click("#edit-view [data-action=\"orientation\"]").await;
    b.click("#edit-view [data-action=\"fit\"]").await;
    b.click("#edit-view [data-action=\"collapse-all\"]").await;
    b.js("while (window.held.length) window.held.shift()();")
        .await;
    b.until(
        "the tree folded",
        "document.querySelectorAll('#edit-view g.node[data-collapsed]').length > 0",
    )
    .await;
    assert_eq!(b.js("return window.syncOpened;").await, json!([]));
    b.close().await;
}

#[tokio::test(flavor = "multi_thread")]
async fn an_answer_to_a_tree_replaced_since_is_dropped() {
    let _slot = browser_slot().await;
    let Some(b) = sized_browser().await else {
        return;
    };
    let dir = workspace();
    let studio = serve(dir.path());
    open_in_editor(&b, &studio.url(), NAV2_TREE).await;
    hold_layouts(&b).await;
    // Two trees one after the other; the second's answer comes first, the first's after it.
    b.js(&format!(
        "const d = {DRAWING};
         window.first = d.setTree({}, {{ keepView: true }});
         window.second = d.setTree({}, {{ keepView: true }});",
        renamed("first:", "_first"),
        renamed("second:", "_second")
    ))
    .await;
    assert_eq!(b.js("return window.held.length;").await, json!(2));
    b.js("window.held[1](); return window.second;").await;
    let second = drawn_paths(&b).await;
    assert!(
        second
            .as_array()
            .unwrap()
            .iter()
            .all(|p| p.as_str().unwrap().starts_with("second:")),
        "{second}"
    );
    b.js("window.held[0](); return window.first;").await;
    // The first tree's answer came last, and is dropped: the drawing keeps the second tree,
    // its nodes and their names.
    assert_eq!(drawn_paths(&b).await, second);
    let names = b
        .js(&format!(
            "return {DRAWING}.nodes.every((n) => n.name.endsWith('_second'))
               && Array.from(document.querySelectorAll('#edit-view g.node text.name'))
                    .some((t) => t.textContent.includes('_second'))
               && Array.from(document.querySelectorAll('#edit-view g.node text.name'))
                    .every((t) => !t.textContent.includes('_first'));"
        ))
        .await;
    assert_eq!(names, json!(true));
    b.close().await;
}

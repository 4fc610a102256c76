//! "Fit" as a person at a 1500×950 window meets it, on each of Nav2's sixteen default trees
//! (one browser for all): the page draws each tree where `neurotree show --format svg` does
//! (at full detail, unfolded, top-down: the same places up to one scale and offset); after
//! "panels" and "fit" every node lies inside the canvas, each name at least 11 px tall, and
//! the overview covers none; and the same in the watch view, and beside its scene panel the
//! navigator whole, as large as fits. On
//! Nav2's navigator: the overview keeps off the nodes and turns off, a value cut on its
//! node is whole on hover and in the side panel, and a compact node shows its ports on
//! hover, on selection and zoomed in.

use std::path::Path;
use std::time::Duration;

use neurotree_toolkit::render::render_svg;
use neurotree_toolkit::{Registry, Status, XmlLoader};
use serde_json::{json, Value};

use fantoccini::actions::{InputSource, MouseActions, PointerAction};

use super::canvas::{open_in_editor, sized_browser};
use super::{browser_slot, css_path, registry, serve, workspace, Browser, Run, NAV2_TREE};

/// The least height of a name on the screen after "fit".
const LEAST_NAME: f64 = 11.0;

/// Nav2's default trees: every file of `corpus/nav2` but its model.
fn nav2_defaults() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus/nav2");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("the Nav2 corpus")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|f| f.ends_with(".xml") && f != "nav2_tree_nodes.xml")
        .map(|f| format!("corpus/nav2/{f}"))
        .collect();
    files.sort();
    files
}

/// The registry `neurotree show --nav2` draws with: Nav2's controls, and for each type its
/// model only describes a stand-in of its category, which keeps its name and ports.
fn drawing_registry() -> Registry<()> {
    let declared = registry();
    let mut drawn = registry();
    for t in declared.types().filter(|t| t.is_model_only()) {
        drawn.remove(&t.name);
        let ports = t.ports.clone();
        let done = match t.category {
            neurotree_toolkit::Category::Condition => {
                drawn.register_condition(&t.name, ports, |_| true)
            }
            _ => drawn.register_action(&t.name, ports, |_| Status::Success),
        };
        done.expect("a stand-in registered");
    }
    drawn
}

/// Each node's top centre in the SVG, by node id: a box's `x`, `y` and `width`, a
/// decorator's hexagon's points.
fn svg_places(svg: &str) -> Vec<(f64, f64)> {
    let attr = |el: &str, name: &str| -> f64 {
        let at = el.find(&format!(" {name}=\"")).expect("the attribute") + name.len() + 3;
        el[at..at + el[at..].find('"').unwrap()]
            .parse()
            .expect("a number")
    };
    let mut places = Vec::new();
    for i in 0.. {
        let Some(start) = svg.find(&format!("<g id=\"n{i}\"")) else {
            break;
        };
        let node = &svg[start..start + svg[start..].find("</g>").unwrap()];
        let shape = &node[node.find("</title>").unwrap() + 8..];
        if shape.starts_with("<polygon") {
            let at = shape.find("points=\"").unwrap() + 8;
            let points: Vec<(f64, f64)> = shape[at..at + shape[at..].find('"').unwrap()]
                .split(' ')
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect();
            let left = points.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
            let right = points.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
            let top = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
            places.push(((left + right) / 2.0, top));
        } else {
            places.push((
                attr(shape, "x") + attr(shape, "width") / 2.0,
                attr(shape, "y"),
            ));
        }
    }
    places
}

/// The page's nodes in `view`, by index: the `translate(x,y)` each is drawn at.
async fn page_places(b: &Browser, view: &str) -> Vec<(f64, f64)> {
    let v = b
        .js(&format!(
            "return [...document.querySelectorAll('#{view}-view g.node[data-node-path]')]
               .sort((a, b) => a.dataset.index - b.dataset.index)
               .map(g => g.getAttribute('transform').match(/translate\\(([-\\d.]+),([-\\d.]+)\\)/).slice(1).map(Number));"
        ))
        .await;
    v.as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect()
}

/// Asserts that `page` is `svg` scaled by one factor and moved by one offset, each place
/// within the SVG's rounding to a tenth.
fn assert_same_places(file: &str, page: &[(f64, f64)], svg: &[(f64, f64)]) {
    assert_eq!(page.len(), svg.len(), "{file}: as many nodes as the SVG");
    let extent = |ps: &[(f64, f64)]| {
        let xs = ps.iter().map(|p| p.0);
        xs.clone().fold(f64::NEG_INFINITY, f64::max) - xs.fold(f64::INFINITY, f64::min)
    };
    let scale = extent(svg) / extent(page);
    let (dx, dy) = (svg[0].0 - page[0].0 * scale, svg[0].1 - page[0].1 * scale);
    for (i, (p, s)) in page.iter().zip(svg).enumerate() {
        let (x, y) = (p.0 * scale + dx, p.1 * scale + dy);
        assert!(
            (x - s.0).abs() <= 0.2 && (y - s.1).abs() <= 0.2,
            "{file}: node {i} is at ({x:.1}, {y:.1}) on the page (scale {scale}), at {s:?} in the SVG"
        );
    }
}

/// What a person sees in `view` after "fit": `[shown nodes, outside the canvas (paths),
/// least name height, covered by the overview (paths), the toolbar's fit choice]`.
async fn after_fit(b: &Browser, view: &str) -> Value {
    b.js(&format!(
        "const root = document.querySelector('#{view}-view');
         const canvas = root.querySelector('.tree-svg').getBoundingClientRect();
         const mini = root.querySelector('[data-minimap]');
         const m = mini && !mini.hidden ? mini.getBoundingClientRect() : null;
         const groups = [...root.querySelectorAll('g.node[data-node-path]:not([display])')];
         const outside = [], covered = [];
         let least = Infinity;
         for (const g of groups) {{
           const r = g.getBoundingClientRect();
           if (r.left < canvas.left - 0.5 || r.top < canvas.top - 0.5 || r.right > canvas.right + 0.5 || r.bottom > canvas.bottom + 0.5)
             outside.push(g.dataset.nodePath);
           if (m && r.left < m.right && r.right > m.left && r.top < m.bottom && r.bottom > m.top) covered.push(g.dataset.nodePath);
           for (const t of g.querySelectorAll('text.name')) least = Math.min(least, t.getBoundingClientRect().height);
         }}
         return [groups.length, outside, least, covered, root.querySelector('[data-fit-choice]').textContent,
                 root.querySelector('.tree-drawing').dataset.fit || null];"
    ))
    .await
}

fn assert_fitted(file: &str, view: &str, seen: &Value, nodes: usize) {
    assert_eq!(
        seen[0],
        json!(nodes),
        "{file} in {view}: every node shown: {seen}"
    );
    assert_eq!(
        seen[1],
        json!([]),
        "{file} in {view}: nodes outside the canvas: {seen}"
    );
    let least = seen[2].as_f64().unwrap();
    assert!(
        least >= LEAST_NAME,
        "{file} in {view}: a name {least:.1} px tall"
    );
    assert_eq!(
        seen[3],
        json!([]),
        "{file} in {view}: under the overview: {seen}"
    );
    assert_eq!(seen[5], json!("whole"), "{file} in {view}: {seen}");
    let choice = seen[4].as_str().unwrap();
    assert!(
        choice.starts_with("fit: ")
            && (choice.contains("top down") || choice.contains("left to right")),
        "{file} in {view}: the toolbar says {choice:?}"
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn nav2_default_trees_are_laid_out_as_the_svg_and_fit_whole_in_the_editor_and_the_watch_view()
{
    let _slot = browser_slot().await;
    let Some(b) = sized_browser().await else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let files = nav2_defaults();
    assert_eq!(files.len(), 16, "Nav2's sixteen default trees: {files:?}");
    for file in &files {
        let to = dir.path().join(file);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(corpus.join(file), &to).unwrap();
    }
    let studio = serve(dir.path());
    let drawn_with = drawing_registry();
    for file in &files {
        let text = std::fs::read_to_string(dir.path().join(file)).unwrap();
        let mut loader = XmlLoader::new(&drawn_with);
        loader.load_str(&text, file).unwrap();
        let blueprint = loader.build_main().unwrap();
        let svg = svg_places(&render_svg(&blueprint, None));

        open_in_editor(&b, &studio.url(), file).await;
        assert_eq!(
            b.js("return document.querySelector('#edit-view .tree-drawing').dataset.detail;")
                .await,
            json!("full"),
            "{file}: opens at full detail"
        );
        assert_same_places(file, &page_places(&b, "edit").await, &svg);

        b.click("#edit-view [data-action=\"panels\"]").await;
        b.click("#edit-view [data-action=\"fit\"]").await;
        let seen = after_fit(&b, "edit").await;
        println!("studio: {file} fitted in the editor: {seen}");
        assert_fitted(file, "the editor", &seen, svg.len());
    }

    // The watch view, its side panel hidden (its scene panel, when the run draws one, stays
    // beside the tree).
    for file in &files {
        let text = std::fs::read_to_string(dir.path().join(file)).unwrap();
        let tree = super::load(&text, file);
        let nodes = tree.blueprint().len();
        let run = Run::start(&studio, tree, file, Duration::from_millis(50));
        b.goto(&format!("{}#view=watch", studio.url())).await;
        b.client.refresh().await.unwrap();
        b.until(
            "the tree watched",
            "performance.getEntriesByName('studio:watch-drawn').length",
        )
        .await;
        b.click("#watch-view [data-action=\"panels\"]").await;
        b.click("#watch-view [data-action=\"fit\"]").await;
        let seen = after_fit(&b, "watch").await;
        println!("studio: {file} fitted in the watch view: {seen}");
        assert_fitted(file, "the watch view", &seen, nodes);
        drop(run);
    }
    b.close().await;
}

/// The paths of the nodes of `view` the overview covers (none when it is hidden), and
/// whether it is shown.
async fn under_overview(b: &Browser, view: &str) -> Value {
    b.js(&format!(
        "const root = document.querySelector('#{view}-view');
         const mini = root.querySelector('[data-minimap]');
         if (!mini || mini.hidden) return [[], false];
         const m = mini.getBoundingClientRect();
         return [[...root.querySelectorAll('g.node[data-node-path]:not([display])')].filter(g => {{
           const r = g.getBoundingClientRect();
           return r.width && r.left < m.right && r.right > m.left && r.top < m.bottom && r.bottom > m.top;
         }}).map(g => g.dataset.nodePath), true];"
    ))
    .await
}

#[tokio::test(flavor = "multi_thread")]
async fn the_navigator_keeps_its_overview_off_its_nodes_and_shows_cut_values_and_compact_nodes_whole(
) {
    let _slot = browser_slot().await;
    let Some(b) = sized_browser().await else {
        return;
    };
    let dir = workspace();
    let studio = serve(dir.path());
    open_in_editor(&b, &studio.url(), NAV2_TREE).await;

    // At full detail the tree is larger than the view: the overview is there, over no node,
    // and wherever the view is moved it keeps off them.
    assert_eq!(under_overview(&b, "edit").await, json!([[], true]));
    for (dx, dy) in [(-400, -300), (300, -500), (600, 200)] {
        b.js(&format!(
            "const d = document.querySelector('#edit-view .tree-drawing').treeDrawing;
             d.view.x += {dx}; d.view.y += {dy}; d.applyView();"
        ))
        .await;
        let under = under_overview(&b, "edit").await;
        assert_eq!(under[0], json!([]), "moved by ({dx}, {dy}): {under}");
    }
    // The toolbar turns it off, and on again.
    let before = under_overview(&b, "edit").await;
    b.click("#edit-view [data-action=\"overview\"]").await;
    assert_eq!(under_overview(&b, "edit").await, json!([[], false]));
    assert_eq!(
        b.attr("#edit-view [data-action=\"overview\"]", "aria-pressed")
            .await,
        Some("false".into())
    );
    b.click("#edit-view [data-action=\"overview\"]").await;
    assert_eq!(under_overview(&b, "edit").await, before, "on again");

    // The controller's error code is cut on its node, whole in the line's title and in the
    // side panel.
    open_in_editor(&b, &studio.url(), NAV2_TREE).await;
    let follow = css_path("NavigateRecovery/NavigateWithReplanning/FollowPath/FollowPath");
    let cut = b
        .js(&format!(
            "const g = document.querySelector('{}');
             return [...g.querySelectorAll('g.cut')].map(c => [c.dataset.whole, c.querySelector('title').textContent, c.querySelector('text.port').textContent]);",
            follow.replace('\'', "\\'")
        ))
        .await;
    let error_code = cut
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c[0].as_str().unwrap().contains("error_code_id"))
        .unwrap_or_else(|| panic!("the error code's line is cut: {cut}"));
    assert_eq!(
        error_code[0],
        json!("out error_code_id: {follow_path_error_code}")
    );
    assert_eq!(
        error_code[1], error_code[0],
        "the title holds the line whole"
    );
    let shown = error_code[2].as_str().unwrap();
    assert!(
        shown.ends_with('…')
            && shown.chars().count() < error_code[0].as_str().unwrap().chars().count(),
        "{shown}"
    );
    b.click(&follow).await;
    let panel = b
        .js("return document.querySelector('#edit-view .side-panel input[data-port=\"error_code_id\"]').value;")
        .await;
    assert_eq!(panel, json!("{follow_path_error_code}"));

    // Fitted, the nodes show their names; the selected one its ports over it, another its
    // own while the pointer is over it, and every node its ports zoomed in.
    b.click("#edit-view [data-action=\"panels\"]").await;
    b.click("#edit-view [data-action=\"fit\"]").await;
    let drawing = "document.querySelector('#edit-view .tree-drawing')";
    assert_eq!(
        b.js(&format!("return {drawing}.dataset.detail;")).await,
        json!("compact")
    );
    assert_eq!(b.count(&format!("#edit-view {follow} text.port")).await, 0);
    let card = format!(
        "const c = document.querySelector('#edit-view [data-card-of]');
         const d = {drawing}.treeDrawing;
         return c ? [d.nodes[Number(c.dataset.cardOf)].path, c.querySelectorAll('text.port').length] : null;"
    );
    let selected = b.js(&card).await;
    assert_eq!(
        selected,
        json!([
            "NavigateRecovery/NavigateWithReplanning/FollowPath/FollowPath",
            5
        ]),
        "the selection's card"
    );
    let spin = css_path("NavigateRecovery/Sequence/RecoveryFallback/RecoveryActions/Spin");
    let hover = MouseActions::new("mouse".into()).then(PointerAction::MoveToElement {
        element: b.element(&spin).await,
        duration: None,
        x: 0.0,
        y: 0.0,
    });
    b.client.perform_actions(hover).await.unwrap();
    let hovered = b.js(&card).await;
    assert_eq!(
        hovered[0],
        json!("NavigateRecovery/Sequence/RecoveryFallback/RecoveryActions/Spin")
    );
    assert!(hovered[1].as_u64().unwrap() >= 3, "{hovered}");
    for _ in 0..3 {
        b.click("#edit-view [data-action=\"zoom-in\"]").await;
    }
    assert_eq!(
        b.js(&format!("return {drawing}.dataset.detail;")).await,
        json!("full")
    );
    assert_eq!(b.count(&format!("#edit-view {follow} text.port")).await, 5);
    assert_eq!(
        b.js("return document.querySelector('#edit-view [data-fit-choice]').textContent;")
            .await,
        json!("full detail")
    );
    b.close().await;
}

#[tokio::test(flavor = "multi_thread")]
async fn the_watch_view_fits_the_navigator_whole_beside_its_scene_panel_as_large_as_fits() {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;

    use neurotree_toolkit::scene::{Scene, Style};

    let _slot = browser_slot().await;
    let Some(b) = sized_browser().await else {
        return;
    };
    let dir = workspace();
    let studio = serve(dir.path());
    let text = std::fs::read_to_string(dir.path().join(NAV2_TREE)).unwrap();
    let mut tree = super::load(&text, NAV2_TREE);
    let nodes = tree.blueprint().len();
    let mut watch = studio.watch(&mut tree, NAV2_TREE);
    let stop = Arc::new(AtomicBool::new(false));
    let running = Arc::clone(&stop);
    let thread = std::thread::spawn(move || {
        let mut scene = Scene::new([0.0, 0.0], [20.0, 10.0]);
        scene.polyline(
            "path",
            vec![[1.0, 1.0], [19.0, 9.0]],
            Style::stroke("#2b8a3e", 0.2),
        );
        while !running.load(Ordering::Relaxed) {
            watch.between_ticks(&mut tree);
            watch.show_scene(Some(&scene));
            tree.tick_once(&mut ()).expect("the tree ticks");
            std::thread::sleep(Duration::from_millis(50));
        }
    });
    b.goto(&format!("{}#view=watch", studio.url())).await;
    b.client.refresh().await.unwrap();
    b.until(
        "the scene shown",
        "document.querySelector('#watch-view [data-scene]:not([hidden]) [data-scene-item=path]')",
    )
    .await;
    b.click("#watch-view [data-action=\"panels\"]").await;
    b.click("#watch-view [data-action=\"fit\"]").await;
    let seen = after_fit(&b, "watch").await;
    println!("studio: the navigator fitted above its scene: {seen}");
    assert_eq!(seen[0], json!(nodes), "{seen}");
    assert_eq!(seen[1], json!([]), "nodes outside the canvas: {seen}");
    assert_eq!(seen[3], json!([]), "under the overview: {seen}");
    assert_eq!(seen[5], json!("whole"), "{seen}");
    // As large as fits: the tree spans the canvas across or down, less its margins, and the
    // scene panel is beside it, not under it.
    let spans = b
        .js("const root = document.querySelector('#watch-view');
             const c = root.querySelector('.tree-svg').getBoundingClientRect();
             const s = root.querySelector('[data-scene]').getBoundingClientRect();
             const rs = [...root.querySelectorAll('g.node[data-node-path] > .body > .shape')].map(g => g.getBoundingClientRect());
             const w = Math.max(...rs.map(r => r.right)) - Math.min(...rs.map(r => r.left));
             const h = Math.max(...rs.map(r => r.bottom)) - Math.min(...rs.map(r => r.top));
             return [w / c.width, h / c.height, c.bottom <= s.top + 0.5 || c.right <= s.left + 0.5, s.height];")
        .await;
    let (across, down) = (spans[0].as_f64().unwrap(), spans[1].as_f64().unwrap());
    assert!(
        across.max(down) > 0.9,
        "the tree spans {across:.2} across, {down:.2} down: {spans}"
    );
    assert_eq!(
        spans[2],
        json!(true),
        "the scene panel beside the canvas: {spans}"
    );
    assert!(
        spans[3].as_f64().unwrap() > 100.0,
        "the scene panel shown: {spans}"
    );
    stop.store(true, Ordering::Relaxed);
    let _ = thread.join();
    b.close().await;
}

//! The studio's HTTP API as the page uses it: files, checks located at their nodes,
//! saving, the palette, pictures, replays, and the guards around all of it.

use crate::common;

use std::fs;
use std::path::Path;

use common::{get, post, request};
use neurotree_studio::{Studio, StudioOptions};
use neurotree_toolkit::Registry;
use serde_json::json;

const TREE: &str = r#"<?xml version="1.0"?>
<root BTCPP_format="4" main_tree_to_execute="Main">
  <!-- kept as written -->
  <BehaviorTree ID="Main">
    <Sequence name="root">
      <RetryUntilSuccessful num_attempts="3"><Approach target="{goal}"/></RetryUntilSuccessful>
      <SubTree ID="Dock"/>
    </Sequence>
  </BehaviorTree>
  <BehaviorTree ID="Dock"><AlwaysSuccess name="docked"/></BehaviorTree>
  <TreeNodesModel>
    <Action ID="Approach"><input_port name="target" type="double">where to</input_port></Action>
  </TreeNodesModel>
</root>
"#;

fn studio(dir: &Path) -> Studio {
    fs::write(dir.join("tree.xml"), TREE).unwrap();
    fs::create_dir(dir.join("logs")).unwrap();
    let options = StudioOptions {
        root: dir.to_path_buf(),
        open: vec!["tree.xml".into()],
        ..StudioOptions::default()
    };
    Studio::serve(options, Registry::new).unwrap()
}

#[test]
fn the_session_and_the_files_are_listed() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    assert!(studio.url().starts_with("http://127.0.0.1:"));
    let session = get(studio.addr(), "/api/session").json();
    assert_eq!(session["open"], json!(["tree.xml"]));
    assert_eq!(session["watch"], false);
    fs::write(dir.path().join("logs/run.btlog"), b"x").unwrap();
    let files = get(studio.addr(), "/api/files").json();
    assert_eq!(
        files["files"],
        json!([{"path": "logs/run.btlog", "kind": "btlog"}, {"path": "tree.xml", "kind": "tree"}])
    );
    // The page itself is served, with its modules.
    let index = get(studio.addr(), "/");
    assert_eq!(index.status, 200);
    assert!(index.body.contains("<html"), "{}", index.body);
}

#[test]
fn a_file_opens_with_its_check_and_errors_are_located_at_their_node() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    let file = get(studio.addr(), "/api/file?path=tree.xml").json();
    assert_eq!(file["text"], TREE);
    assert_eq!(file["check"]["ok"], true, "{}", file["check"]);
    assert_eq!(file["check"]["trees"], json!(["Dock", "Main"]));
    assert_eq!(file["check"]["main"], "Main");

    let broken = TREE.replace("num_attempts=\"3\"", "num_attempts=\"three\"");
    let check = post(
        studio.addr(),
        "/api/check",
        &json!({"path": "tree.xml", "text": broken}),
    )
    .json();
    assert_eq!(check["ok"], false);
    let error = &check["errors"][0];
    assert_eq!(error["kind"], "BadValue");
    assert_eq!(error["tree"], "Main");
    // The RetryUntilSuccessful: the root Sequence's first element child.
    assert_eq!(error["element"], json!([0, 0]));
    assert!(
        error["message"]
            .as_str()
            .unwrap()
            .starts_with("tree.xml:6:"),
        "{error}"
    );

    let unknown = TREE.replace("<AlwaysSuccess name=\"docked\"/>", "<Dockk/>");
    let check = post(
        studio.addr(),
        "/api/check",
        &json!({"path": "tree.xml", "text": unknown}),
    )
    .json();
    assert_eq!(check["errors"][0]["kind"], "UnknownNode");
    assert_eq!(check["errors"][0]["tree"], "Dock");
    assert_eq!(check["errors"][0]["element"], json!([0]));
    // The advice is how the studio is given node types: the flags it is started with.
    let message = check["errors"][0]["message"].as_str().unwrap();
    assert!(
        message.ends_with(neurotree_studio::UNKNOWN_TYPE_ADVICE),
        "{message}"
    );
    assert!(message.contains("--model FILE") && message.contains("--nav2"));
}

#[test]
fn saving_writes_the_file_and_refuses_what_is_not_xml_or_changed_on_disk() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    let mtime = get(studio.addr(), "/api/file?path=tree.xml").json()["mtime"].clone();
    let edited = TREE.replace("num_attempts=\"3\"", "num_attempts=\"5\"");
    let saved = post(
        studio.addr(),
        "/api/save",
        &json!({"path": "tree.xml", "text": edited, "mtime": mtime}),
    );
    assert_eq!(saved.status, 200, "{}", saved.body);
    assert_eq!(saved.json()["check"]["ok"], true);
    assert_eq!(
        fs::read_to_string(dir.path().join("tree.xml")).unwrap(),
        edited
    );
    assert_eq!(
        get(studio.addr(), "/api/stat?path=tree.xml").json()["mtime"],
        saved.json()["mtime"]
    );

    let bad = post(
        studio.addr(),
        "/api/save",
        &json!({"path": "tree.xml", "text": "<root>"}),
    );
    assert_eq!(bad.status, 422);
    assert_eq!(
        fs::read_to_string(dir.path().join("tree.xml")).unwrap(),
        edited
    );

    // Saved against a version older than the file's.
    let stale = post(
        studio.addr(),
        "/api/save",
        &json!({"path": "tree.xml", "text": TREE, "mtime": 1}),
    );
    assert_eq!(stale.status, 409);
    assert_eq!(
        fs::read_to_string(dir.path().join("tree.xml")).unwrap(),
        edited
    );
}

#[test]
fn paths_out_of_the_folder_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    for path in [
        "../tree.xml",
        "/etc/passwd",
        "logs/../../x.xml",
        "%2Fetc%2Fpasswd",
    ] {
        let answer = get(studio.addr(), &format!("/api/file?path={path}"));
        assert_eq!(answer.status, 403, "{path}: {}", answer.body);
    }
    let write = post(
        studio.addr(),
        "/api/save",
        &json!({"path": "../evil.xml", "text": "<root/>"}),
    );
    assert_eq!(write.status, 403);
    assert!(!dir.path().parent().unwrap().join("evil.xml").exists());
    assert_eq!(get(studio.addr(), "/api/file?path=nothing.xml").status, 404);
}

#[test]
fn requests_from_elsewhere_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    let addr = studio.addr();
    // DNS rebinding: a foreign name for this address.
    let rebound = request(
        addr,
        "GET",
        "/api/session",
        &[("Host", "attacker.example:80")],
        None,
    );
    assert_eq!(rebound.status, 403);
    // A write from a page of another origin.
    let body = json!({"path": "x.xml", "text": "<root/>"}).to_string();
    let foreign = request(
        addr,
        "POST",
        "/api/save",
        &[("Origin", "http://attacker.example")],
        Some(&body),
    );
    assert_eq!(foreign.status, 403);
    assert!(!dir.path().join("x.xml").exists());
    let own = format!("http://{addr}");
    let same = request(
        addr,
        "POST",
        "/api/save",
        &[("Origin", own.as_str())],
        Some(&body),
    );
    assert_eq!(same.status, 200, "{}", same.body);
    assert!(common::Page::try_connect(addr, Some("http://attacker.example")).is_err());
    assert!(studio.refused() >= 2);
}

#[test]
fn a_studio_open_to_the_network_asks_for_its_token() {
    let dir = tempfile::tempdir().unwrap();
    let options = StudioOptions {
        bind: "0.0.0.0".parse().unwrap(),
        root: dir.path().to_path_buf(),
        ..StudioOptions::default()
    };
    let studio = Studio::serve(options, Registry::new).unwrap();
    let url = studio.url();
    let token = url.split("?token=").nth(1).expect("a token in the URL");
    assert_eq!(token.len(), 32);
    let addr = std::net::SocketAddr::from(([127, 0, 0, 1], studio.addr().port()));
    assert_eq!(get(addr, "/api/session").status, 401);
    assert_eq!(get(addr, "/api/session?token=wrong").status, 401);
    let ok = get(addr, &format!("/api/session?token={token}"));
    assert_eq!(ok.status, 200);
    assert_eq!(ok.json()["token"], true);
}

#[test]
fn the_palette_has_the_built_ins_and_the_file_models() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    let plain = get(studio.addr(), "/api/palette").json();
    let types = plain["types"].as_array().unwrap();
    assert!(types
        .iter()
        .any(|t| t["type"] == "Sequence" && t["category"] == "control"));
    assert!(!types.iter().any(|t| t["type"] == "Approach"));
    // A name a file may write for a built-in, drawn as that built-in.
    assert!(plain["aliases"]
        .as_array()
        .unwrap()
        .iter()
        .any(|a| a["name"] == "inverter" && a["type"] == "Inverter"));
    let with_file = get(studio.addr(), "/api/palette?path=tree.xml").json();
    let approach = with_file["types"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["type"] == "Approach")
        .expect("the file's model")
        .clone();
    assert_eq!(approach["category"], "action");
    assert_eq!(approach["builtin"], false);
    assert_eq!(approach["ports"][0]["name"], "target");
    assert_eq!(approach["ports"][0]["description"], "where to");
}

#[test]
fn a_tree_is_drawn_as_svg() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    let svg = post(
        studio.addr(),
        "/api/svg",
        &json!({"path": "tree.xml", "text": TREE}),
    );
    assert_eq!(svg.status, 200);
    assert!(
        svg.body.starts_with("<svg"),
        "{}",
        &svg.body[..80.min(svg.body.len())]
    );
    assert!(svg.body.contains("Approach"));
    assert!(svg.body.contains("docked"));
}

#[test]
fn a_tree_is_laid_out_as_the_svg_lays_it_out_and_a_bad_request_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    let nodes = json!([
        {"name": "root", "type": "Sequence", "category": "control", "children": [1, 2]},
        {"name": "again", "type": "RetryUntilSuccessful", "category": "decorator",
         "ports": [["num_attempts", "3"]], "directions": {"num_attempts": "input"}, "children": [3]},
        {"name": "Dock", "type": "SubTree", "category": "subtree"},
        {"name": "Approach", "type": "Approach", "category": "action",
         "ports": [["target", "{goal}"]], "directions": {"target": "input"}}
    ]);
    let answer = post(
        studio.addr(),
        "/api/layout",
        &json!({"nodes": nodes, "boxes": true, "layouts": [
            {"orientation": "TB", "detail": "full"},
            {"orientation": "LR", "detail": "compact", "folded": [1]}
        ]}),
    );
    assert_eq!(answer.status, 200, "{}", answer.body);
    let answer = answer.json();
    let boxes = answer["boxes"].as_array().unwrap();
    assert_eq!(boxes[0]["glyph"], "→");
    assert_eq!(boxes[1]["shape"], "decorator");
    assert_eq!(boxes[1]["ports"][0]["whole"], "in num_attempts: 3");
    assert_eq!(boxes[3]["ports"][0]["binding"], true);
    let [top_down, folded] = [&answer["layouts"][0], &answer["layouts"][1]];
    // The root centred over its two children, at the top; the leaf under the decorator.
    let x = |l: &serde_json::Value, i: usize| l["nodes"][i]["x"].as_f64().unwrap();
    assert_eq!(x(top_down, 0), (x(top_down, 1) + x(top_down, 2)) / 2.0);
    assert_eq!(top_down["nodes"][0]["y"], 0.0);
    assert_eq!(x(top_down, 3), x(top_down, 1));
    // Left to right with the decorator folded: its child has no place.
    assert!(folded["nodes"][3].is_null());
    assert!(x(folded, 1) > x(folded, 0));

    let bad = post(
        studio.addr(),
        "/api/layout",
        &json!({"nodes": nodes, "layouts": [{"orientation": "diagonal", "detail": "full"}]}),
    );
    assert_eq!(bad.status, 400);
    assert!(
        bad.body
            .contains("orientation `diagonal` is not known; give TB or LR"),
        "{}",
        bad.body
    );
}

#[test]
fn layouts_of_a_huge_tree_are_refused_past_the_places_an_answer_holds() {
    let dir = tempfile::tempdir().unwrap();
    let studio = studio(dir.path());
    // 17,000 bare nodes under one root: a body of a few hundred kilobytes.
    let mut nodes = vec![json!({"name": "root", "children": (1..17_000).collect::<Vec<_>>()})];
    nodes.extend((1..17_000).map(|_| json!({"name": "a"})));
    let wanted = |n: usize| vec![json!({"orientation": "TB", "detail": "compact"}); n];
    let refused = post(
        studio.addr(),
        "/api/layout",
        &json!({"nodes": nodes, "layouts": wanted(128)}),
    );
    assert_eq!(
        refused.status,
        400,
        "{}",
        &refused.body[..200.min(refused.body.len())]
    );
    assert!(
        refused
            .body
            .contains("128 layouts of 17000 nodes asked for at once; ask for at most 123 layouts"),
        "{}",
        refused.body
    );
    let answered = post(
        studio.addr(),
        "/api/layout",
        &json!({"nodes": nodes, "layouts": wanted(2)}),
    );
    assert_eq!(answered.status, 200);
    let answer = answered.json();
    assert_eq!(answer["layouts"].as_array().unwrap().len(), 2);
    assert_eq!(
        answer["layouts"][1]["nodes"].as_array().unwrap().len(),
        17_000
    );
}

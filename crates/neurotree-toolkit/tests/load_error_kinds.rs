//! Each kind of load error, from a small file that makes it: what a program branches on.

use std::path::PathBuf;

use neurotree_toolkit::xml::XmlLoader;
use neurotree_toolkit::{LoadError, LoadErrorKind, Registry, Status};

/// `<root>` around `trees`, with `main` as the main tree.
fn file(main: &str, trees: &str) -> String {
    format!(r#"<root BTCPP_format="4" main_tree_to_execute="{main}">{trees}</root>"#)
}

/// A file whose main tree `Main` has `body` as its root node.
fn main_tree(body: &str) -> String {
    file(
        "Main",
        &format!(r#"<BehaviorTree ID="Main">{body}</BehaviorTree>"#),
    )
}

/// The error of loading `text` and building its main tree with `registry`.
fn error_with(registry: &Registry<()>, text: &str) -> LoadError {
    let mut loader = XmlLoader::new(registry);
    match loader.load_str(text, "kinds.xml") {
        Ok(()) => loader.build_main().expect_err("the file should not build"),
        Err(e) => e,
    }
}

/// The kind of the error of loading `text` and building its main tree.
fn kind(text: &str) -> LoadErrorKind {
    error_with(&Registry::new(), text).kind()
}

/// A path for a file of this test that no other test uses.
fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!(
        "neurotree-load-error-kinds-{}-{name}",
        std::process::id()
    ))
}

#[test]
fn a_file_that_cannot_be_opened_is_io() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    let e = loader
        .load_file("/nonexistent/neurotree/tree.xml")
        .unwrap_err();
    assert_eq!(e.kind(), LoadErrorKind::Io);
    // About the file as a whole: no place in it.
    assert_eq!((e.line, e.col), (0, 0));
    assert!(e
        .to_string()
        .starts_with("/nonexistent/neurotree/tree.xml: error: cannot open the file"));
}

#[test]
fn a_file_past_the_size_limit_is_too_large() {
    let path = scratch("big.xml");
    std::fs::write(&path, main_tree("<AlwaysSuccess/>")).unwrap();
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).max_file_bytes(10);
    let result = loader.load_file(&path);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(result.unwrap_err().kind(), LoadErrorKind::TooLarge);
}

#[test]
fn malformed_xml_is_syntax() {
    assert_eq!(
        kind(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">"#),
        LoadErrorKind::Syntax
    );
}

#[test]
fn a_misshapen_document_is_structure() {
    assert_eq!(kind("<tree/>"), LoadErrorKind::Structure);
    assert_eq!(
        kind(&file("Main", r#"<BehaviorTree ID="Main"/>"#)),
        LoadErrorKind::Structure
    );
    assert_eq!(
        kind(&file("Main", "<Unexpected/>")),
        LoadErrorKind::Structure
    );
    assert_eq!(kind(&main_tree("<Action/>")), LoadErrorKind::Structure);
    assert_eq!(kind(&main_tree("<SubTree/>")), LoadErrorKind::Structure);
}

#[test]
fn a_malformed_model_is_structure() {
    let mut registry = Registry::<()>::new();
    let e = registry
        .add_model_str(
            r#"<root BTCPP_format="4"><TreeNodesModel><Action/></TreeNodesModel></root>"#,
            "model.xml",
        )
        .unwrap_err();
    assert_eq!(e.kind(), LoadErrorKind::Structure);
}

#[test]
fn another_format_is_unsupported() {
    assert_eq!(
        kind(
            r#"<root BTCPP_format="2"><BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree></root>"#
        ),
        LoadErrorKind::UnsupportedFormat
    );
}

#[test]
fn an_include_that_cannot_be_followed_is_include() {
    assert_eq!(
        kind(&file("Main", r#"<include path="nowhere/missing.xml"/>"#)),
        LoadErrorKind::Include
    );
    assert_eq!(kind(&file("Main", "<include/>")), LoadErrorKind::Include);
}

#[test]
fn an_included_file_keeps_the_kind_of_its_error() {
    let dir = scratch("include");
    std::fs::create_dir_all(&dir).unwrap();
    let main = dir.join("main.xml");
    std::fs::write(&main, file("Main", r#"<include path="sub.xml"/>"#)).unwrap();
    let padding = " ".repeat(400);
    let sub = main_tree(&format!("<AlwaysSuccess/>{padding}"));
    std::fs::write(dir.join("sub.xml"), sub).unwrap();
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).max_file_bytes(200);
    let result = loader.load_file(&main);
    std::fs::remove_dir_all(&dir).unwrap();
    let e = result.unwrap_err();
    // Placed at the <include>, of the kind the included file's error has.
    assert!(e.file.ends_with("main.xml"), "{e}");
    assert_eq!(e.kind(), LoadErrorKind::TooLarge, "{e}");
}

#[test]
fn a_tree_id_loaded_twice_is_duplicate_tree() {
    let tree = r#"<BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>"#;
    assert_eq!(
        kind(&file("Main", &format!("{tree}{tree}"))),
        LoadErrorKind::DuplicateTree
    );
}

#[test]
fn an_unregistered_type_is_unknown_node() {
    assert_eq!(
        kind(&main_tree("<NoSuchNode/>")),
        LoadErrorKind::UnknownNode
    );
}

#[test]
fn a_type_only_a_model_describes_is_model_only_when_built() {
    let mut registry = Registry::<()>::new();
    registry
        .add_model_str(
            r#"<root BTCPP_format="4"><TreeNodesModel><Action ID="Described"/></TreeNodesModel></root>"#,
            "model.xml",
        )
        .unwrap();
    let text = main_tree("<Described/>");
    assert_eq!(
        error_with(&registry, &text).kind(),
        LoadErrorKind::ModelOnly
    );
    // Validating accepts it: only running needs an implementation.
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(&text, "kinds.xml").unwrap();
    assert_eq!(loader.validate("Main"), Ok(()));
}

#[test]
fn an_attribute_that_is_no_port_is_unknown_port() {
    assert_eq!(
        kind(&main_tree(r#"<AlwaysSuccess speed="3"/>"#)),
        LoadErrorKind::UnknownPort
    );
}

#[test]
fn a_port_left_out_without_default_is_missing_port() {
    assert_eq!(
        kind(&main_tree("<Repeat><AlwaysSuccess/></Repeat>")),
        LoadErrorKind::MissingPort
    );
    // A SubTree port that the model declares without a default.
    let text = file(
        "Main",
        r#"<BehaviorTree ID="Main"><SubTree ID="Child"/></BehaviorTree>
           <BehaviorTree ID="Child"><AlwaysSuccess/></BehaviorTree>
           <TreeNodesModel><SubTree ID="Child"><input_port name="goal"/></SubTree></TreeNodesModel>"#,
    );
    assert_eq!(kind(&text), LoadErrorKind::MissingPort);
}

#[test]
fn a_literal_that_does_not_convert_is_bad_value() {
    assert_eq!(
        kind(&main_tree(
            r#"<Repeat num_cycles="many"><AlwaysSuccess/></Repeat>"#
        )),
        LoadErrorKind::BadValue
    );
    let text = file(
        "Main",
        r#"<BehaviorTree ID="Main"><SubTree ID="Child" _autoremap="maybe"/></BehaviorTree>
           <BehaviorTree ID="Child"><AlwaysSuccess/></BehaviorTree>"#,
    );
    assert_eq!(kind(&text), LoadErrorKind::BadValue);
}

#[test]
fn a_condition_script_that_does_not_parse_is_script() {
    assert_eq!(
        kind(&main_tree(r#"<AlwaysSuccess _skipIf="1 +"/>"#)),
        LoadErrorKind::Script
    );
    // The code of a Script node, and a std node's port left out, are told apart by kind.
    assert_eq!(
        kind(&main_tree(r#"<Script code="x := "/>"#)),
        LoadErrorKind::Script
    );
    assert_eq!(kind(&main_tree("<Script/>")), LoadErrorKind::MissingPort);
    assert_eq!(
        kind(&main_tree(r#"<Script code="{entry}"/>"#)),
        LoadErrorKind::BadValue
    );
}

#[test]
fn an_undefined_underscore_attribute_is_reserved_attribute() {
    assert_eq!(
        kind(&main_tree(r#"<AlwaysSuccess _colour="red"/>"#)),
        LoadErrorKind::ReservedAttribute
    );
}

#[test]
fn a_wrong_number_of_children_is_child_count() {
    assert_eq!(kind(&main_tree("<Inverter/>")), LoadErrorKind::ChildCount);
    assert_eq!(
        kind(&main_tree(
            "<AlwaysSuccess><AlwaysSuccess/></AlwaysSuccess>"
        )),
        LoadErrorKind::ChildCount
    );
    // A threshold above the number of children, which the builder refuses.
    assert_eq!(
        kind(&main_tree(
            r#"<Parallel success_count="3" failure_count="1"><AlwaysSuccess/></Parallel>"#
        )),
        LoadErrorKind::ChildCount
    );
}

#[test]
fn a_tree_that_contains_itself_is_subtree_cycle() {
    let text = file(
        "Main",
        r#"<BehaviorTree ID="Main"><SubTree ID="Other"/></BehaviorTree>
           <BehaviorTree ID="Other"><SubTree ID="Main"/></BehaviorTree>"#,
    );
    assert_eq!(kind(&text), LoadErrorKind::SubtreeCycle);
}

#[test]
fn a_tree_id_nobody_loaded_is_unknown_tree() {
    assert_eq!(
        kind(&main_tree(r#"<SubTree ID="Elsewhere"/>"#)),
        LoadErrorKind::UnknownTree
    );
    assert_eq!(
        kind(&file(
            "Absent",
            r#"<BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>"#
        )),
        LoadErrorKind::UnknownTree
    );
    let registry = Registry::<()>::new();
    let loader = XmlLoader::new(&registry);
    assert_eq!(
        loader.build("Main").unwrap_err().kind(),
        LoadErrorKind::UnknownTree
    );
    assert_eq!(
        loader.validate("Main").unwrap_err().kind(),
        LoadErrorKind::UnknownTree
    );
}

#[test]
fn no_tree_to_start_from_is_no_main_tree() {
    assert_eq!(
        kind(r#"<root BTCPP_format="4"/>"#),
        LoadErrorKind::NoMainTree
    );
}

#[test]
fn several_trees_and_no_main_one_is_ambiguous_main_tree() {
    let text = r#"<root BTCPP_format="4">
        <BehaviorTree ID="A"><AlwaysSuccess/></BehaviorTree>
        <BehaviorTree ID="B"><AlwaysFailure/></BehaviorTree>
    </root>"#;
    assert_eq!(kind(text), LoadErrorKind::AmbiguousMainTree);
}

#[test]
fn nesting_past_the_limits_is_too_deep() {
    // Past the depth a tree may have.
    let depth = 300;
    let body = format!(
        "{}<AlwaysSuccess/>{}",
        "<Inverter>".repeat(depth),
        "</Inverter>".repeat(depth)
    );
    assert_eq!(kind(&main_tree(&body)), LoadErrorKind::TooDeep);
    // Past the nesting the reader reads.
    let depth = 1100;
    let body = format!(
        "{}{}",
        "<Inverter>".repeat(depth),
        "</Inverter>".repeat(depth)
    );
    assert_eq!(kind(&main_tree(&body)), LoadErrorKind::TooDeep);
}

#[test]
fn a_tree_past_the_node_limit_is_too_many_nodes() {
    let text = file(
        "Main",
        r#"<BehaviorTree ID="Main">
             <Sequence><SubTree ID="Child"/><SubTree ID="Child"/></Sequence>
           </BehaviorTree>
           <BehaviorTree ID="Child">
             <Sequence><AlwaysSuccess/><AlwaysSuccess/></Sequence>
           </BehaviorTree>"#,
    );
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).max_nodes(4);
    loader.load_str(&text, "kinds.xml").unwrap();
    assert_eq!(
        loader.build_main().unwrap_err().kind(),
        LoadErrorKind::TooManyNodes
    );
    let errors = loader.validate_all("Main", 10);
    assert!(!errors.is_empty());
    assert!(
        errors
            .iter()
            .all(|e| e.kind() == LoadErrorKind::TooManyNodes),
        "{errors:?}"
    );
}

#[test]
fn a_mock_named_after_a_control_only_is_mock_not_leaf() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).mock("Steps", vec![Status::Success]);
    loader
        .load_str(
            &main_tree(r#"<Sequence name="Steps"><AlwaysFailure/></Sequence>"#),
            "kinds.xml",
        )
        .unwrap();
    assert_eq!(
        loader.build_main().unwrap_err().kind(),
        LoadErrorKind::MockNotLeaf
    );
}

#[test]
fn validate_all_gives_each_error_its_kind() {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            &main_tree(
                r#"<Sequence><NoSuchNode/><AlwaysSuccess speed="3"/><Inverter/></Sequence>"#,
            ),
            "kinds.xml",
        )
        .unwrap();
    let kinds: Vec<LoadErrorKind> = loader
        .validate_all("Main", 10)
        .iter()
        .map(LoadError::kind)
        .collect();
    assert_eq!(
        kinds,
        [
            LoadErrorKind::UnknownNode,
            LoadErrorKind::UnknownPort,
            LoadErrorKind::ChildCount
        ]
    );
}

#[test]
fn an_error_made_outside_the_loader_keeps_its_kind_and_place() {
    let e = LoadError::new(LoadErrorKind::BadValue, "trace.jsonl", 3, 7, "not a status");
    assert_eq!(e.kind(), LoadErrorKind::BadValue);
    assert_eq!(e.to_string(), "trace.jsonl:3:7: error: not a status");
}

//! What BehaviorTree.CPP 4.10 refuses when it loads a file or builds its tree, refused here
//! with the same rule; each test quotes BehaviorTree.CPP's own message.

use std::sync::Arc;

use neurotree_toolkit::script::ScriptErrorKind;
use neurotree_toolkit::xml::XmlLoader;
use neurotree_toolkit::{
    Handle, LoadError, LoadErrorKind, ManualClock, PortSpec, Registry, RegistryError, Status, Tree,
};

/// `<root>` around `trees`, with `Main` as the main tree.
fn file(trees: &str) -> String {
    format!(r#"<root BTCPP_format="4" main_tree_to_execute="Main">{trees}</root>"#)
}

/// A file whose main tree `Main` has `body` as its root node.
fn main_tree(body: &str) -> String {
    file(&format!(r#"<BehaviorTree ID="Main">{body}</BehaviorTree>"#))
}

/// The error of loading `text` and building its main tree with `registry`.
fn error_with(registry: &Registry<()>, text: &str) -> LoadError {
    let mut loader = XmlLoader::new(registry);
    match loader.load_str(text, "refused.xml") {
        Ok(()) => loader.build_main().expect_err("the file should not build"),
        Err(e) => e,
    }
}

/// The error of loading and building `text` with the built-in nodes.
fn error(text: &str) -> LoadError {
    error_with(&Registry::new(), text)
}

/// `text` loads and its main tree builds.
fn builds(text: &str) {
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader.load_str(text, "accepted.xml").unwrap();
    loader.build_main().unwrap();
}

// ----- 1. tree and SubTree IDs -----

#[test]
fn a_reserved_tree_id_is_refused() {
    // xml_parsing.cpp, validateModelName: "'Root' is a reserved name and cannot be used as a
    // node type".
    for id in ["Root", "root"] {
        let e = error(&file(&format!(
            r#"<BehaviorTree ID="{id}"><AlwaysSuccess/></BehaviorTree>"#
        )));
        assert_eq!(e.kind(), LoadErrorKind::BadName, "{e}");
        assert!(e.message.contains("reserved"), "{e}");
        assert_eq!(e.line, 1);
    }
}

#[test]
fn a_tree_id_with_a_forbidden_character_is_refused() {
    // validateModelName: "Model name '...' contains forbidden character ' '" (and the others
    // of findForbiddenChar in basic_types.cpp).
    for id in [
        "Main Tree",
        "main.tree",
        "a/b",
        "a:b",
        "a*b",
        "a?b",
        "a|b",
        "a\\b",
    ] {
        let e = error(&file(&format!(
            r#"<BehaviorTree ID="{id}"><AlwaysSuccess/></BehaviorTree>"#
        )));
        assert_eq!(e.kind(), LoadErrorKind::BadName, "{id}: {e}");
        assert!(e.message.contains("forbidden character"), "{e}");
    }
    // A tab written as a character reference is a control character.
    let e = error(&file(
        r#"<BehaviorTree ID="a&#9;b"><AlwaysSuccess/></BehaviorTree>"#,
    ));
    assert!(e.message.contains("control character (ASCII 9)"), "{e}");
    // Letters beyond ASCII are allowed, as BehaviorTree.CPP passes multibyte UTF-8.
    builds(&file(
        r#"<BehaviorTree ID="Main"><SubTree ID="Bäume"/></BehaviorTree>
           <BehaviorTree ID="Bäume"><AlwaysSuccess/></BehaviorTree>"#,
    ));
}

#[test]
fn an_empty_tree_id_among_other_elements_is_refused() {
    // VerifyXML: "The tag <BehaviorTree> must have the attribute [ID]" when <root> holds
    // more than one element.
    for tree in [
        r#"<BehaviorTree ID=""><AlwaysSuccess/></BehaviorTree>"#,
        r#"<BehaviorTree><AlwaysSuccess/></BehaviorTree>"#,
    ] {
        let text = format!(
            r#"<root BTCPP_format="4">{tree}<BehaviorTree ID="Other"><AlwaysSuccess/></BehaviorTree></root>"#
        );
        let registry = Registry::<()>::new();
        let e = XmlLoader::new(&registry)
            .load_str(&text, "refused.xml")
            .unwrap_err();
        assert_eq!(e.kind(), LoadErrorKind::BadName, "{e}");
        assert!(e.message.contains("needs an ID"), "{e}");
    }
    // Alone in its file, a tree needs no ID (BehaviorTree.CPP's own tutorials rely on it).
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            r#"<root BTCPP_format="4"><BehaviorTree><AlwaysSuccess/></BehaviorTree></root>"#,
            "alone.xml",
        )
        .unwrap();
    loader.build_main().unwrap();
}

#[test]
fn a_tree_named_like_a_registered_node_is_refused() {
    // VerifyXML: "The attribute [ID] of tag <BehaviorTree> must not use the name of a
    // registered Node".
    let e = error(&file(
        r#"<BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>
           <BehaviorTree ID="Sequence"><AlwaysSuccess/></BehaviorTree>"#,
    ));
    assert_eq!(e.kind(), LoadErrorKind::BadName, "{e}");
    assert!(e.message.contains("registered node type"), "{e}");
    assert_eq!(e.line, 2);
    let mut registry = Registry::new();
    registry
        .register_action("Main", vec![], |_| Status::Success)
        .unwrap();
    let e = error_with(&registry, &main_tree("<AlwaysSuccess/>"));
    assert_eq!(e.kind(), LoadErrorKind::BadName, "{e}");
}

#[test]
fn a_subtree_id_refused_as_a_tree_id_is_refused() {
    // VerifyXML validates a <SubTree>'s ID as a model name, and: "The attribute [ID] of tag
    // <SubTree> must not use the name of a registered Node".
    for (id, says) in [
        ("my child", "forbidden character"),
        ("", "is empty"),
        ("Root", "reserved"),
        ("Fallback", "registered node type"),
    ] {
        let e = error(&main_tree(&format!(
            r#"<Sequence><AlwaysSuccess/><SubTree ID="{id}"/></Sequence>"#
        )));
        assert_eq!(e.kind(), LoadErrorKind::BadName, "{id}: {e}");
        assert!(e.message.contains(says), "{e}");
        assert!(e.message.contains("SubTree ID"), "{e}");
    }
}

#[test]
fn a_node_type_written_with_a_forbidden_character_is_refused() {
    // VerifyXML validates the element name of a node that is not written <Action ID=...>:
    // "Model name 'my.Thing' contains forbidden character '.'". Mocking unknown nodes does
    // not let it through.
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    let e = loader
        .load_str(&main_tree("<my.Thing/>"), "refused.xml")
        .unwrap_err();
    assert_eq!(e.kind(), LoadErrorKind::BadName, "{e}");
    assert!(e.message.contains("'.'"), "{e}");
}

// ----- 2. port names -----

#[test]
fn a_model_port_name_behaviortree_cpp_refuses_is_refused() {
    // CreatePort (basic_types.h): "The name of a port must not be `name` or `ID` and must
    // start with an alphabetic character. Underscore is reserved."
    for port in ["name", "ID", "_skipIf", "2fast", "_private", "go.al", "a b"] {
        let model = format!(
            r#"<root BTCPP_format="4"><TreeNodesModel>
                 <Action ID="Go"><input_port name="{port}"/></Action>
               </TreeNodesModel></root>"#
        );
        let mut registry = Registry::<()>::new();
        let e = registry.add_model_str(&model, "model.xml").unwrap_err();
        assert_eq!(e.kind(), LoadErrorKind::BadName, "{port}: {e}");
        assert!(e.message.contains("`Go`"), "{e}");
        assert_eq!(e.line, 2, "{e}");
    }
}

#[test]
fn a_subtree_model_port_name_behaviortree_cpp_refuses_is_refused() {
    // parseSubtreeModelPorts → validatePortName: "Port name 'name' is a reserved attribute
    // name", "Port name '1st' cannot start with a digit", "... contains forbidden
    // character"; and "Missing attribute [name] in port (SubTree model)".
    for (port, says) in [
        ("name", "reserved"),
        ("_autoremap", "reserved"),
        ("1st", "digit"),
        ("a.b", "forbidden character"),
    ] {
        let text = file(&format!(
            r#"<TreeNodesModel><SubTree ID="Child"><input_port name="{port}"/></SubTree></TreeNodesModel>
               <BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>"#
        ));
        let e = error(&text);
        assert_eq!(e.kind(), LoadErrorKind::BadName, "{port}: {e}");
        assert!(e.message.contains(says), "{e}");
    }
    let e = error(&file(
        r#"<TreeNodesModel><SubTree ID="Child"><input_port/></SubTree></TreeNodesModel>
           <BehaviorTree ID="Main"><AlwaysSuccess/></BehaviorTree>"#,
    ));
    assert_eq!(e.kind(), LoadErrorKind::Structure, "{e}");
    // A SubTree's model port may start with `_` (validatePortName checks only digits).
    builds(&file(
        r#"<TreeNodesModel><SubTree ID="Child"><input_port name="_x" default="1"/></SubTree></TreeNodesModel>
           <BehaviorTree ID="Main"><SubTree ID="Child"/></BehaviorTree>
           <BehaviorTree ID="Child"><AlwaysSuccess/></BehaviorTree>"#,
    ));
}

#[test]
fn registering_a_port_name_behaviortree_cpp_refuses_is_refused() {
    // CreatePort: "The name of a port must not be `name` or `ID` and must start with an
    // alphabetic character. Underscore is reserved."
    let mut registry = Registry::<()>::new();
    for port in ["name", "ID", "_post", "9lives", "with space"] {
        let e = registry
            .register_action("Go", vec![PortSpec::input::<i64>(port)], |_| {
                Status::Success
            })
            .unwrap_err();
        assert!(
            matches!(&e, RegistryError::BadPortName { node, port: p, .. } if node == "Go" && p == port),
            "{e}"
        );
        let e = registry
            .register_condition("Is", vec![PortSpec::input::<i64>(port)], |_| true)
            .unwrap_err();
        assert!(matches!(e, RegistryError::BadPortName { .. }), "{e}");
    }
    assert!(registry.get("Go").is_none());
    registry
        .register_action("Go", vec![PortSpec::input::<i64>("speed_2")], |_| {
            Status::Success
        })
        .unwrap();
}

// ----- 3. SubTrees of the same name -----

const CHILD: &str = r#"<BehaviorTree ID="Child"><AlwaysSuccess/></BehaviorTree>"#;

#[test]
fn two_subtrees_of_the_same_name_in_one_tree_are_refused() {
    // recursivelyCreateSubtree: "Duplicate SubTree path detected: 'x'. Multiple SubTree nodes
    // with the same 'name' attribute under the same parent are not allowed. Please use unique
    // names or omit the 'name' attribute to auto-generate unique paths."
    let e = error(&file(&format!(
        r#"<BehaviorTree ID="Main">
             <Sequence>
               <SubTree ID="Child" name="x"/>
               <Fallback><SubTree ID="Child" name="x"/></Fallback>
             </Sequence>
           </BehaviorTree>{CHILD}"#
    )));
    assert_eq!(e.kind(), LoadErrorKind::DuplicateSubTreePath, "{e}");
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("path `x`"), "{e}");
    // The same name in different subtree instances gives different paths; no name, or
    // different names, are fine.
    builds(&file(&format!(
        r#"<BehaviorTree ID="Main">
             <Sequence>
               <SubTree ID="Middle" name="a"/>
               <SubTree ID="Middle" name="b"/>
               <SubTree ID="Child"/>
               <SubTree ID="Child"/>
             </Sequence>
           </BehaviorTree>
           <BehaviorTree ID="Middle"><SubTree ID="Child" name="x"/></BehaviorTree>{CHILD}"#
    )));
    // `validate` refuses it too.
    let registry = Registry::<()>::new();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            &file(&format!(
                r#"<BehaviorTree ID="Main"><Sequence><SubTree ID="Child" name="x"/><SubTree ID="Child" name="x"/></Sequence></BehaviorTree>{CHILD}"#
            )),
            "refused.xml",
        )
        .unwrap();
    assert_eq!(
        loader.validate("Main").unwrap_err().kind(),
        LoadErrorKind::DuplicateSubTreePath
    );
}

// ----- 4. blank scripts -----

#[test]
fn a_blank_script_is_refused() {
    // script_parser.cpp, ParseScript: "Empty Script", thrown by ScriptNode's,
    // ScriptCondition's and PreconditionNode's constructors (loadExecutor), and by
    // BehaviorTreeFactory::instantiateTreeNode for a pre/post-condition: "Error in the
    // script \"\"\nEmpty Script".
    for body in [
        r#"<Script code=""/>"#,
        r#"<Script code="   "/>"#,
        r#"<ScriptCondition code=""/>"#,
        r#"<Precondition if=" "><AlwaysSuccess/></Precondition>"#,
        r#"<AlwaysSuccess _skipIf=""/>"#,
        r#"<AlwaysSuccess _post=" "/>"#,
        r#"<AlwaysSuccess _while=""/>"#,
    ] {
        let e = error(&main_tree(body));
        assert_eq!(e.kind(), LoadErrorKind::Script, "{body}: {e}");
        assert!(e.message.contains("empty script"), "{e}");
    }
    let e = neurotree_toolkit::script::Script::parse(" \n ").unwrap_err();
    assert_eq!(e.kind, ScriptErrorKind::Empty);
}

// ----- 5. a ReactiveSequence's asynchronous children -----

#[test]
fn a_reactive_sequence_with_two_async_sequences_is_refused() {
    // VerifyXML: "A ReactiveSequence cannot have more than one async child." — it counts the
    // children written <AsyncSequence>, the asynchronous control BehaviorTree.CPP registers.
    let e = error(&main_tree(
        r#"<ReactiveSequence>
             <AsyncSequence><AlwaysSuccess/></AsyncSequence>
             <AsyncSequence><AlwaysSuccess/></AsyncSequence>
           </ReactiveSequence>"#,
    ));
    assert_eq!(e.kind(), LoadErrorKind::ReactiveAsync, "{e}");
    assert!(e.message.contains("more than one async child"), "{e}");
    let e = error(&main_tree(
        r#"<Control ID="ReactiveSequence">
             <AsyncSequence><AlwaysSuccess/></AsyncSequence>
             <AsyncSequence><AlwaysSuccess/></AsyncSequence>
           </Control>"#,
    ));
    assert_eq!(e.kind(), LoadErrorKind::ReactiveAsync, "{e}");
    // One is fine; BehaviorTree.CPP checks only ReactiveSequence.
    builds(&main_tree(
        r#"<ReactiveSequence>
             <AlwaysSuccess/>
             <AsyncSequence><AlwaysSuccess/></AsyncSequence>
           </ReactiveSequence>"#,
    ));
    builds(&main_tree(
        r#"<ReactiveFallback>
             <AsyncSequence><AlwaysFailure/></AsyncSequence>
             <AsyncSequence><AlwaysSuccess/></AsyncSequence>
           </ReactiveFallback>"#,
    ));
}

/// Running for one tick, then Success; counts its starts and halts.
struct Step;

impl neurotree_toolkit::StatefulAction<Vec<&'static str>> for Step {
    fn on_start(&mut self, h: &mut Handle<'_, Vec<&'static str>>) -> Status {
        h.ctx_mut().push("start");
        Status::Running
    }
    fn on_running(&mut self, _: &mut Handle<'_, Vec<&'static str>>) -> Status {
        Status::Success
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Vec<&'static str>>) {
        h.ctx_mut().push("halted");
    }
}

#[test]
fn a_second_running_child_of_a_loaded_reactive_sequence_halts_the_first_as_by_default() {
    // reactive_sequence.cpp: `throw_if_multiple_running = false` by default, so 4.10 throws
    // "[ReactiveSequence]: only a single child can return RUNNING." only after
    // ReactiveSequence::EnableException(true). By default the child that returns RUNNING
    // halts the others and the node returns RUNNING: a loaded tree does the same (no error),
    // and its program may turn the check on with Tree::reject_multiple_running.
    let mut registry = Registry::<Vec<&'static str>>::new();
    registry.register_stateful("Step", vec![], || Step).unwrap();
    let mut loader = XmlLoader::new(&registry);
    loader
        .load_str(
            &file(
                r#"<BehaviorTree ID="Main"><ReactiveSequence><Step/><Step/></ReactiveSequence></BehaviorTree>"#,
            ),
            "reactive.xml",
        )
        .unwrap();
    let bp = Arc::new(loader.build_main().unwrap());
    let mut tree = Tree::with_clock(Arc::clone(&bp), ManualClock::new());
    let mut log = Vec::new();
    for _ in 0..4 {
        assert_eq!(tree.tick_once(&mut log), Ok(Status::Running));
    }
    // Tick 2 starts the second Step; tick 3 restarts the first, which halts the second.
    assert_eq!(log, ["start", "start", "start", "halted", "start"]);
    let mut strict = Tree::with_clock(bp, ManualClock::new());
    strict.reject_multiple_running(true);
    let mut log = Vec::new();
    assert_eq!(strict.tick_once(&mut log), Ok(Status::Running));
    let e = strict.tick_once(&mut log).unwrap_err();
    assert!(e.to_string().contains("only a single child"), "{e}");
}

// ----- 6. entries of a model's ports exist when the tree is built -----

#[test]
fn an_entry_a_model_node_binds_exists_for_a_later_script() {
    // xml_parsing.cpp, createNodeFromXML: "Initialize the ports in the BB to set the type" —
    // blackboard->createEntry(port_key, port_info) for each port remapped to {key}, before
    // the node is made; so a Script may then assign the entry with `=`, which needs it to
    // exist (else "... Use := to create a new entry").
    let mut registry = Registry::<()>::new();
    registry
        .add_model_str(
            r#"<root BTCPP_format="4"><TreeNodesModel>
                 <Action ID="ComputePath"><output_port name="path" type="std::string"/></Action>
               </TreeNodesModel></root>"#,
            "model.xml",
        )
        .unwrap();
    let text = main_tree(
        r#"<Sequence>
             <ComputePath path="{plan}"/>
             <Script code="plan = 'straight'"/>
           </Sequence>"#,
    );
    let mut loader = XmlLoader::new(&registry).mock_unknown(true);
    loader.load_str(&text, "model_ports.xml").unwrap();
    let mut tree = Tree::with_clock(Arc::new(loader.build_main().unwrap()), ManualClock::new());
    assert!(tree.blackboard().contains("plan"));
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
    assert_eq!(
        tree.blackboard().get::<String>("plan"),
        Ok("straight".to_string())
    );
    // A mock of a model's node keeps its ports too.
    let mut loader = XmlLoader::new(&registry).mock("ComputePath", vec![Status::Success]);
    loader
        .load_str(
            &main_tree(
                r#"<Sequence><ComputePath path="{plan}"/><Script code="plan = 'x'"/></Sequence>"#,
            ),
            "mocked.xml",
        )
        .unwrap();
    let mut tree = Tree::with_clock(Arc::new(loader.build_main().unwrap()), ManualClock::new());
    assert_eq!(tree.tick_once(&mut ()), Ok(Status::Success));
}

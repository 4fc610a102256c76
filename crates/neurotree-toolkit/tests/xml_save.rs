//! Saving: a blueprint written as XML loads back into the same blueprint, for hand-written
//! cases and for random trees of every built-in, registered leaves, subtrees and scripts.

use neurotree::xml::{write_xml, SaveOptions};
use neurotree::{Blueprint, PortSpec, Registry, StatefulAction, Status, XmlLoader};
use proptest::prelude::*;

use crate::signature as support;
use support::signature;

struct Idle;
impl StatefulAction<()> for Idle {
    fn on_start(&mut self, _: &mut neurotree::Handle<'_, ()>) -> Status {
        Status::Running
    }
    fn on_running(&mut self, _: &mut neurotree::Handle<'_, ()>) -> Status {
        Status::Success
    }
}

fn registry() -> Registry<()> {
    let mut r = Registry::new();
    r.register_action(
        "MoveTo",
        vec![
            PortSpec::input::<f64>("speed").default_value("0.5"),
            PortSpec::input::<String>("goal"),
            PortSpec::output::<String>("result"),
        ],
        |_| Status::Success,
    )
    .unwrap();
    r.register_condition("IsReady", vec![PortSpec::inout::<i32>("level")], |_| true)
        .unwrap();
    r.register_stateful("Wait", vec![], || Idle).unwrap();
    r
}

fn load(registry: &Registry<()>, text: &str, id: &str) -> Blueprint<()> {
    let mut loader = XmlLoader::new(registry);
    loader
        .load_str(text, "tree.xml")
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    loader.build(id).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Loads `text`, saves, loads the saved file, and checks both blueprints and both saves
/// are the same; returns the saved text.
fn round_trip(text: &str) -> String {
    let registry = registry();
    let first = load(&registry, text, "Main");
    let opts = SaveOptions {
        tree_id: "Main".into(),
        ..SaveOptions::default()
    };
    let saved = write_xml(&first, &registry, &opts);
    let second = load(&registry, &saved, "Main");
    assert_eq!(signature(&first), signature(&second), "{saved}");
    assert_eq!(write_xml(&second, &registry, &opts), saved);
    saved
}

#[test]
fn a_tree_with_every_feature_survives_saving() {
    let saved = round_trip(
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
          <BehaviorTree ID="Main">
            <Sequence name="top">
              <IsReady level="{lvl}" _skipIf="lvl &gt; 3" _onSuccess="done := true"/>
              <Parallel success_count="2" failure_count="-1">
                <MoveTo goal="{@target}" result="{out}"/>
                <Timeout msec="250"><Wait/></Timeout>
              </Parallel>
              <SubTree ID="Dock" name="dock_here" pose="{target}" speed="1.5" _autoremap="true"/>
              <SubTree ID="Dock"/>
              <Script code="msg := 'a &amp; b';&#10;n := 2"/>
            </Sequence>
          </BehaviorTree>
          <BehaviorTree ID="Dock">
            <RetryUntilSuccessful num_attempts="3">
              <Fallback><MoveTo goal="{pose}"/><AlwaysFailure/></Fallback>
            </RetryUntilSuccessful>
          </BehaviorTree>
        </root>"#,
    );
    // One definition for the subtree used twice; its remapping on the SubTree element.
    assert_eq!(
        saved.matches(r#"<BehaviorTree ID="Dock">"#).count(),
        1,
        "{saved}"
    );
    assert!(
        saved.contains(
            r#"<SubTree ID="Dock" name="dock_here" pose="{target}" speed="1.5" _autoremap="true"/>"#
        ),
        "{saved}"
    );
    // Defaults are written out, so the file no longer depends on the model.
    assert!(saved.contains(r#"speed="0.5""#), "{saved}");
    // A script's line break survives as a character reference.
    assert!(saved.contains("&#10;"), "{saved}");
    assert!(saved.contains(r#"<TreeNodesModel>"#), "{saved}");
    assert!(saved.contains(r#"<Action ID="MoveTo">"#), "{saved}");
}

#[test]
fn uids_follow_node_ids_and_each_subtree_instance_gets_its_own_tree() {
    let registry = registry();
    let bp = load(
        &registry,
        r#"<root BTCPP_format="4">
          <BehaviorTree ID="Main">
            <Sequence><SubTree ID="S"/><SubTree ID="S" name="again"/></Sequence>
          </BehaviorTree>
          <BehaviorTree ID="S"><Inverter><AlwaysFailure/></Inverter></BehaviorTree>
        </root>"#,
        "Main",
    );
    let xml = write_xml(
        &bp,
        &registry,
        &SaveOptions {
            uids: true,
            models: false,
            ..SaveOptions::default()
        },
    );
    let doc = roxmltree_free_uids(&xml);
    assert_eq!(doc, vec![1, 2, 3, 4, 5, 6, 7], "{xml}");
    assert_eq!(xml.matches("<BehaviorTree ID=\"S\"").count(), 2, "{xml}");
    assert!(xml.contains(r#"_fullpath="Sequence/again""#), "{xml}");
    assert!(!xml.contains("TreeNodesModel"), "{xml}");
}

#[test]
fn subtree_instances_come_out_depth_first_as_behaviortree_cpp_writes_them() {
    let registry = registry();
    let bp = load(
        &registry,
        r#"<root BTCPP_format="4">
          <BehaviorTree ID="Main">
            <Sequence><SubTree ID="A" name="a"/><SubTree ID="X" name="x_in_main"/></Sequence>
          </BehaviorTree>
          <BehaviorTree ID="A">
            <Sequence><SubTree ID="X" name="x_in_a"/><AlwaysSuccess/></Sequence>
          </BehaviorTree>
          <BehaviorTree ID="X"><AlwaysFailure/></BehaviorTree>
        </root>"#,
        "Main",
    );
    let uids = SaveOptions {
        uids: true,
        models: false,
        ..SaveOptions::default()
    };
    let xml = write_xml(&bp, &registry, &uids);
    // Each instance right after the tree that opens it, so that a reader taking the trees
    // of one ID in turn while walking the tree pairs each SubTree with its own.
    let trees: Vec<&str> = xml
        .lines()
        .filter(|l| l.trim_start().starts_with("<BehaviorTree"))
        .map(str::trim)
        .collect();
    assert_eq!(
        trees,
        [
            r#"<BehaviorTree ID="MainTree">"#,
            r#"<BehaviorTree ID="A" _fullpath="Sequence/a">"#,
            r#"<BehaviorTree ID="X" _fullpath="Sequence/a/Sequence/x_in_a">"#,
            r#"<BehaviorTree ID="X" _fullpath="Sequence/x_in_main">"#,
        ],
        "{xml}"
    );
    // Without uids, each ID once, depth-first too.
    let plain = write_xml(&bp, &registry, &SaveOptions::default());
    let ids: Vec<&str> = plain
        .lines()
        .filter_map(|l| l.trim().strip_prefix("<BehaviorTree ID=\""))
        .collect();
    assert_eq!(ids, [r#"MainTree">"#, r#"A">"#, r#"X">"#], "{plain}");
}

/// The `_uid` values in document order of their elements' node ids: the main tree first,
/// then each subtree instance.
fn roxmltree_free_uids(xml: &str) -> Vec<u32> {
    let mut uids: Vec<u32> = xml
        .split("_uid=\"")
        .skip(1)
        .map(|rest| rest[..rest.find('"').unwrap()].parse().unwrap())
        .collect();
    uids.sort_unstable();
    uids
}

#[test]
fn builder_trees_save_their_closures_in_the_explicit_form() {
    let bp = Blueprint::<()>::builder()
        .sequence("root", |s| {
            s.condition("ready", |_: &()| true)
                .repeat("thrice", 3, |r| {
                    r.action("go", |_: &mut ()| Status::Success)
                })
        })
        .build()
        .unwrap();
    let mut registry = Registry::new();
    let xml = write_xml(&bp, &registry, &SaveOptions::default());
    assert!(xml.contains(r#"<Condition ID="ready"/>"#), "{xml}");
    assert!(xml.contains(r#"<Action ID="go"/>"#), "{xml}");
    assert!(
        xml.contains(r#"<Repeat name="thrice" num_cycles="3">"#),
        "{xml}"
    );
    // Registering the leaves by those names makes the file load into the same shape.
    registry
        .register_condition("ready", vec![], |_| true)
        .unwrap();
    registry
        .register_action("go", vec![], |_| Status::Success)
        .unwrap();
    let back = load(&registry, &xml, "MainTree");
    let shape = |bp: &Blueprint<()>| {
        bp.ids()
            .map(|id| (bp.name(id).to_string(), bp.children(id).len()))
            .collect::<Vec<_>>()
    };
    assert_eq!(shape(&back), shape(&bp));
}

// ---- random trees ----

/// A node of a random tree, written as XML by [`Node::xml`].
#[derive(Clone, Debug)]
enum Node {
    Leaf(&'static str),
    Decorator(&'static str, Box<Node>),
    Control(&'static str, Vec<Node>),
    SubTree(String),
}

const LEAVES: [&str; 8] = [
    r#"<AlwaysSuccess/>"#,
    r#"<AlwaysFailure name="no &amp; never"/>"#,
    r#"<MoveTo goal="{target}" speed="2.5"/>"#,
    r#"<MoveTo goal="home" result="{@last}" _onFailure="fails += 1"/>"#,
    r#"<IsReady level="{=}" _failureIf="level &lt; 0"/>"#,
    r#"<Wait name="pause"/>"#,
    r#"<Sleep msec="40"/>"#,
    r#"<Script code="a := 1; b := a + 2"/>"#,
];

const DECORATORS: [&str; 8] = [
    r#"<Inverter>"#,
    r#"<ForceSuccess _while="ok">"#,
    r#"<Repeat num_cycles="4">"#,
    r#"<RetryUntilSuccessful num_attempts="-1">"#,
    r#"<Timeout msec="1500">"#,
    r#"<Delay delay_msec="10">"#,
    r#"<Cooldown cooldown_msec="300">"#,
    r#"<RunOnce then_skip="false">"#,
];

const CONTROLS: [&str; 7] = [
    r#"<Sequence>"#,
    r#"<Fallback name="choose">"#,
    r#"<ReactiveSequence>"#,
    r#"<ReactiveFallback>"#,
    r#"<SequenceWithMemory>"#,
    r#"<Parallel success_count="1" failure_count="1">"#,
    r#"<ParallelAll max_failures="2">"#,
];

impl Node {
    fn xml(&self, out: &mut String) {
        match self {
            Node::Leaf(text) => out.push_str(text),
            Node::Decorator(open, child) => {
                out.push_str(open);
                child.xml(out);
                out.push_str(&close(open));
            }
            Node::Control(open, children) => {
                out.push_str(open);
                for c in children {
                    c.xml(out);
                }
                out.push_str(&close(open));
            }
            Node::SubTree(attrs) => {
                // Numbered: two SubTrees of one name in a tree are refused, as in
                // BehaviorTree.CPP.
                let n = out.matches("<SubTree").count();
                let attrs = attrs.replace(r#"name="inner""#, &format!(r#"name="inner{n}""#));
                out.push_str(&format!("<SubTree ID=\"Sub\" {attrs}/>"));
            }
        }
    }
}

fn close(open: &str) -> String {
    let tag = open[1..].split([' ', '>']).next().unwrap();
    format!("</{tag}>")
}

fn node() -> impl Strategy<Value = Node> {
    let leaf = prop_oneof![
        4 => prop::sample::select(&LEAVES[..]).prop_map(Node::Leaf),
        1 => prop::sample::select(vec![
            String::new(),
            r#"target="{goal}""#.to_string(),
            r#"name="inner" target="1;2" _autoremap="true""#.to_string(),
        ])
        .prop_map(Node::SubTree),
    ];
    leaf.prop_recursive(5, 40, 4, |inner| {
        prop_oneof![
            (prop::sample::select(&DECORATORS[..]), inner.clone())
                .prop_map(|(d, c)| Node::Decorator(d, Box::new(c))),
            (
                prop::sample::select(&CONTROLS[..]),
                prop::collection::vec(inner, 2..4)
            )
                .prop_map(|(c, cs)| Node::Control(c, cs)),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_trees_load_back_the_same(main in node()) {
        let mut body = String::new();
        main.xml(&mut body);
        let text = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">{body}</BehaviorTree>
               <BehaviorTree ID="Sub"><Sequence><MoveTo goal="{{target}}"/><Wait/></Sequence></BehaviorTree>
               </root>"#
        );
        round_trip(&text);
    }
}

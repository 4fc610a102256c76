//! Built-in nodes read their ports as BehaviorTree.CPP's do: a literal once, when the tree
//! is loaded; `{key}` from the blackboard each time the node reads it (Repeat, Retry,
//! Parallel, ParallelAll and RunOnce at every tick, Timeout, Delay and Sleep at every tick
//! too, TryCatch's `catch_on_halt` when halted), converting numbers as BehaviorTree.CPP's
//! `Any` does. Counts of ticks are asserted exactly.

use std::time::Duration;

use neurotree::xml::{write_xml, SaveOptions};
use neurotree::{Clock, ManualClock, PortSpec, Registry, Status, TickError, Tree, XmlLoader};

/// Counts the calls of `Step`, and reads an `i32` port in `ReadI32`.
#[derive(Default)]
struct Ctx {
    steps: u32,
    read: Vec<Result<i32, String>>,
}

fn registry() -> Registry<Ctx> {
    let mut r = Registry::<Ctx>::new();
    r.register_action("Step", vec![], |h| {
        h.ctx_mut().steps += 1;
        Status::Success
    })
    .unwrap();
    r.register_action("Fail", vec![], |h| {
        h.ctx_mut().steps += 1;
        Status::Failure
    })
    .unwrap();
    r.register_action("ReadI32", vec![PortSpec::input::<i32>("n")], |h| {
        let read = h.input::<i32>("n").map_err(|e| e.to_string());
        let ok = read.is_ok();
        h.ctx_mut().read.push(read);
        Status::from(ok)
    })
    .unwrap();
    r
}

fn tree(xml: &str) -> Tree<Ctx> {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader.load_str(xml, "ports.xml").unwrap();
    Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new())
}

fn main_tree(body: &str) -> String {
    format!(r#"<root BTCPP_format="4"><BehaviorTree ID="Main">{body}</BehaviorTree></root>"#)
}

#[test]
fn repeat_reads_its_count_from_the_blackboard_like_the_tutorial() {
    // BehaviorTree.CPP's tutorial writes <Repeat num_cycles="{wp_size}">.
    let mut t = tree(&main_tree(
        r#"<Sequence>
             <Script code="wp_size := 3"/>
             <Repeat num_cycles="{wp_size}"><Step/></Repeat>
           </Sequence>"#,
    ));
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 3);
    // Another tree, whose entry has another number type, then text.
    let mut t2 = tree(&main_tree(
        r#"<Repeat num_cycles="{wp_size}"><Step/></Repeat>"#,
    ));
    t2.blackboard_mut().set("wp_size", 5_u8).unwrap();
    let mut ctx = Ctx::default();
    assert_eq!(t2.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 5);
    // A text entry converts too.
    t2.blackboard_mut().replace_in(
        neurotree::ScopeId::ROOT,
        "wp_size",
        String::from("2"),
        Duration::ZERO,
    );
    let mut ctx = Ctx::default();
    assert_eq!(t2.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 2);
}

#[test]
fn retry_reads_its_count_again_after_each_failure() {
    let mut t = tree(&main_tree(
        r#"<RetryUntilSuccessful num_attempts="{n}"><Fail/></RetryUntilSuccessful>"#,
    ));
    t.blackboard_mut().set("n", 4_i32).unwrap();
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Failure));
    assert_eq!(ctx.steps, 4);
}

#[test]
fn an_unreadable_or_out_of_range_entry_is_an_error_naming_node_and_port() {
    let mut t = tree(&main_tree(
        r#"<Repeat name="again" num_cycles="{n}"><Step/></Repeat>"#,
    ));
    let mut ctx = Ctx::default();
    // Declared by the port but never written.
    let e = t.tick_once(&mut ctx).unwrap_err();
    assert!(
        matches!(&e, TickError::Node { path, message, .. }
            if path == "again" && message.contains("num_cycles")),
        "{e}"
    );
    // Never a wrap.
    t.blackboard_mut().set("n", 3_000_000_000_i64).unwrap();
    let e = t.tick_once(&mut ctx).unwrap_err();
    assert_eq!(
        e.to_string(),
        "again (#0): port `num_cycles`: the entry's value 3000000000 does not fit i32"
    );
    assert_eq!(ctx.steps, 0);
}

#[test]
fn a_scripts_numbers_read_as_any_integer_type() {
    let mut t = tree(&main_tree(
        r#"<Sequence>
             <Script code="n := 3"/>
             <ReadI32 n="{n}"/>
             <Script code="n := 4000000000"/>
             <ReadI32 n="{n}"/>
           </Sequence>"#,
    ));
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Failure));
    assert_eq!(
        ctx.read,
        [
            Ok(3),
            Err("port `n`: the entry's value 4000000000 does not fit i32".into())
        ]
    );
}

#[test]
fn timeout_delay_and_sleep_read_milliseconds_from_entries() {
    let clock = ManualClock::new();
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            &main_tree(
                r#"<Sequence>
                     <Sleep msec="{nap}"/>
                     <Delay delay_msec="{wait}"><Step/></Delay>
                   </Sequence>"#,
            ),
            "ports.xml",
        )
        .unwrap();
    let mut t = Tree::with_clock(loader.build_main().unwrap().into(), clock.clone());
    t.blackboard_mut().set("nap", 200_i64).unwrap();
    t.blackboard_mut().set("wait", 100_u32).unwrap();
    let mut ctx = Ctx::default();
    let mut ticks = 0;
    while t.tick_once(&mut ctx) == Ok(Status::Running) {
        clock.advance(Duration::from_millis(50));
        ticks += 1;
    }
    // 200 ms of sleep, then 100 ms of delay, in steps of 50 ms.
    assert_eq!((ticks, ctx.steps), (6, 1));
    assert_eq!(clock.now(), Duration::from_millis(300));
}

#[test]
fn parallel_thresholds_from_entries_are_checked_at_each_tick() {
    let mut t = tree(&main_tree(
        r#"<Parallel name="par" success_count="{need}" failure_count="1">
             <Step/><Step/>
           </Parallel>"#,
    ));
    t.blackboard_mut().set("need", 2_i64).unwrap();
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 2);
    // More than its children: BehaviorTree.CPP throws "can never succeed" at the tick.
    t.blackboard_mut().set("need", 3_i64).unwrap();
    let e = t.tick_once(&mut ctx).unwrap_err();
    assert_eq!(
        e.to_string(),
        "par (#0): its threshold 3 is more than its 2 children: it can never succeed"
    );
}

#[test]
fn a_saved_tree_keeps_its_entry_bindings() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            &main_tree(r#"<Repeat num_cycles="{n}"><Step/></Repeat>"#),
            "ports.xml",
        )
        .unwrap();
    let bp = loader.build_main().unwrap();
    let xml = write_xml(&bp, &r, &SaveOptions::default());
    assert!(xml.contains(r#"num_cycles="{n}""#), "{xml}");
    let mut again = XmlLoader::new(&r);
    again.load_str(&xml, "saved.xml").unwrap();
    let mut t = Tree::with_clock(again.build_main().unwrap().into(), ManualClock::new());
    t.blackboard_mut().set("n", 2_i64).unwrap();
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 2);
}

#[test]
fn precondition_reads_if_and_else_from_entries() {
    let mut t = tree(&main_tree(
        r#"<Precondition if="{check}" else="{otherwise}"><Step/></Precondition>"#,
    ));
    let bb = t.blackboard_mut();
    bb.set("check", String::from("go == 1")).unwrap();
    bb.set("otherwise", String::from("SKIPPED")).unwrap();
    bb.set("go", 0_i64).unwrap();
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Err(TickError::RootSkipped));
    t.blackboard_mut().set("go", 1_i64).unwrap();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    // A new script in the entry is the one checked next.
    t.blackboard_mut()
        .set("check", String::from("go == 2"))
        .unwrap();
    t.blackboard_mut()
        .set("otherwise", String::from("FAILURE"))
        .unwrap();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Failure));
    assert_eq!(ctx.steps, 1);
}

#[test]
fn a_loops_if_empty_is_read_from_its_entry_when_the_queue_is_empty() {
    let mut t = tree(&main_tree(
        r#"<LoopInt queue="" value="{v}" if_empty="{when_empty}"><Step/></LoopInt>"#,
    ));
    t.blackboard_mut()
        .set("when_empty", String::from("FAILURE"))
        .unwrap();
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Failure));
    t.blackboard_mut()
        .set("when_empty", String::from("SUCCESS"))
        .unwrap();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 0);
}

#[test]
fn a_models_subtree_ports_give_defaults_and_mandatory_ports() {
    let file = |subtree: &str| {
        format!(
            r#"<root BTCPP_format="4" main_tree_to_execute="Main">
                 <BehaviorTree ID="Main">{subtree}</BehaviorTree>
                 <BehaviorTree ID="Walk">
                   <Repeat num_cycles="{{steps}}"><Step/></Repeat>
                 </BehaviorTree>
                 <TreeNodesModel>
                   <SubTree ID="Walk">
                     <input_port name="steps" default="2"/>
                     <input_port name="target"/>
                   </SubTree>
                 </TreeNodesModel>
               </root>"#
        )
    };
    let r = registry();
    // `steps` is left out: the model's default applies; `target` is mandatory.
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(&file(r#"<SubTree ID="Walk" target="{goal}"/>"#), "walk.xml")
        .unwrap();
    let mut t = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.steps, 2);
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(&file(r#"<SubTree ID="Walk"/>"#), "walk.xml")
        .unwrap();
    let e = loader.build_main().unwrap_err();
    assert_eq!(
        e.to_string(),
        "walk.xml:2:42: error: the TreeNodesModel declares port `target` of SubTree `Walk` \
         with no default, so it is mandatory; remap it here (target=\"{key}\") or give it a value"
    );
    // Autoremapping takes the ports from the parent instead, as in BehaviorTree.CPP.
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            &file(r#"<SubTree ID="Walk" _autoremap="true"/>"#),
            "walk.xml",
        )
        .unwrap();
    assert!(loader.build_main().is_ok());
}

#[test]
fn a_number_given_to_a_subtree_is_a_number_its_scripts_add_to() {
    let r = registry();
    let mut loader = XmlLoader::new(&r);
    loader
        .load_str(
            r#"<root BTCPP_format="4" main_tree_to_execute="Main">
                 <BehaviorTree ID="Main"><SubTree ID="Count" n="3" label="x"/></BehaviorTree>
                 <BehaviorTree ID="Count">
                   <Sequence>
                     <Script code="m := n + 1; tag := label .. '!'"/>
                     <ReadI32 n="{m}"/>
                     <ReadI32 n="{n}"/>
                   </Sequence>
                 </BehaviorTree>
               </root>"#,
            "count.xml",
        )
        .unwrap();
    let mut t = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
    let mut ctx = Ctx::default();
    assert_eq!(t.tick_once(&mut ctx), Ok(Status::Success));
    assert_eq!(ctx.read, [Ok(4), Ok(3)]);
}

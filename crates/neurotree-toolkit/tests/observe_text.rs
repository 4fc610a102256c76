//! The console logger and the JSON-lines trace, line for line, on the scripted patrol
//! (see `support/patrol.rs` for what each tick does).

use crate::patrol;

use neurotree::observe::{ConsoleLogger, JsonlTrace};

#[test]
fn console_logger_writes_one_plain_line_per_change() {
    let (mut tree, clock) = patrol::start();
    let log = ConsoleLogger::new(tree.blueprint(), Vec::new());
    tree.set_observer(log.clone());
    patrol::run(&mut tree, &clock);
    log.flush().unwrap();
    let text = log.with_writer(|out| String::from_utf8(out.clone()).unwrap());
    let expected = [
        "[0.100s] patrol IDLE -> RUNNING",
        "[0.100s] patrol/battery_ok IDLE -> SUCCESS",
        "[0.100s] patrol/route IDLE -> RUNNING",
        "[0.100s] patrol/route/once IDLE -> RUNNING",
        "[0.100s] patrol/route/once/wave IDLE -> SUCCESS",
        "[0.100s] patrol/route/once/wave SUCCESS -> IDLE",
        "[0.100s] patrol/route/once RUNNING -> SUCCESS",
        "[0.100s] patrol/route/move IDLE -> RUNNING",
        "[0.100s] patrol/battery_ok SUCCESS -> IDLE",
        "[0.200s] patrol/battery_ok IDLE -> FAILURE",
        "[0.200s] patrol/battery_ok FAILURE -> IDLE",
        "[0.200s] patrol/route/once SUCCESS -> IDLE",
        "[0.200s] patrol/route/move RUNNING -> IDLE",
        "[0.200s] patrol/route RUNNING -> IDLE",
        "[0.200s] patrol RUNNING -> FAILURE",
        "[0.200s] patrol FAILURE -> IDLE",
        "[0.300s] patrol IDLE -> RUNNING",
        "[0.300s] patrol/battery_ok IDLE -> SUCCESS",
        "[0.300s] patrol/route IDLE -> RUNNING",
        "[0.300s] patrol/route/move IDLE -> RUNNING",
        "[0.300s] patrol/battery_ok SUCCESS -> IDLE",
        "[0.400s] patrol/battery_ok IDLE -> SUCCESS",
        "[0.400s] patrol/battery_ok SUCCESS -> IDLE",
        "[0.500s] patrol/battery_ok IDLE -> SUCCESS",
        "[0.500s] patrol/route/move RUNNING -> SUCCESS",
        "[0.500s] patrol/route/scan IDLE -> SUCCESS",
        "[0.500s] patrol/route/move SUCCESS -> IDLE",
        "[0.500s] patrol/route/scan SUCCESS -> IDLE",
        "[0.500s] patrol/route RUNNING -> SUCCESS",
        "[0.500s] patrol/battery_ok SUCCESS -> IDLE",
        "[0.500s] patrol/route SUCCESS -> IDLE",
        "[0.500s] patrol RUNNING -> SUCCESS",
        "[0.500s] patrol SUCCESS -> IDLE",
    ];
    assert_eq!(text.lines().collect::<Vec<_>>(), expected);
    assert!(text.ends_with('\n'));
}

#[test]
fn jsonl_trace_writes_changes_and_tick_ends() {
    let (mut tree, clock) = patrol::start();
    let trace = JsonlTrace::new(tree.blueprint(), Vec::new());
    tree.set_observer(trace.clone());
    patrol::run(&mut tree, &clock);
    trace.flush().unwrap();
    let text = trace.with_writer(|out| String::from_utf8(out.clone()).unwrap());
    let expected = [
        r#"{"tick":1,"time_us":100000,"id":0,"node":"patrol","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":1,"time_us":100000,"id":1,"node":"patrol/battery_ok","from":"IDLE","to":"SUCCESS"}"#,
        r#"{"tick":1,"time_us":100000,"id":2,"node":"patrol/route","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":1,"time_us":100000,"id":3,"node":"patrol/route/once","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":1,"time_us":100000,"id":4,"node":"patrol/route/once/wave","from":"IDLE","to":"SUCCESS"}"#,
        r#"{"tick":1,"time_us":100000,"id":4,"node":"patrol/route/once/wave","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":1,"time_us":100000,"id":3,"node":"patrol/route/once","from":"RUNNING","to":"SUCCESS"}"#,
        r#"{"tick":1,"time_us":100000,"id":5,"node":"patrol/route/move","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":1,"time_us":100000,"id":1,"node":"patrol/battery_ok","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":1,"time_us":100000,"status":"RUNNING"}"#,
        r#"{"tick":2,"time_us":200000,"id":1,"node":"patrol/battery_ok","from":"IDLE","to":"FAILURE"}"#,
        r#"{"tick":2,"time_us":200000,"id":1,"node":"patrol/battery_ok","from":"FAILURE","to":"IDLE"}"#,
        r#"{"tick":2,"time_us":200000,"id":3,"node":"patrol/route/once","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":2,"time_us":200000,"id":5,"node":"patrol/route/move","from":"RUNNING","to":"IDLE"}"#,
        r#"{"tick":2,"time_us":200000,"id":2,"node":"patrol/route","from":"RUNNING","to":"IDLE"}"#,
        r#"{"tick":2,"time_us":200000,"id":0,"node":"patrol","from":"RUNNING","to":"FAILURE"}"#,
        r#"{"tick":2,"time_us":200000,"id":0,"node":"patrol","from":"FAILURE","to":"IDLE"}"#,
        r#"{"tick":2,"time_us":200000,"status":"FAILURE"}"#,
        r#"{"tick":3,"time_us":300000,"id":0,"node":"patrol","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":3,"time_us":300000,"id":1,"node":"patrol/battery_ok","from":"IDLE","to":"SUCCESS"}"#,
        r#"{"tick":3,"time_us":300000,"id":2,"node":"patrol/route","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":3,"time_us":300000,"id":5,"node":"patrol/route/move","from":"IDLE","to":"RUNNING"}"#,
        r#"{"tick":3,"time_us":300000,"id":1,"node":"patrol/battery_ok","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":3,"time_us":300000,"status":"RUNNING"}"#,
        r#"{"tick":4,"time_us":400000,"id":1,"node":"patrol/battery_ok","from":"IDLE","to":"SUCCESS"}"#,
        r#"{"tick":4,"time_us":400000,"id":1,"node":"patrol/battery_ok","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":4,"time_us":400000,"status":"RUNNING"}"#,
        r#"{"tick":5,"time_us":500000,"id":1,"node":"patrol/battery_ok","from":"IDLE","to":"SUCCESS"}"#,
        r#"{"tick":5,"time_us":500000,"id":5,"node":"patrol/route/move","from":"RUNNING","to":"SUCCESS"}"#,
        r#"{"tick":5,"time_us":500000,"id":6,"node":"patrol/route/scan","from":"IDLE","to":"SUCCESS"}"#,
        r#"{"tick":5,"time_us":500000,"id":5,"node":"patrol/route/move","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":5,"time_us":500000,"id":6,"node":"patrol/route/scan","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":5,"time_us":500000,"id":2,"node":"patrol/route","from":"RUNNING","to":"SUCCESS"}"#,
        r#"{"tick":5,"time_us":500000,"id":1,"node":"patrol/battery_ok","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":5,"time_us":500000,"id":2,"node":"patrol/route","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":5,"time_us":500000,"id":0,"node":"patrol","from":"RUNNING","to":"SUCCESS"}"#,
        r#"{"tick":5,"time_us":500000,"id":0,"node":"patrol","from":"SUCCESS","to":"IDLE"}"#,
        r#"{"tick":5,"time_us":500000,"status":"SUCCESS"}"#,
    ];
    assert_eq!(text.lines().collect::<Vec<_>>(), expected);
    assert!(text.ends_with('\n'));
}

#[test]
fn jsonl_changes_between_ticks_carry_the_last_tick() {
    let (mut tree, clock) = patrol::start();
    let trace = JsonlTrace::new(tree.blueprint(), Vec::new());
    tree.set_observer(trace.clone());
    let mut world = patrol::World {
        battery_ok: true,
        halts: 0,
    };
    clock.advance(std::time::Duration::from_millis(100));
    assert_eq!(tree.tick_once(&mut world), Ok(neurotree::Status::Running));
    trace.with_writer(Vec::clear);
    clock.advance(std::time::Duration::from_millis(50));
    tree.halt(&mut world);
    assert_eq!(world.halts, 1);
    let text = trace.with_writer(|out| String::from_utf8(out.clone()).unwrap());
    assert_eq!(
        text.lines().collect::<Vec<_>>(),
        [
            r#"{"tick":1,"time_us":150000,"id":3,"node":"patrol/route/once","from":"SUCCESS","to":"IDLE"}"#,
            r#"{"tick":1,"time_us":150000,"id":5,"node":"patrol/route/move","from":"RUNNING","to":"IDLE"}"#,
            r#"{"tick":1,"time_us":150000,"id":2,"node":"patrol/route","from":"RUNNING","to":"IDLE"}"#,
            r#"{"tick":1,"time_us":150000,"id":0,"node":"patrol","from":"RUNNING","to":"IDLE"}"#,
        ]
    );
}

#[test]
fn jsonl_carries_a_reason_on_the_change_to_failure() {
    struct Blocked;
    impl neurotree::Action<()> for Blocked {
        fn tick(&self, h: &mut neurotree::Handle<'_, ()>) -> neurotree::Status {
            h.fail_with(106, "blocked")
        }
    }
    let bp = neurotree::Builder::<()>::new()
        .action_node("follow", Blocked)
        .build_shared()
        .unwrap();
    let mut tree = neurotree::Tree::with_clock(bp, neurotree::ManualClock::new());
    let trace = JsonlTrace::new(tree.blueprint(), Vec::new());
    tree.set_observer(trace.clone());
    assert_eq!(tree.tick_once(&mut ()), Ok(neurotree::Status::Failure));
    let text = trace.with_writer(|out| String::from_utf8(out.clone()).unwrap());
    assert_eq!(
        text.lines().collect::<Vec<_>>(),
        [
            r#"{"tick":1,"time_us":0,"id":0,"node":"follow","from":"IDLE","to":"FAILURE","reason":"blocked","code":106}"#,
            r#"{"tick":1,"time_us":0,"id":0,"node":"follow","from":"FAILURE","to":"IDLE"}"#,
            r#"{"tick":1,"time_us":0,"status":"FAILURE"}"#,
        ]
    );
}

#[test]
fn console_logger_ends_a_failure_with_its_reason() {
    struct Blocked;
    impl neurotree::Action<()> for Blocked {
        fn tick(&self, h: &mut neurotree::Handle<'_, ()>) -> neurotree::Status {
            h.fail_with(106, "blocked")
        }
    }
    let bp = neurotree::Builder::<()>::new()
        .fallback("go", |f| {
            f.always_failure("check")
                .action_node("follow_path", Blocked)
        })
        .build_shared()
        .unwrap();
    let clock = neurotree::ManualClock::new();
    let mut tree = neurotree::Tree::with_clock(bp, clock.clone());
    let log = ConsoleLogger::new(tree.blueprint(), Vec::new());
    tree.set_observer(log.clone());
    clock.advance(std::time::Duration::from_millis(100));
    assert_eq!(tree.tick_once(&mut ()), Ok(neurotree::Status::Failure));
    let text = log.with_writer(|out| String::from_utf8(out.clone()).unwrap());
    // Only the change the reason was given for carries it: not the Fallback's, nor a
    // failure without a reason.
    assert_eq!(
        text.lines().collect::<Vec<_>>(),
        [
            "[0.100s] go IDLE -> RUNNING",
            "[0.100s] go/check IDLE -> FAILURE",
            "[0.100s] go/follow_path IDLE -> FAILURE: blocked (error 106)",
            "[0.100s] go/check FAILURE -> IDLE",
            "[0.100s] go/follow_path FAILURE -> IDLE",
            "[0.100s] go RUNNING -> FAILURE",
            "[0.100s] go FAILURE -> IDLE",
        ]
    );
}

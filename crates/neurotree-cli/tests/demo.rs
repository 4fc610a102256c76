//! `neurotree demo`'s engine: the default run, its frames, other goals, seeds and trees.

use std::path::PathBuf;
use std::time::Duration;

use neurotree::robotics::Pose2D;
use neurotree::sim::{Cell, TimedObstacle};
use neurotree::Status;
use neurotree_cli::demo::{
    DemoConfig, DemoError, DemoRun, DemoSummary, Layout, DEFAULT_GOAL, NAVIGATE_TO_POSE_XML,
};

const NAVIGATOR: &str = "navigate_to_pose_w_replanning_and_recovery.xml";

#[test]
fn the_embedded_navigator_is_the_file_in_the_repository() {
    let file = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../corpus/nav2")
            .join(NAVIGATOR),
    )
    .unwrap();
    assert_eq!(file, NAVIGATE_TO_POSE_XML);
}

fn demo(config: DemoConfig) -> DemoRun {
    DemoRun::new(&config).unwrap()
}

fn runs(list: &[(&str, u32)]) -> Vec<(String, u32)> {
    list.iter().map(|(l, n)| (l.to_string(), *n)).collect()
}

#[test]
fn the_default_run_meets_the_obstacle_recovers_and_arrives() {
    let mut run = demo(DemoConfig::default());
    assert_eq!(
        run.scenario().obstacle,
        Some(
            TimedObstacle::new(Cell::new(22, 5), Duration::from_millis(23_050))
                .until(Duration::from_millis(26_050))
        )
    );
    let summary = run.run_to_end();
    let distance = summary.distance;
    let pose = summary.pose;
    assert!((distance - 40.9).abs() < 0.005, "{distance}");
    assert!(pose.distance(&DEFAULT_GOAL) <= 0.25, "{pose:?}");
    assert_eq!(
        summary,
        DemoSummary {
            outcome: Status::Success,
            ticks: 430,
            time: Duration::from_millis(42_900),
            distance,
            replans: 38,
            recoveries: 4,
            recovery_runs: runs(&[
                ("ComputePathToPose recovery", 0),
                ("FollowPath recovery", 2),
                ("ClearingActions", 1),
                ("Spin", 1),
                ("Wait", 0),
                ("BackUp", 0),
            ]),
            pose,
            goal: DEFAULT_GOAL,
            error: None,
            error_codes: vec![],
            within_tolerance: None,
        }
    );
    assert_eq!(
        summary.to_string(),
        "Summary\n  \
         outcome     SUCCESS\n  \
         ticks       430\n  \
         time        42.9 s\n  \
         distance    40.90 m\n  \
         replans     38\n  \
         recoveries  4 (FollowPath recovery 2, ClearingActions 1, Spin 1)\n  \
         robot       (36.35, 1.50), 0.15 m from the goal (36.50, 1.50)\n\
         navigation succeeded\n"
    );
    // Over: more ticks change nothing.
    assert_eq!(run.tick(), Status::Success);
    assert_eq!(run.ticks(), 430);
}

#[test]
fn every_frame_is_the_same_on_every_run() {
    let frames = |layout| {
        let mut run = demo(DemoConfig::default());
        let mut frames = Vec::new();
        while !run.is_over() {
            run.tick();
            frames.push(run.frame(layout));
        }
        frames
    };
    let stacked = frames(Layout::Stacked);
    assert_eq!(stacked.len(), 430);
    assert_eq!(stacked, frames(Layout::Stacked));
    // Plain text: no escape sequences, no tabs.
    assert!(stacked.iter().all(|f| !f.contains(['\x1b', '\t'])));
    // The tree of the side-by-side layout starts in the same column on every line.
    for frame in frames(Layout::SideBySide).iter().step_by(37) {
        for line in frame.lines().take(20) {
            assert_eq!(line.chars().nth(42), Some(' '), "{line}");
            assert_ne!(line.chars().nth(43), Some(' '), "{line}");
        }
    }
}

#[test]
fn the_first_frame_shows_the_plan_the_goal_and_the_statuses() {
    let mut run = demo(DemoConfig::default());
    run.tick();
    let frame = run.frame(Layout::Stacked);
    let top: Vec<&str> = frame.lines().take(22).collect();
    assert_eq!(
        top,
        [
            "tick 1     t =   0.0 s   RUNNING",
            "robot (1.50, 13.50)  heading 0°",
            "motion moving",
            "0.0 m   0 replans   0 recoveries",
            "",
            "########################################",
            "#R.........#...........................#",
            "#.*........#.....................##....#",
            "#..******..#.....######..........##....#",
            "#....###.*.#...........................#",
            "#....###..***..........................#",
            "#..........#.*....######...............#",
            "#..........#..*........................#",
            "#..........#...*.............######....#",
            "#....###...#....********...............#",
            "#....###...#.....######.*****..........#",
            "#..........................#.*.........#",
            "#..........#...............#..*........#",
            "#..........#...............#...*****G..#",
            "########################################",
            "  > ComputePathToPose: a path of 36 poses, 40.0 m",
            "",
        ]
    );
    assert!(frame.contains("\n│   └── [R] FollowPath (RecoveryNode)\n"));
    assert!(frame.contains("\n│       ├── [R] FollowPath (StatefulAction)\n"));
    let ascii = demo(DemoConfig {
        unicode: false,
        ..DemoConfig::default()
    });
    assert!(ascii
        .frame(Layout::Stacked)
        .contains("\n\\-- [ ] Sequence\n"));
    assert!(run.intro().starts_with(
        "NeuroTree demo: Nav2's navigator drives a simulated robot\n\
         tree      corpus/nav2/navigate_to_pose_w_replanning_and_recovery.xml\n\
         goal      (36.50, 1.50) m\n\
         seed      0: an obstacle steps into cell (22, 5) at 23.1 s, until 26.1 s\n"
    ));
}

#[test]
fn the_story_is_told_in_the_notes() {
    let mut run = demo(DemoConfig::default());
    let mut notes = Vec::new();
    while !run.is_over() {
        run.tick();
        notes.extend(run.notes().iter().cloned());
    }
    let blocked = "FollowPath failed: blocked (error 106)";
    let told: Vec<&str> = notes
        .iter()
        .map(String::as_str)
        .filter(|n| !n.starts_with("ComputePathToPose: "))
        .collect();
    assert_eq!(
        told,
        [
            "an obstacle appears in cell (22, 5)",
            blocked,
            "recovery: FollowPath recovery",
            "ClearLocalCostmap-Context: cleared the local costmap",
            blocked,
            "recovery: ClearingActions",
            "ClearLocalCostmap-Subtree: cleared the local costmap",
            "ClearGlobalCostmap-Subtree: cleared the global costmap",
            blocked,
            "recovery: FollowPath recovery",
            "ClearLocalCostmap-Context: cleared the local costmap",
            blocked,
            "recovery: Spin",
            "Spin: done",
            "the obstacle in cell (22, 5) is gone",
        ]
    );
}

#[test]
fn an_unreachable_goal_fails_at_once() {
    for goal in [Pose2D::new(0.5, 0.5, 0.0), Pose2D::new(80.0, 3.0, 0.0)] {
        let mut run = demo(DemoConfig {
            goal,
            ..DemoConfig::default()
        });
        assert_eq!(run.scenario().obstacle, None);
        let summary = run.run_to_end();
        assert_eq!(
            (summary.outcome, summary.ticks, summary.recoveries),
            (Status::Failure, 1, 1)
        );
        assert_eq!(summary.distance, 0.0);
        assert!(summary.to_string().contains("  outcome     FAILURE\n"));
        // Nav2's planner error: the goal on a wall, or outside the map.
        let code = if goal.x > 40.0 { 204 } else { 206 };
        assert_eq!(
            summary
                .error_codes
                .iter()
                .map(|(entry, code, _)| (entry.as_str(), *code))
                .collect::<Vec<_>>(),
            [("compute_path_error_code", code)]
        );
        assert!(summary.to_string().ends_with("navigation failed\n"));
    }
}

#[test]
fn seeds_vary_the_obstacle() {
    let outcomes: Vec<(Cell, u32, u32, u32)> = (1..5)
        .map(|seed| {
            let mut run = demo(DemoConfig {
                seed,
                ..DemoConfig::default()
            });
            let cell = run.scenario().obstacle.map(|o| o.cell).unwrap();
            let s = run.run_to_end();
            assert_eq!(s.outcome, Status::Success, "seed {seed}");
            (cell, s.ticks, s.replans, s.recoveries)
        })
        .collect();
    assert_eq!(
        outcomes,
        [
            (Cell::new(24, 4), 416, 37, 4),
            (Cell::new(9, 10), 410, 37, 1),
            (Cell::new(22, 5), 430, 38, 4),
            (Cell::new(7, 11), 418, 38, 1),
        ]
    );
}

#[test]
fn another_tree_file_drives_the_same_world() {
    let dir = std::env::temp_dir().join(format!("neurotree-nav2-demo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let simple = dir.join("simple.xml");
    std::fs::write(
        &simple,
        r#"<root BTCPP_format="4">
  <BehaviorTree ID="Simple">
    <Sequence>
      <ComputePathToPose goal="{goal}" path="{path}"/>
      <FollowPath path="{path}"/>
    </Sequence>
  </BehaviorTree>
</root>"#,
    )
    .unwrap();
    let mut run = demo(DemoConfig {
        tree: Some(simple.clone()),
        seed: 2,
        ..DemoConfig::default()
    });
    // Planned once, it drives into the obstacle and gives up.
    let summary = run.run_to_end();
    assert_eq!(
        (summary.outcome, summary.replans, summary.recoveries),
        (Status::Failure, 0, 0)
    );
    assert!(run
        .intro()
        .contains(&format!("tree      {}\n", simple.display())));

    let broken = dir.join("broken.xml");
    std::fs::write(
        &broken,
        "<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"T\">\n  <Spin spin_dist=\"far\"/>\n</BehaviorTree>\n</root>\n",
    )
    .unwrap();
    let Err(DemoError::Load(error)) = DemoRun::new(&DemoConfig {
        tree: Some(broken.clone()),
        ..DemoConfig::default()
    }) else {
        panic!("a bad literal is a load error");
    };
    assert_eq!((error.line, error.col), (3, 3));
    assert!(
        error
            .to_string()
            .starts_with(&format!("{}:3:3: error: ", broken.display())),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `neurotree demo ARGS --fast` from the repository's root: exit code, standard output,
/// standard error.
fn demo_cli(args: &[&str]) -> (i32, String, String) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_neurotree"))
        .current_dir(root)
        .arg("demo")
        .args(args)
        .arg("--fast")
        .output()
        .unwrap();
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    (
        out.status.code().unwrap(),
        text(out.stdout),
        text(out.stderr),
    )
}

fn last_line(text: &str) -> &str {
    text.trim_end().lines().last().unwrap_or("")
}

/// Nav2's default navigator trees that run on the simulated robot, with the extra flags
/// they need (a tree that never ends is given a duration).
const RUNNING_TREES: [(&str, &[&str]); 16] = [
    ("follow_point.xml", &["--duration", "60"]),
    ("navigate_on_route_graph_w_recovery.xml", &[]),
    (
        "navigate_w_routing_global_planning_and_control_w_recovery.xml",
        &[],
    ),
    // Starting on its dock, charging and facing the way it docks: it undocks first.
    (
        "opennav_docking_bt__application_example.xml",
        &["--battery", "90", "--heading", "180"],
    ),
    (
        "nav_to_pose_with_consistent_replanning_and_if_path_becomes_invalid.xml",
        &[],
    ),
    ("navigate_through_poses_w_replanning_and_recovery.xml", &[]),
    ("navigate_to_pose_w_bounds_check.xml", &[]),
    ("navigate_to_pose_w_replanning_and_recovery.xml", &[]),
    (
        "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml",
        &[],
    ),
    (
        "navigate_w_recovery_and_replanning_only_if_path_becomes_invalid.xml",
        &[],
    ),
    ("navigate_w_replanning_distance.xml", &[]),
    ("navigate_w_replanning_only_if_goal_is_updated.xml", &[]),
    (
        "navigate_w_replanning_only_if_path_becomes_invalid.xml",
        &[],
    ),
    ("navigate_w_replanning_speed.xml", &[]),
    ("navigate_w_replanning_time.xml", &[]),
    // Its square turns left: from the corner the robot starts in, facing south.
    ("odometry_calibration.xml", &["--heading", "-90"]),
];

#[test]
fn every_tree_of_nav2_in_the_corpus_is_run() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../corpus/nav2");
    let mut trees: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".xml") && name != "nav2_tree_nodes.xml")
        .collect();
    trees.sort();
    let mut running: Vec<&str> = RUNNING_TREES.iter().map(|(t, _)| *t).collect();
    running.sort_unstable();
    assert_eq!(trees, running);
}

#[test]
fn each_default_tree_reaches_the_goal_when_nothing_blocks_it() {
    for (tree, extra) in RUNNING_TREES {
        let path = format!("corpus/nav2/{tree}");
        let mut args = vec!["--tree", path.as_str(), "--no-obstacle"];
        args.extend_from_slice(extra);
        let (code, out, err) = demo_cli(&args);
        assert_eq!(
            (code, last_line(&out)),
            (0, "navigation succeeded"),
            "{tree}\n{out}{err}"
        );
        // --fast draws the last frame only.
        assert_eq!(out.matches("\ntick ").count(), 1, "{tree}");
        assert!(out.contains("from the goal (36.50, 1.50)"), "{tree}");
    }
}

#[test]
fn the_obstacle_stops_the_trees_without_recoveries_with_nav2s_error_code() {
    let unhindered = [
        "navigate_through_poses_w_replanning_and_recovery.xml",
        "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml",
        "nav_to_pose_with_consistent_replanning_and_if_path_becomes_invalid.xml",
        "navigate_to_pose_w_replanning_and_recovery.xml",
        "navigate_w_recovery_and_replanning_only_if_path_becomes_invalid.xml",
        // Replanning every metre, it plans around the obstacle before it gets there.
        "navigate_w_replanning_distance.xml",
        // Its square is far from the obstacle.
        "odometry_calibration.xml",
        // Their routes go through the upper door, away from the obstacle.
        "navigate_on_route_graph_w_recovery.xml",
        "navigate_w_routing_global_planning_and_control_w_recovery.xml",
        // Its NavigateToPose plans again when blocked.
        "opennav_docking_bt__application_example.xml",
    ];
    for (tree, extra) in RUNNING_TREES {
        let path = format!("corpus/nav2/{tree}");
        let mut args = vec!["--tree", path.as_str()];
        args.extend_from_slice(extra);
        let (code, out, err) = demo_cli(&args);
        if unhindered.contains(&tree) {
            assert_eq!(
                (code, last_line(&out)),
                (0, "navigation succeeded"),
                "{tree}\n{out}{err}"
            );
        } else {
            assert_eq!(
                (code, last_line(&out)),
                (2, "navigation failed"),
                "{tree}\n{out}{err}"
            );
            assert!(
                out.contains(
                    "\n  error code  106 (follow_path_error_code): blocked by an obstacle in cell (22, 5)\n"
                ),
                "{tree}\n{out}"
            );
        }
    }
}

#[test]
fn an_unreachable_goal_exits_2_with_the_planners_error_code() {
    let (code, out, _) = demo_cli(&["--goal", "0.5,0.5"]);
    assert_eq!((code, last_line(&out)), (2, "navigation failed"));
    assert!(
        out.contains("\n  error code  206 (compute_path_error_code): "),
        "{out}"
    );
}

#[test]
fn a_tree_that_never_ends_is_stopped_by_max_ticks_or_judged_after_its_duration() {
    let tree = "corpus/nav2/follow_point.xml";
    let (code, out, _) = demo_cli(&["--tree", tree, "--no-obstacle", "--max-ticks", "800"]);
    assert_eq!(
        (code, last_line(&out)),
        (3, "navigation stopped unfinished")
    );
    // Ten seconds in, the robot is still on its way: outside its tolerance.
    let (code, out, _) = demo_cli(&["--tree", tree, "--no-obstacle", "--duration", "10"]);
    assert_eq!((code, last_line(&out)), (2, "navigation failed"), "{out}");
    assert!(out.contains("\n  duration    over, the robot outside its tolerance\n"));
    let (code, out, _) = demo_cli(&["--tree", tree, "--no-obstacle", "--duration", "60"]);
    assert_eq!(code, 0);
    assert!(out.contains("\n  duration    over, the robot within its tolerance\n"));
    assert!(out.contains("\n  time        60.0 s\n"), "{out}");
}

#[test]
fn the_odometry_square_turns_into_the_wall_facing_east() {
    let tree = "corpus/nav2/odometry_calibration.xml";
    let (code, out, _) = demo_cli(&["--tree", tree]);
    assert_eq!((code, last_line(&out)), (2, "navigation failed"));
    assert!(
        out.contains("\n  error code  723 (drive_on_heading_error_code): an obstacle or a wall in cell (3, 14)\n"),
        "{out}"
    );
    let (code, out, _) = demo_cli(&["--tree", tree, "--heading", "-90"]);
    assert_eq!(code, 0);
    // Three times round a 2 m square, back where it started.
    assert!(out.contains("\n  distance    24.00 m\n"), "{out}");
    assert!(out.contains("\n  robot       (1.50, 13.50),"), "{out}");
}

#[test]
fn a_tree_with_a_node_the_world_cannot_give_a_meaning_is_refused_saying_why() {
    let dir = std::env::temp_dir().join(format!("neurotree-teleop-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tree = dir.join("teleop.xml");
    std::fs::write(
        &tree,
        r#"<root BTCPP_format="4"><BehaviorTree ID="T"><AssistedTeleop/></BehaviorTree></root>"#,
    )
    .unwrap();
    let (code, out, err) = demo_cli(&["--tree", tree.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(out.is_empty());
    assert!(
        err.contains(
            "error: `AssistedTeleop` is a Nav2 node the demo's simulated robot does not implement: \
             it lets a person drive the robot, and the simulated world has no person to drive"
        ),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_route_graph_trees_follow_the_warehouses_graph_and_report_an_unreachable_goal() {
    let tree = "corpus/nav2/navigate_on_route_graph_w_recovery.xml";
    let (code, out, _) = demo_cli(&["--tree", tree]);
    assert_eq!(code, 0, "{out}");
    // Up to node 1, along the graph to node 6, down to the goal: longer than the
    // planner's way through the lower door.
    assert!(out.contains("\n  distance    46.20 m\n"), "{out}");
    let (code, out, _) = demo_cli(&["--tree", tree, "--goal", "0.5,0.5"]);
    assert_eq!((code, last_line(&out)), (2, "navigation failed"));
    // The route is found; its last mile, to a goal in a wall, is not.
    assert!(
        out.contains("\n  error code  206 (compute_path_error_code): "),
        "{out}"
    );
}

#[test]
fn the_docking_example_undocks_works_and_docks_again() {
    let tree = "corpus/nav2/opennav_docking_bt__application_example.xml";
    let (code, out, _) = demo_cli(&["--tree", tree, "--battery", "90", "--heading", "180"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("\n  robot       (1.50, 13.50),"), "{out}");
    // A picking location that cannot be reached fails the application, which the tree
    // forces to succeed, and the robot docks all the same, as Nav2's example does.
    let (code, out, _) = demo_cli(&["--tree", tree, "--goal", "0.5,0.5"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("\n  error code  9000 (nav_to_pose_error_code): "),
        "{out}"
    );
    // With too little charge for the trip, the battery runs out on the way back.
    let (code, out, _) = demo_cli(&["--tree", tree, "--battery", "60", "--heading", "180"]);
    assert_eq!((code, last_line(&out)), (2, "navigation failed"));
    assert!(
        out.contains("\n  error code  999 (dock_robot_error_code): the battery is empty\n"),
        "{out}"
    );
}

#[test]
fn a_tree_with_nav2s_old_names_runs_with_a_warning() {
    let dir = std::env::temp_dir().join(format!("neurotree-old-names-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tree = dir.join("kilted.xml");
    std::fs::write(
        &tree,
        r#"<root BTCPP_format="4"><BehaviorTree ID="T">
  <IsStopped duration_stopped="500"/>
</BehaviorTree></root>"#,
    )
    .unwrap();
    let (code, out, err) = demo_cli(&["--tree", tree.to_str().unwrap()]);
    // The robot stands still from the start: more than 500 ms at the seventh tick.
    assert_eq!(
        (code, last_line(&out)),
        (0, "navigation succeeded"),
        "{err}"
    );
    assert!(out.contains("\n  ticks       7\n"), "{out}");
    assert_eq!(
        err,
        format!(
            "{}:2:3: warning: `IsStopped` is `CheckStopStatus` now (renamed in Nav2 after Kilted); it loads as `CheckStopStatus`, write that\n",
            tree.display()
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

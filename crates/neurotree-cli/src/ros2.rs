//! `neurotree ros2`: Nav2's navigator and the simulated Nav2 servers as ROS 2 processes.
//!
//! - `ros2 sim`: the demo's warehouse ([`demo::Scenario`] of a seed, with the demo's dock
//!   and route graph) served as Nav2's servers ([`SimServers`]): planner, smoother,
//!   controller, behaviors, costmaps, route, docking, following, navigation through poses,
//!   collision monitor, localization, odometry.
//! - `ros2 navigator`: a `navigate_to_pose` action server running a tree (Nav2's
//!   `navigate_to_pose_w_replanning_and_recovery.xml` by default) for each goal
//!   ([`Navigator`]), over the warehouse's static map.
//! - `ros2 demo`: both as child processes of this binary, a goal sent to the far corner of
//!   the store, progress printed from the feedback, a summary; both stopped at the end.
//!
//! Everything is on 127.0.0.1 ([`RosOptions::loopback`]), in DDS domain `--domain`; the
//! goals go in the layout of Nav2 release `--nav2` (main by default).

use std::io::{self, Write};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use neurotree::robotics::Pose2D;
use neurotree::sim::nav2::{EventLog, Nav2Params, Nav2Sim};
use neurotree::sim::GridWorld;
use neurotree_cli::demo::{
    dock, route_graph, Scenario, DEFAULT_GOAL, NAVIGATE_TO_POSE_XML, WAREHOUSE,
};

use neurotree::nav2::Nav2Release;
use neurotree_ros2::msg::nav2_msgs::{NavigateToPose, NavigateToPoseGoal};
use neurotree_ros2::nav2::convert::{pose_2d, pose_stamped};
use neurotree_ros2::nav2::{Navigator, NavigatorOptions, SimOptions, SimServers};
use neurotree_ros2::ros2_client::action::GoalStatusEnum;
use neurotree_ros2::{RosNode, RosOptions};

use crate::Outcome;

/// How long the demo waits for the navigator to accept its goal.
const ACCEPT_WITHIN: Duration = Duration::from_secs(20);

/// The subcommands of `neurotree ros2`.
#[derive(clap::Subcommand, Debug)]
pub enum Ros2Command {
    /// Serve the demo's warehouse as Nav2's planner, controller, behavior and costmap
    /// servers (compute_path_to_pose, follow_path, spin, backup, wait, clear_entirely_*).
    Sim {
        /// Picks the obstacle that steps onto the robot's path (as `neurotree demo`).
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// The DDS domain (ROS_DOMAIN_ID).
        #[arg(long, default_value_t = 0)]
        domain: u16,
        /// Simulated seconds per wall second.
        #[arg(long, default_value_t = 1.0, value_parser = parse_positive)]
        time_scale: f64,
        /// Stop after this many seconds [default: run until killed].
        #[arg(long, value_name = "SECS")]
        duration: Option<u64>,
        /// Read the goals of this Nav2 release: jazzy, kilted or main.
        #[arg(long, value_name = "RELEASE", default_value = "main")]
        nav2: Nav2Release,
    },
    /// Serve navigate_to_pose: for each goal, tick the tree at 10 Hz with its leaves
    /// calling Nav2's servers over ROS 2; feedback, result; a cancel halts the tree.
    Navigator {
        /// The tree to run [default: Nav2's navigate_to_pose_w_replanning_and_recovery.xml].
        #[arg(long, value_name = "FILE")]
        tree: Option<PathBuf>,
        /// The DDS domain (ROS_DOMAIN_ID).
        #[arg(long, default_value_t = 0)]
        domain: u16,
        /// Stop after this many seconds [default: run until killed].
        #[arg(long, value_name = "SECS")]
        duration: Option<u64>,
        /// Send the goals of this Nav2 release: jazzy, kilted or main.
        #[arg(long, value_name = "RELEASE", default_value = "main")]
        nav2: Nav2Release,
        #[command(flatten)]
        studio: crate::studio::StudioFlags,
    },
    /// Start `ros2 sim` and `ros2 navigator` as processes, send the robot across the
    /// warehouse, print its progress and a summary, stop both.
    Demo {
        /// Picks the obstacle that steps onto the robot's path.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// The DDS domain (ROS_DOMAIN_ID).
        #[arg(long, default_value_t = 0)]
        domain: u16,
        /// Simulated seconds per wall second.
        #[arg(long, default_value_t = 4.0, value_parser = parse_positive)]
        time_scale: f64,
        /// Give up after this many seconds.
        #[arg(long, value_name = "SECS", default_value_t = 120)]
        timeout: u64,
        /// The Nav2 release both speak: jazzy, kilted or main.
        #[arg(long, value_name = "RELEASE", default_value = "main")]
        nav2: Nav2Release,
    },
}

/// A number above zero.
fn parse_positive(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("`{text}` should be a number above 0")),
    }
}

/// Runs the subcommand `command` of `neurotree ros2`.
pub fn execute(command: Ros2Command, out: &mut impl Write) -> io::Result<Outcome> {
    match command {
        Ros2Command::Sim {
            seed,
            domain,
            time_scale,
            duration,
            nav2,
        } => sim(
            seed,
            domain,
            time_scale,
            nav2,
            duration.map(Duration::from_secs),
            out,
        ),
        Ros2Command::Navigator {
            tree,
            domain,
            duration,
            nav2,
            studio,
        } => navigator(
            tree,
            domain,
            nav2,
            duration.map(Duration::from_secs),
            &studio,
            out,
        ),
        Ros2Command::Demo {
            seed,
            domain,
            time_scale,
            timeout,
            nav2,
        } => {
            let options = DemoOptions {
                seed,
                domain,
                time_scale,
                goal: DEFAULT_GOAL,
                timeout: Duration::from_secs(timeout),
                nav2,
            };
            demo(&options, out)
        }
    }
}

/// `ros2 sim`: serves the warehouse of `seed` until `duration` passes (or forever).
pub fn sim(
    seed: u64,
    domain: u16,
    time_scale: f64,
    release: Nav2Release,
    duration: Option<Duration>,
    out: &mut impl Write,
) -> io::Result<Outcome> {
    let params = Nav2Params::default();
    let world = Scenario::new(seed, DEFAULT_GOAL, &params)
        .and_then(|s| s.world())
        .map_err(io::Error::other)?;
    let log = EventLog::new();
    // The demo's dock and route graph, for DockRobot, UndockRobot and the route nodes.
    let sim = Nav2Sim::new(world)
        .with_params(params)
        .with_log(log.clone())
        .with_dock(dock())
        .with_route_graph(route_graph());
    let ros = RosNode::new("nav2_sim", &RosOptions::loopback(domain)).map_err(io::Error::other)?;
    let options = SimOptions {
        time_scale,
        release,
        ..SimOptions::default()
    };
    let mut servers = SimServers::new(&ros, sim, options).map_err(io::Error::other)?;
    writeln!(
        out,
        "[sim] serving the warehouse (seed {seed}) in domain {domain}, {time_scale}x real time"
    )?;
    out.flush()?;
    let until = duration.map(|d| Instant::now() + d);
    let mut next = Instant::now();
    while until.is_none_or(|u| Instant::now() < u) {
        servers.spin_once().map_err(io::Error::other)?;
        for line in log.take() {
            let t = servers.sim().world.now().as_secs_f64();
            writeln!(out, "[sim] {t:6.1} s  {line}")?;
        }
        out.flush()?;
        next += servers.wall_period();
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else {
            next = now;
        }
    }
    Ok(Outcome::Done)
}

/// `ros2 navigator`: serves `navigate_to_pose` with `tree` (or Nav2's navigator).
pub fn navigator(
    tree: Option<PathBuf>,
    domain: u16,
    release: Nav2Release,
    duration: Option<Duration>,
    studio: &crate::studio::StudioFlags,
    out: &mut impl Write,
) -> io::Result<Outcome> {
    let (xml, file) = match &tree {
        Some(path) => (std::fs::read_to_string(path)?, path.display().to_string()),
        None => (
            NAVIGATE_TO_POSE_XML.to_owned(),
            "navigate_to_pose_w_replanning_and_recovery.xml".to_owned(),
        ),
    };
    let map = GridWorld::parse(WAREHOUSE, 1.0).map_err(io::Error::other)?;
    let ros =
        RosNode::new("bt_navigator", &RosOptions::loopback(domain)).map_err(io::Error::other)?;
    let options = NavigatorOptions {
        release,
        ..NavigatorOptions::default()
    };
    let mut navigator = match Navigator::on_map(&ros, &xml, &file, map, &options) {
        Ok(navigator) => navigator,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(Outcome::Refused);
        }
    };
    writeln!(
        out,
        "[navigator] serving navigate_to_pose with {file} in domain {domain}"
    )?;
    out.flush()?;
    let files: Vec<PathBuf> = tree.iter().cloned().collect();
    let nav2 = crate::registry::Nav2Args {
        nav2: Some(neurotree::nav2::Nav2Release::Main),
    };
    let mut served = match crate::studio::Served::start(studio, &files, nav2, &mut io::stderr())? {
        Ok(served) => served,
        Err(()) => return Ok(Outcome::Refused),
    };
    if let Some(served) = &mut served {
        let observer = served.attach(navigator.tree_mut(), &file);
        navigator.add_observer(observer);
    }
    let until = duration.map(|d| Instant::now() + d);
    let mut next = Instant::now();
    let mut seen = navigator.stats();
    while until.is_none_or(|u| Instant::now() < u) {
        if let Some(served) = &mut served {
            // A page may hold the navigator here, between two ticks, or take its tree back
            // to a kept tick; the goal and the robot go on as they are.
            if let Some(to) = served.between_nav2_ticks(navigator.tree_mut()) {
                writeln!(
                    out,
                    "[navigator] back to tick {to}: the tree goes on from there, the later \
                     ticks dropped"
                )?;
                out.flush()?;
            }
        }
        navigator.spin_once().map_err(io::Error::other)?;
        let now = navigator.stats();
        if now != seen {
            writeln!(
                out,
                "[navigator] goals {}: {} succeeded, {} aborted, {} cancelled; {} recoveries",
                now.goals,
                now.succeeded,
                now.aborted,
                now.canceled,
                navigator.recoveries()
            )?;
            out.flush()?;
            seen = now;
        }
        next += navigator.period();
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else {
            next = now;
        }
    }
    Ok(Outcome::Done)
}

/// A child process killed when dropped.
struct Spawned(Child);

impl Drop for Spawned {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn spawn(args: &[String]) -> io::Result<Spawned> {
    let exe = std::env::current_exe()?;
    let child = Command::new(exe)
        .arg("ros2")
        .args(args)
        .stdin(Stdio::null())
        .spawn()?;
    Ok(Spawned(child))
}

/// What `ros2 demo` runs.
pub struct DemoOptions {
    /// The obstacle's seed.
    pub seed: u64,
    /// The DDS domain.
    pub domain: u16,
    /// Simulated seconds per wall second.
    pub time_scale: f64,
    /// Where the robot is sent.
    pub goal: Pose2D,
    /// How long the demo may take, in wall time.
    pub timeout: Duration,
    /// The Nav2 release whose goals the navigator sends and the simulator reads.
    pub nav2: Nav2Release,
}

/// `ros2 demo`: the simulator and the navigator as child processes, one goal, a summary.
pub fn demo(options: &DemoOptions, out: &mut impl Write) -> io::Result<Outcome> {
    let domain = options.domain.to_string();
    // Both stop when the demo returns, however it returns; and on their own after the
    // timeout, should the demo itself be killed.
    let lifetime = (options.timeout.as_secs() + 5).to_string();
    let _sim = spawn(&[
        "sim".into(),
        "--seed".into(),
        options.seed.to_string(),
        "--domain".into(),
        domain.clone(),
        "--time-scale".into(),
        options.time_scale.to_string(),
        "--duration".into(),
        lifetime.clone(),
        "--nav2".into(),
        options.nav2.name().into(),
    ])?;
    let _navigator = spawn(&[
        "navigator".into(),
        "--domain".into(),
        domain,
        "--duration".into(),
        lifetime,
        "--nav2".into(),
        options.nav2.name().into(),
    ])?;
    let started = Instant::now();
    let deadline = started + options.timeout;
    let ros = RosNode::new("neurotree_demo", &RosOptions::loopback(options.domain))
        .map_err(io::Error::other)?;
    let client = ros
        .action_client::<NavigateToPose>("navigate_to_pose")
        .map_err(io::Error::other)?;
    let goal = options.goal;
    writeln!(
        out,
        "[demo] sending the robot to ({:.1}, {:.1}) over ROS 2 (domain {})",
        goal.x, goal.y, options.domain
    )?;
    out.flush()?;

    // The first goal may go out before the navigator is discovered: send it again until
    // it is answered.
    let accept_by = (started + ACCEPT_WITHIN).min(deadline);
    let mut goal_id = None;
    while goal_id.is_none() && Instant::now() < accept_by {
        let message = NavigateToPoseGoal {
            pose: pose_stamped(goal),
            behavior_tree: String::new(),
        };
        let (request, id) = client.send_goal(message).map_err(|e| other(&e))?;
        let answer_by = Instant::now() + Duration::from_secs(2);
        while Instant::now() < answer_by {
            match client
                .receive_goal_response(request)
                .map_err(|e| other(&e))?
            {
                Some(response) if response.accepted => {
                    goal_id = Some(id);
                    break;
                }
                Some(_) => {
                    writeln!(out, "[demo] the navigator rejected the goal")?;
                    return Ok(Outcome::RunFailed);
                }
                None => std::thread::sleep(Duration::from_millis(20)),
            }
        }
    }
    let Some(goal_id) = goal_id else {
        writeln!(
            out,
            "[demo] the navigator did not answer within {ACCEPT_WITHIN:?}"
        )?;
        return Ok(Outcome::Stopped);
    };
    writeln!(out, "[demo] goal accepted")?;
    let result_request = client.request_result(goal_id).map_err(|e| other(&e))?;

    let mut recoveries = 0;
    let mut last_print = Instant::now();
    let mut latest = None;
    let outcome = loop {
        while let Ok(Some(feedback)) = client.receive_feedback(goal_id) {
            recoveries = recoveries.max(feedback.number_of_recoveries);
            latest = Some(feedback);
        }
        if last_print.elapsed() >= Duration::from_secs(1) {
            if let Some(feedback) = &latest {
                let robot = pose_2d(&feedback.current_pose);
                writeln!(
                    out,
                    "[demo] {:5.1} s  robot ({:5.2}, {:5.2})  {:5.1} m to go  recoveries {}",
                    started.elapsed().as_secs_f64(),
                    robot.x,
                    robot.y,
                    feedback.distance_remaining,
                    feedback.number_of_recoveries
                )?;
                out.flush()?;
            }
            last_print = Instant::now();
        }
        if let Some((status, result)) = client
            .receive_result(result_request)
            .map_err(|e| other(&e))?
        {
            break Some((status, result));
        }
        if Instant::now() >= deadline {
            // Stop the navigation before stopping the processes.
            let _ = client.cancel_goal(goal_id);
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };

    writeln!(out, "Summary")?;
    let (word, code) = match &outcome {
        Some((GoalStatusEnum::Succeeded, _)) => ("SUCCESS", Outcome::Done),
        Some((GoalStatusEnum::Canceled, _)) => ("CANCELED", Outcome::RunFailed),
        Some(_) => ("FAILURE", Outcome::RunFailed),
        None => ("RUNNING (timed out)", Outcome::Stopped),
    };
    writeln!(out, "  outcome     {word}")?;
    writeln!(
        out,
        "  time        {:.1} s",
        started.elapsed().as_secs_f64()
    )?;
    writeln!(out, "  recoveries  {recoveries}")?;
    if let Some(feedback) = &latest {
        let robot = pose_2d(&feedback.current_pose);
        writeln!(
            out,
            "  last pose   ({:.2}, {:.2}), {:.2} m from the goal ({:.2}, {:.2})",
            robot.x,
            robot.y,
            robot.distance(&goal),
            goal.x,
            goal.y
        )?;
    }
    if let Some((_, result)) = &outcome {
        if !result.error_msg.is_empty() {
            writeln!(
                out,
                "  error       {} (code {})",
                result.error_msg, result.error_code
            )?;
        }
    }
    out.flush()?;
    Ok(code)
}

fn other(e: &impl std::fmt::Debug) -> io::Error {
    io::Error::other(format!("{e:?}"))
}

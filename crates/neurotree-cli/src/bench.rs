//! `neurotree bench`: quick in-process measurements of the reference workloads.
//!
//! - `tree1111`: one instance of BehaviorTree.CPP's benchmark shape (1,111 nodes, every
//!   node visited per tick), ticked in a loop: nanoseconds per tick and per visited node,
//!   and the bytes of per-instance state. Built with the builder (closure conditions), and
//!   as `tree1111_xml` loaded from `tree1111.xml` (registered conditions).
//! - `many_agents`: many instances of the 50-node agent tree sharing one blueprint and one
//!   manual clock, each ticked once per frame: milliseconds per frame and bytes per
//!   instance.
//! - `crowd`: the same agents as a [`Crowd`](neurotree::crowd::Crowd), each frame ticked on
//!   every thread of a rayon pool (`--threads`, or `RAYON_NUM_THREADS`, or every core):
//!   milliseconds per frame and bytes per member.
//! - `crowd_sleeping`: the same agents behind a leaf that sleeps until an alert, 1% of them
//!   alerted each frame (a blackboard write, delivered by `Crowd::frame_with` on the
//!   frame's threads): the members awake per
//!   frame and milliseconds per frame, which follow the agents awake rather than the crowd.
//! - `crowd_awake`: the sleeping crowd again with about 1 %, 3.7 % and 20 % of it awake in
//!   each frame: nanoseconds per awake member, and their ratio to the `crowd` line's
//!   nanoseconds per member (what an agent that acts costs in a crowd that mostly sleeps,
//!   against one in a crowd all awake).
//!
//! - `cores`: a value bounced between two threads through one atomic, before the crowd
//!   lines and after them: nanoseconds per round trip, which say whether the host placed
//!   the two cores beside each other or apart (a crowd's two-thread figures follow it), and
//!   how many times as fast two threads ran a loop of arithmetic as one.
//! - `tick_times`: each tick timed alone, at least 100,000 of them (10,000 with `--quick`), for tree1111 loaded from
//!   XML and for Nav2's navigator driving the demo's simulated robot (one navigation after
//!   another, seeds 0, 1, 2, ...): the median, p99, p99.9 and the slowest tick, and the same
//!   for the navigator's ticks in which a path was planned. A robot's loop misses its period
//!   on its worst tick, which a mean hides.
//!
//! The crowd frames run back to back, unless `--idle-us N` puts N microseconds of other
//! work on the calling thread before each, as a game's frame does: the crowd's threads then
//! idle between frames and wake for each, as they do in a game.
//!
//! These are wall-clock figures from [`Instant`], good for a first look on a new machine;
//! the criterion benchmarks (`cargo bench -p neurotree-bench --bench tick`) are the careful ones.

use std::hint::black_box;
use std::io::{self, Write};
use std::sync::Arc;
use std::time::{Duration, Instant};

use neurotree::{Blueprint, Clock, ManualClock, Status, Tree};
use neurotree_bench::latency::{TickPercentiles, TickTimes};
use neurotree_bench::{agent_tree, tree1111, tree1111_xml, Agent, TREE1111_NODES_PER_TICK};

use crate::Outcome;

mod cores;
mod crowd;
pub use cores::*;
pub use crowd::*;

/// What `neurotree bench` was asked to do.
#[derive(clap::Args, Clone, Debug)]
pub struct BenchArgs {
    /// One JSON object per benchmark, one per line.
    #[arg(long)]
    pub json: bool,
    /// Measure for a fifth of the usual time.
    #[arg(long)]
    pub quick: bool,
    /// Instances in the many-agents and crowd benchmarks.
    #[arg(long, default_value_t = 100_000)]
    pub agents: usize,
    /// Threads of the crowd benchmark (0: `RAYON_NUM_THREADS`, or every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Per cent of the sleeping crowd alerted before each frame (they wake, and stay awake a
    /// few frames).
    #[arg(long, default_value_t = 1.0)]
    pub alert_percent: f64,
    /// Frames timed in the crowd benchmarks, at least (default 20, 5 with `--quick`); more
    /// are timed until 0.3 s of frames have run (0.03 s with `--quick`), but for the
    /// sleeping crowd's lines, which time as many frames as 30,000,000 divided by the
    /// agents (3,000,000 with `--quick`), the same on any number of threads.
    #[arg(long)]
    pub frames: Option<u32>,
    /// Microseconds the calling thread spends on other work (a busy wait, not timed) before
    /// each timed crowd frame, as a game's frame does between its crowd's: the crowd's
    /// threads fall idle meanwhile and must wake for the frame. 0: frames back to back.
    #[arg(long, default_value_t = 0)]
    pub idle_us: u64,
    /// Runs only these benchmarks (comma-separated: tree1111, many_agents, cores, crowd,
    /// crowd_sleeping, crowd_awake, tick_times).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
}

impl BenchArgs {
    /// `true` if benchmark `name` is to run.
    fn runs(&self, name: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|o| o == name)
    }

    /// Frames timed in the crowd benchmarks.
    fn crowd_frames(&self) -> u32 {
        self.frames.unwrap_or(if self.quick { 5 } else { 20 })
    }
}

/// Result of the tree1111 benchmark.
#[derive(Clone, Debug)]
pub struct Tree1111Result {
    /// `tree1111` (builder) or `tree1111_xml` (loaded from XML).
    pub name: &'static str,
    /// Ticks timed.
    pub ticks: u64,
    /// Mean nanoseconds per tick.
    pub ns_per_tick: f64,
    /// Nodes one tick visits.
    pub nodes_per_tick: usize,
    /// Mean nanoseconds per visited node.
    pub ns_per_node: f64,
    /// Bytes of per-instance node state.
    pub state_bytes: usize,
}

/// Result of the many-agents benchmark.
#[derive(Clone, Debug)]
pub struct ManyAgentsResult {
    /// Instances ticked per frame.
    pub agents: usize,
    /// Frames timed.
    pub frames: u32,
    /// Mean milliseconds per frame.
    pub ms_per_frame: f64,
    /// Bytes per instance: its node state plus the `Tree` value itself.
    pub bytes_per_instance: usize,
}

/// Ticks tree1111 (`blueprint`, reported as `name`) for about a second (a fifth with
/// `quick`) after a warm-up.
pub fn tree1111_bench(
    opts: &BenchArgs,
    name: &'static str,
    blueprint: Arc<Blueprint<()>>,
) -> Tree1111Result {
    let target = if opts.quick {
        Duration::from_millis(200)
    } else {
        Duration::from_secs(1)
    };
    let mut tree = Tree::with_clock(blueprint, ManualClock::new());
    let mut tick = |n: u64| {
        for _ in 0..n {
            let status = black_box(tree.tick_once(black_box(&mut ())));
            debug_assert_eq!(status, Ok(Status::Success));
        }
    };
    // Warm up for a tenth of the target, and learn how many ticks make a batch of ~1 ms so
    // that reading the clock does not weigh on the measure.
    let warm_up = Instant::now();
    let mut warm_ticks = 0u64;
    while warm_up.elapsed() < target / 10 {
        tick(16);
        warm_ticks += 16;
    }
    let per_ms = warm_ticks as f64 / (warm_up.elapsed().as_secs_f64() * 1e3);
    let batch = (per_ms as u64).max(1);

    let start = Instant::now();
    let mut ticks = 0u64;
    while start.elapsed() < target {
        tick(batch);
        ticks += batch;
    }
    let elapsed = start.elapsed();
    let ns_per_tick = elapsed.as_nanos() as f64 / ticks as f64;
    Tree1111Result {
        name,
        ticks,
        ns_per_tick,
        nodes_per_tick: TREE1111_NODES_PER_TICK,
        ns_per_node: ns_per_tick / TREE1111_NODES_PER_TICK as f64,
        state_bytes: tree.state_bytes(),
    }
}

/// Ticks `opts.agents` agent trees once per frame, 20 frames (5 with `quick`) after two
/// warm-up frames, advancing the shared clock 16 ms per frame. Each agent gets one pass,
/// `tick_exactly_once`, as a game loop gives each agent one tick per frame.
pub fn many_agents_bench(opts: &BenchArgs) -> ManyAgentsResult {
    const FRAME: Duration = Duration::from_millis(16);
    let frames = if opts.quick { 5 } else { 20 };
    let blueprint = agent_tree();
    let clock = ManualClock::new();
    let shared: Arc<dyn Clock> = Arc::new(clock.clone());
    let mut trees: Vec<Tree<Agent>> = (0..opts.agents)
        .map(|_| Tree::with_shared_clock(Arc::clone(&blueprint), Arc::clone(&shared)))
        .collect();
    let mut agents: Vec<Agent> = (0..opts.agents).map(|i| Agent::new(i as u32)).collect();
    let mut frame = || {
        clock.advance(FRAME);
        for (tree, agent) in trees.iter_mut().zip(agents.iter_mut()) {
            let _ = black_box(tree.tick_exactly_once(agent));
        }
    };
    for _ in 0..2 {
        frame();
    }
    let start = Instant::now();
    for _ in 0..frames {
        frame();
    }
    let elapsed = start.elapsed();
    let bytes_per_instance =
        trees.first().map_or(0, |t| t.state_bytes()) + std::mem::size_of::<Tree<Agent>>();
    ManyAgentsResult {
        agents: opts.agents,
        frames,
        ms_per_frame: elapsed.as_secs_f64() * 1e3 / f64::from(frames),
        bytes_per_instance,
    }
}

/// Ticks timed one by one in the tick-time benchmarks, at least (a tenth with `--quick`).
pub const TIMED_TICKS: usize = 100_000;

/// Result of a tick-time benchmark.
#[derive(Clone, Debug)]
pub struct TickTimesResult {
    /// `tree1111_xml`, `nav2_navigator` or `nav2_navigator_planning`.
    pub tree: &'static str,
    /// The percentiles of the ticks timed.
    pub percentiles: TickPercentiles,
}

/// Times `ticks` ticks of tree1111 loaded from XML one by one, after as many untimed ones.
pub fn tree1111_tick_times(ticks: usize) -> TickTimesResult {
    let mut tree = Tree::with_clock(tree1111_xml::<()>(), ManualClock::new());
    for _ in 0..ticks {
        black_box(tree.tick_once(&mut ()).ok());
    }
    let mut times = TickTimes::with_capacity(ticks);
    for _ in 0..ticks {
        let status = times.time(|| tree.tick_once(black_box(&mut ())));
        debug_assert_eq!(status, Ok(Status::Success));
    }
    TickTimesResult {
        tree: "tree1111_xml",
        percentiles: times.percentiles(),
    }
}

/// Times at least `ticks` ticks of Nav2's navigator (as the demo loads it) driving
/// the simulated robot, one navigation after another from seed 0 (a first navigation
/// untimed); only the tree's ticks are timed, not the world's steps between them. Two
/// results: every tick (`nav2_navigator`), and the ticks in which the planner server computed
/// a path (`nav2_navigator_planning`), the ticks that make the tail.
pub fn nav2_tick_times(
    ticks: usize,
) -> Result<[TickTimesResult; 2], neurotree_cli::demo::DemoError> {
    use neurotree_cli::demo::{DemoConfig, DemoRun};
    let mut all = TickTimes::with_capacity(ticks + 4096);
    let mut planning = TickTimes::with_capacity(ticks / 8);
    let mut seed = 0;
    let mut timed = false;
    while all.len() < ticks {
        let mut run = DemoRun::new(&DemoConfig {
            seed,
            ..DemoConfig::default()
        })?;
        while !run.is_over() {
            let plans = run.sim().plans();
            let (_, took) = run.tick_timed();
            if timed {
                all.record(took);
                if run.sim().plans() > plans {
                    planning.record(took);
                }
            }
        }
        timed = true;
        seed += 1;
    }
    Ok([
        TickTimesResult {
            tree: "nav2_navigator",
            percentiles: all.percentiles(),
        },
        TickTimesResult {
            tree: "nav2_navigator_planning",
            percentiles: planning.percentiles(),
        },
    ])
}

/// Runs the benchmarks and writes a table, or one JSON object per line with `--json`; a
/// benchmark that ran has nothing to fail on.
pub fn execute(opts: &BenchArgs, out: &mut impl Write) -> io::Result<Outcome> {
    let json = opts.json;
    if !json {
        writeln!(out, "{:<12} {:<20} {:>14}", "benchmark", "measure", "value")?;
    }
    for (name, blueprint) in [("tree1111", tree1111()), ("tree1111_xml", tree1111_xml())] {
        if !opts.runs("tree1111") {
            break;
        }
        let t = tree1111_bench(opts, name, blueprint);
        if json {
            writeln!(out, "{}", tree1111_json(&t))?;
        } else {
            row(out, name, "ticks", t.ticks.to_string())?;
            row(out, "", "ns per tick", format!("{:.1}", t.ns_per_tick))?;
            row(out, "", "nodes per tick", t.nodes_per_tick.to_string())?;
            row(out, "", "ns per node", format!("{:.3}", t.ns_per_node))?;
            row(out, "", "state bytes", t.state_bytes.to_string())?;
        }
        out.flush()?;
    }
    if opts.runs("many_agents") {
        many_agents_lines(opts, out)?;
    }
    cores_line(opts, "start", out)?;
    let crowd = opts
        .runs("crowd")
        .then(|| crowd_lines(opts, out))
        .transpose()?;
    if opts.runs("crowd_sleeping") {
        crowd_sleeping_lines(opts, out)?;
    }
    if opts.runs("crowd_awake") {
        crowd_awake_lines(opts, crowd.as_ref(), out)?;
    }
    cores_line(opts, "end", out)?;
    if opts.runs("tick_times") {
        tick_times_lines(opts, out)?;
    }
    Ok(Outcome::Done)
}

/// The `cores` line, before the crowd lines and after them: the host may move the cores
/// between the two.
fn cores_line(opts: &BenchArgs, at: &'static str, out: &mut impl Write) -> io::Result<()> {
    if !opts.runs("cores") {
        return Ok(());
    }
    let Some(c) = cores_bench(at, opts.quick) else {
        return Ok(());
    };
    if opts.json {
        writeln!(out, "{}", cores_json(&c))?;
    } else {
        row(out, "cores", "at", at.to_string())?;
        row(out, "", "round trip ns", format!("{:.1}", c.round_trip_ns))?;
        row(
            out,
            "",
            "arithmetic speed-up",
            format!("{:.3}", c.arithmetic_speedup),
        )?;
    }
    out.flush()
}

fn many_agents_lines(opts: &BenchArgs, out: &mut impl Write) -> io::Result<()> {
    let json = opts.json;
    let m = many_agents_bench(opts);
    if json {
        writeln!(out, "{}", many_agents_json(&m))?;
    } else {
        row(out, "many_agents", "agents", m.agents.to_string())?;
        row(out, "", "frames", m.frames.to_string())?;
        row(out, "", "ms per frame", format!("{:.3}", m.ms_per_frame))?;
        row(
            out,
            "",
            "bytes per instance",
            m.bytes_per_instance.to_string(),
        )?;
    }
    out.flush()
}

fn tick_times_lines(opts: &BenchArgs, out: &mut impl Write) -> io::Result<()> {
    let json = opts.json;
    let timed = if opts.quick {
        TIMED_TICKS / 10
    } else {
        TIMED_TICKS
    };
    let [nav2, planning] = nav2_tick_times(timed).map_err(|e| io::Error::other(e.to_string()))?;
    for t in [tree1111_tick_times(timed), nav2, planning] {
        if json {
            writeln!(out, "{}", tick_times_json(&t))?;
        } else {
            let p = t.percentiles;
            row(out, "tick_times", "tree", t.tree.to_string())?;
            row(out, "", "ticks", p.ticks.to_string())?;
            row(out, "", "p50 ns", p.p50.to_string())?;
            row(out, "", "p99 ns", p.p99.to_string())?;
            row(out, "", "p99.9 ns", p.p999.to_string())?;
            row(out, "", "max ns", p.max.to_string())?;
        }
        out.flush()?;
    }
    Ok(())
}

fn tick_times_json(t: &TickTimesResult) -> String {
    let p = t.percentiles;
    format!(
        r#"{{"name":"tick_times","tree":"{}","ticks":{},"p50_ns":{},"p99_ns":{},"p999_ns":{},"max_ns":{}}}"#,
        t.tree, p.ticks, p.p50, p.p99, p.p999, p.max
    )
}

fn row(out: &mut impl Write, bench: &str, measure: &str, value: String) -> io::Result<()> {
    writeln!(out, "{bench:<12} {measure:<20} {value:>14}")
}

fn tree1111_json(t: &Tree1111Result) -> String {
    format!(
        r#"{{"name":"{}","ticks":{},"ns_per_tick":{:.3},"nodes_per_tick":{},"ns_per_node":{:.4},"state_bytes":{}}}"#,
        t.name, t.ticks, t.ns_per_tick, t.nodes_per_tick, t.ns_per_node, t.state_bytes
    )
}

fn many_agents_json(m: &ManyAgentsResult) -> String {
    format!(
        r#"{{"name":"many_agents","agents":{},"frames":{},"ms_per_frame":{:.4},"bytes_per_instance":{}}}"#,
        m.agents, m.frames, m.ms_per_frame, m.bytes_per_instance
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_lines_have_the_documented_shape() {
        let t = Tree1111Result {
            name: "tree1111",
            ticks: 1000,
            ns_per_tick: 812.5,
            nodes_per_tick: 1111,
            ns_per_node: 0.7313,
            state_bytes: 1339,
        };
        assert_eq!(
            tree1111_json(&t),
            r#"{"name":"tree1111","ticks":1000,"ns_per_tick":812.500,"nodes_per_tick":1111,"ns_per_node":0.7313,"state_bytes":1339}"#
        );
        let m = ManyAgentsResult {
            agents: 100_000,
            frames: 20,
            ms_per_frame: 12.25,
            bytes_per_instance: 320,
        };
        assert_eq!(
            many_agents_json(&m),
            r#"{"name":"many_agents","agents":100000,"frames":20,"ms_per_frame":12.2500,"bytes_per_instance":320}"#
        );
        let c = CrowdResult {
            agents: 100_000,
            threads: 2,
            frames: 20,
            ms_per_frame: 4.5,
            ms_per_frame_median: 4.0,
            bytes_per_member: 600,
            bytes_per_member_mean: 760,
            idle_us: 0,
        };
        assert_eq!(
            crowd_json(&c),
            r#"{"name":"crowd","agents":100000,"threads":2,"ms_per_frame":4.5000,"frames":20,"bytes_per_member":600,"bytes_per_member_mean":760,"ns_per_member":45.0,"ms_per_frame_median":4.0000,"ns_per_member_median":40.0}"#
        );
        let s = CrowdSleepingResult {
            agents: 100_000,
            threads: 1,
            alert_percent: 1.0,
            awake_per_frame: 1000.0,
            ms_per_frame: 0.25,
            ms_per_frame_median: 0.2,
            bytes_per_member: 640,
            bytes_per_member_mean: 700,
            idle_us: 0,
        };
        assert_eq!(
            crowd_sleeping_json(&s),
            r#"{"name":"crowd_sleeping","agents":100000,"awake_per_frame":1000.0,"ms_per_frame":0.2500,"ns_per_awake":250.0,"bytes_per_member":640,"bytes_per_member_mean":700}"#
        );
        assert_eq!(
            crowd_awake_json(&s, Some((250.0 / 45.0, 200.0 / 40.0))),
            r#"{"name":"crowd_awake","agents":100000,"threads":1,"alert_percent":1.000,"awake_percent":1.00,"awake_per_frame":1000.0,"ms_per_frame":0.2500,"ms_per_frame_median":0.2000,"ns_per_awake":250.0,"ns_per_awake_median":200.0,"bytes_per_member":640,"bytes_per_member_mean":700,"awake_cost_ratio":5.56,"awake_cost_ratio_median":5.00}"#
        );
        // Frames timed after other work say so; frames back to back, as before.
        let idle = CrowdSleepingResult { idle_us: 900, ..s };
        assert_eq!(
            crowd_sleeping_json(&idle),
            r#"{"name":"crowd_sleeping","agents":100000,"awake_per_frame":1000.0,"ms_per_frame":0.2500,"ns_per_awake":250.0,"bytes_per_member":640,"bytes_per_member_mean":700,"idle_us":900}"#
        );
        let idle = CrowdResult { idle_us: 900, ..c };
        assert!(crowd_json(&idle).ends_with(r#""ns_per_member_median":40.0,"idle_us":900}"#));
        let t = TickTimesResult {
            tree: "tree1111_xml",
            percentiles: TickPercentiles {
                ticks: 100_000,
                p50: 900,
                p99: 1100,
                p999: 2500,
                max: 40_000,
            },
        };
        assert_eq!(
            tick_times_json(&t),
            r#"{"name":"tick_times","tree":"tree1111_xml","ticks":100000,"p50_ns":900,"p99_ns":1100,"p999_ns":2500,"max_ns":40000}"#
        );
    }

    #[test]
    fn a_sleeping_crowd_s_lines_time_the_same_frames_on_any_threads() {
        let opts = |agents, threads, quick, frames| BenchArgs {
            json: true,
            quick,
            agents,
            threads,
            alert_percent: 1.0,
            frames,
            idle_us: 0,
            only: Vec::new(),
        };
        for threads in [1, 2] {
            assert_eq!(sleeping_frames(&opts(100_000, threads, false, None)), 300);
            assert_eq!(sleeping_frames(&opts(1_000_000, threads, false, None)), 30);
            assert_eq!(sleeping_frames(&opts(1_000_000, threads, true, None)), 5);
            assert_eq!(sleeping_frames(&opts(100, threads, false, None)), 2_000);
            assert_eq!(
                sleeping_frames(&opts(100_000, threads, false, Some(500))),
                500
            );
        }
        // Exactly that many, however quick the frames.
        let mut calls = 0;
        let (frames, times, _) = time_frames(&opts(1, 1, true, None), Some(7), || {
            calls += 1;
            0
        });
        assert_eq!((frames, times.len(), calls), (7, 7, 7));
    }

    #[test]
    fn the_other_work_before_each_frame_is_not_timed() {
        let opts = BenchArgs {
            json: true,
            quick: true,
            agents: 1,
            threads: 1,
            alert_percent: 1.0,
            frames: Some(2),
            idle_us: 5_000,
            only: Vec::new(),
        };
        let start = Instant::now();
        let mut calls = 0;
        let (frames, times, total) = time_frames(&opts, None, || {
            calls += 1;
            0
        });
        let wall = start.elapsed();
        assert_eq!((frames, times.len(), calls), (calls, calls as usize, calls));
        // Each frame came after 5 ms of other work, none of which was timed.
        assert!(wall >= Duration::from_millis(5) * frames, "{wall:?}");
        assert_eq!(total, times.iter().sum::<Duration>());
        assert!(total < wall / 10, "{total:?} timed of {wall:?}");
        // Past the frames asked for, the other work counts towards the clock's limit: ten
        // times the least timed (a tenth of it with `--quick`: 0.3 s), not the hundred
        // frames of 5 ms (1 s) that the least timed alone would run.
        assert!(wall < LEAST_TIMED * 2, "{wall:?}");
    }

    #[test]
    fn the_navigator_is_timed_tick_by_tick_over_whole_navigations() {
        // Two navigations at least: the first is not timed.
        let [all, planning] = nav2_tick_times(50).expect("the demo's navigator loads");
        let (p, q) = (all.percentiles, planning.percentiles);
        assert!(p.ticks >= 50, "{} ticks timed", p.ticks);
        assert!(p.p50 <= p.p99 && p.p99 <= p.p999 && p.p999 <= p.max);
        assert!(p.p50 > 0, "a tick of the navigator takes some time");
        // A navigation plans at least once, in ticks that are among those timed.
        assert!(
            q.ticks >= 1 && q.ticks < p.ticks,
            "{} of {}",
            q.ticks,
            p.ticks
        );
        assert!(q.max <= p.max);
    }
}

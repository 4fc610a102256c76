//! The crowd benchmarks of `neurotree bench`: `crowd`, `crowd_sleeping` and `crowd_awake`,
//! their frames timed alike ([`time_frames`]) and their lines.

use std::hint::black_box;
use std::io::{self, Write};
use std::time::{Duration, Instant};

use neurotree::ManualClock;
use neurotree_bench::{
    agent_crowd, crowd_bytes_per_member, crowd_bytes_per_member_mean, sleepy_agent_crowd,
    wake_each_once, Agent,
};

use super::{row, BenchArgs};

/// Frames an alerted sleepy agent stays awake, on average (its agent tree's Delay, Sleep and
/// dodge): the sleeping crowd has this many times its alert rate awake.
pub const AWAKE_FRAMES_PER_ALERT: f64 = 3.7137;

/// The shares of the sleeping crowd awake per frame that `crowd_awake` measures, in per cent.
pub const AWAKE_PERCENTS: [f64; 3] = [1.0, 3.7, 20.0];

/// Result of the crowd benchmark.
#[derive(Clone, Debug)]
pub struct CrowdResult {
    /// Members ticked per frame.
    pub agents: usize,
    /// Threads the frames ran on.
    pub threads: usize,
    /// Frames timed.
    pub frames: u32,
    /// Mean milliseconds per frame.
    pub ms_per_frame: f64,
    /// The median frame's milliseconds: on a shared machine, less moved by the frames in
    /// which another process held the core.
    pub ms_per_frame_median: f64,
    /// Bytes per member: its slot in the crowd and its tree's node state, for a member
    /// whose tree has made no failure record ([`crowd_bytes_per_member`]).
    pub bytes_per_member: usize,
    /// The same over every member after the timed frames, failure records included
    /// ([`crowd_bytes_per_member_mean`]).
    pub bytes_per_member_mean: usize,
    /// Microseconds of other work before each timed frame (`--idle-us`).
    pub idle_us: u64,
}

impl CrowdResult {
    /// Mean nanoseconds a frame spends per member.
    pub fn ns_per_member(&self) -> f64 {
        self.ms_per_frame * 1e6 / self.agents.max(1) as f64
    }

    /// Nanoseconds the median frame spends per member.
    pub fn ns_per_member_median(&self) -> f64 {
        self.ms_per_frame_median * 1e6 / self.agents.max(1) as f64
    }
}

/// The median of `times`, in milliseconds.
pub(super) fn median_ms(mut times: Vec<Duration>) -> f64 {
    times.sort_unstable();
    times
        .get(times.len() / 2)
        .map_or(0.0, |t| t.as_secs_f64() * 1e3)
}

/// Frames the crowd all awake runs before it is timed. A tree makes its failure record the
/// first time one of its nodes gives a reason: an eighth of the agents' trees do in their
/// first twelve frames, and when records took 1,280 bytes those frames took up to three
/// times as long as later ones, which a mean over twenty frames would carry. A few more
/// make theirs in the frames timed (one in five or six has a record by the end of them).
pub const WARM_FRAMES: u32 = 10;

/// Runs `opts.agents` agents as a crowd on `opts.threads` threads, every agent due every
/// frame: at least 20 frames (5 with `quick`) and [`LEAST_TIMED`] timed after
/// [`WARM_FRAMES`], the clock advancing 16 ms per frame.
pub fn crowd_bench(opts: &BenchArgs) -> CrowdResult {
    const FRAME: Duration = Duration::from_millis(16);
    let clock = ManualClock::new();
    let mut crowd = agent_crowd(opts.agents, opts.threads, clock.clone());
    let mut frame = || {
        clock.advance(FRAME);
        black_box(crowd.frame());
    };
    for _ in 0..WARM_FRAMES {
        frame();
    }
    let (frames, times, elapsed) = time_frames(opts, None, || {
        frame();
        0
    });
    CrowdResult {
        agents: opts.agents,
        threads: crowd.threads(),
        frames,
        ms_per_frame: elapsed.as_secs_f64() * 1e3 / f64::from(frames),
        ms_per_frame_median: median_ms(times),
        bytes_per_member: crowd_bytes_per_member(&crowd),
        bytes_per_member_mean: crowd_bytes_per_member_mean(&crowd),
        idle_us: opts.idle_us,
    }
}

/// Result of the sleeping-crowd benchmark.
#[derive(Clone, Debug)]
pub struct CrowdSleepingResult {
    /// Members.
    pub agents: usize,
    /// Threads the frames ran on.
    pub threads: usize,
    /// Per cent of the crowd alerted before each frame.
    pub alert_percent: f64,
    /// Members ticked per frame, on average over the frames timed.
    pub awake_per_frame: f64,
    /// Mean milliseconds per frame, the alerts' writes included.
    pub ms_per_frame: f64,
    /// The median frame's milliseconds, the alerts' writes included.
    pub ms_per_frame_median: f64,
    /// Bytes per member: its slot in the crowd and its tree's node state, for a member
    /// whose tree has made no failure record ([`crowd_bytes_per_member`]).
    pub bytes_per_member: usize,
    /// The same over every member after the timed frames, failure records included
    /// ([`crowd_bytes_per_member_mean`]).
    pub bytes_per_member_mean: usize,
    /// Microseconds of other work before each timed frame (`--idle-us`).
    pub idle_us: u64,
}

impl CrowdSleepingResult {
    /// Mean nanoseconds a frame spends per member awake in it: what an agent that acts
    /// costs in a crowd that mostly sleeps, beside [`CrowdResult::ns_per_member`].
    pub fn ns_per_awake(&self) -> f64 {
        self.ms_per_frame * 1e6 / self.awake_per_frame.max(1.0)
    }

    /// Nanoseconds the median frame spends per member awake in it.
    pub fn ns_per_awake_median(&self) -> f64 {
        self.ms_per_frame_median * 1e6 / self.awake_per_frame.max(1.0)
    }

    /// Per cent of the members awake per frame.
    pub fn awake_percent(&self) -> f64 {
        self.awake_per_frame * 100.0 / self.agents.max(1) as f64
    }
}

/// Runs `opts.agents` sleepy agents as a crowd, alerting `alert_percent` of them (at
/// least one) before each frame, in turn: at least 20 frames (5 with `quick`) and
/// [`LEAST_TIMED`] timed after every member was woken once ([`wake_each_once`]: a
/// member's first wake may make its failure record, which a crowd pays once, and a million
/// members' timed frames would otherwise be made of first wakes) and ten more frames, the
/// clock advancing 16 ms per frame.
pub fn crowd_sleeping_bench(opts: &BenchArgs, alert_percent: f64) -> CrowdSleepingResult {
    const FRAME: Duration = Duration::from_millis(16);
    let clock = ManualClock::new();
    let mut crowd = sleepy_agent_crowd(opts.agents, opts.threads, clock.clone());
    wake_each_once(&mut crowd, &clock, FRAME);
    let ids: Vec<_> = crowd.iter().map(|m| m.id()).collect();
    let per_frame = ((ids.len() as f64 * alert_percent / 100.0) as usize)
        .max(1)
        .min(ids.len());
    let mut next = 0;
    let mut alerted = Vec::with_capacity(per_frame);
    let mut frame = |crowd: &mut neurotree::crowd::Crowd<Agent>| {
        alerted.clear();
        for _ in 0..per_frame {
            alerted.push(ids[next % ids.len()]);
            next += 1;
        }
        clock.advance(FRAME);
        // On the frame's threads, as a game delivers a frame's events to its agents.
        black_box(crowd.frame_with(&alerted, |mut m| {
            let _ = m.tree_mut().blackboard_mut().set("alert", true);
        }))
    };
    for _ in 0..10 {
        frame(&mut crowd);
    }
    let mut ticked = 0;
    let (frames, times, elapsed) = time_frames(opts, Some(sleeping_frames(opts)), || {
        ticked += frame(&mut crowd).ticked;
        0
    });
    CrowdSleepingResult {
        agents: opts.agents,
        threads: crowd.threads(),
        alert_percent,
        awake_per_frame: ticked as f64 / f64::from(frames),
        ms_per_frame: elapsed.as_secs_f64() * 1e3 / f64::from(frames),
        ms_per_frame_median: median_ms(times),
        bytes_per_member: crowd_bytes_per_member(&crowd),
        bytes_per_member_mean: crowd_bytes_per_member_mean(&crowd),
        idle_us: opts.idle_us,
    }
}

/// The least time the crowd benchmarks spend in timed frames (a tenth with `--quick`): a
/// frame of a mostly sleeping crowd lasts a fraction of a millisecond, and twenty of them
/// would measure little but the machine's hiccups.
pub const LEAST_TIMED: Duration = Duration::from_millis(300);

/// Member-frames a sleeping crowd's line times at least: frames of it divided by its
/// members (300 frames of 100,000, 30 of a million; a tenth with `--quick`).
pub const SLEEPING_MEMBER_FRAMES: u64 = 30_000_000;

/// The frames a sleeping crowd's line times, whatever its threads: as many as its members
/// divide [`SLEEPING_MEMBER_FRAMES`] into, at most 2,000, or `--frames` if more. The same
/// on any number of threads, since its share awake is still falling over the first
/// hundreds of frames after the warm-up: a line timed until enough time had passed timed
/// twice as many frames on two threads as on one, later ones, with a tenth fewer members
/// awake at 100,000 (BENCHMARKS.md, "Against the goals", 10:19 UTC).
pub fn sleeping_frames(opts: &BenchArgs) -> u32 {
    let member_frames = if opts.quick {
        SLEEPING_MEMBER_FRAMES / 10
    } else {
        SLEEPING_MEMBER_FRAMES
    };
    let by_members = (member_frames / opts.agents.max(1) as u64).min(2_000) as u32;
    by_members.max(opts.crowd_frames())
}

/// Times `frame` `fixed` times if given, else at least `frames` times and for at least
/// [`LEAST_TIMED`] of frames (at most a hundred times `frames`, and past `frames` for at
/// most ten times [`LEAST_TIMED`] of the clock, the other work included), each after
/// `opts.idle_us` of other work: the frames timed, each one's time, and their total.
pub(super) fn time_frames(
    opts: &BenchArgs,
    fixed: Option<u32>,
    mut frame: impl FnMut() -> u64,
) -> (u32, Vec<Duration>, Duration) {
    let frames = fixed.unwrap_or(opts.crowd_frames());
    let least = if opts.quick {
        LEAST_TIMED / 10
    } else {
        LEAST_TIMED
    };
    let most = frames.saturating_mul(100);
    let idle = Duration::from_micros(opts.idle_us);
    let mut times = Vec::with_capacity(frames as usize);
    let mut total = Duration::ZERO;
    let mut timed = 0;
    let start = Instant::now();
    let more = |total: Duration, timed: u32, start: Instant| {
        fixed.is_none() && total < least && timed < most && start.elapsed() < least * 10
    };
    while timed < frames || more(total, timed, start) {
        if !idle.is_zero() {
            let at = Instant::now();
            while at.elapsed() < idle {
                std::hint::spin_loop();
            }
        }
        let at = Instant::now();
        black_box(frame());
        let took = at.elapsed();
        times.push(took);
        total += took;
        timed += 1;
    }
    (timed, times, total)
}

pub(super) fn crowd_lines(opts: &BenchArgs, out: &mut impl Write) -> io::Result<CrowdResult> {
    let json = opts.json;
    let c = crowd_bench(opts);
    if json {
        writeln!(out, "{}", crowd_json(&c))?;
    } else {
        row(out, "crowd", "agents", c.agents.to_string())?;
        row(out, "", "threads", c.threads.to_string())?;
        row(out, "", "frames", c.frames.to_string())?;
        row(out, "", "ms per frame", format!("{:.3}", c.ms_per_frame))?;
        row(out, "", "bytes per member", c.bytes_per_member.to_string())?;
        row(
            out,
            "",
            "bytes per member, mean",
            c.bytes_per_member_mean.to_string(),
        )?;
        if c.idle_us > 0 {
            row(out, "", "idle us before", c.idle_us.to_string())?;
        }
        row(
            out,
            "",
            "ns per member",
            format!("{:.1}", c.ns_per_member()),
        )?;
    }
    out.flush()?;
    Ok(c)
}

pub(super) fn crowd_sleeping_lines(opts: &BenchArgs, out: &mut impl Write) -> io::Result<()> {
    let json = opts.json;
    let s = crowd_sleeping_bench(opts, opts.alert_percent);
    if json {
        writeln!(out, "{}", crowd_sleeping_json(&s))?;
    } else {
        row(out, "crowd_sleeping", "agents", s.agents.to_string())?;
        row(
            out,
            "",
            "awake per frame",
            format!("{:.1}", s.awake_per_frame),
        )?;
        frame_rows(out, &s)?;
        row(out, "", "bytes per member", s.bytes_per_member.to_string())?;
        row(
            out,
            "",
            "bytes per member, mean",
            s.bytes_per_member_mean.to_string(),
        )?;
        if s.idle_us > 0 {
            row(out, "", "idle us before", s.idle_us.to_string())?;
        }
    }
    out.flush()
}

/// A sleeping crowd's time per frame and per awake member, as text rows.
fn frame_rows(out: &mut impl Write, s: &CrowdSleepingResult) -> io::Result<()> {
    row(out, "", "ms per frame", format!("{:.3}", s.ms_per_frame))?;
    row(
        out,
        "",
        "ns per awake member",
        format!("{:.1}", s.ns_per_awake()),
    )
}

/// The sleeping crowd at each of [`AWAKE_PERCENTS`], beside `crowd`'s line when it ran.
pub(super) fn crowd_awake_lines(
    opts: &BenchArgs,
    crowd: Option<&CrowdResult>,
    out: &mut impl Write,
) -> io::Result<()> {
    for percent in AWAKE_PERCENTS {
        let s = crowd_sleeping_bench(opts, percent / AWAKE_FRAMES_PER_ALERT);
        let ratio = crowd.map(|c| {
            (
                s.ns_per_awake() / c.ns_per_member(),
                s.ns_per_awake_median() / c.ns_per_member_median(),
            )
        });
        if opts.json {
            writeln!(out, "{}", crowd_awake_json(&s, ratio))?;
        } else {
            row(out, "crowd_awake", "agents", s.agents.to_string())?;
            row(out, "", "threads", s.threads.to_string())?;
            row(out, "", "awake %", format!("{:.2}", s.awake_percent()))?;
            frame_rows(out, &s)?;
            if let Some((mean, median)) = ratio {
                row(out, "", "/ crowd's per member", format!("{mean:.2}"))?;
                row(out, "", "the same, medians", format!("{median:.2}"))?;
            }
        }
        out.flush()?;
    }
    Ok(())
}

/// `,"idle_us":N` when the frames were timed after other work, else nothing: the lines of
/// frames back to back keep their shape.
pub(super) fn idle_field(idle_us: u64) -> String {
    if idle_us == 0 {
        String::new()
    } else {
        format!(r#","idle_us":{idle_us}"#)
    }
}

pub(super) fn crowd_sleeping_json(s: &CrowdSleepingResult) -> String {
    format!(
        r#"{{"name":"crowd_sleeping","agents":{},"awake_per_frame":{:.1},"ms_per_frame":{:.4},"ns_per_awake":{:.1},"bytes_per_member":{},"bytes_per_member_mean":{}{}}}"#,
        s.agents,
        s.awake_per_frame,
        s.ms_per_frame,
        s.ns_per_awake(),
        s.bytes_per_member,
        s.bytes_per_member_mean,
        idle_field(s.idle_us)
    )
}

/// A `crowd_awake` line; `ratio`: its cost per awake member over the crowd's per member,
/// from the means and from the medians.
pub(super) fn crowd_awake_json(s: &CrowdSleepingResult, ratio: Option<(f64, f64)>) -> String {
    let ratio = ratio.map_or(String::new(), |(mean, median)| {
        format!(r#","awake_cost_ratio":{mean:.2},"awake_cost_ratio_median":{median:.2}"#)
    });
    format!(
        r#"{{"name":"crowd_awake","agents":{},"threads":{},"alert_percent":{:.3},"awake_percent":{:.2},"awake_per_frame":{:.1},"ms_per_frame":{:.4},"ms_per_frame_median":{:.4},"ns_per_awake":{:.1},"ns_per_awake_median":{:.1},"bytes_per_member":{},"bytes_per_member_mean":{}{ratio}{}}}"#,
        s.agents,
        s.threads,
        s.alert_percent,
        s.awake_percent(),
        s.awake_per_frame,
        s.ms_per_frame,
        s.ms_per_frame_median,
        s.ns_per_awake(),
        s.ns_per_awake_median(),
        s.bytes_per_member,
        s.bytes_per_member_mean,
        idle_field(s.idle_us)
    )
}

pub(super) fn crowd_json(c: &CrowdResult) -> String {
    format!(
        r#"{{"name":"crowd","agents":{},"threads":{},"ms_per_frame":{:.4},"frames":{},"bytes_per_member":{},"bytes_per_member_mean":{},"ns_per_member":{:.1},"ms_per_frame_median":{:.4},"ns_per_member_median":{:.1}{}}}"#,
        c.agents,
        c.threads,
        c.ms_per_frame,
        c.frames,
        c.bytes_per_member,
        c.bytes_per_member_mean,
        c.ns_per_member(),
        c.ms_per_frame_median,
        c.ns_per_member_median(),
        idle_field(c.idle_us)
    )
}

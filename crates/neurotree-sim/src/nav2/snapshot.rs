//! The simulation as of one moment, to go back to: what rewinding a watched run restores
//! beside the tree's own state.

use std::time::Duration;

use neurotree_core::Clock;

use super::Nav2Sim;

/// A [`Nav2Sim`] as it was at one moment ([`Nav2Sim::snapshot`]): the world, the servers'
/// goals and counters, and the time.
#[derive(Clone, Debug)]
pub struct Nav2SimState {
    sim: Nav2Sim,
    now: Duration,
}

impl Nav2Sim {
    /// The simulation as it is now, for [`restore`](Self::restore) to go back to.
    ///
    /// ```
    /// use std::time::Duration;
    /// use neurotree::robotics::Pose2D;
    /// use neurotree::sim::nav2::Nav2Sim;
    /// use neurotree::sim::GridWorld;
    ///
    /// let mut sim = Nav2Sim::new(GridWorld::parse("R....", 1.0).unwrap());
    /// let path = sim.world.plan(sim.world.robot(), Pose2D::new(4.5, 0.5, 0.0)).unwrap();
    /// sim.world.follow(path, 1.0);
    /// let before = sim.snapshot();
    /// for _ in 0..10 {
    ///     sim.step();
    /// }
    /// assert_eq!(sim.world.now(), Duration::from_secs(1));
    /// sim.restore(&before);
    /// assert_eq!((sim.world.now(), sim.world.robot().x), (Duration::ZERO, 0.5));
    /// ```
    pub fn snapshot(&self) -> Nav2SimState {
        Nav2SimState {
            sim: self.clone(),
            now: self.world.now(),
        }
    }

    /// Puts the simulation back as `state` has it, the clock too. The clock and the event
    /// log stay the ones this simulation was made with (the tree reads that clock).
    pub fn restore(&mut self, state: &Nav2SimState) {
        let clock = self.world.clock();
        let log = self.log.take();
        *self = state.sim.clone();
        self.world.clock = clock;
        self.log = log;
        self.world.clock.set(state.now);
        debug_assert_eq!(self.world.clock.now(), state.now);
    }
}

#[cfg(test)]
mod tests {
    //! Rewinding a run of each leaf that keeps state: saved after any tick that leaves it
    //! running, and restored with the world into a fresh tree, it runs on as the
    //! uninterrupted run does.

    use std::time::Duration;

    use neurotree_core::Status;
    use neurotree_nav2::robotics::{Pose2D, RouteNode};

    use super::super::testing::{watched, Bench};
    use super::super::{Dock, Nav2Sim, RouteGraph, LEAVES};
    use crate::{Battery, Cell, GridWorld, TimedObstacle};

    /// What a tick shows: the tree's status, the time, and where the robot is.
    type Seen = (Status, Duration, Pose2D);

    /// A leaf's run to rewind: the bench to start it on, what moves the world before each
    /// tick (beside the world's own motions), and the most ticks to run.
    struct Case {
        name: &'static str,
        bench: fn() -> Bench,
        before_tick: fn(&mut Nav2Sim),
        limit: usize,
    }

    fn nothing(_: &mut Nav2Sim) {}

    /// Ticks `b` up to `ticks` times, stepping the world between ticks as `neurotree demo`
    /// does (before every tick but the first of the run, `first` says which it is); stops
    /// after a tick that completes the tree.
    fn run(b: &mut Bench, case: &Case, first: bool, ticks: usize) -> Vec<Seen> {
        let mut seen = Vec::new();
        for i in 0..ticks {
            if i > 0 || !first {
                b.sim.step();
            }
            (case.before_tick)(&mut b.sim);
            let status = b.tick();
            seen.push((status, b.sim.world.now(), b.sim.world.robot()));
            if status != Status::Running {
                break;
            }
        }
        seen
    }

    /// Saves after every tick of the run that leaves the tree running, restores into a
    /// fresh bench, and compares the rest of the run with the uninterrupted one; the
    /// number of ticks tried.
    fn rewinds_anywhere(case: &Case) -> usize {
        let straight = run(&mut (case.bench)(), case, true, case.limit);
        assert_eq!(
            straight.last().map(|s| s.0),
            Some(Status::Success),
            "{}: {straight:?}",
            case.name
        );
        let mut tried = 0;
        for at in 1..straight.len() {
            let mut b = (case.bench)();
            assert_eq!(run(&mut b, case, true, at), straight[..at], "{}", case.name);
            let tree = b.tree.save_state().unwrap_or_else(|e| {
                panic!("{}: cannot save after tick {at}: {e}", case.name);
            });
            let world = b.sim.snapshot();
            let mut fresh = (case.bench)();
            fresh.sim.restore(&world);
            fresh.tree.restore_state(&tree).unwrap();
            let rest = run(&mut fresh, case, false, case.limit - at);
            assert_eq!(
                rest,
                straight[at..],
                "{}, restored after tick {at}",
                case.name
            );
            tried += 1;
        }
        tried
    }

    /// A corridor with the charger and its dock at the west end, the dock facing west.
    fn dock_bench(xml: &str, on_dock: bool) -> Bench {
        let dock = Dock::new(
            "home",
            "charging_dock",
            Pose2D::new(1.5, 0.5, std::f64::consts::PI),
        );
        let mut world = GridWorld::parse("#C...R#", 1.0)
            .unwrap()
            .with_battery(Battery::at(50.0));
        if on_dock {
            world.set_robot(dock.pose).unwrap();
        }
        let mut b = Bench::with_world(world, xml);
        b.sim.docks.push(dock);
        b.set("type", "charging_dock".to_string());
        b
    }

    /// A hall with an obstacle that steps in front of the robot after half a second.
    fn hall_bench(xml: &str) -> Bench {
        let world = GridWorld::parse(".....\nR....\n.....", 1.0)
            .unwrap()
            .with_timed_obstacle(TimedObstacle::new(
                Cell::new(3, 1),
                Duration::from_millis(500),
            ));
        let mut b = Bench::with_world(world, xml);
        b.set_goal(Pose2D::new(4.5, 1.5, 0.0));
        b.set(
            "goals",
            vec![Pose2D::new(2.5, 2.5, 0.0), Pose2D::new(4.5, 0.5, 0.0)],
        );
        b
    }

    /// A corridor, the robot driving east along it at half a metre a second.
    fn driving_bench(xml: &str) -> Bench {
        let mut b = Bench::new("R.........", xml);
        let path = b
            .sim
            .world
            .plan(b.sim.world.robot(), Pose2D::new(9.5, 0.5, 0.0))
            .unwrap();
        b.sim.world.follow(path, 0.5);
        b
    }

    /// The object walks east at half a metre a second from 2 s to 6 s.
    fn walk_object(sim: &mut Nav2Sim) {
        let t = sim.world.now().as_secs_f64();
        let x = 3.5 + 0.5 * (t - 2.0).clamp(0.0, 4.0);
        sim.set_object(Some(Pose2D::new(x, 0.5, 0.0)));
    }

    const CASES: [Case; 11] = [
        Case {
            name: "DockRobot",
            bench: || {
                dock_bench(
                    r#"<DockRobot dock_id="home" error_code_id="{code}"/>"#,
                    false,
                )
            },
            before_tick: nothing,
            limit: 100,
        },
        Case {
            name: "UndockRobot",
            bench: || dock_bench(r#"<UndockRobot dock_type="{type}"/>"#, true),
            before_tick: nothing,
            limit: 100,
        },
        Case {
            name: "NavigateToPose",
            bench: || hall_bench(r#"<NavigateToPose goal="{goal}"/>"#),
            before_tick: nothing,
            limit: 200,
        },
        Case {
            name: "NavigateThroughPoses",
            bench: || hall_bench(r#"<NavigateThroughPoses goals="{goals}"/>"#),
            before_tick: nothing,
            limit: 200,
        },
        Case {
            name: "ComputeAndTrackRoute",
            bench: || {
                let mut b = Bench::new(
                    ".......\n.......\n...#...\nR......",
                    r#"<Parallel success_count="2" failure_count="1">
                         <ComputeAndTrackRoute start_id="1" goal_id="4" path="{path}" next_node_id="{next}"/>
                         <FollowPath path="{path}"/>
                       </Parallel>"#,
                );
                b.sim.route_graph = Some(
                    RouteGraph::new(vec![
                        RouteNode::new(1, 0.5, 0.5),
                        RouteNode::new(4, 6.5, 0.5),
                        RouteNode::new(5, 3.5, 0.5),
                    ])
                    .with_way(1, 5)
                    .with_way(5, 4),
                );
                b
            },
            before_tick: nothing,
            limit: 200,
        },
        Case {
            name: "FollowObject",
            // Started after a wait, so that its start time is not the run's.
            bench: || {
                Bench::new(
                    "R.........",
                    r#"<Sequence><Wait wait_duration="0.5"/><FollowObject max_duration="7.0"/></Sequence>"#,
                )
            },
            before_tick: walk_object,
            limit: 200,
        },
        Case {
            name: "DistanceTraveled",
            bench: || driving_bench(&watched(r#"<DistanceTraveled distance="1.0"/>"#)),
            before_tick: nothing,
            limit: 100,
        },
        Case {
            name: "TimeExpired",
            bench: || Bench::new("R", &watched(r#"<TimeExpired seconds="0.7"/>"#)),
            before_tick: nothing,
            limit: 100,
        },
        Case {
            name: "FollowPath",
            // Planned again every second, from wherever the robot is.
            bench: || {
                let mut b = Bench::new(
                    ".....\nR....\n.....",
                    r#"<PipelineSequence>
                         <RateController hz="1.0"><ComputePathToPose goal="{goal}" path="{path}"/></RateController>
                         <FollowPath path="{path}"/>
                       </PipelineSequence>"#,
                );
                b.set_goal(Pose2D::new(4.5, 2.5, 0.0));
                b
            },
            before_tick: nothing,
            limit: 200,
        },
        Case {
            name: "Spin",
            bench: || Bench::new("R", r#"<Spin spin_dist="1.57"/>"#),
            before_tick: nothing,
            limit: 100,
        },
        Case {
            name: "CheckStopStatus",
            bench: || {
                Bench::new(
                    "R",
                    r#"<CheckStopStatus velocity_threshold="0.1" duration_stopped="450"/>"#,
                )
            },
            before_tick: nothing,
            limit: 100,
        },
    ];

    #[test]
    fn each_stateful_leaf_restored_with_the_world_after_any_running_tick_runs_on_the_same() {
        for case in &CASES {
            let tried = rewinds_anywhere(case);
            // Every case runs a while: its rewinds are not vacuous.
            assert!(tried >= 5, "{}: {tried}", case.name);
        }
    }

    #[test]
    fn every_simulated_leaf_can_be_saved() {
        for name in LEAVES {
            let mut b = Bench::new("R", &format!("<{name}/>"));
            let _ = b.tree.tick_once(&mut b.sim);
            b.tree
                .save_state()
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
}

//! Nav2's odometry nodes over ROS 2: IsStuck and CheckStopStatus subscribed to the `odom`
//! that [`SimServers`](neurotree_ros2::nav2::SimServers) publishes.

use crate::common;

use std::time::{Duration, Instant};

use common::{free_domain, nav2_tree, tick_until_done, Served};
use neurotree_sim::nav2::Nav2Sim;
use neurotree_sim::GridWorld;
use neurotree_toolkit::Status;

/// A hall three cells high; the robot at the left end, (1.5, 3.5).
const HALL: &str = "
    ##############
    #R...........#
    #............#
    #............#
    ##############";

const LIMIT: Duration = common::HANG;

fn serve(domain: u16) -> Served {
    // Twice real time: each odometry message stays the newest for 50 ms of wall time,
    // several of the tests' 10 ms ticks.
    Served::start(
        domain,
        Nav2Sim::new(GridWorld::parse(HALL, 1.0).unwrap()),
        2.0,
    )
}

pub(crate) fn is_stuck_succeeds_after_the_robot_brakes_from_two_metres_a_second_to_standstill() {
    let domain = free_domain();
    let served = serve(domain.id);
    let mut tree = nav2_tree(domain.id, "<IsStuck/>");
    // Odometry is published every step: a few reach the tree's subscription.
    common::after_steps(&served.stats, 4);
    assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Failure);
    // Driving at 2 m/s, cut off after a second: -20 m/s² over the next 0.1 s step.
    let mut tree = nav2_tree(
        domain.id,
        r#"<Sequence>
             <ForceSuccess><Timeout msec="1000">
               <DriveOnHeading dist_to_travel="6.0" speed="2.0"/>
             </Timeout></ForceSuccess>
             <Inverter><KeepRunningUntilFailure><Inverter><IsStuck/></Inverter></KeepRunningUntilFailure></Inverter>
           </Sequence>"#,
    );
    let status = tick_until_done(&mut tree, &mut (), LIMIT);
    let seen = served.stats.get();
    assert_eq!(status, Status::Success, "{seen:?}");
    assert_eq!(seen.drive_on_heading.cancels, 1, "{seen:?}");
    // Standing still since: no longer stuck.
    let mut tree = nav2_tree(domain.id, "<IsStuck/>");
    // Odometry is published every step: a few reach the tree's subscription.
    common::after_steps(&served.stats, 4);
    assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Failure);
}

pub(crate) fn check_stop_status_runs_while_stopped_succeeds_after_the_duration_and_fails_in_motion()
{
    let domain = free_domain();
    let served = serve(domain.id);
    // Before any goal the world's clock stands and the odometry is unstamped: the
    // duration is the tree's.
    let mut tree = nav2_tree(domain.id, r#"<CheckStopStatus duration_stopped="500"/>"#);
    let start = Instant::now();
    assert_eq!(tree.tick_once(&mut ()).unwrap(), Status::Running);
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert!(start.elapsed() >= Duration::from_millis(500));
    // Driving: Failure, which ends the drive.
    let mut tree = nav2_tree(
        domain.id,
        r#"<Parallel success_count="1" failure_count="1">
             <DriveOnHeading dist_to_travel="6.0" speed="1.0"/>
             <Delay delay_msec="1000"><CheckStopStatus/></Delay>
           </Parallel>"#,
    );
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Failure);
    // The halted drive's cancel request reaches the server a step later.
    let until = Instant::now() + common::HANG;
    while served.stats.get().drive_on_heading.cancels == 0 && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(10));
    }
    let seen = served.stats.get();
    assert_eq!(
        (
            seen.drive_on_heading.cancels,
            seen.drive_on_heading.succeeded
        ),
        (1, 0),
        "{seen:?}"
    );
    assert!(seen.robot.x > 1.6 && seen.robot.x < 7.0, "{seen:?}");
    // The clock runs now and stamps the odometry: a second of simulated time stopped.
    let mut tree = nav2_tree(domain.id, r#"<CheckStopStatus duration_stopped="1000"/>"#);
    let start = Instant::now();
    assert_eq!(tick_until_done(&mut tree, &mut (), LIMIT), Status::Success);
    assert!(start.elapsed() >= Duration::from_millis(400));
}

//! The integration tests of `neurotree-ros2`, one binary: each file beside this one is a
//! module of it, and what they share is a module here, declared once.
//!
//! The tests spend most of their time waiting (for DDS discovery, for a simulated world
//! that runs on the wall clock), not computing, so they run more at once than the machine
//! has cores: twice as many, and at least four (`--test-threads` or `RUST_TEST_THREADS`
//! still decides). libtest cannot be told this from inside a test binary, so this binary
//! runs its tests with `libtest-mimic`: the same command line and report, but a test's
//! output is not captured. A test is a plain `pub(crate) fn` listed in [`TESTS`]; one not
//! listed is dead code, which clippy `-D warnings` refuses.

use libtest_mimic::{Arguments, Trial};

mod common;

mod action;
mod battery;
mod behaviors;
mod clearing;
mod costs;
mod cyclonedds;
mod discovery;
mod navigator;
mod odometry;
mod planning;
mod releases;
mod robot;
mod servers;
mod service;
mod subscriber;

/// Every test, by its module and name.
macro_rules! tests {
    ($($module:ident :: $name:ident,)*) => {
        const TESTS: &[(&str, fn())] = &[$(
            (concat!(stringify!($module), "::", stringify!($name)), $module::$name),
        )*];
    };
}

tests! {
    action::an_accepted_goal_runs_with_feedback_and_succeeds_with_the_result,
    action::a_rejected_goal_fails_with_the_reason,
    action::without_a_server_the_node_fails_after_wait_for_server_timeout,
    action::halting_a_running_goal_sends_the_server_a_cancel_request,
    action::registered_for_xml_the_node_has_behaviortree_ros2_ports_and_reports_why_it_failed,
    battery::on_the_charger_with_a_quarter_left_the_battery_is_charging_and_low,
    battery::off_the_charger_the_battery_is_not_charging_nor_low_above_the_minimum,
    behaviors::drive_on_heading_drives_the_served_robot_straight_on,
    behaviors::drive_on_heading_into_the_wall_fails_with_the_servers_collision_code,
    behaviors::a_spin_cancelled_by_someone_else_succeeds_as_nav2s_does,
    behaviors::cancel_spin_asks_the_server_to_cancel_and_the_spin_succeeds,
    clearing::each_region_clearing_forgets_nav2s_square_of_the_costmap_it_names,
    clearing::a_service_no_costmap_serves_fails_the_node,
    costs::check_pose_occupancy_succeeds_on_a_wall_and_fails_on_the_floor_and_off_the_map,
    costs::remove_in_collision_goals_keeps_the_free_goals_and_fails_without_goals_or_an_answer,
    costs::toggle_collision_monitor_switches_the_served_monitor_and_relocalization_is_counted,
    cyclonedds::a_cyclone_dds_node_and_a_tree_exchange_std_msgs_string_on_chatter,
    discovery::two_loopback_participants_discover_each_other_and_exchange_a_message,
    navigator::the_navigator_drives_the_robot_to_the_goal_through_an_obstacle_with_a_recovery,
    navigator::cancelling_the_goal_halts_the_tree_and_cancels_follow_path_on_the_server,
    navigator::an_application_trees_navigate_to_pose_is_served_by_the_navigator,
    navigator::the_navigator_loads_every_node_type_of_nav2_main_and_refuses_an_unknown_one_by_name,
    odometry::is_stuck_succeeds_after_the_robot_brakes_from_two_metres_a_second_to_standstill,
    odometry::check_stop_status_runs_while_stopped_succeeds_after_the_duration_and_fails_in_motion,
    planning::a_path_through_the_poses_is_planned_and_smoothed_by_the_servers,
    planning::the_servers_error_codes_reach_the_tree,
    releases::each_release_sends_its_goals_and_its_servers_read_them,
    releases::a_jazzy_goal_is_not_read_by_main_servers_which_go_on_serving,
    robot::a_navigator_over_the_robots_own_context_runs_its_leaf_between_nav2s_clients,
    servers::compute_route_writes_the_servers_route_and_fails_with_its_code,
    servers::compute_and_track_route_follows_the_robot_along_the_route_to_its_end,
    servers::the_new_cancel_nodes_cancel_route_tracking_following_and_teleop_which_then_succeed,
    servers::dock_robot_docks_at_the_servers_dock_and_undock_robot_backs_off_it,
    servers::navigate_through_poses_takes_the_robot_through_each_pose_and_fails_with_the_servers_code,
    servers::follow_object_follows_for_max_duration_fails_unseen_and_follows_a_published_pose,
    servers::assisted_teleop_times_out_as_nav2s_and_fails_only_as_a_recovery,
    servers::a_new_path_or_route_goal_while_the_goal_runs_is_sent_in_its_place_as_nav2s,
    service::a_request_is_answered_and_the_node_succeeds,
    service::without_a_server_the_node_fails_and_writes_the_reason_to_error_msg,
    subscriber::the_condition_fails_until_a_message_arrives_then_outputs_the_newest,
}

fn main() {
    let mut args = Arguments::from_args();
    if args.test_threads.is_none() {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let asked = std::env::var("RUST_TEST_THREADS").ok();
        args.test_threads = Some(match asked.and_then(|n| n.parse().ok()) {
            Some(threads) => threads,
            None => (2 * cores).max(4),
        });
    }
    let trials = TESTS
        .iter()
        .map(|&(name, test)| {
            Trial::test(name, move || {
                test();
                Ok(())
            })
        })
        .collect();
    libtest_mimic::run(&args, trials).exit();
}

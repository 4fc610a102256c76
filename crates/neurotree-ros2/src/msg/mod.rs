//! The ROS 2 messages, services and actions the Nav2 navigator needs, as Rust types with
//! their ROS 2 names (ROS 2 Jazzy's definitions).
//!
//! | package | types |
//! |---|---|
//! | [`builtin_interfaces`] | `Time`, `Duration` |
//! | [`std_msgs`] | `Header`, `String`, `Empty` |
//! | [`geometry_msgs`] | `Point`, `Quaternion`, `Pose`, `PoseStamped`, `Vector3`, `Twist`, `PoseWithCovariance`, `TwistWithCovariance` |
//! | [`nav_msgs`] | `Path`, `Goals`, `Odometry` |
//! | [`nav2_msgs`] | the actions of Nav2's planner, smoother, controller, behaviors, navigators, route, docking and following servers; the costmaps' clearing and `GetCosts` services, `Toggle`; `Route`, `WaypointStatus` |
//! | [`sensor_msgs`] | `BatteryState` |
//! | [`std_srvs`] | service `Empty` |
//!
//! Field order is the wire format: each struct lists the fields of its `.msg` file in order.
//! A definition with no field (`std_msgs/Empty`, an empty feedback) carries the one byte
//! that ROS 2's code generators add, `structure_needs_at_least_one_member`.

pub mod builtin_interfaces;
pub mod geometry_msgs;
pub mod nav2_msgs;
pub mod nav_msgs;
pub mod sensor_msgs;
pub mod std_msgs;
pub mod std_srvs;

#[cfg(test)]
mod tests {
    //! The bytes ROS 2 puts on the wire for a few messages (CDR, little-endian), as laid out
    //! by their `.msg` files: a field order or type mistake changes them.

    use super::builtin_interfaces::Duration;
    use super::geometry_msgs::{Pose, PoseStamped};
    use super::nav2_msgs::{
        ClearEntireCostmapRequest, ComputeRouteGoal, GetCostsResponse, SpinGoal,
    };
    use super::nav_msgs::Odometry;
    use super::std_msgs::{Empty, Header, String};
    use byteorder::LittleEndian;

    fn cdr<T: serde::Serialize>(value: &T) -> Vec<u8> {
        rustdds::serialization::to_vec::<T, LittleEndian>(value).unwrap()
    }

    #[test]
    fn an_empty_message_is_one_byte() {
        assert_eq!(cdr(&Empty::default()), [0]);
        assert_eq!(cdr(&ClearEntireCostmapRequest::default()), [0]);
    }

    #[test]
    fn a_string_is_its_length_with_the_nul_then_its_bytes_and_a_nul() {
        assert_eq!(cdr(&String::from("hi")), [3, 0, 0, 0, b'h', b'i', 0]);
    }

    #[test]
    fn a_spin_goal_is_a_float32_then_a_duration() {
        let goal = SpinGoal {
            target_yaw: 1.0,
            time_allowance: Duration { sec: 2, nanosec: 3 },
        };
        let mut expected = 1.0f32.to_le_bytes().to_vec();
        expected.extend(2i32.to_le_bytes());
        expected.extend(3u32.to_le_bytes());
        assert_eq!(cdr(&goal), expected);
    }

    #[test]
    fn a_route_goal_puts_its_node_ids_around_a_pose_stamped_aligned_to_8() {
        let goal = ComputeRouteGoal {
            start_id: 7,
            goal_id: 9,
            use_poses: true,
            ..ComputeRouteGoal::default()
        };
        let bytes = cdr(&goal);
        assert_eq!(&bytes[0..2], &[7, 0]);
        // The start's header at 4: stamp (8), an empty frame id (4 + 1); its pose at 24.
        assert_eq!(&bytes[12..17], &[1, 0, 0, 0, 0]);
        assert_eq!(
            &bytes[80..82],
            &[9, 0],
            "goal_id after the start's 56-byte pose"
        );
        // The goal's pose ends at 160; then use_start and use_poses.
        assert_eq!(&bytes[160..], &[0, 1]);
    }

    #[test]
    fn kilteds_behavior_goals_add_one_byte_and_its_through_poses_goal_a_header() {
        use super::nav2_msgs::kilted;
        let jazzy = cdr(&SpinGoal::default());
        let checked = cdr(&kilted::SpinGoal {
            disable_collision_checks: true,
            ..kilted::SpinGoal::default()
        });
        assert_eq!(checked.len(), jazzy.len() + 1);
        assert_eq!(checked[..jazzy.len()], jazzy[..]);
        assert_eq!(checked.last(), Some(&1));
        // Goals: a header (stamp, empty frame id) before the poses' count.
        let goal = kilted::ComputePathThroughPosesGoal::default();
        assert_eq!(
            &cdr(&goal)[..17],
            &[0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0]
        );
    }

    #[test]
    fn mains_clearing_requests_name_plugins_after_the_square() {
        use super::nav2_msgs::main;
        let request = main::ClearCostmapAroundRobotRequest {
            reset_distance: 2.0,
            plugins: vec!["obstacle_layer".into()],
        };
        let mut expected = 2.0f32.to_le_bytes().to_vec();
        expected.extend(1u32.to_le_bytes());
        expected.extend(cdr(&String::from("obstacle_layer").data));
        assert_eq!(cdr(&request), expected);
        assert_eq!(cdr(&main::ClearResponse { success: true }), [1]);
    }

    #[test]
    fn odometry_covariances_are_36_float64_without_a_length() {
        let mut odometry = Odometry {
            header: Header {
                frame_id: "odom".into(),
                ..Header::default()
            },
            child_frame_id: "base_link".into(),
            ..Odometry::default()
        };
        odometry.pose.covariance.0[0] = 2.0;
        odometry.twist.twist.linear.x = 0.5;
        let bytes = cdr(&odometry);
        // Header 17, child frame at 20 (4 + 10) to 34, the pose at 40, its covariance at
        // 96, the twist at 384, its covariance at 432 to 720.
        assert_eq!(bytes.len(), 720);
        assert_eq!(&bytes[96..104], &2.0f64.to_le_bytes());
        assert_eq!(&bytes[384..392], &0.5f64.to_le_bytes());
        let back: Odometry = rustdds::cdr_encoding::from_bytes::<Odometry, LittleEndian>(&bytes)
            .unwrap()
            .0;
        assert_eq!(back, odometry);
    }

    #[test]
    fn get_costs_answers_a_length_prefixed_float32_list_then_success() {
        let response = GetCostsResponse {
            costs: vec![0.0, 254.0],
            success: true,
        };
        let mut expected = 2u32.to_le_bytes().to_vec();
        expected.extend(0.0f32.to_le_bytes());
        expected.extend(254.0f32.to_le_bytes());
        expected.push(1);
        assert_eq!(cdr(&response), expected);
    }

    #[test]
    fn a_pose_stamped_is_its_header_then_seven_float64_aligned_to_8() {
        let pose = PoseStamped {
            header: Header {
                frame_id: "map".into(),
                ..Header::default()
            },
            pose: Pose::default(),
        };
        let bytes = cdr(&pose);
        // stamp (8) + "map" (4 + 4) = 16, already aligned; then x, y, z, qx, qy, qz, qw.
        assert_eq!(bytes.len(), 16 + 7 * 8);
        assert_eq!(&bytes[8..16], &[4, 0, 0, 0, b'm', b'a', b'p', 0]);
        assert_eq!(&bytes[64..72], &1.0f64.to_le_bytes(), "w of the identity");
    }
}

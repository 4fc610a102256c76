//! The ROS 2 messages, services and actions the Nav2 navigator needs, as Rust types with
//! their ROS 2 names (ROS 2 Jazzy's definitions).
//!
//! | package | types |
//! |---|---|
//! | [`builtin_interfaces`] | `Time`, `Duration` |
//! | [`std_msgs`] | `Header`, `String`, `Empty` |
//! | [`geometry_msgs`] | `Point`, `Quaternion`, `Pose`, `PoseStamped`, `Vector3`, `Twist` |
//! | [`nav_msgs`] | `Path` |
//! | [`nav2_msgs`] | actions `NavigateToPose`, `ComputePathToPose`, `FollowPath`, `Spin`, `BackUp`, `Wait`; service `ClearEntireCostmap` |
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

#[cfg(test)]
mod tests {
    //! The bytes ROS 2 puts on the wire for a few messages (CDR, little-endian), as laid out
    //! by their `.msg` files: a field order or type mistake changes them.

    use super::builtin_interfaces::Duration;
    use super::geometry_msgs::{Pose, PoseStamped};
    use super::nav2_msgs::{ClearEntireCostmapRequest, SpinGoal};
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

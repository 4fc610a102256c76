//! `geometry_msgs`: points, orientations, poses and velocities.

include!(concat!(env!("OUT_DIR"), "/geometry_msgs.rs"));

impl Quaternion {
    /// A rotation of `yaw` radians about z.
    pub fn from_yaw(yaw: f64) -> Self {
        let (s, c) = (yaw / 2.0).sin_cos();
        Self {
            x: 0.0,
            y: 0.0,
            z: s,
            w: c,
        }
    }

    /// The rotation about z, in radians (-π, π].
    pub fn yaw(&self) -> f64 {
        let siny = 2.0 * (self.w * self.z + self.x * self.y);
        let cosy = 1.0 - 2.0 * (self.y * self.y + self.z * self.z);
        siny.atan2(cosy)
    }
}

/// A 6×6 covariance matrix, row-major (x, y, z, rotation about x, y, z): ROS 2's
/// `float64[36]`, a fixed array, so no length goes on the wire.
pub type Covariance = super::FixedArray<f64, 36>;

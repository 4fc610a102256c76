//! The robot's battery: it drains as the robot moves and charges on the charger.

/// A battery level in percent, with the rates that move it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Battery {
    level: f64,
    /// Percent used per metre driven.
    pub drain_per_metre: f64,
    /// Percent used per radian turned on the spot.
    pub drain_per_radian: f64,
    /// Percent gained per second on the charger while standing still.
    pub charge_per_second: f64,
}

impl Default for Battery {
    /// Full, 1 % per metre, 0.1 % per radian, 5 % per second of charging.
    fn default() -> Self {
        Self {
            level: 100.0,
            drain_per_metre: 1.0,
            drain_per_radian: 0.1,
            charge_per_second: 5.0,
        }
    }
}

impl Battery {
    /// The default battery at `level` percent (clamped to 0..=100).
    pub fn at(level: f64) -> Self {
        Self {
            level: clamp(level),
            ..Self::default()
        }
    }

    /// The charge left, in percent.
    pub fn level(&self) -> f64 {
        self.level
    }

    /// `true` when nothing is left to move with.
    pub fn is_empty(&self) -> bool {
        self.level <= 0.0
    }

    /// How many metres the charge left still drives.
    pub fn range(&self) -> f64 {
        if self.drain_per_metre > 0.0 {
            self.level / self.drain_per_metre
        } else {
            f64::INFINITY
        }
    }

    /// Uses the charge for driving `metres` and turning `radians`.
    pub(crate) fn drain(&mut self, metres: f64, radians: f64) {
        let used = metres.abs() * self.drain_per_metre + radians.abs() * self.drain_per_radian;
        self.level = clamp(self.level - used);
    }

    /// Charges for `seconds`.
    pub(crate) fn charge(&mut self, seconds: f64) {
        self.level = clamp(self.level + seconds * self.charge_per_second);
    }
}

fn clamp(level: f64) -> f64 {
    if level.is_nan() {
        0.0
    } else {
        level.clamp(0.0, 100.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drains_with_motion_and_charges_up_to_full() {
        let mut b = Battery::at(50.0);
        b.drain(10.0, 0.0);
        assert_eq!(b.level(), 40.0);
        b.drain(0.0, 10.0);
        assert_eq!(b.level(), 39.0);
        assert_eq!(b.range(), 39.0);
        b.charge(2.0);
        assert_eq!(b.level(), 49.0);
        b.charge(100.0);
        assert_eq!(b.level(), 100.0);
        b.drain(1_000.0, 0.0);
        assert_eq!(b.level(), 0.0);
        assert!(b.is_empty());
        assert_eq!(Battery::at(f64::NAN).level(), 0.0);
        assert_eq!(Battery::at(120.0).level(), 100.0);
    }
}

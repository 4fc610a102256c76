//! The simulated sensors: a lidar, a camera and a battery gauge.
//!
//! Each is a [`SensorReader`], so the [sensor node](neurotree_nav2::robotics::sensor) reads it
//! as it would a real device. The world samples every sensor at the end of each
//! [`step`](super::GridWorld::step), the way a driver keeps the latest message of a device that
//! publishes at its own rate; a read returns that sample. Noise comes from a seeded generator
//! ([`GridWorld::with_seed`](super::GridWorld::with_seed)), so runs repeat exactly.
//!
//! | sensor | values | quality |
//! |---|---|---|
//! | [`Lidar`] | `ranges`, `min_range`, `hits` | fixed, 1.0 unless set |
//! | [`Camera`] | `objects`, `count`, `nearest` | `base` minus a random share of `jitter` |
//! | [`BatterySensor`] | `level` (percent), `charging` | 1.0 |
//!
//! - The lidar's `ranges` are in metres, one per beam, counter-clockwise from the heading;
//!   `hits` are the centres of the cells the beams hit.
//! - The camera's `objects` are the centres of the obstacles in view, nearest first; `nearest`
//!   is in metres (the range if none). Its quality is drawn afresh per frame.
//!
//! The camera sees obstacles, not walls, as an object detector would; neither sensor sees
//! through walls' cells, but the camera ignores occlusion between obstacles.

use std::f64::consts::PI;
use std::time::Duration;

use super::battery::Battery;
use super::grid::Cell;
use super::world::Truth;
use neurotree_nav2::robotics::{Pose2D, SensorData, SensorError, SensorReader};

/// What every simulated sensor shares: the latest sample, availability, a generator.
#[derive(Clone, Debug)]
struct Device {
    latest: Option<SensorData>,
    available: bool,
    rng: fastrand::Rng,
}

impl Device {
    fn new(seed: u64) -> Self {
        Self {
            latest: None,
            available: true,
            rng: fastrand::Rng::with_seed(seed),
        }
    }

    fn read(&self) -> Result<SensorData, SensorError> {
        if !self.available {
            return Err(SensorError::Unavailable);
        }
        self.latest
            .clone()
            .ok_or_else(|| SensorError::ReadFailed("no sample yet".into()))
    }
}

/// A planar lidar: beams all around, each measuring the distance to the first occupied cell.
#[derive(Clone, Debug)]
pub struct Lidar {
    device: Device,
    beams: u16,
    max_range: f64,
    noise: f64,
    quality: f64,
}

impl Lidar {
    pub(super) fn new(seed: u64) -> Self {
        Self {
            device: Device::new(seed),
            beams: 16,
            max_range: 4.0,
            noise: 0.0,
            quality: 1.0,
        }
    }

    pub(super) fn reseed(&mut self, seed: u64) {
        self.device.rng = fastrand::Rng::with_seed(seed);
    }

    /// Sets the number of beams (at least one) and their range in metres.
    pub fn configure(&mut self, beams: u16, max_range: f64) {
        self.beams = beams.max(1);
        self.max_range = max_range.max(0.0);
    }

    /// Adds uniform noise of up to ± `metres` to every range.
    pub fn set_noise(&mut self, metres: f64) {
        self.noise = metres.abs();
    }

    /// Sets the quality the samples report.
    pub fn set_quality(&mut self, quality: f64) {
        self.quality = quality;
    }

    /// Switches the device on or off; reads fail while it is off.
    pub fn set_available(&mut self, available: bool) {
        self.device.available = available;
    }

    pub(super) fn sample(&mut self, truth: &Truth<'_>, robot: Pose2D) {
        let res = truth.map.resolution();
        let here = truth.map.cell_at(&robot);
        // Steps of a sixteenth of a cell find every cell a beam crosses but its corners.
        let step = res / 16.0;
        let mut ranges = Vec::with_capacity(usize::from(self.beams));
        let mut hits: Vec<Pose2D> = Vec::new();
        for beam in 0..self.beams {
            let angle = robot.theta + 2.0 * PI * f64::from(beam) / f64::from(self.beams);
            let (dx, dy) = (angle.cos(), angle.sin());
            let mut range = self.max_range;
            let mut s = 0.0;
            while s < self.max_range {
                s += step;
                let point = Pose2D::new(robot.x + s * dx, robot.y + s * dy, 0.0);
                let cell = truth.map.cell_at(&point);
                match cell {
                    _ if cell == here => continue,
                    Some(c) if !truth.is_occupied(c) => continue,
                    // An occupied cell, or the edge of the map.
                    _ => {
                        range = s.min(self.max_range);
                        let centre = cell.map(|c| truth.map.centre(c));
                        if let Some(centre) = centre.filter(|c| !hits.contains(c)) {
                            hits.push(centre);
                        }
                        break;
                    }
                }
            }
            if self.noise > 0.0 {
                range = (range + (self.device.rng.f64() * 2.0 - 1.0) * self.noise).max(0.0);
            }
            ranges.push(range);
        }
        let min_range = ranges.iter().copied().fold(self.max_range, f64::min);
        self.device.latest = Some(
            SensorData::new(truth.now, self.quality)
                .with("ranges", ranges)
                .with("min_range", min_range)
                .with("hits", hits),
        );
    }
}

impl SensorReader for Lidar {
    fn read(&mut self) -> Result<SensorData, SensorError> {
        self.device.read()
    }
    fn sensor_type(&self) -> &str {
        "lidar"
    }
    fn is_available(&self) -> bool {
        self.device.available
    }
}

/// A forward camera with an object detector: it reports the obstacles in its field of view.
#[derive(Clone, Debug)]
pub struct Camera {
    device: Device,
    field_of_view: f64,
    range: f64,
    base: f64,
    jitter: f64,
}

impl Camera {
    pub(super) fn new(seed: u64) -> Self {
        Self {
            device: Device::new(seed),
            field_of_view: PI / 2.0,
            range: 3.0,
            base: 0.95,
            jitter: 0.0,
        }
    }

    pub(super) fn reseed(&mut self, seed: u64) {
        self.device.rng = fastrand::Rng::with_seed(seed);
    }

    /// Sets the field of view (radians, centred on the heading) and the range in metres.
    pub fn configure(&mut self, field_of_view: f64, range: f64) {
        self.field_of_view = field_of_view.abs();
        self.range = range.max(0.0);
    }

    /// Frames report a quality of `base` minus a random share of `jitter` (glare, blur).
    pub fn set_quality(&mut self, base: f64, jitter: f64) {
        self.base = base;
        self.jitter = jitter.abs();
    }

    /// Switches the device on or off; reads fail while it is off.
    pub fn set_available(&mut self, available: bool) {
        self.device.available = available;
    }

    pub(super) fn sample(&mut self, truth: &Truth<'_>, robot: Pose2D) {
        let mut seen: Vec<(f64, Cell)> = truth
            .timed
            .iter()
            .filter(|o| o.is_present(truth.now))
            .map(|o| o.cell)
            .filter_map(|cell| {
                let centre = truth.map.centre(cell);
                let distance = centre.distance(&robot);
                let bearing = (centre.y - robot.y).atan2(centre.x - robot.x) - robot.theta;
                let off_axis = bearing.sin().atan2(bearing.cos()).abs();
                (distance <= self.range && off_axis <= self.field_of_view / 2.0)
                    .then_some((distance, cell))
            })
            .collect();
        seen.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        seen.dedup_by_key(|s| s.1);
        let quality = self.base - self.device.rng.f64() * self.jitter;
        let objects: Vec<Pose2D> = seen.iter().map(|(_, c)| truth.map.centre(*c)).collect();
        self.device.latest = Some(
            SensorData::new(truth.now, quality)
                .with("count", objects.len() as f64)
                .with("nearest", seen.first().map_or(self.range, |s| s.0))
                .with("objects", objects),
        );
    }
}

impl SensorReader for Camera {
    fn read(&mut self) -> Result<SensorData, SensorError> {
        self.device.read()
    }
    fn sensor_type(&self) -> &str {
        "camera"
    }
    fn is_available(&self) -> bool {
        self.device.available
    }
}

/// The battery gauge.
#[derive(Clone, Debug)]
pub struct BatterySensor {
    device: Device,
}

impl Default for BatterySensor {
    fn default() -> Self {
        Self {
            device: Device::new(0),
        }
    }
}

impl BatterySensor {
    /// Switches the gauge on or off; reads fail while it is off.
    pub fn set_available(&mut self, available: bool) {
        self.device.available = available;
    }

    pub(super) fn sample(&mut self, now: Duration, battery: &Battery, charging: bool) {
        self.device.latest = Some(
            SensorData::new(now, 1.0)
                .with("level", battery.level())
                .with("charging", charging),
        );
    }
}

impl SensorReader for BatterySensor {
    fn read(&mut self) -> Result<SensorData, SensorError> {
        self.device.read()
    }
    fn sensor_type(&self) -> &str {
        "battery"
    }
    fn is_available(&self) -> bool {
        self.device.available
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{GridWorld, TimedObstacle};

    /// A 7 × 3 room, the robot in the middle row on the left, facing +x.
    fn room() -> GridWorld {
        GridWorld::parse(
            "
            .......
            R......
            .......",
            1.0,
        )
        .unwrap()
    }

    #[test]
    fn the_lidar_measures_to_the_first_occupied_cell_or_the_edge() {
        let mut w = room().with_timed_obstacle(TimedObstacle::new(Cell::new(3, 1), Duration::ZERO));
        w.lidar().configure(4, 10.0);
        w.step(Duration::ZERO);
        let scan = w.lidar().read().unwrap();
        // Ahead, left, behind, right; measured in sixteenths of a cell.
        assert_eq!(
            scan.numbers("ranges"),
            Some(&[2.5, 1.5, 0.5625, 1.5625][..])
        );
        assert_eq!(scan.number("min_range"), Some(0.5625));
        assert_eq!(scan.poses("hits"), Some(&[Pose2D::new(3.5, 1.5, 0.0)][..]));
        assert_eq!((scan.quality, scan.timestamp), (1.0, Duration::ZERO));
        assert_eq!(w.lidar().sensor_type(), "lidar");
    }

    #[test]
    fn lidar_noise_repeats_with_its_seed() {
        let scan = |seed| {
            let mut w = room().with_seed(seed);
            w.lidar().set_noise(0.1);
            w.step(Duration::from_millis(100));
            w.lidar()
                .read()
                .unwrap()
                .numbers("ranges")
                .unwrap()
                .to_vec()
        };
        assert_eq!(scan(7), scan(7));
        assert_ne!(scan(7), scan(8));
        let clean = room().lidar().read().unwrap();
        let noisy = scan(7);
        let ranges = clean.numbers("ranges").unwrap();
        assert!(noisy
            .iter()
            .zip(ranges)
            .all(|(n, c)| (n - c).abs() <= 0.1 && n != c));
    }

    #[test]
    fn the_camera_sees_obstacles_in_its_field_of_view_and_range() {
        let mut w = room()
            .with_timed_obstacle(TimedObstacle::new(Cell::new(2, 1), Duration::ZERO))
            .with_timed_obstacle(TimedObstacle::new(Cell::new(0, 0), Duration::ZERO))
            .with_timed_obstacle(TimedObstacle::new(Cell::new(3, 2), Duration::ZERO))
            .with_timed_obstacle(TimedObstacle::new(Cell::new(1, 1), Duration::from_secs(1)));
        let frame = w.camera().read().unwrap();
        // Below (0, 0) is out of view; (3, 2) is 3.16 m away, beyond the 3 m range.
        assert_eq!(
            frame.poses("objects"),
            Some(&[Pose2D::new(2.5, 1.5, 0.0)][..])
        );
        assert_eq!(frame.number("count"), Some(1.0));
        assert_eq!(frame.number("nearest"), Some(2.0));
        assert_eq!(frame.quality, 0.95);
        w.step(Duration::from_secs(1));
        let frame = w.camera().read().unwrap();
        assert_eq!(frame.number("count"), Some(2.0));
        assert_eq!(frame.number("nearest"), Some(1.0));
        assert_eq!(frame.timestamp, Duration::from_secs(1));
        w.camera().configure(std::f64::consts::PI * 2.0, 1.0);
        w.step(Duration::ZERO);
        let frame = w.camera().read().unwrap();
        assert_eq!(frame.number("count"), Some(2.0), "{frame:?}");
    }

    #[test]
    fn camera_quality_jitters_the_same_way_for_the_same_seed() {
        let qualities = |seed| {
            let mut w = room().with_seed(seed);
            w.camera().set_quality(0.9, 0.4);
            (0..20)
                .map(|_| {
                    w.step(Duration::from_millis(100));
                    w.camera().read().unwrap().quality
                })
                .collect::<Vec<f64>>()
        };
        let a = qualities(3);
        assert_eq!(a, qualities(3));
        assert_ne!(a, qualities(4));
        assert!(a.iter().all(|q| (0.5..=0.9).contains(q)));
        assert!(a.iter().any(|q| *q < 0.7) && a.iter().any(|q| *q >= 0.7));
    }

    #[test]
    fn unavailable_sensors_refuse_to_read() {
        let mut w = room();
        w.lidar().set_available(false);
        w.camera().set_available(false);
        w.battery_sensor().set_available(false);
        assert_eq!(w.lidar().read(), Err(SensorError::Unavailable));
        assert_eq!(w.camera().read(), Err(SensorError::Unavailable));
        assert_eq!(w.battery_sensor().read(), Err(SensorError::Unavailable));
        assert!(!w.lidar().is_available());
        w.lidar().set_available(true);
        assert!(w.lidar().read().is_ok());
    }

    #[test]
    fn the_battery_gauge_reads_level_and_charging() {
        let mut w = GridWorld::parse("RC", 1.0)
            .unwrap()
            .with_battery(crate::Battery::at(40.0));
        let gauge = w.battery_sensor().read().unwrap();
        assert_eq!(gauge.number("level"), Some(40.0));
        assert_eq!(gauge.flag("charging"), Some(false));
        let to = Pose2D::new(1.5, 0.5, 0.0);
        let path = neurotree_nav2::robotics::Path::new(vec![w.robot(), to]);
        w.follow(path, 1.0);
        w.step(Duration::from_secs(1));
        w.step(Duration::from_secs(1));
        let gauge = w.battery_sensor().read().unwrap();
        assert_eq!(gauge.number("level"), Some(44.0));
        assert_eq!(gauge.flag("charging"), Some(true));
        assert_eq!(w.battery_sensor().sensor_type(), "battery");
    }
}

//! Sensor nodes: read a sensor, check the reading's quality, publish it on the blackboard.
//!
//! [`SensorNode`] has the ports `output` and `min_quality` (default 0). Never Running.
//!
//! - Sensor unavailable → Failure (the sensor is not read).
//! - Read error → Failure.
//! - Reading quality below `min_quality` → Failure.
//! - Else the reading is written to the `output` entry → Success.
//!
//! A sensor is anything that implements [`SensorReader`]: a driver for a real device, or one
//! of the simulated sensors of `neurotree::sim`.
//!
//! # Where the sensor lives
//!
//! The node does not own its sensor: it reaches it through the user's context `C` with an
//! accessor, `Fn(&mut C) -> &mut dyn SensorReader` (for example `|r: &mut Robot| &mut r.lidar`).
//! A sensor is a device of the robot, not of one tree: the robot (the context) owns it, the
//! rest of the program (a driver thread's buffer, a logger, the simulator that produces its
//! samples) reaches it too, and one blueprint serves many robots, each with its own sensors.
//! The node therefore keeps no state and is a plain [`Action`], shared by every instance of
//! the blueprint: a sensor node keeps no state of its own by construction.
//!
//! ```
//! use std::time::Duration;
//! use neurotree::robotics::{RoboticsBuilder, SensorData, SensorError, SensorReader};
//! use neurotree::{Blueprint, ManualClock, Status, Tree};
//!
//! /// A thermometer that reads 21.5 °C.
//! struct Thermometer;
//! impl SensorReader for Thermometer {
//!     fn read(&mut self) -> Result<SensorData, SensorError> {
//!         Ok(SensorData::new(Duration::ZERO, 0.9).with("celsius", 21.5))
//!     }
//!     fn sensor_type(&self) -> &str { "thermometer" }
//! }
//!
//! struct Robot { thermometer: Thermometer }
//!
//! let blueprint = Blueprint::<Robot>::builder()
//!     .sensor("read_temperature", "temperature", 0.8, |r: &mut Robot| &mut r.thermometer)
//!     .build_shared()
//!     .unwrap();
//! let mut tree = Tree::with_clock(blueprint, ManualClock::new());
//! let mut robot = Robot { thermometer: Thermometer };
//! assert_eq!(tree.tick_once(&mut robot), Ok(Status::Success));
//! let reading: SensorData = tree.blackboard().get("temperature").unwrap();
//! assert_eq!(reading.number("celsius"), Some(21.5));
//! ```

use std::cmp::Ordering;
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use neurotree_core::{Action, Handle, Status};

use super::Pose2D;
use neurotree_toolkit::registry::{PortSpec, Registry, RegistryError};

/// Why a sensor gave no reading.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SensorError {
    /// The device is switched off, disconnected or not yet initialised.
    #[error("the sensor is not available")]
    Unavailable,
    /// The device answered, but not with a reading.
    #[error("the sensor read failed: {0}")]
    ReadFailed(String),
}

neurotree_core::debug_shows_message!(
    enum SensorError {
        Unavailable,
        ReadFailed(source),
    }
);

/// One named value of a reading.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SensorValue {
    /// A single measurement (a range, a battery level, a temperature).
    Number(f64),
    /// A series of measurements (the ranges of a scan).
    Numbers(Vec<f64>),
    /// A position (a detected object, a fix).
    Pose(Pose2D),
    /// Several positions (every object a camera detected).
    Poses(Vec<Pose2D>),
    /// A yes/no state (charging, triggered).
    Flag(bool),
}

impl From<f64> for SensorValue {
    fn from(v: f64) -> Self {
        SensorValue::Number(v)
    }
}

impl From<Vec<f64>> for SensorValue {
    fn from(v: Vec<f64>) -> Self {
        SensorValue::Numbers(v)
    }
}

impl From<Pose2D> for SensorValue {
    fn from(v: Pose2D) -> Self {
        SensorValue::Pose(v)
    }
}

impl From<Vec<Pose2D>> for SensorValue {
    fn from(v: Vec<Pose2D>) -> Self {
        SensorValue::Poses(v)
    }
}

impl From<bool> for SensorValue {
    fn from(v: bool) -> Self {
        SensorValue::Flag(v)
    }
}

/// A reading: when it was taken, how trustworthy it is, and its named values.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SensorData {
    /// When the reading was taken, on the same time base as the tree's clock.
    pub timestamp: Duration,
    /// How trustworthy the reading is, from 0.0 (useless) to 1.0 (perfect).
    pub quality: f64,
    /// The measurements, by name.
    pub values: BTreeMap<String, SensorValue>,
}

impl SensorData {
    /// A reading with no values yet.
    pub fn new(timestamp: Duration, quality: f64) -> Self {
        Self {
            timestamp,
            quality,
            values: BTreeMap::new(),
        }
    }

    /// The reading with `name` set to `value`.
    pub fn with(mut self, name: &str, value: impl Into<SensorValue>) -> Self {
        self.values.insert(name.to_string(), value.into());
        self
    }

    /// The value `name`, if it is a [`SensorValue::Number`].
    pub fn number(&self, name: &str) -> Option<f64> {
        match self.values.get(name)? {
            SensorValue::Number(v) => Some(*v),
            _ => None,
        }
    }

    /// The value `name`, if it is a [`SensorValue::Numbers`].
    pub fn numbers(&self, name: &str) -> Option<&[f64]> {
        match self.values.get(name)? {
            SensorValue::Numbers(v) => Some(v),
            _ => None,
        }
    }

    /// The value `name`, if it is a [`SensorValue::Pose`].
    pub fn pose(&self, name: &str) -> Option<Pose2D> {
        match self.values.get(name)? {
            SensorValue::Pose(v) => Some(*v),
            _ => None,
        }
    }

    /// The value `name`, if it is a [`SensorValue::Poses`].
    pub fn poses(&self, name: &str) -> Option<&[Pose2D]> {
        match self.values.get(name)? {
            SensorValue::Poses(v) => Some(v),
            _ => None,
        }
    }

    /// The value `name`, if it is a [`SensorValue::Flag`].
    pub fn flag(&self, name: &str) -> Option<bool> {
        match self.values.get(name)? {
            SensorValue::Flag(v) => Some(*v),
            _ => None,
        }
    }
}

/// A source of readings: a device driver, or a simulated sensor.
pub trait SensorReader {
    /// Takes a reading.
    fn read(&mut self) -> Result<SensorData, SensorError>;

    /// What kind of sensor this is (`"lidar"`, `"camera"`, `"battery"`...).
    fn sensor_type(&self) -> &str;

    /// `false` while the device cannot be read at all; the node then fails without reading.
    fn is_available(&self) -> bool {
        true
    }
}

/// Finds the sensor in the context.
type SensorAccess<C> = dyn Send + Sync + Fn(&mut C) -> &mut dyn SensorReader;

/// The sensor node: see the [module documentation](self) for its semantics and ports.
pub struct SensorNode<C> {
    access: Arc<SensorAccess<C>>,
}

impl<C> Clone for SensorNode<C> {
    fn clone(&self) -> Self {
        Self {
            access: Arc::clone(&self.access),
        }
    }
}

impl<C> SensorNode<C> {
    /// A node reading the sensor that `access` finds in the context.
    pub fn new<F>(access: F) -> Self
    where
        F: Fn(&mut C) -> &mut dyn SensorReader,
        F: Send + Sync + 'static,
    {
        Self {
            access: Arc::new(access),
        }
    }

    /// The ports the node reads and writes, for [`Registry`] declarations.
    pub fn ports() -> Vec<PortSpec> {
        vec![
            PortSpec::output::<SensorData>("output")
                .describe("the entry that receives the reading"),
            PortSpec::input::<f64>("min_quality")
                .default_value("0")
                .describe("readings of lower quality (0..1) fail the node"),
        ]
    }
}

impl<C> Action<C> for SensorNode<C> {
    fn tick(&self, h: &mut Handle<'_, C>) -> Status {
        // An absent `min_quality` port means no threshold: the port's default is 0.
        let min_quality = match h.input::<f64>("min_quality") {
            Ok(q) => q,
            Err(neurotree_core::PortError::NoSuchPort { .. }) => 0.0,
            Err(_) => return Status::Failure,
        };
        let sensor = (self.access)(h.ctx_mut());
        if !sensor.is_available() {
            return Status::Failure;
        }
        let Ok(reading) = sensor.read() else {
            return Status::Failure;
        };
        // A NaN quality compares as nothing, so it is rejected too.
        let good_enough = matches!(
            reading.quality.partial_cmp(&min_quality),
            Some(Ordering::Greater | Ordering::Equal)
        );
        if !good_enough {
            return Status::Failure;
        }
        match h.output("output", reading) {
            Ok(()) => Status::Success,
            Err(_) => Status::Failure,
        }
    }
}

/// Registers a sensor node type for XML under `name`, reading the sensor `access` finds:
/// `<ReadLidar output="{scan}" min_quality="0.8"/>`.
pub fn register_sensor<C, F>(
    registry: &mut Registry<C>,
    name: &str,
    access: F,
) -> Result<(), RegistryError>
where
    C: 'static,
    F: Fn(&mut C) -> &mut dyn SensorReader,
    F: Send + Sync + 'static,
{
    let node = SensorNode::new(access);
    registry.register_action(name, SensorNode::<C>::ports(), move |h| node.tick(h))?;
    registry.describe(
        name,
        "Reads a sensor; fails if it is unavailable, the read fails or the quality is below min_quality; else writes the reading to output.",
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robotics::RoboticsBuilder;
    use neurotree_toolkit::{Blueprint, ManualClock, Port, Tree, XmlLoader};

    /// A sensor that answers from a script and counts its reads.
    struct Scripted {
        available: bool,
        next: Result<f64, SensorError>,
        reads: u32,
    }

    impl SensorReader for Scripted {
        fn read(&mut self) -> Result<SensorData, SensorError> {
            self.reads += 1;
            let quality = self.next.clone()?;
            Ok(
                SensorData::new(Duration::from_millis(u64::from(self.reads)), quality)
                    .with("range", 2.5)
                    .with("ranges", vec![1.0, 2.0]),
            )
        }
        fn sensor_type(&self) -> &str {
            "scripted"
        }
        fn is_available(&self) -> bool {
            self.available
        }
    }

    struct Robot {
        lidar: Scripted,
    }

    fn robot(available: bool, next: Result<f64, SensorError>) -> Robot {
        Robot {
            lidar: Scripted {
                available,
                next,
                reads: 0,
            },
        }
    }

    fn tree(min_quality: f64) -> Tree<Robot> {
        let bp = Blueprint::<Robot>::builder()
            .sensor("lidar", "scan", min_quality, |r: &mut Robot| &mut r.lidar)
            .build_shared()
            .unwrap();
        Tree::with_clock(bp, ManualClock::new())
    }

    #[test]
    fn a_good_reading_is_written_to_the_output_entry() {
        let mut t = tree(0.8);
        let mut r = robot(true, Ok(0.8));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Success));
        let scan: SensorData = t.blackboard().get("scan").unwrap();
        assert_eq!(scan.quality, 0.8);
        assert_eq!(scan.timestamp, Duration::from_millis(1));
        assert_eq!(scan.number("range"), Some(2.5));
        assert_eq!(scan.numbers("ranges"), Some(&[1.0, 2.0][..]));
        assert_eq!(scan.number("ranges"), None);
        // Every tick reads again and replaces the entry.
        assert_eq!(t.tick_once(&mut r), Ok(Status::Success));
        let scan: SensorData = t.blackboard().get("scan").unwrap();
        assert_eq!(scan.timestamp, Duration::from_millis(2));
        assert_eq!(r.lidar.reads, 2);
    }

    #[test]
    fn an_unavailable_sensor_fails_without_being_read() {
        let mut t = tree(0.0);
        let mut r = robot(false, Ok(1.0));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Failure));
        assert_eq!(r.lidar.reads, 0);
        assert!(t.blackboard().get::<SensorData>("scan").is_err());
    }

    #[test]
    fn a_read_error_fails_and_writes_nothing() {
        let mut t = tree(0.0);
        let mut r = robot(true, Err(SensorError::ReadFailed("timeout".into())));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Failure));
        assert_eq!(r.lidar.reads, 1);
        assert!(t.blackboard().get::<SensorData>("scan").is_err());
    }

    #[test]
    fn quality_below_the_threshold_fails_and_keeps_the_old_reading() {
        let mut t = tree(0.8);
        let mut r = robot(true, Ok(0.9));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Success));
        r.lidar.next = Ok(0.79);
        assert_eq!(t.tick_once(&mut r), Ok(Status::Failure));
        r.lidar.next = Ok(f64::NAN);
        assert_eq!(t.tick_once(&mut r), Ok(Status::Failure));
        let scan: SensorData = t.blackboard().get("scan").unwrap();
        assert_eq!(scan.timestamp, Duration::from_millis(1));
        assert_eq!(r.lidar.reads, 3);
    }

    #[test]
    fn an_output_bound_to_a_literal_fails() {
        let bp = Blueprint::<Robot>::builder()
            .action_node("lidar", SensorNode::new(|r: &mut Robot| &mut r.lidar))
            .ports([Port::literal("output", "scan")])
            .build_shared()
            .unwrap();
        let mut t = Tree::with_clock(bp, ManualClock::new());
        let mut r = robot(true, Ok(1.0));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Failure));
    }

    #[test]
    fn registered_for_xml_with_its_ports() {
        let mut registry = Registry::<Robot>::new();
        register_sensor(&mut registry, "ReadLidar", |r: &mut Robot| &mut r.lidar).unwrap();
        let model = registry.tree_nodes_model();
        assert!(model.contains(r#"<Action ID="ReadLidar">"#), "{model}");
        assert!(
            model.contains(r#"name="min_quality" type="f64" default="0""#),
            "{model}"
        );
        let mut loader = XmlLoader::new(&registry);
        loader
            .load_str(
                r#"<root BTCPP_format="4">
                     <BehaviorTree ID="Main">
                       <Sequence>
                         <ReadLidar output="{scan}" min_quality="0.5"/>
                         <ReadLidar output="{strict}" min_quality="0.95"/>
                       </Sequence>
                     </BehaviorTree>
                   </root>"#,
                "sensor.xml",
            )
            .unwrap();
        let mut t = Tree::with_clock(loader.build_main().unwrap().into(), ManualClock::new());
        let mut r = robot(true, Ok(0.9));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Failure));
        assert!(t.blackboard().get::<SensorData>("scan").is_ok());
        assert!(t.blackboard().get::<SensorData>("strict").is_err());
        assert_eq!(r.lidar.reads, 2);

        let bad = r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                       <ReadLidar output="{scan}" min_quality="good"/>
                     </BehaviorTree></root>"#;
        let mut loader = XmlLoader::new(&registry);
        loader.load_str(bad, "bad.xml").unwrap();
        let err = loader.build_main().unwrap_err();
        assert!(err.message.contains("min_quality"), "{err}");
    }

    #[test]
    fn a_missing_threshold_port_accepts_any_quality() {
        let bp = Blueprint::<Robot>::builder()
            .action_node("lidar", SensorNode::new(|r: &mut Robot| &mut r.lidar))
            .ports([Port::entry("output", "scan")])
            .build_shared()
            .unwrap();
        let mut t = Tree::with_clock(bp, ManualClock::new());
        let mut r = robot(true, Ok(0.0));
        assert_eq!(t.tick_once(&mut r), Ok(Status::Success));
    }
}

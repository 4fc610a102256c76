//! A variant's faults, as a campaign writes them: `none`, or faults joined by ` + `:
//!
//! - `PATH=STATUS@K` (`#CODE`): node PATH (a path; else every node of that type, else of
//!   that name) returns STATUS on its Kth call, writing CODE to its `error_code_id`
//!   ([`neurotree::fault`]): `ComputePathToPose=FAILURE@3#106`; `ClearEntireCostmap=RUNNING@1`
//!   is a service that does not answer; `Spin=PANIC@2` panics on the 2nd call.
//! - `FollowPath*F`: the controller takes F times as long (it drives F times slower).
//! - `battery=P%@Ss`: the battery falls to P percent at S simulated seconds.

use std::time::Duration;

use neurotree::fault::NodeFault;

use crate::demo::DemoConfig;

/// What one fault value does to a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Faults {
    /// Nodes that misbehave on a call.
    pub nodes: Vec<NodeFault>,
    /// How many times as long the controller takes.
    pub slower: Option<f64>,
    /// The battery's fall: when, and to what level.
    pub battery: Option<(Duration, f64)>,
}

impl Faults {
    /// Reads `text`: `none`, or faults joined by ` + `, each `PATH=STATUS@K` (`#CODE`),
    /// `FollowPath*F` or `battery=P%@Ss`.
    pub fn parse(text: &str) -> Result<Faults, String> {
        let mut faults = Faults::default();
        if text.trim() == "none" {
            return Ok(faults);
        }
        for part in text.split(" + ") {
            let part = part.trim();
            if let Some(factor) = part.strip_prefix("FollowPath*") {
                match factor.parse::<f64>() {
                    Ok(f) if f > 0.0 && f.is_finite() => faults.slower = Some(f),
                    _ => return Err(format!("`{part}`: FollowPath*F takes a factor above 0")),
                }
            } else if let Some(rest) = part.strip_prefix("battery=") {
                let parsed = rest.split_once("%@").and_then(|(level, at)| {
                    let level = level.trim().parse::<f64>().ok()?;
                    let at = at.trim().strip_suffix('s')?.parse::<f64>().ok()?;
                    ((0.0..=100.0).contains(&level) && at >= 0.0 && at.is_finite())
                        .then(|| (Duration::from_secs_f64(at), level))
                });
                match parsed {
                    Some(fall) => faults.battery = Some(fall),
                    None => {
                        return Err(format!(
                            "`{part}`: write the battery's fall as battery=PERCENT%@SECONDSs, \
                             such as battery=10%@30s"
                        ))
                    }
                }
            } else {
                faults.nodes.push(part.parse()?);
            }
        }
        Ok(faults)
    }

    /// Puts the faults into the run's configuration.
    pub fn apply(&self, config: &mut DemoConfig) {
        config.faults.extend(self.nodes.iter().cloned());
        if let Some(f) = self.slower {
            config.params.speed /= f;
        }
        if self.battery.is_some() {
            config.battery_drop = self.battery;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotree::Status;

    #[test]
    fn each_kind_of_fault_reads() {
        let f = Faults::parse("ComputePathToPose=FAILURE@3#106 + FollowPath*2 + battery=10%@30s")
            .unwrap();
        assert_eq!(
            f.nodes,
            [NodeFault::new("ComputePathToPose", 3, Status::Failure).with_error_code(106)]
        );
        assert_eq!(f.slower, Some(2.0));
        assert_eq!(f.battery, Some((Duration::from_secs(30), 10.0)));
        assert_eq!(Faults::parse("none").unwrap(), Faults::default());
        assert!(Faults::parse("battery=10@30")
            .unwrap_err()
            .contains("battery=PERCENT"));
        assert!(Faults::parse("Spin=MAYBE@1").is_err());
        assert!(Faults::parse("Spin=FAILURE@0").is_err());
    }
}

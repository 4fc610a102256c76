//! Why agents are awake: the last frame's counts, as a resource and as diagnostics.

use bevy_diagnostic::{Diagnostic, DiagnosticPath, Diagnostics};
use bevy_ecs::reflect::ReflectResource;
use bevy_ecs::resource::Resource;
use bevy_reflect::Reflect;
use neurotree::crowd::FrameReport;
use neurotree::{AwakeCounts, AwakeReason};

/// The agents the last frame ticked that stayed awake, by reason (see
/// [`Tree::why_awake`](neurotree::Tree::why_awake)), and those that slept through it. With
/// several plugins (context types), the last one to tick writes it.
///
/// The same figures are diagnostics: `neurotree/awake`, `neurotree/asleep` and
/// `neurotree/awake/REASON` (REASON as [`AwakeReason::name`] spells it:
/// `undeclared_leaf`, `reactive_condition`, ...).
#[derive(Resource, Reflect, Clone, Debug, Default, PartialEq)]
#[reflect(Resource)]
pub struct AwakeAgents {
    /// Agents ticked in the last frame.
    pub ticked: u64,
    /// Agents that slept through it: not visited.
    pub asleep: u64,
    /// Agents ticked that stayed awake.
    pub awake: u64,
    /// How many stayed awake for each reason, by its name, the reasons with none left out.
    pub by_reason: Vec<(String, u32)>,
    /// The same counts, as the crowd gave them.
    #[reflect(ignore)]
    pub counts: AwakeCounts,
}

impl AwakeAgents {
    /// The figures of a frame's report.
    pub(crate) fn of(report: &FrameReport) -> Self {
        Self {
            ticked: report.ticked,
            asleep: report.asleep,
            awake: report.awake.total(),
            by_reason: report
                .awake
                .iter()
                .map(|(reason, n)| (reason.name().to_string(), n))
                .collect(),
            counts: report.awake,
        }
    }
}

/// The diagnostic of agents awake.
pub const AWAKE: DiagnosticPath = DiagnosticPath::const_new("neurotree/awake");
/// The diagnostic of agents asleep.
pub const ASLEEP: DiagnosticPath = DiagnosticPath::const_new("neurotree/asleep");

/// The diagnostic of agents awake for `reason`.
pub fn awake_for(reason: AwakeReason) -> DiagnosticPath {
    DiagnosticPath::new(format!("neurotree/awake/{}", reason.name()))
}

/// Every diagnostic the plugin measures.
pub(crate) fn diagnostics() -> impl Iterator<Item = Diagnostic> {
    [AWAKE, ASLEEP]
        .into_iter()
        .chain(AwakeReason::ALL.iter().map(|&r| awake_for(r)))
        .map(Diagnostic::new)
}

/// Measures the last frame's figures.
pub(crate) fn measure(diagnostics: &mut Diagnostics<'_, '_>, report: &FrameReport) {
    diagnostics.add_measurement(&AWAKE, || report.awake.total() as f64);
    diagnostics.add_measurement(&ASLEEP, || report.asleep as f64);
    for reason in AwakeReason::ALL {
        let n = report.awake.get(reason);
        diagnostics.add_measurement(&awake_for(reason), || f64::from(n));
    }
}

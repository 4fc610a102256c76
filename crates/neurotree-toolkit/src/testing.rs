//! Test helpers for the built-ins that need `std`: scripted leaves registered by name, whose
//! ticks, halts and messages are recorded in the context, so that each test reads as "given
//! this XML and these child outcomes, after these ticks, these statuses and counts".

pub(crate) use neurotree_core::{Status, TickError, Tree};

use neurotree_core::{Handle, ManualClock, StatefulAction};

use crate::registry::{PortSpec, Registry};
use crate::xml::XmlLoader;

pub(crate) const S: Status = Status::Success;
pub(crate) const F: Status = Status::Failure;
pub(crate) const R: Status = Status::Running;

/// The context of the scripted leaves `L0`, `L1`, ... and of `Say`.
pub(crate) struct Lab {
    /// Outcomes per leaf; the last repeats forever.
    pub scripts: Vec<Vec<Status>>,
    /// Calls of `on_start` or `on_running` per leaf.
    pub ticks: Vec<u32>,
    /// Calls of `on_halted` per leaf.
    pub halts: Vec<u32>,
    /// What `Say` was given, in order.
    pub said: Vec<String>,
    pub clock: ManualClock,
}

/// A stateful leaf playing its script from the [`Lab`].
struct Scripted(usize);

impl Scripted {
    fn next(&self, h: &mut Handle<'_, Lab>) -> Status {
        let lab = h.ctx_mut();
        lab.ticks[self.0] += 1;
        let script = &lab.scripts[self.0];
        script[(lab.ticks[self.0] as usize - 1).min(script.len() - 1)]
    }
}

impl StatefulAction<Lab> for Scripted {
    fn on_start(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        self.next(h)
    }
    fn on_running(&mut self, h: &mut Handle<'_, Lab>) -> Status {
        self.next(h)
    }
    fn on_halted(&mut self, h: &mut Handle<'_, Lab>) {
        h.ctx_mut().halts[self.0] += 1;
    }
}

impl Lab {
    pub(crate) fn new(scripts: &[&[Status]]) -> Self {
        Self {
            scripts: scripts.iter().map(|s| s.to_vec()).collect(),
            ticks: vec![0; scripts.len()],
            halts: vec![0; scripts.len()],
            said: Vec::new(),
            clock: ManualClock::new(),
        }
    }

    /// The built-ins, `L0`..`L{n-1}` for the scripts, and `Say(message)`, which records its
    /// message and succeeds.
    pub(crate) fn registry(&self) -> Registry<Lab> {
        let mut r = Registry::new();
        for i in 0..self.scripts.len() {
            r.register_stateful(&format!("L{i}"), vec![], move || Scripted(i))
                .unwrap();
        }
        r.register_action("Say", vec![PortSpec::input::<String>("message")], |h| {
            let m = h
                .input::<String>("message")
                .unwrap_or_else(|e| e.to_string());
            h.ctx_mut().said.push(m);
            Status::Success
        })
        .unwrap();
        r
    }

    /// A tree of the main tree of `xml`.
    pub(crate) fn load(&self, xml: &str) -> Result<Tree<Lab>, crate::LoadError> {
        self.load_with(&self.registry(), xml)
    }

    /// A tree of the main tree of `xml`, its nodes from `registry` (which
    /// [`registry`](Self::registry) made, then the test added to).
    pub(crate) fn load_with(
        &self,
        registry: &Registry<Lab>,
        xml: &str,
    ) -> Result<Tree<Lab>, crate::LoadError> {
        let mut loader = XmlLoader::new(registry);
        loader.load_str(xml, "test.xml")?;
        let bp = loader.build_main()?;
        Ok(Tree::with_clock(bp.into(), self.clock.clone()))
    }

    /// A tree of `body`, the one node of a main tree.
    pub(crate) fn tree(&self, body: &str) -> Tree<Lab> {
        let xml = format!(
            r#"<root BTCPP_format="4" main_tree_to_execute="T"><BehaviorTree ID="T">{body}</BehaviorTree></root>"#
        );
        self.load(&xml).expect("test tree loads")
    }

    pub(crate) fn tick(&mut self, tree: &mut Tree<Lab>) -> Result<Status, TickError> {
        tree.tick_once(self)
    }
}

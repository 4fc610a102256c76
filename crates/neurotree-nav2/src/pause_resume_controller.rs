//! PauseResumeController: run the first child, or pause it on request and run the others.

use neurotree_core::nodes::semantics::{Order, Semantics, Statuses};
use neurotree_core::{Arity, CustomNode, CustomSpec, NodeCtx, NodeStatus};

/// PauseResumeController's semantics: a request moves it from child to child at any tick.
pub const SEMANTICS: Semantics = Semantics::new(Order::AllAtOnce, |_, _| {
    Statuses::SUCCESS
        .or(Statuses::FAILURE)
        .or(Statuses::RUNNING)
});

/// The states of a [`PauseResumeController`], as Nav2 names them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PauseState {
    /// Ticking child 0.
    #[default]
    Resumed,
    /// Ticking child 1 (if there is one).
    Paused,
    /// A pause was asked for; the next tick resets the children and goes to `OnPause`.
    PauseRequested,
    /// Ticking child 2 until it completes, then `Paused`.
    OnPause,
    /// A resume was asked for; the next tick resets the children and goes to `OnResume`.
    ResumeRequested,
    /// Ticking child 3 until it completes, then `Resumed`.
    OnResume,
}

impl PauseState {
    /// The child this state ticks.
    fn child(self) -> usize {
        match self {
            PauseState::Resumed => 0,
            PauseState::Paused => 1,
            PauseState::OnPause => 2,
            // The request states are left before any child is ticked.
            PauseState::OnResume | PauseState::PauseRequested | PauseState::ResumeRequested => 3,
        }
    }

    /// Nav2's `switchToNextState`: a request goes to its event, an event to its end state.
    fn next(self) -> Self {
        match self {
            PauseState::PauseRequested => PauseState::OnPause,
            PauseState::OnPause => PauseState::Paused,
            PauseState::ResumeRequested => PauseState::OnResume,
            PauseState::OnResume => PauseState::Resumed,
            end => end,
        }
    }
}

/// PauseResumeController: run child 0; on a pause request run child 2 (ON_PAUSE) to its end,
/// then child 1 (PAUSED) until a resume request runs child 3 (ON_RESUME) and back to child
/// 0, as Nav2's `pause_resume_controller.cpp` does. Children 1 to 3 are optional.
///
/// Ports `pause_service_name` and `resume_service_name`. Nav2 offers two `Trigger`
/// services under these names; here the services are blackboard entries of those names,
/// holding a `bool`: writing `true` calls the service, and the node answers at its next
/// tick (where Nav2 spins its executor) by writing `false` back, the pause before the
/// resume. A pause is accepted in any state but Paused, a resume only when Paused; a call
/// that is not accepted is answered (set back to `false`) and does nothing, as Nav2 answers
/// `success = false`. Without the ports no call ever comes, and the node only runs child 0.
///
/// Each tick: from Idle, start Resumed; take the calls; a pending request resets the
/// children and moves to its event state; a state whose child is missing moves on and
/// returns Running; else tick that state's child:
///
/// - Running: Running.
/// - Success or Skipped: Success when Resumed; otherwise move on (an event to its end state)
///   and return Running.
/// - Failure: Failure (the state stays; a halt or a new run goes back to Resumed).
///
/// A halt goes back to Resumed. Nav2 checks the number of children (1 to 4) at the first
/// tick; here the loader refuses another number.
#[derive(Debug, Default)]
pub struct PauseResumeController {
    state: PauseState,
}

impl PauseResumeController {
    /// The node kind for a [`Builder`](neurotree_toolkit::Builder).
    pub fn spec<C>() -> CustomSpec<C> {
        CustomSpec::new(
            "PauseResumeController",
            Arity::Range { min: 1, max: 4 },
            Box::new(|| Box::new(PauseResumeController::default())),
        )
    }

    /// The state the node is in, as Nav2's `getState`.
    pub fn state(&self) -> PauseState {
        self.state
    }

    /// Answers a call of the service named by `port`: `true` if one was pending.
    fn take_call<C>(node: &mut NodeCtx<'_, '_, C>, port: &str) -> Result<bool, String> {
        let Ok(Some(name)) = super::port_value::<C, String>(node, port) else {
            return Ok(false);
        };
        let called = super::goals::entry_owned::<C, bool>(node, &name)?.unwrap_or(false);
        if called {
            let (scope, now) = (node.scope(), node.now());
            node.blackboard()
                .set_in(scope, &name, false, now)
                .map_err(|e| format!("`{port}`: {e}"))?;
        }
        Ok(called)
    }
}

impl<C> CustomNode<C> for PauseResumeController {
    fn save_state(&self) -> Option<Vec<u8>> {
        Some(neurotree_core::state::encode(&(self.state,)))
    }

    fn restore_state(&mut self, state: &[u8]) -> bool {
        neurotree_core::state::decode(state)
            .map(|(state,)| self.state = state)
            .is_some()
    }

    fn tick(&mut self, node: &mut NodeCtx<'_, '_, C>) -> NodeStatus {
        if node.previous_status() == NodeStatus::Idle {
            self.state = PauseState::Resumed;
        }
        node.set_running();
        let calls = Self::take_call(node, "pause_service_name")
            .and_then(|p| Self::take_call(node, "resume_service_name").map(|r| (p, r)));
        let (pause, resume) = match calls {
            Ok(calls) => calls,
            Err(e) => {
                node.fail(e);
                return NodeStatus::Failure;
            }
        };
        if pause && self.state != PauseState::Paused {
            self.state = PauseState::PauseRequested;
        }
        if resume && self.state == PauseState::Paused {
            self.state = PauseState::ResumeRequested;
        }
        if matches!(
            self.state,
            PauseState::PauseRequested | PauseState::ResumeRequested
        ) {
            node.reset_children();
            self.state = self.state.next();
        }
        let child = self.state.child();
        if child >= node.child_count() {
            self.state = self.state.next();
            return NodeStatus::Running;
        }
        match node.tick_child(child) {
            NodeStatus::Running => NodeStatus::Running,
            NodeStatus::Success | NodeStatus::Skipped => {
                if self.state == PauseState::Resumed {
                    return NodeStatus::Success;
                }
                self.state = self.state.next();
                NodeStatus::Running
            }
            _ => NodeStatus::Failure,
        }
    }

    fn halt(&mut self, _node: &mut NodeCtx<'_, '_, C>) {
        self.state = PauseState::Resumed;
    }
}

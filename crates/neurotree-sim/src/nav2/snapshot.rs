//! The simulation as of one moment, to go back to: what rewinding a watched run restores
//! beside the tree's own state.

use std::time::Duration;

use neurotree_core::Clock;

use super::Nav2Sim;

/// A [`Nav2Sim`] as it was at one moment ([`Nav2Sim::snapshot`]): the world, the servers'
/// goals and counters, and the time.
#[derive(Clone, Debug)]
pub struct Nav2SimState {
    sim: Nav2Sim,
    now: Duration,
}

impl Nav2Sim {
    /// The simulation as it is now, for [`restore`](Self::restore) to go back to.
    ///
    /// ```
    /// use std::time::Duration;
    /// use neurotree::robotics::Pose2D;
    /// use neurotree::sim::nav2::Nav2Sim;
    /// use neurotree::sim::GridWorld;
    ///
    /// let mut sim = Nav2Sim::new(GridWorld::parse("R....", 1.0).unwrap());
    /// let path = sim.world.plan(sim.world.robot(), Pose2D::new(4.5, 0.5, 0.0)).unwrap();
    /// sim.world.follow(path, 1.0);
    /// let before = sim.snapshot();
    /// for _ in 0..10 {
    ///     sim.step();
    /// }
    /// assert_eq!(sim.world.now(), Duration::from_secs(1));
    /// sim.restore(&before);
    /// assert_eq!((sim.world.now(), sim.world.robot().x), (Duration::ZERO, 0.5));
    /// ```
    pub fn snapshot(&self) -> Nav2SimState {
        Nav2SimState {
            sim: self.clone(),
            now: self.world.now(),
        }
    }

    /// Puts the simulation back as `state` has it, the clock too. The clock and the event
    /// log stay the ones this simulation was made with (the tree reads that clock).
    pub fn restore(&mut self, state: &Nav2SimState) {
        let clock = self.world.clock();
        let log = self.log.take();
        *self = state.sim.clone();
        self.world.clock = clock;
        self.log = log;
        self.world.clock.set(state.now);
        debug_assert_eq!(self.world.clock.now(), state.now);
    }
}

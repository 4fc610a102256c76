//! Obstacles that come and go on the world's clock: a door that closes, a person who stops
//! in a corridor, a pallet left for a while.

use std::time::Duration;

use super::grid::Cell;

/// An obstacle filling `cell` from `appears` until `vanishes` (forever if `None`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimedObstacle {
    /// The cell it fills.
    pub cell: Cell,
    /// World time at which it appears.
    pub appears: Duration,
    /// World time at which it is gone again, if ever.
    pub vanishes: Option<Duration>,
}

impl TimedObstacle {
    /// An obstacle that appears in `cell` at `appears` and stays.
    pub const fn new(cell: Cell, appears: Duration) -> Self {
        Self {
            cell,
            appears,
            vanishes: None,
        }
    }

    /// The obstacle, gone again at `vanishes`.
    pub const fn until(mut self, vanishes: Duration) -> Self {
        self.vanishes = Some(vanishes);
        self
    }

    /// `true` if it is there at time `now`: from `appears` (included) to `vanishes`
    /// (excluded).
    pub fn is_present(&self, now: Duration) -> bool {
        self.appears <= now && self.vanishes.is_none_or(|v| now < v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn present_from_appearing_until_vanishing() {
        let s = Duration::from_secs;
        let o = TimedObstacle::new(Cell::new(1, 1), s(2)).until(s(5));
        let seen: Vec<bool> = (0..7).map(|t| o.is_present(s(t))).collect();
        assert_eq!(seen, [false, false, true, true, true, false, false]);
        let forever = TimedObstacle::new(Cell::new(1, 1), s(0));
        assert!(forever.is_present(s(1_000_000)));
    }
}

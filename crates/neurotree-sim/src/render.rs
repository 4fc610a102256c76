//! The world as plain text: one character per cell, top row first, under a status line.
//!
//! ```text
//! t=2.00s pose=(2.50, 1.50, 0.00) battery=98.0% travelled=2.00m motion=moving
//! ########
//! #..R*XG#
//! #...**.#
//! ########
//! ```
//!
//! Each cell shows the first that applies: `R` the robot, `X` an obstacle present now, `#` a
//! wall, `G` the end of the path being followed, `*` the rest of that path, `C` the charger,
//! `x` an obstacle the global costmap remembers that has gone, `.` free.

use std::fmt::Write as _;

use super::grid::Cell;
use super::world::GridWorld;
use neurotree_nav2::robotics::Pose2D;

/// The glyphs, for a legend under a rendering.
pub const LEGEND: &str =
    "R robot  X obstacle  # wall  G goal  * path  C charger  x remembered obstacle (gone)  . free";

impl GridWorld {
    /// The world as text: see the [module documentation](self).
    pub fn render(&self) -> String {
        let ahead = self.path_ahead();
        self.render_with(ahead, ahead.last().copied())
    }

    /// The world as text with `path` drawn as the path and `goal` as the goal, instead of
    /// the path being followed: for views that show a plan while the robot does something
    /// else (spins, waits, stands blocked).
    pub fn render_with(&self, path: &[Pose2D], goal: Option<Pose2D>) -> String {
        let map = self.map();
        let goal = goal.and_then(|p| map.cell_at(&p));
        let path: Vec<Cell> = path.iter().filter_map(|p| map.cell_at(p)).collect();
        let truth = self.truth();
        let costmap = self.costmap(super::CostmapLayer::Global);
        let robot = self.robot();
        let mut out = String::new();
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "t={:.2}s pose=({:.2}, {:.2}, {:.2}) battery={:.1}% travelled={:.2}m motion={}",
            self.now().as_secs_f64(),
            robot.x,
            robot.y,
            robot.theta,
            self.battery().level(),
            self.distance_travelled(),
            self.motion_status(),
        );
        for y in (0..map.height()).rev() {
            for x in 0..map.width() {
                let cell = Cell::new(x, y);
                let glyph = if cell == self.robot_cell() {
                    'R'
                } else if truth.is_obstacle(cell) {
                    'X'
                } else if map.is_wall(cell) {
                    '#'
                } else if Some(cell) == goal {
                    'G'
                } else if path.contains(&cell) {
                    '*'
                } else if Some(cell) == self.charger() {
                    'C'
                } else if costmap.is_marked(cell) {
                    'x'
                } else {
                    '.'
                };
                out.push(glyph);
            }
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use crate::{Cell, GridWorld, TimedObstacle};
    use neurotree_nav2::robotics::Pose2D;

    #[test]
    fn the_rendering_shows_everything_in_plain_ascii() {
        let mut w = GridWorld::parse(
            "
            #########
            #R.....C#
            #.......#
            #########",
            1.0,
        )
        .unwrap()
        // Seen at the start, gone at 1 s: remembered as `x`.
        .with_timed_obstacle(
            TimedObstacle::new(Cell::new(2, 1), Duration::ZERO).until(Duration::from_secs(1)),
        )
        // Far from the robot, not known to it yet.
        .with_timed_obstacle(TimedObstacle::new(Cell::new(5, 2), Duration::ZERO));
        w.step(Duration::from_secs(1));
        let path = w.plan(w.robot(), Pose2D::new(6.5, 1.5, 0.0)).unwrap();
        w.follow(path, 1.0);
        w.step(Duration::from_secs(1));
        assert_eq!(
            w.render(),
            "t=2.00s pose=(2.50, 2.50, 0.00) battery=99.0% travelled=1.00m motion=moving\n\
             #########\n\
             #.R*.X.C#\n\
             #.x.**G.#\n\
             #########\n"
        );
    }

    #[test]
    fn a_plan_and_a_goal_are_drawn_while_the_robot_stands() {
        let w = GridWorld::parse(
            "
            #######
            #R....#
            #######",
            1.0,
        )
        .unwrap();
        let plan = [Pose2D::new(2.5, 1.5, 0.0), Pose2D::new(3.5, 1.5, 0.0)];
        let frame = w.render_with(&plan, Some(Pose2D::new(5.5, 1.5, 0.0)));
        assert_eq!(
            frame.lines().skip(1).collect::<Vec<_>>(),
            ["#######", "#R**.G#", "#######"]
        );
        // Not following anything, the plain rendering shows neither.
        assert_eq!(w.render().lines().nth(2), Some("#R....#"));
    }
}

//! What the robot believes is in the way, and routes around it.
//!
//! A [`Costmap`] starts from the static map (the walls the robot was given) and learns
//! obstacles as the robot senses them; it forgets nothing on its own, so an obstacle that has
//! gone stays in the way until the costmap is [cleared](Costmap::clear) — which is why
//! navigation stacks clear their costmaps as a recovery. Planning is A* (from the
//! `pathfinding` crate) over the 8-connected grid, moving diagonally only between two free
//! side cells so that no route cuts a corner.
//!
//! Nav2's costmaps also *inflate* what is blocked: the cells near a wall or an obstacle get
//! a cost that keeps plans clear of it. [`Costmap::inflated`] names those cells, within a
//! radius of a blocked one, for a view to show (the studio's scene panel); the simulated
//! planner routes through them as through free cells, its robot being a point.

use pathfinding::prelude::astar;

use super::grid::{Cell, GridMap};
use neurotree_nav2::robotics::{Obstacle, Path, Pose2D};

/// Step costs in tenths of a cell, so that A* runs on integers: 10 straight, 14 diagonal.
const STRAIGHT: u32 = 10;
const DIAGONAL: u32 = 14;

/// The eight moves, in the fixed order that makes ties between equal routes reproducible.
const MOVES: [(i32, i32); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

/// The robot's belief of which cells are blocked: the static walls plus what it has sensed.
#[derive(Clone, Debug, PartialEq)]
pub struct Costmap {
    map: GridMap,
    /// Sensed obstacles, indexed like the map's cells.
    marks: Vec<bool>,
}

impl Costmap {
    /// A costmap that knows the walls of `map` and nothing else.
    pub fn new(map: &GridMap) -> Self {
        let cells = map.cells().count();
        Self {
            map: map.clone(),
            marks: vec![false; cells],
        }
    }

    /// The static map under it.
    pub fn map(&self) -> &GridMap {
        &self.map
    }

    fn index(&self, cell: Cell) -> Option<usize> {
        // `contains` checks both coordinates non-negative and in range.
        self.map
            .contains(cell)
            .then(|| cell.y as usize * self.map.width() as usize + cell.x as usize)
    }

    /// `true` if `cell` is a wall, a sensed obstacle or outside the map.
    pub fn is_blocked(&self, cell: Cell) -> bool {
        self.map.is_wall(cell) || self.is_marked(cell)
    }

    /// `true` if an obstacle was sensed in `cell` (walls are not marks).
    pub fn is_marked(&self, cell: Cell) -> bool {
        self.index(cell).is_some_and(|i| self.marks[i])
    }

    /// Records an obstacle sensed in `cell`; returns `true` if it was not known yet.
    pub fn mark(&mut self, cell: Cell) -> bool {
        match self.index(cell) {
            Some(i) if !self.marks[i] => {
                self.marks[i] = true;
                true
            }
            _ => false,
        }
    }

    /// The cells marked as sensed obstacles, bottom row first.
    pub fn marked(&self) -> impl Iterator<Item = Cell> + '_ {
        self.map.cells().filter(|c| self.is_marked(*c))
    }

    /// The free cells within `radius` metres (centre to centre) of a blocked cell (a wall
    /// or a sensed obstacle; not the map's outside), bottom row first: the cells Nav2's
    /// inflation layer raises the cost of. A radius under one cell inflates nothing.
    ///
    /// ```
    /// use neurotree::sim::{Cell, GridWorld, CostmapLayer};
    ///
    /// let world = GridWorld::parse("R..#..", 1.0).unwrap();
    /// let costmap = world.costmap(CostmapLayer::Global);
    /// let inflated: Vec<Cell> = costmap.inflated(1.0).collect();
    /// assert_eq!(inflated, [Cell::new(2, 0), Cell::new(4, 0)]);
    /// ```
    pub fn inflated(&self, radius: f64) -> impl Iterator<Item = Cell> + '_ {
        // Offsets are in whole cells; `reach` bounds them so the search stays local.
        let cells = radius / self.map.resolution();
        let reach = if cells.is_finite() && cells >= 1.0 {
            // A radius past the map's size reaches no further than the map does.
            cells.min(f64::from(self.map.width().max(self.map.height()))) as i32
        } else {
            0
        };
        let within = move |dx: i32, dy: i32| f64::from(dx * dx + dy * dy) <= cells * cells;
        self.map.cells().filter(move |c| {
            reach > 0
                && !self.is_blocked(*c)
                && (-reach..=reach).any(|dy| {
                    (-reach..=reach).any(|dx| {
                        let near = Cell::new(c.x + dx, c.y + dy);
                        within(dx, dy) && self.map.contains(near) && self.is_blocked(near)
                    })
                })
        })
    }

    /// Forgets every sensed obstacle; the walls stay.
    pub fn clear(&mut self) {
        self.marks.iter_mut().for_each(|m| *m = false);
    }

    /// Forgets the sensed obstacles in the cells for which `forget` is `true`; the walls
    /// stay. Returns how many were forgotten.
    pub fn clear_where(&mut self, forget: impl Fn(Cell) -> bool) -> usize {
        let cells: Vec<Cell> = self.marked().filter(|c| forget(*c)).collect();
        for cell in &cells {
            if let Some(i) = self.index(*cell) {
                self.marks[i] = false;
            }
        }
        cells.len()
    }

    /// The cheapest 8-connected route of free cells from `from` to `to`, both included,
    /// also avoiding the cells for which `avoid` is `true`. The start cell may be blocked
    /// (the robot is standing there); a blocked goal has no route.
    pub fn route(&self, from: Cell, to: Cell, avoid: impl Fn(Cell) -> bool) -> Option<Vec<Cell>> {
        let blocked = |c: Cell| self.is_blocked(c) || avoid(c);
        if !self.map.contains(from) || blocked(to) {
            return None;
        }
        let successors = |c: &Cell| {
            let c = *c;
            MOVES.iter().filter_map(move |&(dx, dy)| {
                let next = Cell::new(c.x + dx, c.y + dy);
                let diagonal = dx != 0 && dy != 0;
                let side_blocked = diagonal
                    && (blocked(Cell::new(c.x + dx, c.y)) || blocked(Cell::new(c.x, c.y + dy)));
                (!blocked(next) && !side_blocked)
                    .then_some((next, if diagonal { DIAGONAL } else { STRAIGHT }))
            })
        };
        // Octile distance: exact on an empty grid, so A* stays optimal.
        let heuristic = |c: &Cell| {
            let (dx, dy) = ((c.x - to.x).unsigned_abs(), (c.y - to.y).unsigned_abs());
            DIAGONAL * dx.min(dy) + STRAIGHT * (dx.max(dy) - dx.min(dy))
        };
        astar(&from, successors, heuristic, |c| *c == to).map(|(cells, _)| cells)
    }

    /// A path in metres from `start` to `goal` around everything known and `obstacles`:
    /// `start` itself, the centres of the cells between, and `goal` itself. Each pose faces
    /// the next; the last keeps the goal's heading. `None` if either pose is off the map or
    /// no route exists.
    pub fn plan(&self, start: Pose2D, goal: Pose2D, obstacles: &[Obstacle]) -> Option<Path> {
        let from = self.map.cell_at(&start)?;
        let to = self.map.cell_at(&goal)?;
        let avoid = |c: Cell| {
            let centre = self.map.centre(c);
            c != from && obstacles.iter().any(|o| o.covers(centre.x, centre.y))
        };
        let cells = self.route(from, to, avoid)?;
        let mut poses = Vec::with_capacity(cells.len() + 1);
        poses.push(start);
        poses.extend(cells.iter().skip(1).map(|c| self.map.centre(*c)));
        if poses.len() > 1 {
            poses.pop();
        }
        poses.push(goal);
        for i in 0..poses.len() - 1 {
            let (a, b) = (poses[i], poses[i + 1]);
            if a.x != b.x || a.y != b.y {
                poses[i].theta = (b.y - a.y).atan2(b.x - a.x);
            }
        }
        Some(Path::new(poses))
    }

    /// `true` if no pose of `path` lies on a blocked cell or off the map.
    pub fn is_path_free(&self, path: &Path) -> bool {
        path.poses
            .iter()
            .all(|p| self.map.cell_at(p).is_some_and(|c| !self.is_blocked(c)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::parse;

    fn costmap(text: &str) -> (Costmap, Cell) {
        let p = parse(text, 1.0).unwrap();
        (Costmap::new(&p.map), p.robot)
    }

    #[test]
    fn routes_go_around_walls_without_cutting_corners() {
        let (c, robot) = costmap(
            "#######
             #R.#..#
             #..#..#
             #.....#
             #######",
        );
        let cells = c.route(robot, Cell::new(5, 3), |_| false).unwrap();
        assert_eq!(cells.first(), Some(&robot));
        assert_eq!(cells.last(), Some(&Cell::new(5, 3)));
        assert!(cells.iter().all(|cell| !c.is_blocked(*cell)));
        for w in cells.windows(2) {
            let (dx, dy) = (w[1].x - w[0].x, w[1].y - w[0].y);
            assert!(dx.abs() <= 1 && dy.abs() <= 1, "{w:?}");
            if dx != 0 && dy != 0 {
                assert!(!c.is_blocked(Cell::new(w[0].x + dx, w[0].y)), "{w:?}");
                assert!(!c.is_blocked(Cell::new(w[0].x, w[0].y + dy)), "{w:?}");
            }
        }
        // Three moves down to the wall's foot (the second diagonal would cut its corner),
        // three back up: seven cells.
        assert_eq!(cells.len(), 7);
    }

    #[test]
    fn a_blocked_goal_or_an_enclosed_one_has_no_route() {
        let (c, robot) = costmap(
            "######
             #R.#.#
             ######",
        );
        assert_eq!(c.route(robot, Cell::new(3, 1), |_| false), None);
        assert_eq!(c.route(robot, Cell::new(4, 1), |_| false), None);
        assert_eq!(c.route(robot, Cell::new(9, 9), |_| false), None);
        assert_eq!(
            c.route(robot, Cell::new(2, 1), |_| false),
            Some(vec![robot, Cell::new(2, 1)])
        );
    }

    #[test]
    fn marks_block_until_cleared_and_walls_stay() {
        let (mut c, robot) = costmap(
            "#####
             #R..#
             #####",
        );
        let goal = Cell::new(3, 1);
        assert!(c.mark(Cell::new(2, 1)));
        assert!(!c.mark(Cell::new(2, 1)));
        assert!(!c.mark(Cell::new(7, 7)));
        assert_eq!(c.marked().collect::<Vec<_>>(), [Cell::new(2, 1)]);
        assert_eq!(c.route(robot, goal, |_| false), None);
        c.clear();
        assert_eq!(c.marked().count(), 0);
        assert!(c.is_blocked(Cell::new(0, 1)));
        assert_eq!(c.route(robot, goal, |_| false).map(|r| r.len()), Some(3));
    }

    #[test]
    fn inflated_cells_are_the_free_ones_within_the_radius_of_a_wall_or_a_mark() {
        let (mut c, _) = costmap(
            "#.....
             ......
             R.....
             ......",
        );
        assert!(c.mark(Cell::new(4, 1)));
        let inflated = |c: &Costmap, radius| c.inflated(radius).collect::<Vec<_>>();
        let cells = |list: &[(i32, i32)]| {
            list.iter()
                .map(|&(x, y)| Cell::new(x, y))
                .collect::<Vec<_>>()
        };
        // One metre: the sides of the wall (in the top left corner, y = 3) and of the
        // mark; bottom row first.
        assert_eq!(
            inflated(&c, 1.0),
            cells(&[(4, 0), (3, 1), (5, 1), (0, 2), (4, 2), (1, 3)])
        );
        // 1.5 m takes the corners too (√2 m away), not the cells two away.
        assert_eq!(
            inflated(&c, 1.5),
            cells(&[
                (3, 0),
                (4, 0),
                (5, 0),
                (3, 1),
                (5, 1),
                (0, 2),
                (1, 2),
                (3, 2),
                (4, 2),
                (5, 2),
                (1, 3),
            ])
        );
        // Under a cell, nothing; the map's outside inflates nothing.
        assert_eq!(inflated(&c, 0.99), []);
        assert_eq!(inflated(&c, f64::NAN), []);
        c.clear();
        assert_eq!(inflated(&c, 1.0), cells(&[(0, 2), (1, 3)]));
        // A radius past the map reaches every free cell, and only those.
        assert_eq!(c.inflated(1e9).count(), 23);
    }

    #[test]
    fn inflation_is_measured_in_metres_whatever_the_resolution() {
        let p = parse(
            "#######
             .......
             .......
             .......
             ...#...
             R......",
            0.5,
        )
        .unwrap();
        let c = Costmap::new(&p.map);
        for radius in [0.5, 0.75, 1.0, 1.2, 1.5] {
            // By definition: free, and a blocked cell's centre within the radius.
            let expected: Vec<Cell> = p
                .map
                .cells()
                .filter(|cell| !c.is_blocked(*cell))
                .filter(|cell| {
                    let here = p.map.centre(*cell);
                    p.map
                        .cells()
                        .filter(|b| c.is_blocked(*b))
                        .any(|b| p.map.centre(b).distance(&here) <= radius + 1e-9)
                })
                .collect();
            assert_eq!(c.inflated(radius).collect::<Vec<_>>(), expected, "{radius}");
        }
        // Half-metre cells: a metre is two cells, so the row under the wall and the one
        // under it are inflated, and the pillar's cell has eight neighbours within 0.75 m.
        assert_eq!(c.inflated(1.0).filter(|cell| cell.y >= 3).count(), 14);
        assert_eq!(c.inflated(0.75).filter(|cell| cell.y <= 2).count(), 8);
    }

    #[test]
    fn plans_are_in_metres_and_end_on_the_goal_pose() {
        let p = parse(
            "#####
             #R..#
             #...#
             #####",
            0.5,
        )
        .unwrap();
        let c = Costmap::new(&p.map);
        let start = Pose2D::new(0.7, 1.2, 0.3);
        let goal = Pose2D::new(1.6, 1.1, 1.0);
        let path = c.plan(start, goal, &[]).unwrap();
        assert_eq!(
            path.poses,
            [
                Pose2D::new(0.7, 1.2, (1.25f64 - 1.2).atan2(1.25 - 0.7)),
                Pose2D::new(1.25, 1.25, (1.1f64 - 1.25).atan2(1.6 - 1.25)),
                Pose2D::new(1.6, 1.1, 1.0),
            ]
        );
        assert!(c.is_path_free(&path));
        // The same cell: straight there.
        let near = c.plan(start, Pose2D::new(0.6, 1.1, 0.0), &[]).unwrap();
        assert_eq!(near.poses.len(), 2);
        // An obstacle disc over the middle cell forces the lower row.
        let disc = Obstacle::new(1.25, 1.25, 0.1);
        let around = c.plan(start, goal, &[disc]).unwrap();
        assert_eq!(around.poses.len(), 5);
        assert!(around.poses.iter().all(|p| !disc.covers(p.x, p.y)));
        assert_eq!(c.plan(start, Pose2D::new(9.0, 9.0, 0.0), &[]), None);
        let walled = Path::new(vec![start, Pose2D::new(0.25, 1.25, 0.0)]);
        assert!(!c.is_path_free(&walled));
    }
}

//! The world as a [`Scene`], for a viewer that draws it beside the tree (the studio's
//! scene panel): the floor, the walls, the charger, the cells the global costmap marked,
//! the obstacles present now and the robot.
//!
//! Item ids: `floor`, `wall` (one polygon per run of wall cells in a row), `charger`,
//! `costmap` (one square per marked cell), `obstacle` (one per obstacle present), `robot`
//! (a triangle pointing where the robot heads). Whoever shows a plan adds it, with its
//! goal: [`GridWorld::scene_with`] draws them as `path` and `goal`.
//!
//! ```
//! use neurotree::robotics::Pose2D;
//! use neurotree::sim::GridWorld;
//!
//! let world = GridWorld::parse("##...\nR...C", 1.0).unwrap();
//! let path = [Pose2D::new(0.5, 0.5, 0.0), Pose2D::new(3.5, 0.5, 0.0)];
//! let scene = world.scene_with(&path, Some(Pose2D::new(3.5, 0.5, 0.0)));
//! let ids: Vec<&str> = scene.items().iter().map(|i| i.id.as_str()).collect();
//! assert_eq!(ids, ["floor", "wall", "charger", "path", "goal", "robot"]);
//! assert_eq!(scene.bounds(), [[0.0, 0.0], [5.0, 2.0]]);
//! ```

use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::scene::{Point, Scene, Style};

use super::grid::Cell;
use super::world::{CostmapLayer, GridWorld};

impl GridWorld {
    /// The world as a scene, with the path being followed and its end: see the
    /// [module documentation](self).
    pub fn scene(&self) -> Scene {
        let ahead = self.path_ahead();
        self.scene_with(ahead, ahead.last().copied())
    }

    /// The world as a scene with `path` and `goal` drawn (ids `path` and `goal`) instead of
    /// the path being followed.
    pub fn scene_with(&self, path: &[Pose2D], goal: Option<Pose2D>) -> Scene {
        let map = self.map();
        let r = map.resolution();
        let (w, h) = (f64::from(map.width()) * r, f64::from(map.height()) * r);
        let mut scene = Scene::new([0.0, 0.0], [w, h]);
        scene.polygon("floor", rect(0.0, 0.0, w, h), Style::fill("#f4f1ea"));
        // A run of walls in a row is one polygon: a warehouse's walls are a few dozen items,
        // not hundreds of squares.
        for y in 0..map.height() {
            let mut x = 0;
            while x < map.width() {
                if !map.is_wall(Cell::new(x, y)) {
                    x += 1;
                    continue;
                }
                let start = x;
                while x < map.width() && map.is_wall(Cell::new(x, y)) {
                    x += 1;
                }
                let (x0, x1) = (f64::from(start) * r, f64::from(x) * r);
                let y0 = f64::from(y) * r;
                scene.polygon("wall", rect(x0, y0, x1, y0 + r), Style::fill("#495057"));
            }
        }
        if let Some(c) = self.charger() {
            scene.polygon(
                "charger",
                cell_rect(c, r, 0.1),
                Style::fill("#ffe066").with_stroke("#e67700", 0.05 * r),
            );
        }
        let costmap = self.costmap(CostmapLayer::Global);
        for c in costmap.marked() {
            scene.polygon("costmap", cell_rect(c, r, 0.0), Style::fill("#ffc9c9"));
        }
        let truth = self.truth();
        for o in self.timed_obstacles() {
            if truth.is_obstacle(o.cell) {
                scene.polygon(
                    "obstacle",
                    cell_rect(o.cell, r, 0.1),
                    Style::fill("#c92a2a"),
                );
            }
        }
        if path.len() > 1 {
            let points = path.iter().map(|p| [p.x, p.y]).collect();
            scene.polyline("path", points, Style::stroke("#2f9e44", 0.12 * r));
        }
        if let Some(g) = goal {
            scene.circle(
                "goal",
                [g.x, g.y],
                0.3 * r,
                Style::fill("none").with_stroke("#2f9e44", 0.1 * r),
            );
        }
        let robot = self.robot();
        scene.polygon(
            "robot",
            arrow(&robot, 0.4 * r),
            Style::fill("#1c7ed6").with_stroke("#0b3d91", 0.04 * r),
        );
        scene
    }
}

/// The rectangle from `(x0, y0)` to `(x1, y1)`, counter-clockwise.
fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

/// Cell `c`'s square, `inset` of a cell in from each side.
fn cell_rect(c: Cell, r: f64, inset: f64) -> Vec<Point> {
    let (x0, y0) = (f64::from(c.x) * r, f64::from(c.y) * r);
    let d = inset * r;
    rect(x0 + d, y0 + d, x0 + r - d, y0 + r - d)
}

/// A triangle of radius `size` around `pose`, its tip where the pose heads.
fn arrow(pose: &Pose2D, size: f64) -> Vec<Point> {
    let corner = |angle: f64, reach: f64| {
        let a = pose.theta + angle;
        [pose.x + reach * a.cos(), pose.y + reach * a.sin()]
    };
    vec![corner(0.0, size), corner(2.5, size), corner(-2.5, size)]
}

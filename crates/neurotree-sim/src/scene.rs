//! The world as a [`Scene`], for a viewer that draws it beside the tree (the studio's
//! scene panel): the floor, the walls, the charger, the global costmap's inflated and
//! marked cells, the obstacles present now and the robot.
//!
//! Item ids: `floor`, `wall` (rectangles of wall cells: a run in a row, stacked over the
//! same run in the rows below), `charger`, `inflation` (rectangles, likewise, of the cells
//! within [`INFLATION_RADIUS`] of a wall or a mark:
//! [`Costmap::inflated`](crate::Costmap::inflated), drawn lighter than the marks and
//! beneath them), `costmap` (one square per marked cell), `obstacle` (one per obstacle
//! present), `robot` (a triangle pointing where the robot heads). Whoever shows a plan adds
//! it, with its goal: [`GridWorld::scene_with`] draws them as `path` and `goal`. Drawing
//! rectangles of cells rather than cells keeps a warehouse's scene to about a hundred items.
//!
//! ```
//! use neurotree::robotics::Pose2D;
//! use neurotree::sim::GridWorld;
//!
//! let world = GridWorld::parse("##...\nR...C", 1.0).unwrap();
//! let path = [Pose2D::new(0.5, 0.5, 0.0), Pose2D::new(3.5, 0.5, 0.0)];
//! let scene = world.scene_with(&path, Some(Pose2D::new(3.5, 0.5, 0.0)));
//! let ids: Vec<&str> = scene.items().iter().map(|i| i.id.as_str()).collect();
//! assert_eq!(
//!     ids,
//!     ["floor", "wall", "charger", "inflation", "inflation", "path", "goal", "robot"]
//! );
//! assert_eq!(scene.bounds(), [[0.0, 0.0], [5.0, 2.0]]);
//! ```

use std::collections::HashSet;

use neurotree_nav2::robotics::Pose2D;
use neurotree_toolkit::scene::{Point, Scene, Style};

use super::grid::{Cell, GridMap};
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
        for block in blocks(map, |c| map.is_wall(c)) {
            scene.polygon("wall", block, Style::fill("#495057"));
        }
        if let Some(c) = self.charger() {
            scene.polygon(
                "charger",
                cell_rect(c, r, 0.1),
                Style::fill("#ffe066").with_stroke("#e67700", 0.05 * r),
            );
        }
        let costmap = self.costmap(CostmapLayer::Global);
        let inflated: HashSet<Cell> = costmap.inflated(INFLATION_RADIUS).collect();
        for block in blocks(map, |c| inflated.contains(&c)) {
            scene.polygon("inflation", block, Style::fill("#fff0f0"));
        }
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

/// How far from a wall or a sensed obstacle the scene shows the global costmap inflated,
/// in metres. Nav2's default (0.55 m) would inflate nothing on the demo's one-metre cells;
/// one metre shows the cell beside each blocked one.
pub const INFLATION_RADIUS: f64 = 1.0;

/// Rectangles covering the cells for which `inside` is `true`, bottom first: each a run of
/// such cells in a row, stacked over the same run in the rows below. A warehouse's walls
/// and the bands beside them are a few dozen polygons, not hundreds of squares.
fn blocks(map: &GridMap, inside: impl Fn(Cell) -> bool) -> Vec<Vec<Point>> {
    // [x0, x1, y0, y1) in cells; `open` ones reach the row above the last one looked at.
    let mut done: Vec<[i32; 4]> = Vec::new();
    let mut open: Vec<[i32; 4]> = Vec::new();
    for y in 0..map.height() {
        let mut reaching = Vec::new();
        let mut x = 0;
        while x < map.width() {
            if !inside(Cell::new(x, y)) {
                x += 1;
                continue;
            }
            let start = x;
            while x < map.width() && inside(Cell::new(x, y)) {
                x += 1;
            }
            match open.iter().position(|b| b[0] == start && b[1] == x) {
                Some(i) => {
                    let mut block = open.swap_remove(i);
                    block[3] = y + 1;
                    reaching.push(block);
                }
                None => reaching.push([start, x, y, y + 1]),
            }
        }
        done.append(&mut open);
        open = reaching;
    }
    done.append(&mut open);
    done.sort_unstable_by_key(|b| (b[2], b[0]));
    let r = map.resolution();
    done.into_iter()
        .map(|[x0, x1, y0, y1]| {
            let m = |v: i32| f64::from(v) * r;
            rect(m(x0), m(y0), m(x1), m(y1))
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use neurotree_toolkit::scene::{Item, Shape};

    use super::*;
    use crate::TimedObstacle;

    /// The cells the rectangles of the items `id` cover, bottom row first.
    fn covered(scene: &Scene, id: &str) -> Vec<Cell> {
        let mut cells = Vec::new();
        for item in scene.items().iter().filter(|i| i.id == id) {
            let Shape::Polygon { points } = &item.shape else {
                panic!("{item:?}");
            };
            let [x0, y0] = points[0];
            let [x1, y1] = points[2];
            for y in y0.round() as i32..y1.round() as i32 {
                cells.extend((x0.round() as i32..x1.round() as i32).map(|x| Cell::new(x, y)));
            }
        }
        cells.sort_by_key(|c| (c.y, c.x));
        cells
    }

    fn fill<'a>(scene: &'a Scene, id: &str) -> Option<&'a str> {
        let item: &Item = scene.items().iter().find(|i| i.id == id)?;
        item.style.fill.as_deref()
    }

    #[test]
    fn the_inflated_cells_are_drawn_in_runs_apart_from_the_marked_ones() {
        let mut world = GridWorld::parse("#.....\n......\nR.....\n......", 1.0)
            .unwrap()
            .with_timed_obstacle(TimedObstacle::new(Cell::new(4, 1), Duration::ZERO))
            .with_sensing_radius(10.0);
        world.step(Duration::from_millis(100));
        let costmap = world.costmap(CostmapLayer::Global);
        assert_eq!(costmap.marked().collect::<Vec<_>>(), [Cell::new(4, 1)]);
        let scene = world.scene();
        assert!(scene.check().is_ok());
        // The two cells beside the wall and the four beside the mark, in six runs: (4, 0);
        // (3, 1) and (5, 1), split by the mark; (0, 2) and (4, 2); (1, 3).
        let inflated: Vec<Cell> = costmap.inflated(INFLATION_RADIUS).collect();
        assert_eq!(inflated.len(), 6);
        assert_eq!(covered(&scene, "inflation"), inflated);
        let runs = scene.items().iter().filter(|i| i.id == "inflation").count();
        assert_eq!(runs, 6);
        assert_eq!(covered(&scene, "costmap"), [Cell::new(4, 1)]);
        // Lighter than the lethal marks, and beneath them.
        assert_ne!(fill(&scene, "inflation"), fill(&scene, "costmap"));
        let at = |id: &str| scene.items().iter().position(|i| i.id == id).unwrap();
        assert!(at("inflation") < at("costmap"));
    }

    #[test]
    fn a_band_of_inflated_cells_is_one_rectangle() {
        let count = |scene: &Scene, id: &str| scene.items().iter().filter(|i| i.id == id).count();
        let world = GridWorld::parse("##########\n..........\nR.........", 1.0).unwrap();
        let scene = world.scene();
        assert_eq!(
            covered(&scene, "inflation"),
            (0..10).map(|x| Cell::new(x, 1)).collect::<Vec<_>>()
        );
        assert_eq!(count(&scene, "inflation"), 1);
        // A wall across three rows: one rectangle, and one on either side of it.
        let world = GridWorld::parse("..#..\n..#..\nR.#..", 1.0).unwrap();
        let scene = world.scene();
        assert_eq!((count(&scene, "wall"), count(&scene, "inflation")), (1, 2));
        let band = |x| (0..3).map(move |y| Cell::new(x, y));
        let mut expected: Vec<Cell> = band(1).chain(band(3)).collect();
        expected.sort_by_key(|c| (c.y, c.x));
        assert_eq!(covered(&scene, "inflation"), expected);
        assert_eq!(covered(&scene, "wall"), band(2).collect::<Vec<_>>());
    }
}

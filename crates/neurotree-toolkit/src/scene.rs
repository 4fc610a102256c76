//! A drawing of the world a tree acts on, to show beside the tree: the robot, its map and
//! its path, or a game's level and its agents.
//!
//! A [`Scene`] is a flat list of [`Item`]s in world coordinates (x to the right, y up),
//! each a polygon, a polyline, a circle or a text, with an id that names it and a style.
//! A program makes one after each tick from whatever it keeps; a viewer (the studio's
//! scene panel) draws it, scaled to fit [`Scene::bounds`]. Nothing here knows robots: the
//! simulated warehouse of `neurotree-sim` is one user, a game's map would be another.
//!
//! A scene is meant to be sent to a browser every tick, so it is bounded: at most
//! [`MAX_ITEMS`] items, [`MAX_POINTS`] points in all, ids and texts of at most
//! [`MAX_TEXT`] bytes. [`Scene::check`] says which bound a scene passes; a viewer refuses
//! such a scene rather than draw part of it.
//!
//! ```
//! use neurotree_toolkit::scene::{Scene, Style};
//!
//! let mut scene = Scene::new([0.0, 0.0], [10.0, 5.0]);
//! scene.polygon("wall", vec![[0.0, 0.0], [10.0, 0.0], [10.0, 0.5], [0.0, 0.5]], Style::fill("#555"));
//! scene.polyline("path", vec![[1.0, 1.0], [4.0, 1.0], [4.0, 3.0]], Style::stroke("#1a7", 0.1));
//! scene.circle("robot", [1.0, 1.0], 0.3, Style::fill("#36c"));
//! scene.text("label", [1.0, 1.6], "robot", 0.4, Style::fill("#000"));
//! assert_eq!(scene.items().len(), 4);
//! assert!(scene.check().is_ok());
//! let json = serde_json::to_value(&scene).unwrap();
//! assert_eq!(json["items"][2]["id"], "robot");
//! assert_eq!(json["items"][2]["shape"], "circle");
//! ```

use serde::Serialize;

/// The most items a scene may hold.
pub const MAX_ITEMS: usize = 4096;
/// The most points a scene's polygons and polylines may hold together.
pub const MAX_POINTS: usize = 65_536;
/// The longest id, text or colour, in bytes.
pub const MAX_TEXT: usize = 256;

/// A point in world coordinates: `[x, y]`, y up.
pub type Point = [f64; 2];

/// What to draw, in world coordinates; see the [module documentation](self).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Scene {
    /// The lower left and upper right corners of what to show.
    bounds: [Point; 2],
    items: Vec<Item>,
}

/// One drawable thing with its id.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Item {
    /// Names the item: a viewer marks what it draws with it (the studio as
    /// `data-scene-item`). Several items may share one (the cells of one costmap).
    pub id: String,
    /// What it is.
    #[serde(flatten)]
    pub shape: Shape,
    /// How it looks.
    #[serde(flatten)]
    pub style: Style,
}

/// The forms an item takes.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum Shape {
    /// A closed outline, filled.
    Polygon {
        /// The corners, in order.
        points: Vec<Point>,
    },
    /// An open line through the points.
    Polyline {
        /// The points, in order.
        points: Vec<Point>,
    },
    /// A disc.
    Circle {
        /// Its centre.
        center: Point,
        /// Its radius, in world units.
        radius: f64,
    },
    /// A line of text, its baseline starting at `at`.
    Text {
        /// Where the text begins.
        at: Point,
        /// What it says.
        text: String,
        /// Its height, in world units.
        size: f64,
    },
}

/// Colours (CSS colours: `#rgb`, `#rrggbb`, a name) and the width of lines, in world units.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Style {
    /// The colour inside, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fill: Option<String>,
    /// The colour of the outline or line, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stroke: Option<String>,
    /// The width of the outline or line.
    #[serde(skip_serializing_if = "is_zero")]
    pub width: f64,
}

fn is_zero(w: &f64) -> bool {
    *w == 0.0
}

impl Style {
    /// Filled with `colour`, no outline.
    pub fn fill(colour: &str) -> Self {
        Self {
            fill: Some(colour.into()),
            ..Self::default()
        }
    }

    /// A line or outline of `colour`, `width` wide, nothing filled.
    pub fn stroke(colour: &str, width: f64) -> Self {
        Self {
            stroke: Some(colour.into()),
            width,
            ..Self::default()
        }
    }

    /// This style with an outline of `colour`, `width` wide.
    pub fn with_stroke(mut self, colour: &str, width: f64) -> Self {
        self.stroke = Some(colour.into());
        self.width = width;
        self
    }
}

/// A bound of [`Scene::check`] that a scene passes.
#[derive(Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// More than [`MAX_ITEMS`] items.
    #[error(
        "the scene has {0} items; at most {MAX_ITEMS} are drawn: merge small items into polygons"
    )]
    TooManyItems(usize),
    /// More than [`MAX_POINTS`] points.
    #[error("the scene has {0} points; at most {MAX_POINTS} are drawn: simplify its lines")]
    TooManyPoints(usize),
    /// An id, text or colour longer than [`MAX_TEXT`] bytes.
    #[error("item `{0}` has an id, text or colour over {MAX_TEXT} bytes")]
    TooLong(String),
    /// A coordinate, size or width that is not a finite number.
    #[error("item `{0}` has a coordinate or size that is not a finite number")]
    NotFinite(String),
}

neurotree_core::debug_shows_message!(
    enum SceneError {
        TooManyItems(source),
        TooManyPoints(source),
        TooLong(source),
        NotFinite(source),
    }
);

impl Scene {
    /// An empty scene showing the rectangle from `min` (lower left) to `max` (upper right).
    pub fn new(min: Point, max: Point) -> Self {
        Self {
            bounds: [min, max],
            items: Vec::new(),
        }
    }

    /// The lower left and upper right corners of what to show.
    pub fn bounds(&self) -> [Point; 2] {
        self.bounds
    }

    /// The items, in drawing order (later ones on top).
    pub fn items(&self) -> &[Item] {
        &self.items
    }

    /// Adds `item` on top of the others.
    pub fn push(&mut self, item: Item) -> &mut Self {
        self.items.push(item);
        self
    }

    /// Adds a filled outline through `points`.
    pub fn polygon(&mut self, id: &str, points: Vec<Point>, style: Style) -> &mut Self {
        self.push(Item {
            id: id.into(),
            shape: Shape::Polygon { points },
            style,
        })
    }

    /// Adds an open line through `points`.
    pub fn polyline(&mut self, id: &str, points: Vec<Point>, style: Style) -> &mut Self {
        self.push(Item {
            id: id.into(),
            shape: Shape::Polyline { points },
            style,
        })
    }

    /// Adds a disc.
    pub fn circle(&mut self, id: &str, center: Point, radius: f64, style: Style) -> &mut Self {
        self.push(Item {
            id: id.into(),
            shape: Shape::Circle { center, radius },
            style,
        })
    }

    /// Adds a line of text `size` high, beginning at `at`.
    pub fn text(&mut self, id: &str, at: Point, text: &str, size: f64, style: Style) -> &mut Self {
        self.push(Item {
            id: id.into(),
            shape: Shape::Text {
                at,
                text: text.into(),
                size,
            },
            style,
        })
    }

    /// `Ok` if the scene is within the bounds a viewer draws ([`MAX_ITEMS`],
    /// [`MAX_POINTS`], [`MAX_TEXT`]) and all its numbers are finite.
    pub fn check(&self) -> Result<(), SceneError> {
        if self.items.len() > MAX_ITEMS {
            return Err(SceneError::TooManyItems(self.items.len()));
        }
        let finite = |p: &Point| p[0].is_finite() && p[1].is_finite();
        if !self.bounds.iter().all(finite) {
            return Err(SceneError::NotFinite("bounds".into()));
        }
        let mut points = 0usize;
        for item in &self.items {
            let style = &item.style;
            let texts = [Some(&item.id), style.fill.as_ref(), style.stroke.as_ref()];
            let long = texts.iter().flatten().any(|t| t.len() > MAX_TEXT);
            let (ok, long) = match &item.shape {
                Shape::Polygon { points: p } | Shape::Polyline { points: p } => {
                    points += p.len();
                    (p.iter().all(finite), long)
                }
                Shape::Circle { center, radius } => (finite(center) && radius.is_finite(), long),
                Shape::Text { at, text, size } => (
                    finite(at) && size.is_finite(),
                    long || text.len() > MAX_TEXT,
                ),
            };
            if long {
                return Err(SceneError::TooLong(truncated(&item.id)));
            }
            if !ok || !style.width.is_finite() {
                return Err(SceneError::NotFinite(truncated(&item.id)));
            }
        }
        if points > MAX_POINTS {
            return Err(SceneError::TooManyPoints(points));
        }
        Ok(())
    }
}

/// An id cut to a length an error message can carry.
fn truncated(id: &str) -> String {
    id.chars().take(40).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_bound_is_named_when_passed() {
        let mut scene = Scene::new([0.0, 0.0], [1.0, 1.0]);
        for i in 0..MAX_ITEMS {
            scene.circle("c", [0.0, i as f64], 0.1, Style::fill("red"));
        }
        assert_eq!(scene.check(), Ok(()));
        scene.circle("c", [0.0, 0.0], 0.1, Style::fill("red"));
        assert_eq!(scene.check(), Err(SceneError::TooManyItems(MAX_ITEMS + 1)));

        let mut scene = Scene::new([0.0, 0.0], [1.0, 1.0]);
        scene.polyline("a", vec![[0.0, 0.0]; MAX_POINTS], Style::default());
        assert_eq!(scene.check(), Ok(()));
        scene.polygon("b", vec![[0.0, 0.0]], Style::default());
        assert_eq!(
            scene.check(),
            Err(SceneError::TooManyPoints(MAX_POINTS + 1))
        );

        let mut scene = Scene::new([0.0, 0.0], [1.0, 1.0]);
        scene.text(
            "t",
            [0.0, 0.0],
            &"x".repeat(MAX_TEXT + 1),
            1.0,
            Style::default(),
        );
        assert_eq!(scene.check(), Err(SceneError::TooLong("t".into())));

        let mut scene = Scene::new([0.0, 0.0], [1.0, 1.0]);
        scene.circle("nan", [f64::NAN, 0.0], 1.0, Style::default());
        assert_eq!(scene.check(), Err(SceneError::NotFinite("nan".into())));
    }

    #[test]
    fn items_serialize_flat_with_their_shape_named() {
        let mut scene = Scene::new([0.0, 0.0], [2.0, 2.0]);
        scene.polygon(
            "p",
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
            Style::fill("#abc").with_stroke("#000", 0.05),
        );
        let json = serde_json::to_value(&scene).unwrap();
        assert_eq!(
            json,
            serde_json::json!({
                "bounds": [[0.0, 0.0], [2.0, 2.0]],
                "items": [{"id": "p", "shape": "polygon", "points": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
                           "fill": "#abc", "stroke": "#000", "width": 0.05}]
            })
        );
    }
}

//! The occupancy grid: cells, their size in metres, and which are walls.
//!
//! Cell `(x, y)` covers `[x·r, (x+1)·r) × [y·r, (y+1)·r)` metres for a resolution `r`, with
//! the origin at the map's lower-left corner and `y` growing upwards, as in a ROS map. In a
//! map's text the first line is therefore the top row.

use std::fmt;

use neurotree_nav2::robotics::Pose2D;

/// A cell of the grid, by column `x` and row `y` (row 0 at the bottom).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cell {
    /// Column, from the left.
    pub x: i32,
    /// Row, from the bottom.
    pub y: i32,
}

impl Cell {
    /// The cell at column `x`, row `y`.
    pub const fn new(x: i32, y: i32) -> Self {
        Self { x, y }
    }
}

impl fmt::Display for Cell {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {})", self.x, self.y)
    }
}

/// Why a map or a world could not be made.
#[derive(Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MapError {
    /// The map has no cells.
    #[error("the map is empty: give at least one row of cells")]
    Empty,
    /// Rows of different lengths.
    #[error("row {row} has {found} cells, the first row {expected}: every row must be as wide")]
    Ragged {
        /// 1-based line of the text.
        row: usize,
        /// Width of the first row.
        expected: usize,
        /// Width of this one.
        found: usize,
    },
    /// A character that is not part of the map alphabet.
    #[error("unknown map character `{ch}` at row {row}, column {col}; use # . R C")]
    UnknownChar {
        /// The character.
        ch: char,
        /// 1-based line.
        row: usize,
        /// 1-based column.
        col: usize,
    },
    /// The text places no robot, or more than one.
    #[error("the map must place exactly one robot `R`, found {0}")]
    Robots(usize),
    /// The text places more than one charger.
    #[error("the map may place at most one charger `C`, found {0}")]
    Chargers(usize),
    /// The resolution is not a positive number of metres.
    #[error("the cell size must be a positive number of metres, not {0}")]
    Resolution(f64),
    /// A pose lies outside the map.
    #[error("the {what} at {pose} is outside the map")]
    OutsideMap {
        /// What was placed (`robot`).
        what: &'static str,
        /// Where.
        pose: Pose2D,
    },
    /// A cell is a wall or outside the map.
    #[error("the {what} cell {cell} is a wall or outside the map")]
    Blocked {
        /// What was placed (`robot`, `charger`).
        what: &'static str,
        /// The cell.
        cell: Cell,
    },
}

neurotree_core::debug_shows_message!(enum MapError {
    Empty,
    Ragged { row, expected, found },
    UnknownChar { ch, row, col },
    Robots(source),
    Chargers(source),
    Resolution(source),
    OutsideMap { what, pose },
    Blocked { what, cell },
});

/// The static map: a rectangle of free and wall cells.
#[derive(Clone, Debug, PartialEq)]
pub struct GridMap {
    width: i32,
    height: i32,
    resolution: f64,
    walls: Vec<bool>,
}

impl GridMap {
    /// A map of `width` × `height` free cells of `resolution` metres.
    pub fn new(width: u16, height: u16, resolution: f64) -> Result<Self, MapError> {
        if width == 0 || height == 0 {
            return Err(MapError::Empty);
        }
        if !(resolution > 0.0 && resolution.is_finite()) {
            return Err(MapError::Resolution(resolution));
        }
        Ok(Self {
            width: i32::from(width),
            height: i32::from(height),
            resolution,
            walls: vec![false; usize::from(width) * usize::from(height)],
        })
    }

    /// Columns.
    pub fn width(&self) -> i32 {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> i32 {
        self.height
    }

    /// The side of a cell, in metres.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// `true` if `cell` is inside the map.
    pub fn contains(&self, cell: Cell) -> bool {
        (0..self.width).contains(&cell.x) && (0..self.height).contains(&cell.y)
    }

    fn index(&self, cell: Cell) -> Option<usize> {
        // Both coordinates are checked non-negative and in range, so the casts are exact.
        self.contains(cell)
            .then(|| cell.y as usize * self.width as usize + cell.x as usize)
    }

    /// `true` if `cell` is a wall or outside the map.
    pub fn is_wall(&self, cell: Cell) -> bool {
        self.index(cell).is_none_or(|i| self.walls[i])
    }

    /// Makes `cell` a wall or frees it; cells outside the map are ignored.
    pub fn set_wall(&mut self, cell: Cell, wall: bool) {
        if let Some(i) = self.index(cell) {
            self.walls[i] = wall;
        }
    }

    /// The cell under a position, or `None` outside the map.
    pub fn cell_at(&self, pose: &Pose2D) -> Option<Cell> {
        let x = (pose.x / self.resolution).floor();
        let y = (pose.y / self.resolution).floor();
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        // Out-of-range floats saturate and then fail `contains`.
        let cell = Cell::new(x as i32, y as i32);
        self.contains(cell).then_some(cell)
    }

    /// The centre of `cell`, facing along +x.
    pub fn centre(&self, cell: Cell) -> Pose2D {
        Pose2D::new(
            (f64::from(cell.x) + 0.5) * self.resolution,
            (f64::from(cell.y) + 0.5) * self.resolution,
            0.0,
        )
    }

    /// Every cell, bottom row first.
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        (0..self.height).flat_map(move |y| (0..self.width).map(move |x| Cell::new(x, y)))
    }
}

/// What a map's text places besides walls.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ParsedMap {
    pub(crate) map: GridMap,
    pub(crate) robot: Cell,
    pub(crate) charger: Option<Cell>,
}

/// Reads a map drawn as text, top row first: `#` wall, `.` free, `R` the robot (on a free
/// cell), `C` the charger (a free cell). Surrounding blank lines and indentation are ignored.
pub(crate) fn parse(text: &str, resolution: f64) -> Result<ParsedMap, MapError> {
    let rows: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let width = rows.first().map_or(0, |r| r.chars().count());
    let too_big = |n: usize| u16::try_from(n).is_err();
    if rows.is_empty() || width == 0 || too_big(width) || too_big(rows.len()) {
        return Err(MapError::Empty);
    }
    // Checked just above to fit in u16.
    let mut map = GridMap::new(width as u16, rows.len() as u16, resolution)?;
    let (mut robots, mut chargers) = (Vec::new(), Vec::new());
    let top = map.height - 1;
    for (r, line) in rows.iter().enumerate() {
        let found = line.chars().count();
        if found != width {
            return Err(MapError::Ragged {
                row: r + 1,
                expected: width,
                found,
            });
        }
        for (c, ch) in line.chars().enumerate() {
            // Both indices are below the u16 limits checked above.
            let cell = Cell::new(c as i32, top - r as i32);
            match ch {
                '#' => map.set_wall(cell, true),
                '.' => {}
                'R' => robots.push(cell),
                'C' => chargers.push(cell),
                _ => {
                    return Err(MapError::UnknownChar {
                        ch,
                        row: r + 1,
                        col: c + 1,
                    })
                }
            }
        }
    }
    let [robot] = robots[..] else {
        return Err(MapError::Robots(robots.len()));
    };
    if chargers.len() > 1 {
        return Err(MapError::Chargers(chargers.len()));
    }
    Ok(ParsedMap {
        map,
        robot,
        charger: chargers.first().copied(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_reads_top_row_first() {
        let p = parse(
            "
            #####
            #R.C#
            #..##
            #####",
            0.5,
        )
        .unwrap();
        assert_eq!((p.map.width(), p.map.height()), (5, 4));
        assert_eq!(p.robot, Cell::new(1, 2));
        assert_eq!(p.charger, Some(Cell::new(3, 2)));
        assert!(p.map.is_wall(Cell::new(3, 1)));
        assert!(!p.map.is_wall(Cell::new(2, 1)));
        assert!(p.map.is_wall(Cell::new(-1, 1)));
        assert!(p.map.is_wall(Cell::new(5, 1)));
        assert_eq!(p.map.cells().filter(|c| !p.map.is_wall(*c)).count(), 5);
    }

    #[test]
    fn poses_and_cells_convert_both_ways() {
        let map = GridMap::new(4, 3, 0.5).unwrap();
        assert_eq!(map.centre(Cell::new(2, 1)), Pose2D::new(1.25, 0.75, 0.0));
        assert_eq!(
            map.cell_at(&Pose2D::new(1.25, 0.75, 2.0)),
            Some(Cell::new(2, 1))
        );
        // Lower and left edges belong to the cell; upper and right ones to the next.
        assert_eq!(
            map.cell_at(&Pose2D::new(1.0, 0.5, 0.0)),
            Some(Cell::new(2, 1))
        );
        assert_eq!(map.cell_at(&Pose2D::new(2.0, 0.5, 0.0)), None);
        assert_eq!(map.cell_at(&Pose2D::new(-0.01, 0.5, 0.0)), None);
        assert_eq!(map.cell_at(&Pose2D::new(f64::NAN, 0.5, 0.0)), None);
        assert_eq!(map.cell_at(&Pose2D::new(1e300, 0.5, 0.0)), None);
    }

    #[test]
    fn bad_maps_say_what_is_wrong() {
        assert_eq!(parse("", 1.0).unwrap_err(), MapError::Empty);
        assert_eq!(
            parse("R..\n..", 1.0).unwrap_err(),
            MapError::Ragged {
                row: 2,
                expected: 3,
                found: 2
            }
        );
        assert_eq!(
            parse("R.x", 1.0).unwrap_err(),
            MapError::UnknownChar {
                ch: 'x',
                row: 1,
                col: 3
            }
        );
        assert_eq!(parse("...", 1.0).unwrap_err(), MapError::Robots(0));
        assert_eq!(parse("RR.", 1.0).unwrap_err(), MapError::Robots(2));
        assert_eq!(parse("RCC", 1.0).unwrap_err(), MapError::Chargers(2));
        assert_eq!(parse("R..", 0.0).unwrap_err(), MapError::Resolution(0.0));
        assert!(parse("R..", f64::NAN).is_err());
        assert_eq!(
            MapError::Robots(0).to_string(),
            "the map must place exactly one robot `R`, found 0"
        );
    }
}

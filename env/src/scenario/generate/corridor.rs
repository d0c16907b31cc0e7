//! `corridor`: one corridor of a given width and centreline length with right-angle bends,
//! on a grid of square cells one corridor width wide; every other cell is wall.

use rand::RngExt;

use super::place::{pair_in_box, passage, rect};
use super::{Family, Refusal, Rng};
use crate::declare_params;
use crate::params::Reals;
use crate::physics::PhysicalParams;
use crate::scenario::Draft;
use crate::scenario::file::{MAX_OBSTACLES, MAX_WORLD_BL};

declare_params! {
    /// The parameters of `corridor`.
    #[derive(Debug, Clone)]
    pub struct Corridor {
        /// Length of the corridor's centreline from the start cell to the goal cell (BL).
        #[param("length", Reals::closed(2.0, 5000.0))]
        pub length: f64 = 30.0,
        /// Width of the corridor (BL).
        #[param("width", Reals::closed(0.5, 50.0))]
        pub width: f64 = 3.5,
        /// Number of right-angle bends.
        #[param("bends", 0..=50)]
        pub bends: usize = 2,
    }
}

/// Most cells along a corridor.
const MAX_CELLS: usize = 400;

/// Draws of a random bend sequence before the staircase (alternating turns, which never
/// touches itself) is used.
const TRIES: usize = 100;

impl Corridor {
    /// Cells the corridor advances from its first cell.
    fn steps(&self) -> usize {
        (self.length / self.width).round() as usize
    }
}

/// The cells of a corridor of segments `lengths` (cells), first heading `dir` (0..4, a
/// quarter turn each), turning by `turns` (+1 left, −1 right) between segments; `None` when it
/// meets itself (a cell repeated or beside a cell that is not its neighbour along the path).
fn walk(lengths: &[usize], mut dir: i64, turns: &[i64]) -> Option<Vec<(i64, i64)>> {
    const D: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
    let mut cells = vec![(0i64, 0i64)];
    for (k, &len) in lengths.iter().enumerate() {
        if k > 0 {
            dir = (dir + turns[k - 1]).rem_euclid(4);
        }
        let (dx, dy) = D[dir as usize];
        for _ in 0..len {
            let &(x, y) = cells.last().expect("non-empty");
            cells.push((x + dx, y + dy));
        }
    }
    for i in 0..cells.len() {
        for j in (i + 2)..cells.len() {
            let d = (cells[i].0 - cells[j].0).abs() + (cells[i].1 - cells[j].1).abs();
            if d <= 1 {
                return None;
            }
        }
    }
    Some(cells)
}

impl Family for Corridor {
    fn feasible(&self, physics: &PhysicalParams) -> Result<(), Refusal> {
        passage("width", "a corridor", self.width, physics)?;
        let need = 2 * (self.bends + 1);
        if self.steps() < need {
            return Err(Refusal::new(
                "length",
                format!(
                    "{} bend(s) at width {} BL need a length of at least {} BL (2 cells per straight)",
                    self.bends,
                    self.width,
                    need as f64 * self.width
                ),
            ));
        }
        if self.steps() > MAX_CELLS {
            return Err(Refusal::new(
                "length",
                format!(
                    "{} BL at width {} BL is {} cells; at most {MAX_CELLS}",
                    self.length,
                    self.width,
                    self.steps()
                ),
            ));
        }
        if self.length + self.width > MAX_WORLD_BL {
            return Err(Refusal::new(
                "length",
                format!("the field would be over {MAX_WORLD_BL} BL long"),
            ));
        }
        Ok(())
    }

    fn build(&self, rng: &mut Rng, physics: &PhysicalParams) -> Result<Draft, Refusal> {
        let segments = self.bends + 1;
        let mut lengths = vec![2usize; segments];
        for _ in 0..self.steps() - 2 * segments {
            lengths[rng.random_range(0..segments)] += 1;
        }
        let dir = rng.random_range(0..4i64);
        let mut cells = None;
        for _ in 0..TRIES {
            let turns: Vec<i64> = (0..self.bends)
                .map(|_| if rng.random_bool(0.5) { 1 } else { -1 })
                .collect();
            cells = walk(&lengths, dir, &turns);
            if cells.is_some() {
                break;
            }
        }
        let stairs: Vec<i64> = (0..self.bends as i64).map(|k| 1 - 2 * (k % 2)).collect();
        let cells = match cells {
            Some(c) => c,
            None => walk(&lengths, dir, &stairs).expect("a staircase never meets itself"),
        };
        let (x0, y0) = (
            cells.iter().map(|c| c.0).min().expect("cells"),
            cells.iter().map(|c| c.1).min().expect("cells"),
        );
        let cells: Vec<(usize, usize)> = cells
            .iter()
            .map(|c| ((c.0 - x0) as usize, (c.1 - y0) as usize))
            .collect();
        let columns = cells.iter().map(|c| c.0).max().expect("cells") + 1;
        let rows = cells.iter().map(|c| c.1).max().expect("cells") + 1;
        let w = self.width;
        let mut open = vec![false; columns * rows];
        for &(x, y) in &cells {
            open[y * columns + x] = true;
        }
        // the walls: each row's runs of closed cells, one rectangle per run
        let mut obstacles = Vec::new();
        for y in 0..rows {
            let mut x = 0;
            while x < columns {
                if open[y * columns + x] {
                    x += 1;
                    continue;
                }
                let from = x;
                while x < columns && !open[y * columns + x] {
                    x += 1;
                }
                obstacles.push(rect(
                    from as f64 * w,
                    y as f64 * w,
                    x as f64 * w,
                    (y + 1) as f64 * w,
                ));
            }
        }
        if obstacles.len() > MAX_OBSTACLES {
            return Err(Refusal::new(
                "length",
                format!(
                    "its walls need {} rectangles, more than the {MAX_OBSTACLES} a map may have",
                    obstacles.len()
                ),
            ));
        }
        let cell_box = |(x, y): (usize, usize)| {
            (
                x as f64 * w,
                y as f64 * w,
                (x + 1) as f64 * w,
                (y + 1) as f64 * w,
            )
        };
        Ok(Draft {
            name: String::new(),
            description: format!(
                "corridor: {} BL wide, {} BL long, {} bend(s)",
                self.width,
                self.steps() as f64 * w,
                self.bends
            ),
            width: columns as f64 * w,
            height: rows as f64 * w,
            obstacles,
            medium: None,
            start: pair_in_box(rng, cell_box(cells[0]), physics),
            goal: pair_in_box(rng, cell_box(*cells.last().expect("cells")), physics),
            tolerance: 0.5,
        })
    }

    fn hardest(&self) -> &'static str {
        "width"
    }
}

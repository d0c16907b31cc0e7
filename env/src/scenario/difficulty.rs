//! Difficulty measures of any scenario: how open the map is, the narrowest passage against
//! the pair's turning width, the length and turns of a shortest path of the centre of mass,
//! and the size of the relative move between start and goal.
//!
//! Geometry is measured on a [`FreeGrid`] (cells of 0.1 BL, coarser in worlds over 250 000
//! such cells). The centre-of-mass path keeps the **pair's turning clearance** `(r_min + 1)/2`
//! from walls and obstacles: the pair at its smallest separation, turning freely (a team of
//! three or more needs more; for it the path is a lower bound).

use super::Scenario;
use super::freespace::FreeGrid;
use crate::math::{Vec2, centroid};

/// Consecutive bends of the shortened path the same way round and closer than this many
/// clearances (plus two cells) count as one turn.
const BEND_MERGE: f64 = 2.0;

/// The smallest heading change of a bend that counts as a turn (degrees).
pub const MIN_TURN_DEG: f64 = 20.0;

/// The difficulty of a scenario, every field with its unit. A scenario with several legs: the
/// map measures are the hardest over the legs' maps, the path is the sum of the legs' paths
/// (each leg from the previous goal), the relative move is from the start to the final goal.
#[derive(Debug, Clone, PartialEq)]
pub struct Difficulty {
    /// Fraction of the world's area outside obstacles (0–1; the smallest over the legs' maps).
    pub free_fraction: f64,
    /// Grid cell side the measures used (BL).
    pub grid_bl: f64,
    /// The pair's turning width `r_min + 1`: the smallest disk that holds the pair at any
    /// heading (BL).
    pub min_width_bl: f64,
    /// Clearance the centre-of-mass path keeps from walls and obstacles, `min_width_bl / 2`
    /// (BL).
    pub path_clearance_bl: f64,
    /// The narrowest passage between start and goal centroids: twice the largest clearance a
    /// path of the centre of mass can keep all the way (the start and goal places included)
    /// (BL).
    pub narrowest_passage_bl: f64,
    /// `narrowest_passage_bl / min_width_bl`: below 1 the pair cannot pass turning freely.
    pub passage_ratio: f64,
    /// Length of a shortest path of the centre of mass at `path_clearance_bl` (BL); `None`
    /// when there is none at that clearance.
    pub path_length_bl: Option<f64>,
    /// Turns of that path: bends of at least [`MIN_TURN_DEG`] (nearby bends the same way round
    /// merged into one).
    pub path_turns: Option<usize>,
    /// Total heading change along that path (degrees).
    pub path_turning_deg: Option<f64>,
    /// Straight-line distance from the start centroid to the goal centroid (BL).
    pub centroid_move_bl: f64,
    /// Twice the RMS distance of the agents from their centroid at the start: the separation,
    /// for a pair (BL).
    pub span_start_bl: f64,
    /// The same at the goal (BL).
    pub span_goal_bl: f64,
    /// The rotation of the formation from start to goal, in (−180, 180] (degrees): the change
    /// of the pair's heading, for a team the best-fit rotation of the agents about their
    /// centroid.
    pub rotation_deg: f64,
    /// RMS distance of the goal formation from the rotated start formation, both about their
    /// centroids (BL): `|r_goal − r_start| / 2` for a pair.
    pub shape_change_bl: f64,
}

/// Names of [`Difficulty`]'s fields as result-table columns, in the order of
/// [`Difficulty::columns`].
pub const COLUMNS: [&str; 14] = [
    "free_fraction",
    "grid_bl",
    "min_width_bl",
    "path_clearance_bl",
    "narrowest_passage_bl",
    "passage_ratio",
    "path_length_bl",
    "path_turns",
    "path_turning_deg",
    "centroid_move_bl",
    "span_start_bl",
    "span_goal_bl",
    "rotation_deg",
    "shape_change_bl",
];

/// The relative move from `a` to `b`: (span at a, span at b, rotation in degrees, shape
/// change).
fn relative_move(a: &[Vec2], b: &[Vec2]) -> (f64, f64, f64, f64) {
    let (ca, cb) = (centroid(a), centroid(b));
    let ra: Vec<Vec2> = a.iter().map(|p| p - ca).collect();
    let rb: Vec<Vec2> = b.iter().map(|p| p - cb).collect();
    let n = a.len() as f64;
    let span = |r: &[Vec2]| 2.0 * (r.iter().map(|v| v.norm_squared()).sum::<f64>() / n).sqrt();
    let cross: f64 = ra.iter().zip(&rb).map(|(u, v)| u.perp(v)).sum();
    let dot: f64 = ra.iter().zip(&rb).map(|(u, v)| u.dot(v)).sum();
    let angle = cross.atan2(dot);
    let (c, s) = (angle.cos(), angle.sin());
    let change = ra
        .iter()
        .zip(&rb)
        .map(|(u, v)| (Vec2::new(c * u.x - s * u.y, s * u.x + c * u.y) - v).norm_squared())
        .sum::<f64>()
        / n;
    let mut deg = angle.to_degrees();
    if deg <= -180.0 {
        deg += 360.0;
    }
    (span(&ra), span(&rb), deg, change.sqrt())
}

/// (length, turns, total heading change in degrees) of a polyline, merging consecutive bends
/// the same way round and closer than `merge` BL into one.
fn turns(path: &[Vec2], merge: f64) -> (f64, usize, f64) {
    let length = path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let mut bends: Vec<(Vec2, f64)> = Vec::new();
    for w in path.windows(3) {
        let (u, v) = (w[1] - w[0], w[2] - w[1]);
        if u.norm() == 0.0 || v.norm() == 0.0 {
            continue;
        }
        bends.push((w[1], u.perp(&v).atan2(u.dot(&v)).to_degrees()));
    }
    let total = bends.iter().map(|(_, a)| a.abs()).sum();
    let mut count = 0;
    let mut group: Option<(Vec2, f64)> = None;
    for (p, a) in bends {
        group = match group {
            Some((q, sum)) if (p - q).norm() < merge && sum * a > 0.0 => Some((p, sum + a)),
            Some((_, sum)) => {
                count += usize::from(sum.abs() >= MIN_TURN_DEG);
                Some((p, a))
            }
            None => Some((p, a)),
        };
    }
    if let Some((_, sum)) = group {
        count += usize::from(sum.abs() >= MIN_TURN_DEG);
    }
    (length, count, total)
}

/// The difficulty of `s` (see [`Difficulty`]).
pub fn measure(s: &Scenario) -> Difficulty {
    let min_width = s.physics.r_min + 1.0;
    let clearance = min_width / 2.0;
    let mut free = f64::INFINITY;
    let mut grid_bl: f64 = 0.0;
    let mut widest = f64::INFINITY;
    let mut path: Option<(f64, usize, f64)> = Some((0.0, 0, 0.0));
    let mut from = centroid(&s.start);
    for i in 0..s.legs.len() {
        let grid = FreeGrid::new(&s.world_for_leg(i));
        let to = centroid(&s.legs[i].goal.agents);
        free = free.min(grid.free_fraction());
        grid_bl = grid_bl.max(grid.spacing);
        widest = widest.min(grid.widest_clearance(from, to));
        let leg = grid
            .shortest_path(from, to, clearance)
            .map(|p| turns(&p, BEND_MERGE * clearance + 2.0 * grid.spacing));
        path = path
            .zip(leg)
            .map(|(a, b)| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
        from = to;
    }
    let goal = &s.final_goal().agents;
    let (span_start, span_goal, rotation, shape) = relative_move(&s.start, goal);
    Difficulty {
        free_fraction: free,
        grid_bl,
        min_width_bl: min_width,
        path_clearance_bl: clearance,
        narrowest_passage_bl: 2.0 * widest,
        passage_ratio: 2.0 * widest / min_width,
        path_length_bl: path.map(|p| p.0),
        path_turns: path.map(|p| p.1),
        path_turning_deg: path.map(|p| p.2),
        centroid_move_bl: (centroid(goal) - centroid(&s.start)).norm(),
        span_start_bl: span_start,
        span_goal_bl: span_goal,
        rotation_deg: rotation,
        shape_change_bl: shape,
    }
}

impl Difficulty {
    /// The measures as (column, text) pairs named as in [`COLUMNS`], for a results table; an
    /// absent path gives empty text.
    pub fn columns(&self) -> Vec<(&'static str, String)> {
        let opt = |v: Option<f64>| v.map(|x| format!("{x:.4}")).unwrap_or_default();
        let values = [
            format!("{:.4}", self.free_fraction),
            format!("{:.4}", self.grid_bl),
            format!("{:.4}", self.min_width_bl),
            format!("{:.4}", self.path_clearance_bl),
            format!("{:.4}", self.narrowest_passage_bl),
            format!("{:.4}", self.passage_ratio),
            opt(self.path_length_bl),
            self.path_turns.map(|t| t.to_string()).unwrap_or_default(),
            opt(self.path_turning_deg),
            format!("{:.4}", self.centroid_move_bl),
            format!("{:.4}", self.span_start_bl),
            format!("{:.4}", self.span_goal_bl),
            format!("{:.4}", self.rotation_deg),
            format!("{:.4}", self.shape_change_bl),
        ];
        COLUMNS.into_iter().zip(values).collect()
    }

    /// A few lines for a scenario summary.
    pub fn summary(&self) -> String {
        let path = match (self.path_length_bl, self.path_turns, self.path_turning_deg) {
            (Some(l), Some(t), Some(d)) => {
                format!("{l:.2} BL, {t} turn(s), {d:.0}° of heading change")
            }
            _ => "none".to_string(),
        };
        format!(
            "free space  {:.1}% of the area (grid {} BL)\n\
             passage     narrowest {:.2} BL = {:.2} × the pair's turning width r_min + 1 = {:.2} BL\n\
             path        centre of mass at clearance {:.3} BL: {path}\n\
             move        centroid {:.2} BL, span {:.2} → {:.2} BL, rotation {:.1}°, shape change {:.2} BL\n",
            100.0 * self.free_fraction,
            self.grid_bl,
            self.narrowest_passage_bl,
            self.passage_ratio,
            self.min_width_bl,
            self.path_clearance_bl,
            self.centroid_move_bl,
            self.span_start_bl,
            self.span_goal_bl,
            self.rotation_deg,
            self.shape_change_bl,
        )
    }
}

#[cfg(test)]
mod tests;

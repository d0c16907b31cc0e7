//! Shared pieces of the generators: rounding, rectangles, and placing a pair in a free box.

use std::f64::consts::TAU;

use rand::RngExt;

use super::{Refusal, Rng};
use crate::math::Vec2;
use crate::physics::PhysicalParams;
use crate::world::Obstacle;

/// Extra width (BL) a passage needs beyond the pair's turning width `r_min + 1`, so that
/// the grid check of the corridor (0.1 BL cells) finds it.
pub const MARGIN: f64 = 0.25;

/// Largest separation (BL) of a generated pair.
const PAIR_SEPARATION_MAX: f64 = 2.5;

/// Distance (BL) an agent is kept from the walls of the box it is placed in.
const GAP: f64 = 0.05;

/// `x` rounded to a thousandth of a BL (the files stay short and readable).
pub fn round(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// `p` rounded to a thousandth of a BL.
pub fn round_pt(p: Vec2) -> Vec2 {
    Vec2::new(round(p.x), round(p.y))
}

/// The rectangle `[x0, x1] × [y0, y1]` as a polygon obstacle (corners rounded).
pub fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Obstacle {
    let (x0, y0, x1, y1) = (round(x0), round(y0), round(x1), round(y1));
    Obstacle::Polygon(vec![
        Vec2::new(x0, y0),
        Vec2::new(x1, y0),
        Vec2::new(x1, y1),
        Vec2::new(x0, y1),
    ])
}

/// The pair's turning width `r_min + 1` (BL).
pub fn turning_width(physics: &PhysicalParams) -> f64 {
    physics.r_min + 1.0
}

/// Refuses a passage parameter narrower than the turning width plus [`MARGIN`].
pub fn passage(
    param: &'static str,
    what: &str,
    width: f64,
    physics: &PhysicalParams,
) -> Result<(), Refusal> {
    let need = turning_width(physics) + MARGIN;
    if width < need {
        return Err(Refusal::new(
            param,
            format!(
                "{what} of {width} BL is narrower than the pair's turning width r_min + 1 = {} BL plus {MARGIN} BL: at least {need} BL",
                turning_width(physics)
            ),
        ));
    }
    Ok(())
}

/// Two agents `r` apart about `c`, the second at heading `heading` from the first.
pub fn pair_at(c: Vec2, r: f64, heading: f64) -> Vec<Vec2> {
    let h = Vec2::new(heading.cos(), heading.sin()) * (r / 2.0);
    vec![round_pt(c - h), round_pt(c + h)]
}

/// A pair at a random place, heading and separation inside the free box
/// `[x0, x1] × [y0, y1]`, clear of its sides at any heading: its centre at least
/// `r/2 + 0.55` BL from them.
pub fn pair_in_box(
    rng: &mut Rng,
    (x0, y0, x1, y1): (f64, f64, f64, f64),
    physics: &PhysicalParams,
) -> Vec<Vec2> {
    let half = (x1 - x0).min(y1 - y0) / 2.0;
    let lo = physics.r_min + 0.1;
    let hi = PAIR_SEPARATION_MAX.min(2.0 * (half - 0.5 - GAP)).max(lo);
    let r = rng.random_range(lo..=hi);
    let keep = r / 2.0 + 0.5 + GAP;
    let at = |rng: &mut Rng, a: f64, b: f64| {
        if b - keep > a + keep {
            rng.random_range(a + keep..b - keep)
        } else {
            (a + b) / 2.0
        }
    };
    let c = Vec2::new(at(rng, x0, x1), at(rng, y0, y1));
    pair_at(c, r, rng.random_range(0.0..TAU))
}

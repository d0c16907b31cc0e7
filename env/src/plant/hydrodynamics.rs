//! Hydrodynamic interaction: each agent is carried by the flow the other agents drag along.
//!
//! The Rotne–Prager mobility of two spheres of radius `a` at separation `r` (Rotne & Prager,
//! J. Chem. Phys. 50, 4831 (1969)): the velocity of sphere `i` under a force `F_j` on sphere `j`
//! is `M_ij F_j` with
//!
//! ```text
//! M_ij = 1/(8πηr) [ (1 + 2a²/(3r²)) I + (1 − 2a²/r²) r̂r̂ ],
//! ```
//!
//! which, relative to the self-mobility `1/(6πηa)`, is
//! `(3a/4r) [ (1 + 2a²/3r²) I + (1 − 2a²/r²) r̂r̂ ]`. Under equal and opposite forces the
//! relative mobility along `r̂` is `1 − 3a/(2r) + a³/r³` — 0.46 at r = 1.25 BL and 0.74 at 2.8 BL
//! (a = ½ BL) — and across it `1 − 3a/(4r) − a³/(2r³)`: the agents approach and turn more
//! slowly than the planning model says. A common pull moves a close pair faster. At a clean,
//! flat liquid–air interface crossing the spheres' equators the same ratios hold: a
//! half-immersed sphere's flow is the bulk flow of a sphere under twice the force (the bulk
//! flow is shear-free on that plane), so self- and pair mobilities both double.

use serde::{Deserialize, Serialize};

use super::term::Term;

use crate::math::Vec2;

/// The hydrodynamic-interaction term of a preset (Rotne–Prager; no parameter).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hydrodynamics {
    /// Whether the term acts.
    pub enabled: bool,
}

impl Term for Hydrodynamics {
    super::term::switch_is_enabled_field!();
}

/// Agent radius in BL.
const A: f64 = 0.5;

/// The velocity (relative to the self-mobility) that a force `f` on an agent at `P_j` gives an
/// agent at `P_i`, with `r = P_i − P_j` (BL).
#[inline]
pub fn rotne_prager(r: Vec2, f: Vec2) -> Vec2 {
    let r2 = r.norm_squared();
    let d = r2.sqrt();
    let a2 = A * A / r2;
    let k = 0.75 * A / d;
    let rh = r / d;
    (f * (1.0 + 2.0 * a2 / 3.0) + rh * (rh.dot(&f) * (1.0 - 2.0 * a2))) * k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_mobility_matches_the_closed_form() {
        for &r in &[1.25, 2.0, 2.8, 5.0] {
            let sep = Vec2::new(r, 0.0);
            let f = Vec2::new(1.0, 0.0);
            // agent 2 at +r pushed by +f, agent 1 at 0 by −f: relative velocity along x
            let v2 = f + rotne_prager(sep, -f);
            let v1 = -f + rotne_prager(-sep, f);
            let along = (v2 - v1).x / 2.0;
            assert!((along - (1.0 - 1.5 * A / r + (A / r).powi(3))).abs() < 1e-12);
            let g = Vec2::new(0.0, 1.0);
            let across = ((g + rotne_prager(sep, -g)) - (-g + rotne_prager(-sep, g))).y / 2.0;
            assert!((across - (1.0 - 0.75 * A / r - 0.5 * (A / r).powi(3))).abs() < 1e-12);
        }
        let at = |r: f64| 1.0 - 1.5 * A / r + (A / r).powi(3);
        assert!((at(1.25) - 0.464).abs() < 1e-3 && (at(2.8) - 0.738).abs() < 1e-3);
    }
}

//! Segment start states as free parameters, profiled out of the fit (variable projection).
//!
//! A segment predicted from its first observation starts from a position carrying that
//! frame's detection noise `n₀`; every later residual then holds `−Φ_k(θ) n₀`, where `Φ_k` is
//! the sensitivity of the predicted position at frame `k` to the start. Its expected square,
//! `σ² ‖Φ_k(θ)‖²`, depends on the parameters, so least squares on those residuals favours
//! parameters whose flow contracts (errors in variables): a bias of order σ² that grows with
//! the segment's length. Taking each segment's start state `s` as a free parameter, observed
//! like every other frame (the first frame's rows are `observed − s`), removes it: the fit is
//! then the maximum-likelihood one under white detection noise.
//!
//! The start states are not handed to Levenberg–Marquardt (thousands of them, each touching
//! one segment): each segment's residuals are linearised in its start at the observed one,
//! `r(θ, s) ≈ r(θ, s_obs) + J_s (s − s_obs)`, and the minimum over `s` is the projection
//! `(I − Q Qᵀ) r(θ, s_obs)` onto the complement of `J_s`'s columns (`Q` an orthonormal basis
//! of them). `J_s` comes from forward differences of the prediction, 2 per agent per segment,
//! at the current parameters; the Jacobian in the parameters is projected by the same `Q`
//! (Kaufman's approximation of the variable-projection Jacobian). The linearisation error is
//! of second order in the detection noise.

use magbench_env::Vec2;
use magbench_env::plant::DisturbancePreset;
use nalgebra034::DMatrix;

use super::model::{Model, Segment};

/// Finite-difference step of a start coordinate (BL).
pub const START_STEP_BL: f64 = 1e-4;

/// The start-state directions of one segment's residual rows.
pub struct StartBasis {
    /// Orthonormal basis of the rows' sensitivities to the start state (rows × 2 per agent).
    q: DMatrix<f64>,
}

impl StartBasis {
    /// The basis of segment `s` under `preset`, whose rows from the observed start are `r0`;
    /// `None` when a perturbed prediction touched a wall or stuck.
    pub fn new(model: &Model, preset: &DisturbancePreset, s: &Segment, r0: &[f64]) -> Option<Self> {
        let start = model.observed_start(s);
        let cols = 2 * start.len();
        let mut j = DMatrix::zeros(r0.len(), cols);
        for c in 0..cols {
            let mut p: Vec<Vec2> = start.clone();
            p[c / 2][c % 2] += START_STEP_BL;
            let (r, bad) = model.segment_rows(preset, s, &p);
            if bad {
                return None;
            }
            for (row, (a, b)) in r.iter().zip(r0).enumerate() {
                j[(row, c)] = (a - b) / START_STEP_BL;
            }
        }
        Some(Self { q: j.qr().q() })
    }

    /// `v` with its components along the start-state directions removed.
    pub fn project(&self, v: &mut [f64]) {
        let coef: Vec<f64> = (0..self.q.ncols())
            .map(|c| {
                self.q
                    .column(c)
                    .iter()
                    .zip(v.iter())
                    .map(|(a, b)| a * b)
                    .sum()
            })
            .collect();
        for (c, k) in coef.iter().enumerate() {
            for (x, q) in v.iter_mut().zip(self.q.column(c).iter()) {
                *x -= k * q;
            }
        }
    }
}

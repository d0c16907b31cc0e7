//! The least-squares problem of `shooting-lm` for the `levenberg-marquardt` crate: the
//! decision vector in, the residuals of one rollout through env's model out, the Jacobian by
//! forward differences over rollouts run in parallel (rayon).
//!
//! One problem is one window of the plan: from the window's start, M segments toward its
//! target (a waypoint, or the goal). Residual rows, in order:
//! - target: (q_i(T) − w_i) / tolerance, each coordinate of each agent's end (a miss of one
//!   goal tolerance weighs 1);
//! - per segment k, effort: √(effort / M) · g_k / G for each gradient command (a horizon at
//!   full gradient weighs `effort`);
//! - per segment k, validity: √μ · v / margin for each pair (v = how far its separation comes
//!   within `margin` of r_min or r_max) and each agent (v = how far its clearance to the walls
//!   comes within `margin` of zero), the worst over the segment's integration samples.
//!
//! A rollout is single shooting: q_{k+1} = f(q_k, u_k, δ) with env's propagate; a segment's
//! column of the Jacobian only changes the rows of that segment and those after it, so its
//! rollouts start from the stored state at the segment's start.

use std::cell::RefCell;

use levenberg_marquardt::LeastSquaresProblem;
use magbench_env::{MAX_AGENTS, Vec2};
use nalgebra034::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;

use super::controls::Layout;
use crate::motion::propagate_valid;
use crate::{Plan, Problem};

/// The weights of the residual rows.
#[derive(Debug, Clone, Copy)]
pub struct Weights {
    /// Weight of a horizon held at full gradient, in squared goal tolerances.
    pub effort: f64,
    /// Distance (BL) from a bound of the proximity range or from a wall at which the validity
    /// rows start.
    pub margin: f64,
    /// The penalty parameter μ of the validity rows.
    pub mu: f64,
}

/// One window: where it starts and the positions it aims at.
#[derive(Debug, Clone, Copy)]
pub struct Window<'a> {
    /// The agents at the window's start.
    pub start: &'a [Vec2],
    /// The agents' target positions at its end.
    pub target: &'a [Vec2],
}

/// A checked replay of a decision vector: the plan of its valid segments and whether every
/// segment was valid.
pub struct Replay {
    /// The plan up to the first invalid segment.
    pub plan: Plan,
    /// Whether every segment was valid.
    pub complete: bool,
}

/// Rows of one segment: two effort rows, one per pair, one per agent.
fn segment_rows(n: usize) -> usize {
    2 + n * (n - 1) / 2 + n
}

/// Rows of the whole problem.
pub fn rows(layout: &Layout) -> usize {
    2 * layout.agents + layout.segments * segment_rows(layout.agents)
}

/// Rolls `z` out from segment `from`, whose start is `start`, writing the rows of segments
/// `from..` and the target rows of `win` into `r`; with `states`, each segment's start (and the end) from
/// `from` on is stored there (`n` positions each).
#[allow(clippy::too_many_arguments)]
fn rollout(
    problem: &Problem,
    layout: &Layout,
    w: &Weights,
    win: &Window,
    z: &[f64],
    from: usize,
    start: &[Vec2],
    r: &mut [f64],
    mut states: Option<&mut [Vec2]>,
) {
    let n = layout.agents;
    let (r_min, r_max) = (problem.checker.r_min, problem.checker.r_max);
    let world = &problem.checker.collision;
    let d = problem.periods(layout.periods);
    let effort_w = (w.effort / layout.segments as f64).sqrt();
    let violation_w = w.mu.sqrt() / w.margin;
    let per = segment_rows(n);
    let mut at = [Vec2::zeros(); MAX_AGENTS];
    at[..n].copy_from_slice(start);
    let mut next = at;
    // the last sample with finite positions: a motion that collapses a pair (the dipole force
    // grows as 1/r⁴) stops there, and the segments after it hold it, so the rows stay finite
    // and a solver's step into a collapse is simply a worse step
    let mut last = at;
    let mut alive = true;
    if let Some(s) = states.as_deref_mut() {
        s[from * n..(from + 1) * n].copy_from_slice(start);
    }
    for k in from..layout.segments {
        let u = layout.control(z, k);
        let row = &mut r[2 * n + k * per..2 * n + (k + 1) * per];
        let [ex, ey] = layout.effort(z, k);
        row[0] = effort_w * ex;
        row[1] = effort_w * ey;
        let (pairs, walls) = row[2..].split_at_mut(n * (n - 1) / 2);
        pairs.fill(0.0);
        walls.fill(0.0);
        let mut visit = |s: &[Vec2]| {
            if !s.iter().all(|p| p.x.is_finite() && p.y.is_finite()) {
                return false;
            }
            let mut p = 0;
            for i in 0..n {
                for j in (i + 1)..n {
                    let sep = (s[j] - s[i]).norm();
                    let v = (r_min + w.margin - sep).max(sep - (r_max - w.margin));
                    pairs[p] = pairs[p].max(v.max(0.0) * violation_w);
                    p += 1;
                }
                let v = w.margin - world.clearance_bound(s[i]);
                walls[i] = walls[i].max(v.max(0.0) * violation_w);
            }
            last[..n].copy_from_slice(s);
            true
        };
        if alive {
            alive = problem
                .model
                .propagate_with(&at[..n], &u, d, &mut next[..n], &mut visit);
            at = if alive { next } else { last };
        } else {
            visit(&at[..n]);
        }
        if let Some(s) = states.as_deref_mut() {
            s[(k + 1) * n..(k + 2) * n].copy_from_slice(&at[..n]);
        }
    }
    let tol = problem.goal.tolerance;
    for (i, g) in win.target.iter().enumerate() {
        r[2 * i] = (at[i].x - g.x) / tol;
        r[2 * i + 1] = (at[i].y - g.y) / tol;
    }
}

/// The residuals of `z` in window `win` (every row) and, with `states`, every segment's start
/// and the end.
pub fn residuals(
    problem: &Problem,
    layout: &Layout,
    w: &Weights,
    win: &Window,
    z: &[f64],
    states: Option<&mut [Vec2]>,
) -> Vec<f64> {
    let mut r = vec![0.0; rows(layout)];
    rollout(problem, layout, w, win, z, 0, win.start, &mut r, states);
    r
}

/// `z` replayed from `start` segment by segment with the validity check every other planner's edges pass
/// (crate::motion::propagate_valid): each segment one edge of `layout.periods` periods.
pub fn replay(problem: &Problem, layout: &Layout, start: &[Vec2], z: &[f64]) -> Replay {
    let n = layout.agents;
    let d = problem.periods(layout.periods);
    let mut plan = Plan::at(start);
    plan.flow = problem.model.flow;
    let mut next = [Vec2::zeros(); MAX_AGENTS];
    for k in 0..layout.segments {
        let u = layout.control(z, k);
        if !propagate_valid(problem, plan.end(), &u, d, &mut next[..n]) {
            return Replay {
                plan,
                complete: false,
            };
        }
        plan.push(u, d, next[..n].to_vec());
    }
    Replay {
        plan,
        complete: true,
    }
}

/// Forward-difference step for variable value `x`: √ε · max(1, |x|), the step that balances
/// truncation and rounding error of a forward difference (Nocedal & Wright, eq. 8.6).
fn step(x: f64) -> f64 {
    f64::EPSILON.sqrt() * x.abs().max(1.0)
}

/// The Jacobian of the residuals at `z` in window `win` by forward differences, one column per
/// variable, the columns computed in parallel.
pub fn jacobian(
    problem: &Problem,
    layout: &Layout,
    w: &Weights,
    win: &Window,
    z: &[f64],
) -> DMatrix<f64> {
    let n = layout.agents;
    let mut states = vec![Vec2::zeros(); (layout.segments + 1) * n];
    let base = residuals(problem, layout, w, win, z, Some(&mut states));
    let per = layout.per_segment();
    let columns: Vec<Vec<f64>> = (0..layout.len())
        .into_par_iter()
        .map(|j| {
            let k = j / per;
            let h = step(z[j]);
            let mut zj = z.to_vec();
            zj[j] += h;
            let h = zj[j] - z[j];
            let mut r = base.clone();
            rollout(
                problem,
                layout,
                w,
                win,
                &zj,
                k,
                &states[k * n..(k + 1) * n],
                &mut r,
                None,
            );
            r.iter().zip(&base).map(|(a, b)| (a - b) / h).collect()
        })
        .collect();
    DMatrix::from_fn(base.len(), columns.len(), |i, j| columns[j][i])
}

/// What the solver sees: the decision vector, the weights, and the rule that ends a solve,
/// asked at each accepted iterate (before its Jacobian) with the iterate's checked replay.
pub struct Shooting<'a> {
    /// The problem.
    pub problem: &'a Problem,
    /// The decision vector's shape.
    pub layout: Layout,
    /// The rows' weights.
    pub weights: Weights,
    /// The window.
    pub window: Window<'a>,
    /// The decision vector.
    pub z: Vec<f64>,
    /// Told each accepted iterate's checked replay; true ends the solve before its Jacobian.
    pub stop: RefCell<&'a mut dyn FnMut(Replay) -> bool>,
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Shooting<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, p: &DVector<f64>) {
        self.z.copy_from_slice(p.as_slice());
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.z)
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = residuals(
            self.problem,
            &self.layout,
            &self.weights,
            &self.window,
            &self.z,
            None,
        );
        r.iter()
            .all(|v| v.is_finite())
            .then(|| DVector::from_vec(r))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let replayed = replay(self.problem, &self.layout, self.window.start, &self.z);
        if (self.stop.borrow_mut())(replayed) {
            return None;
        }
        let j = jacobian(
            self.problem,
            &self.layout,
            &self.weights,
            &self.window,
            &self.z,
        );
        j.iter().all(|v| v.is_finite()).then_some(j)
    }
}

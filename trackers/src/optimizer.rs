//! The OBC's one-tick optimizer: the coil command whose predicted outcome is closest to a
//! target state.
//!
//! For a candidate field angle θ the planning model predicts the team one horizon ahead with no
//! gradient. Identical agents receive the same pull, and the pair forces do not depend on where
//! the centre of mass is, so a gradient only adds the same displacement `H·v_pull(θ, G)` to
//! every agent — exactly, also through RK4. The best gradient for that θ is therefore found in
//! closed form: the displacement that best closes the centre-of-mass error, solved per axis and
//! clamped to the coil's bounds (the tri-axial coil's pull is `(G_x cos θ, G_y sin θ)`).
//!
//! The score of a command is
//!
//! ```text
//! J = w_com |c_pred − c_target|² + w_rel Σ_i |(p_i − c)_pred − (p_i − c)_target|²
//!   + w_smooth Δθ² + w_prox Σ_pairs (band violation of r_pred)²
//! ```
//!
//! with `c` the centre of mass, `Δθ` the change of the field angle from the last command (mod
//! π: both polarities give the same pair force, so the polarity nearer the last command is
//! sent, with the gradient signs that go with it), and the band `(r_min + margin, r_max −
//! margin)` of the proximity range. θ is searched by brute force on a fine grid over [0, π),
//! then refined by golden-section search around the best grid angle. A candidate whose
//! predicted agents come closer than `wall_margin` to a wall (and closer than they are now) is
//! rejected; the next best is taken.

use magbench_env::{Control, MAX_AGENTS, PlanningModel, ValidityChecker, Vec2};

/// Weights and search settings of the optimizer.
#[derive(Debug, Clone, PartialEq)]
pub struct ObcWeights {
    /// Weight of the centre-of-mass error.
    pub w_com: f64,
    /// Weight of the formation (relative position) error.
    pub w_rel: f64,
    /// Weight of the field-angle change (per rad²).
    pub w_smooth: f64,
    /// Weight of a predicted separation outside the safe band (per BL²).
    pub w_prox: f64,
    /// Safety margin inside the proximity range (BL).
    pub prox_margin: f64,
    /// Clearance a predicted agent keeps from walls and obstacles (BL).
    pub wall_margin: f64,
    /// Grid points over [0, π).
    pub grid: usize,
    /// Golden-section iterations of the local refinement.
    pub refine: usize,
    /// Prediction horizon in control ticks.
    pub horizon: usize,
}

impl Default for ObcWeights {
    fn default() -> Self {
        ObcWeights {
            w_com: 1.0,
            w_rel: 1.0,
            w_smooth: 1e-5,
            w_prox: 1e3,
            prox_margin: 0.15,
            wall_margin: 0.05,
            grid: 72,
            refine: 12,
            horizon: 1,
        }
    }
}

/// The optimizer's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// The command to send.
    pub control: Control,
    /// Its score.
    pub cost: f64,
    /// The predicted team one horizon ahead under it.
    pub predicted: Vec<Vec2>,
    /// False when no candidate kept clear of the walls (the least bad one is returned).
    pub clear: bool,
}

/// One evaluated candidate.
#[derive(Clone, Copy)]
struct Candidate {
    theta: f64,
    cost: f64,
    grad: [f64; 2],
    pred: [Vec2; MAX_AGENTS],
}

/// The brute-force field-angle optimizer of the OBC.
#[derive(Debug, Clone)]
pub struct ObcOptimizer {
    model: PlanningModel,
    checker: ValidityChecker,
    weights: ObcWeights,
    horizon_s: f64,
    pull_coeff: f64,
    g_max: f64,
}

impl ObcOptimizer {
    /// An optimizer predicting with `model` one `period` (control tick) × `weights.horizon`
    /// ahead, checking predictions with `checker`.
    pub fn new(
        model: PlanningModel,
        checker: ValidityChecker,
        period: f64,
        weights: ObcWeights,
    ) -> Self {
        let pull_coeff = model.kinematics.pull_coeff;
        let g_max = model.coil.gradient_limit();
        let horizon_s = period * weights.horizon.max(1) as f64;
        ObcOptimizer {
            model,
            checker,
            weights,
            horizon_s,
            pull_coeff,
            g_max,
        }
    }

    /// The weights.
    pub fn weights(&self) -> &ObcWeights {
        &self.weights
    }

    /// The prediction horizon (s).
    pub fn horizon(&self) -> f64 {
        self.horizon_s
    }

    /// The command that best brings the team from `x` to `target` one horizon ahead.
    /// `last` is the last command sent (for the smoothness term and the polarity), `hint` an
    /// extra candidate evaluated exactly as given (the plan's own control, say).
    pub fn solve(
        &self,
        x: &[Vec2],
        target: &[Vec2],
        last: Option<&Control>,
        hint: Option<&Control>,
    ) -> Solution {
        let n = x.len();
        assert!(n <= MAX_AGENTS && target.len() == n && n > 0);
        let prev = last.map(|u| u.theta);
        let w = &self.weights;
        let grid = w.grid.max(4);
        let step = std::f64::consts::PI / grid as f64;
        let mut cands: Vec<Candidate> = (0..grid)
            .map(|k| self.evaluate(x, target, k as f64 * step, prev))
            .collect();
        if let Some(h) = hint {
            if h.is_finite() {
                cands.push(self.evaluate_exact(x, target, h, prev));
            }
        }
        let mut best = cands
            .iter()
            .copied()
            .min_by(|a, b| a.cost.total_cmp(&b.cost))
            .expect("a grid");
        // refine the winner by golden-section search over [θ − step, θ + step]
        if w.refine > 0 {
            let r = self.refine(x, target, best.theta, step, prev);
            if r.cost < best.cost {
                best = r;
            }
        }
        let now_clear: Vec<f64> = x
            .iter()
            .map(|p| self.checker.collision.clearance(*p))
            .collect();
        if self.clear_of_walls(&best, n, &now_clear) {
            return self.finish(best, n, prev, true);
        }
        cands.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        for c in &cands {
            if self.clear_of_walls(c, n, &now_clear) {
                return self.finish(*c, n, prev, true);
            }
            let mut z = *c;
            self.zero_pull(x, target, &mut z, prev);
            if self.clear_of_walls(&z, n, &now_clear) {
                return self.finish(z, n, prev, true);
            }
        }
        self.finish(best, n, prev, false)
    }

    fn finish(&self, c: Candidate, n: usize, prev: Option<f64>, clear: bool) -> Solution {
        // send the polarity nearer the last command; flipping θ by π flips the pull
        let mut theta = c.theta;
        let mut grad = c.grad;
        if let Some(p) = prev {
            let d = wrap_half(theta - p);
            let t2 = magbench_env::math::wrap_angle(p + d);
            if (magbench_env::math::wrap_angle(t2 - theta)).abs() > 1.0 {
                grad = [-grad[0], -grad[1]];
            }
            theta = t2;
        }
        Solution {
            control: Control::planar(magbench_env::math::wrap_angle(theta), grad[0], grad[1]),
            cost: c.cost,
            predicted: c.pred[..n].to_vec(),
            clear,
        }
    }

    fn clear_of_walls(&self, c: &Candidate, n: usize, now_clear: &[f64]) -> bool {
        let m = self.weights.wall_margin;
        (0..n).all(|i| {
            let cl = self.checker.collision.clearance(c.pred[i]);
            cl >= m || cl >= now_clear[i] - 1e-9
        })
    }

    fn zero_pull(&self, x: &[Vec2], target: &[Vec2], c: &mut Candidate, prev: Option<f64>) {
        *c = self.evaluate_exact(x, target, &Control::planar(c.theta, 0.0, 0.0), prev);
    }

    fn refine(
        &self,
        x: &[Vec2],
        target: &[Vec2],
        theta: f64,
        step: f64,
        prev: Option<f64>,
    ) -> Candidate {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut a, mut b) = (theta - step, theta + step);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let mut fc = self.evaluate(x, target, c, prev);
        let mut fd = self.evaluate(x, target, d, prev);
        for _ in 0..self.weights.refine {
            if fc.cost < fd.cost {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = self.evaluate(x, target, c, prev);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = self.evaluate(x, target, d, prev);
            }
        }
        if fc.cost < fd.cost { fc } else { fd }
    }

    /// Scores field angle `theta` with its best gradient.
    fn evaluate(&self, x: &[Vec2], target: &[Vec2], theta: f64, prev: Option<f64>) -> Candidate {
        let n = x.len();
        let mut pred = [Vec2::zeros(); MAX_AGENTS];
        self.model.propagate_with(
            x,
            &Control::planar(theta, 0.0, 0.0),
            self.horizon_s,
            &mut pred[..n],
            |_| true,
        );
        let inv_n = 1.0 / n as f64;
        let c0 = pred[..n].iter().sum::<Vec2>() * inv_n;
        let ct = target.iter().sum::<Vec2>() * inv_n;
        let (ax, ay) = self.pull_axes(theta);
        let grad = self.best_gradient(ax, ay, ct - c0);
        let shift = ax * grad[0] + ay * grad[1];
        for p in &mut pred[..n] {
            *p += shift;
        }
        let cost = self.score(&pred[..n], target, c0 + shift, ct, theta, prev);
        Candidate {
            theta,
            cost,
            grad,
            pred,
        }
    }

    /// Scores a command exactly as given (its own gradient).
    fn evaluate_exact(
        &self,
        x: &[Vec2],
        target: &[Vec2],
        u: &Control,
        prev: Option<f64>,
    ) -> Candidate {
        let n = x.len();
        let (u, _) = self.model.coil.clamp(u);
        let u = Control { alpha: 0.0, ..u };
        let mut pred = [Vec2::zeros(); MAX_AGENTS];
        self.model
            .propagate_with(x, &u, self.horizon_s, &mut pred[..n], |_| true);
        let inv_n = 1.0 / n as f64;
        let c = pred[..n].iter().sum::<Vec2>() * inv_n;
        let ct = target.iter().sum::<Vec2>() * inv_n;
        let cost = self.score(&pred[..n], target, c, ct, u.theta, prev);
        Candidate {
            theta: u.theta,
            cost,
            grad: u.grad,
            pred,
        }
    }

    fn score(
        &self,
        pred: &[Vec2],
        target: &[Vec2],
        c: Vec2,
        ct: Vec2,
        theta: f64,
        prev: Option<f64>,
    ) -> f64 {
        let w = &self.weights;
        let mut rel = 0.0;
        for (p, t) in pred.iter().zip(target) {
            rel += ((p - c) - (t - ct)).norm_squared();
        }
        let mut cost = w.w_com * (c - ct).norm_squared() + w.w_rel * rel;
        if let Some(p) = prev {
            let d = wrap_half(theta - p);
            cost += w.w_smooth * d * d;
        }
        let (lo, hi) = (
            self.checker.r_min + w.prox_margin,
            self.checker.r_max - w.prox_margin,
        );
        for i in 0..pred.len() {
            for j in (i + 1)..pred.len() {
                let r = (pred[j] - pred[i]).norm();
                let v = (lo - r).max(0.0) + (r - hi).max(0.0);
                cost += w.w_prox * v * v;
                if r <= self.checker.r_min || r >= self.checker.r_max {
                    cost += w.w_prox;
                }
            }
        }
        cost
    }

    /// The per-axis pull displacement over the horizon per unit gradient at `theta`.
    fn pull_axes(&self, theta: f64) -> (Vec2, Vec2) {
        let k = self.pull_coeff * self.horizon_s;
        let ax = self
            .model
            .coil
            .actuation(&Control::planar(theta, 1.0, 0.0))
            .pull;
        let ay = self
            .model
            .coil
            .actuation(&Control::planar(theta, 0.0, 1.0))
            .pull;
        (Vec2::new(ax.x, ax.y) * k, Vec2::new(ay.x, ay.y) * k)
    }

    /// The gradient (within bounds) whose displacement (`ax` per unit G_x, `ay` per unit G_y)
    /// best matches `want`.
    fn best_gradient(&self, ax: Vec2, ay: Vec2, want: Vec2) -> [f64; 2] {
        let g = self.g_max;
        let scale = ax.norm().max(ay.norm()).max(1e-300);
        if ax.y.abs() <= 1e-12 * scale && ay.x.abs() <= 1e-12 * scale {
            // diagonal (the tri-axial coil): independent per-axis clamps are exact
            let per = |w: f64, a: f64| {
                if a.abs() > 1e-9 * scale {
                    (w / a).clamp(-g, g)
                } else {
                    0.0
                }
            };
            return [per(want.x, ax.x), per(want.y, ay.y)];
        }
        // another coil: least squares, then shrunk into the box along its own direction
        let det = ax.x * ay.y - ay.x * ax.y;
        if det.abs() < 1e-12 * scale * scale {
            return [0.0, 0.0];
        }
        let gx = (want.x * ay.y - ay.x * want.y) / det;
        let gy = (ax.x * want.y - want.x * ax.y) / det;
        let m = gx.abs().max(gy.abs());
        if m > g {
            [gx * g / m, gy * g / m]
        } else {
            [gx, gy]
        }
    }
}

/// Wraps an angle to (−π/2, π/2]: field angles that differ by π give the same pair force.
pub fn wrap_half(a: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let mut w = a.rem_euclid(pi);
    if w > 0.5 * pi {
        w -= pi;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench_env::physics::LocalView;
    use magbench_env::{PhysicalParams, Scenario};
    use std::sync::Arc;

    fn setup() -> (PlanningModel, ValidityChecker) {
        let p = PhysicalParams::default();
        let w = magbench_env::World {
            width: 40.0,
            height: 30.0,
            obstacles: vec![],
        };
        let cw = Arc::new(magbench_env::CollisionWorld::new(&w, 0.5));
        (
            PlanningModel::new(&p),
            ValidityChecker::new(cw, p.r_min, p.r_max),
        )
    }

    #[test]
    fn recovers_a_known_command() {
        let (model, checker) = setup();
        let opt = ObcOptimizer::new(
            model.clone(),
            checker,
            1.0 / 60.0,
            ObcWeights {
                w_smooth: 0.0,
                ..Default::default()
            },
        );
        let x = LocalView {
            xc: 20.0,
            yc: 15.0,
            r: 2.2,
            phi: 0.4,
        }
        .to_pair();
        for u in [
            Control::planar(1.0, 0.03, -0.05),
            Control::planar(-2.0, 0.06, 0.01),
        ] {
            let mut target = [Vec2::zeros(); 2];
            model.propagate_with(&x, &u, 1.0 / 60.0, &mut target, |_| true);
            let s = opt.solve(&x, &target, None, None);
            let err: f64 = s
                .predicted
                .iter()
                .zip(&target)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max);
            assert!(
                err < 1e-6,
                "prediction error {err:e} for {u:?} → {:?}",
                s.control
            );
            assert!(s.clear);
            // the same pair force: θ equal mod π
            assert!(wrap_half(s.control.theta - u.theta).abs() < 1e-3);
        }
    }

    #[test]
    fn polarity_follows_the_last_command_and_flips_the_pull() {
        let (model, checker) = setup();
        let opt = ObcOptimizer::new(model.clone(), checker, 1.0 / 60.0, ObcWeights::default());
        let x = LocalView {
            xc: 20.0,
            yc: 15.0,
            r: 2.2,
            phi: 0.4,
        }
        .to_pair();
        let target = [x[0] + Vec2::new(0.005, 0.0), x[1] + Vec2::new(0.005, 0.0)];
        let a = opt.solve(&x, &target, Some(&Control::planar(0.5, 0.0, 0.0)), None);
        let b = opt.solve(
            &x,
            &target,
            Some(&Control::planar(0.5 + std::f64::consts::PI, 0.0, 0.0)),
            None,
        );
        assert!(
            (magbench_env::math::wrap_angle(a.control.theta - b.control.theta).abs()
                - std::f64::consts::PI)
                .abs()
                < 1e-9
        );
        for (p, q) in a.predicted.iter().zip(&b.predicted) {
            assert!((p - q).norm() < 1e-9, "same outcome for both polarities");
        }
    }

    #[test]
    fn keeps_the_pair_apart_when_the_target_is_too_close() {
        let (model, checker) = setup();
        let opt = ObcOptimizer::new(model, checker.clone(), 1.0 / 60.0, ObcWeights::default());
        let x = LocalView {
            xc: 20.0,
            yc: 15.0,
            r: 1.5,
            phi: 0.0,
        }
        .to_pair();
        let target = LocalView {
            xc: 20.0,
            yc: 15.0,
            r: 1.0,
            phi: 0.0,
        }
        .to_pair();
        let s = opt.solve(&x, &target, None, None);
        let r = (s.predicted[1] - s.predicted[0]).norm();
        assert!(r > checker.r_min + 0.1, "predicted r = {r}");
    }

    #[test]
    fn does_not_push_into_a_wall() {
        let s = Scenario::load("open-field").unwrap();
        let model = PlanningModel::new(&s.physics);
        let checker = s.checker_for_leg(0);
        let opt = ObcOptimizer::new(model, checker.clone(), 1.0 / 60.0, ObcWeights::default());
        // the pair sits just clear of the bottom wall; the target is beyond it
        let x = LocalView {
            xc: 10.0,
            yc: 0.53,
            r: 2.0,
            phi: 0.0,
        }
        .to_pair();
        let target = [x[0] - Vec2::new(0.0, 1.0), x[1] - Vec2::new(0.0, 1.0)];
        let sol = opt.solve(&x, &target, None, None);
        for p in &sol.predicted {
            assert!(checker.collision.clearance(*p) >= 0.0, "{p:?}");
        }
    }
}

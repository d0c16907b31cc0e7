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
//!   + w_smooth Δθ² + w_prox Σ_pairs (band violation of r)² + w_wall Σ_i (wall_margin − cl_i)₊²
//! ```
//!
//! - `c` is the centre of mass;
//! - `Δθ` is the change of the field angle from the last command, mod π: both polarities give
//!   the same pair force, so the polarity nearer the last command is sent, with the gradient
//!   signs that go with it;
//! - the band is `(r_min + prox_margin, r_max − prox_margin)` of the proximity range, checked at
//!   the predicted separation and where it would be if its predicted rate of change lasted
//!   `safety` more ticks — a fast approach is refused while there is still time to stop it (the
//!   camera is a frame late and the true forces differ from the model's);
//! - `cl_i` is agent `i`'s predicted clearance from walls and obstacles, linearised about its
//!   position (only agents near a wall are scored); where the planned path itself is closer to a
//!   wall than `wall_margin` (a plan may hug one), the path's clearance replaces the margin.
//!
//! The closed-form gradient also lets an agent near a wall slide along it: the part of the shift
//! that would take the agent's linearised clearance below half its margin is removed.
//! θ is searched by brute force on a grid over [0, π), then refined by golden-section search
//! around the best grid angle. The winner is checked exactly against the walls: if a predicted
//! agent would touch one, the next best candidate (or its zero-gradient variant) is taken.
//!
//! When the field may leave the plane (`planar`: `auto` does so for three or more agents), the
//! elevation α is searched too, without a quadratic grid: the θ grid is repeated at
//! `alpha_levels` elevations evenly spread over [0, α_max] (one point at α = 90°, where θ does
//! not matter), and the winner is refined by alternating golden-section searches, one in θ and
//! one in α, [`ELEVATED_ROUNDS`] times. The in-plane pull scales with cos α, so the closed-form
//! gradient takes α's pull axes; the smoothness term adds the change of α. Planar solves (α = 0)
//! are the planar arithmetic, bit for bit.

use magbench_env::coil::{DEFAULT_ALPHA_MAX_DEG, Planar};
use magbench_env::input::Rejection;
use magbench_env::math::centroid;
use magbench_env::model::pair_flow::PairStart;
use magbench_env::params::Reals;
use magbench_env::{
    Actuation, Control, MAX_AGENTS, PlanningModel, ValidityChecker, Vec2, declare_params,
};

declare_params! {
    /// Weights and search settings of the optimizer (parameters of `obc` and `lookahead`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct ObcWeights {
        /// Weight of the centre-of-mass error.
        #[param("w_com", Reals::closed(0.0, 1e9))]
        pub w_com: f64 = 1.0,
        /// Weight of the formation (relative position) error.
        #[param("w_rel", Reals::closed(0.0, 1e9))]
        pub w_rel: f64 = 1.0,
        /// Weight of the field-angle change (per rad²).
        #[param("w_smooth", Reals::closed(0.0, 1e9))]
        pub w_smooth: f64 = 1e-5,
        /// Weight of a predicted separation outside the safe band (per BL²).
        #[param("w_prox", Reals::closed(0.0, 1e12))]
        pub w_prox: f64 = 1e3,
        /// Safety margin inside the proximity range (BL).
        #[param("prox_margin", Reals::closed(0.0, 2.0))]
        pub prox_margin: f64 = 0.15,
        /// Extra ticks over which the predicted change of separation is extrapolated for the
        /// proximity check (0 = the prediction only).
        #[param("safety", Reals::closed(0.0, 100.0))]
        pub safety: f64 = 2.0,
        /// Clearance (BL) below which a predicted agent is penalised by `w_wall`; a predicted
        /// contact is never chosen if anything else is possible.
        #[param("wall_margin", Reals::closed(0.0, 2.0))]
        pub wall_margin: f64 = 0.05,
        /// Weight of a predicted clearance below `wall_margin` (per BL²).
        #[param("w_wall", Reals::closed(0.0, 1e9))]
        pub w_wall: f64 = 1.0,
        /// Field angles on the brute-force grid over [0, π).
        #[param("grid", 4..=100_000)]
        pub grid: usize = 24,
        /// Golden-section iterations of the local refinement.
        #[param("refine", 0..=100)]
        pub refine: usize = 10,
        /// Prediction horizon (control ticks).
        #[param("horizon", 1..=120)]
        pub horizon: usize = 1,
        /// Whether the field stays in the plane: `auto` (two agents yes; three or more no where
        /// the medium carries the out-of-plane force, yes in bulk), `true` or `false`.
        #[param("planar")]
        pub planar: Planar = Planar::Auto,
        /// The largest elevation searched (degrees) when the field may leave the plane.
        #[param("alpha_max", Reals::closed(0.0, 90.0))]
        pub alpha_max: f64 = DEFAULT_ALPHA_MAX_DEG,
        /// Elevations on the brute-force grid, evenly from 0 to `alpha_max`, when the field may
        /// leave the plane.
        #[param("alpha_levels", 2..=64)]
        pub alpha_levels: usize = 4,
    }
    check(check_work);
}

/// Most predicted control ticks in one solve (grid points and refinements, times the
/// horizon): a bound chosen so that one control tick is computed in well under a second.
pub const MAX_PREDICTIONS: usize = 200_000;

/// Refuses settings whose one solve predicts more than [`MAX_PREDICTIONS`] ticks.
fn check_work(w: &ObcWeights) -> Result<(), Rejection> {
    let grid = w.grid.saturating_mul(w.alpha_levels);
    let refine = w.refine.saturating_mul(1 + 2 * ELEVATED_ROUNDS);
    let work = grid.saturating_add(refine).saturating_mul(w.horizon);
    if work > MAX_PREDICTIONS {
        return Err(Rejection::new(
            "",
            format!(
                "grid × alpha_levels + refine × {} = {} candidates, each predicted over horizon = {} ticks, is {work} predictions per control tick; at most {MAX_PREDICTIONS} (so that one tick is computed in well under a second): lower grid, refine or horizon",
                1 + 2 * ELEVATED_ROUNDS,
                grid.saturating_add(refine),
                w.horizon
            ),
        ));
    }
    Ok(())
}

/// Alternating θ and α refinements of an elevated solve.
pub const ELEVATED_ROUNDS: usize = 2;

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
    alpha: f64,
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
    /// The grid angles in the plane, their pull axes and their gradient-free actuation (they do
    /// not change from tick to tick).
    grid: Vec<GridPoint>,
    /// The same for elevated solves: the angles at every elevation level.
    elevated: Vec<GridPoint>,
    /// The largest elevation (rad).
    alpha_max: f64,
}

/// One grid command: θ, α, the pull axes and the gradient-free actuation.
type GridPoint = (f64, f64, Vec2, Vec2, Actuation);

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
        let mut opt = ObcOptimizer {
            model,
            checker,
            weights,
            horizon_s,
            pull_coeff,
            g_max,
            grid: vec![],
            elevated: vec![],
            alpha_max: 0.0,
        };
        opt.alpha_max = opt.weights.alpha_max.to_radians();
        let n = opt.weights.grid.max(4);
        opt.grid = (0..n).map(|k| opt.grid_point(k, n, 0.0)).collect();
        let levels = opt.weights.alpha_levels.max(2);
        for l in 0..levels {
            let alpha = opt.alpha_max * l as f64 / (levels - 1) as f64;
            // straight up, θ does not matter: one point
            let angles = if alpha >= std::f64::consts::FRAC_PI_2 - 1e-12 {
                1
            } else {
                n
            };
            for k in 0..angles {
                let p = opt.grid_point(k, n, alpha);
                opt.elevated.push(p);
            }
        }
        opt
    }

    /// Grid angle `k` of `n` over [0, π) at elevation `alpha`.
    fn grid_point(&self, k: usize, n: usize, alpha: f64) -> GridPoint {
        let theta = k as f64 * std::f64::consts::PI / n as f64;
        let (ax, ay) = self.pull_axes(theta, alpha);
        let act = self.model.coil.actuation(&Control {
            theta,
            alpha,
            grad: [0.0, 0.0],
        });
        (theta, alpha, ax, ay, act)
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
        self.solve_along(x, target, target, last, hint)
    }

    /// [`ObcOptimizer::solve`] where the wall margin of agent `i` is at most the clearance of
    /// `path[i]`, the point of its planned path it is meant to be near (the target itself for
    /// the OBC, the projection on the path for the lookahead tracker): a plan that hugs a wall
    /// is followed without penalty, a deviation towards the wall is not.
    pub fn solve_along(
        &self,
        x: &[Vec2],
        target: &[Vec2],
        path: &[Vec2],
        last: Option<&Control>,
        hint: Option<&Control>,
    ) -> Solution {
        let n = x.len();
        assert!(n <= MAX_AGENTS && target.len() == n && path.len() == n && n > 0);
        let w = &self.weights;
        let elevated = !w.planar.is_planar(n, self.model.carries_fz);
        let setup = self.setup(x, target, path, last, elevated);
        let step = std::f64::consts::PI / self.grid.len() as f64;
        let grid = if elevated { &self.elevated } else { &self.grid };
        let mut cands: Vec<Candidate> = grid
            .iter()
            .map(|(theta, alpha, ax, ay, act)| {
                self.evaluate_with(&setup, *theta, *alpha, *ax, *ay, act)
            })
            .collect();
        if let Some(h) = hint.filter(|h| h.is_finite()) {
            cands.push(self.evaluate_exact(&setup, h));
        }
        let mut best = *cands
            .iter()
            .min_by(|a, b| a.cost.total_cmp(&b.cost))
            .expect("a grid");
        // refine the winner by golden-section search over [θ − step, θ + step] (and, elevated,
        // alternately over [α − level step, α + level step])
        if w.refine > 0 {
            let rounds = if elevated { ELEVATED_ROUNDS } else { 1 };
            let a_step = self.alpha_max / (w.alpha_levels.max(2) - 1) as f64;
            for _ in 0..rounds {
                let r = self.refine(&setup, best.theta, best.alpha, step);
                if r.cost < best.cost {
                    best = r;
                }
                if elevated {
                    let r = self.refine_alpha(&setup, best.theta, best.alpha, a_step);
                    if r.cost < best.cost {
                        best = r;
                    }
                }
            }
        }
        if self.clear_of_walls(&setup, &best) {
            return self.finish(best, &setup, true);
        }
        cands.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        for c in &cands {
            if self.clear_of_walls(&setup, c) {
                return self.finish(*c, &setup, true);
            }
            let z = self.evaluate_exact(
                &setup,
                &Control {
                    theta: c.theta,
                    alpha: c.alpha,
                    grad: [0.0, 0.0],
                },
            );
            if self.clear_of_walls(&setup, &z) {
                return self.finish(z, &setup, true);
            }
        }
        self.finish(best, &setup, false)
    }

    /// What every candidate of one solve shares: the state, the target, the last angle and,
    /// for each agent near a wall, its clearance and the clearance gradient (a unit normal,
    /// by central differences), so candidates get a linearised clearance without a query.
    fn setup<'a>(
        &self,
        x: &'a [Vec2],
        target: &'a [Vec2],
        path: &[Vec2],
        last: Option<&Control>,
        elevated: bool,
    ) -> Setup<'a> {
        let n = x.len();
        let inv_n = 1.0 / n as f64;
        let reach = self.weights.wall_margin + WALL_REACH * self.weights.horizon.max(1) as f64;
        let mut near = [None; MAX_AGENTS];
        let col = &self.checker.collision;
        for (i, p) in x.iter().enumerate() {
            let c = col.clearance(*p);
            if c < reach {
                let h = 1e-4;
                let g = Vec2::new(
                    col.clearance(p + Vec2::new(h, 0.0)) - col.clearance(p - Vec2::new(h, 0.0)),
                    col.clearance(p + Vec2::new(0.0, h)) - col.clearance(p - Vec2::new(0.0, h)),
                );
                let normal = if g.norm() > 0.0 {
                    g / g.norm()
                } else {
                    Vec2::zeros()
                };
                // where the plan itself hugs a wall closer than the margin, the margin there is
                // the plan's own clearance: following the plan costs nothing
                let margin = self
                    .weights
                    .wall_margin
                    .min(col.clearance(path[i]).max(WALL_FLOOR));
                near[i] = Some(Near {
                    now: c,
                    normal,
                    margin,
                });
            }
        }
        let mut separations = [0.0; MAX_PAIRS];
        let mut k = 0;
        for i in 0..n {
            for j in (i + 1)..n {
                separations[k] = (x[j] - x[i]).norm();
                k += 1;
            }
        }
        Setup {
            x,
            pair: self.model.pair_start(x),
            separations,
            target,
            ct: target.iter().sum::<Vec2>() * inv_n,
            prev: last.map(|u| u.theta),
            prev_alpha: last.map_or(0.0, |u| u.alpha),
            elevated,
            near,
        }
    }

    fn finish(&self, c: Candidate, s: &Setup, clear: bool) -> Solution {
        // send the polarity nearer the last command; flipping θ by π flips the pull
        let mut theta = c.theta;
        let mut grad = c.grad;
        if let Some(p) = s.prev {
            let d = wrap_half(theta - p);
            let t2 = magbench_env::math::wrap_angle(p + d);
            if (magbench_env::math::wrap_angle(t2 - theta)).abs() > 1.0 {
                grad = [-grad[0], -grad[1]];
            }
            theta = t2;
        }
        Solution {
            control: Control {
                theta: magbench_env::math::wrap_angle(theta),
                alpha: c.alpha,
                grad,
            },
            cost: c.cost,
            predicted: c.pred[..s.x.len()].to_vec(),
            clear,
        }
    }

    /// The exact check of a chosen candidate: no predicted agent touches a wall (one already in
    /// contact may not go deeper).
    fn clear_of_walls(&self, s: &Setup, c: &Candidate) -> bool {
        (0..s.x.len()).all(|i| match s.near[i] {
            None => true,
            Some(w) => {
                let cl = self.checker.collision.clearance(c.pred[i]);
                cl > 0.0 || cl >= w.now - 1e-12
            }
        })
    }

    /// Golden-section search of θ over [θ − step, θ + step] at elevation `alpha`.
    fn refine(&self, s: &Setup, theta: f64, alpha: f64, step: f64) -> Candidate {
        golden(theta - step, theta + step, self.weights.refine, |t| {
            self.evaluate(s, t, alpha)
        })
    }

    /// Golden-section search of α over [α − step, α + step] ∩ [0, α_max] at field angle `theta`.
    fn refine_alpha(&self, s: &Setup, theta: f64, alpha: f64, step: f64) -> Candidate {
        let (lo, hi) = ((alpha - step).max(0.0), (alpha + step).min(self.alpha_max));
        golden(lo, hi, self.weights.refine, |a| self.evaluate(s, theta, a))
    }

    /// Scores field angle `theta` at elevation `alpha` with its best gradient.
    fn evaluate(&self, s: &Setup, theta: f64, alpha: f64) -> Candidate {
        let (ax, ay) = self.pull_axes(theta, alpha);
        let act = self.model.coil.actuation(&Control {
            theta,
            alpha,
            grad: [0.0, 0.0],
        });
        self.evaluate_with(s, theta, alpha, ax, ay, &act)
    }

    /// [`Self::evaluate`] with the pull axes and the gradient-free actuation given.
    #[allow(clippy::too_many_arguments)]
    fn evaluate_with(
        &self,
        s: &Setup,
        theta: f64,
        alpha: f64,
        ax: Vec2,
        ay: Vec2,
        act: &Actuation,
    ) -> Candidate {
        let n = s.x.len();
        let mut pred = [Vec2::zeros(); MAX_AGENTS];
        self.model
            .propagate_from(s.x, s.pair.as_ref(), act, self.horizon_s, &mut pred[..n]);
        let c0 = centroid(&pred[..n]);
        let mut want = s.ct - c0;
        let mut grad = self.best_gradient(ax, ay, want);
        let mut shift = ax * grad[0] + ay * grad[1];
        // an agent near a wall slides along it: the shift loses the part that would bring the
        // agent's linearised clearance below WALL_KEEP (a few projections, then re-clamped)
        for _ in 0..3 {
            let mut moved = false;
            for (i, near) in s.near.iter().enumerate().take(n) {
                if let Some(w) = near {
                    let cl = w.now + w.normal.dot(&(pred[i] + shift - s.x[i]));
                    let keep = (0.5 * w.margin).max(WALL_KEEP);
                    if cl < keep {
                        want = shift + w.normal * (keep - cl);
                        moved = true;
                    }
                }
            }
            if !moved {
                break;
            }
            grad = self.best_gradient(ax, ay, want);
            shift = ax * grad[0] + ay * grad[1];
        }
        for p in &mut pred[..n] {
            *p += shift;
        }
        let cost = self.score(s, &pred[..n], c0 + shift, theta, alpha);
        Candidate {
            theta,
            alpha,
            cost,
            grad,
            pred,
        }
    }

    /// Scores a command exactly as given (its own gradient).
    fn evaluate_exact(&self, s: &Setup, u: &Control) -> Candidate {
        let n = s.x.len();
        let (u, _) = self.model.coil.clamp(u);
        let alpha = if s.elevated {
            u.alpha.clamp(-self.alpha_max, self.alpha_max)
        } else {
            0.0
        };
        let u = Control { alpha, ..u };
        let mut pred = [Vec2::zeros(); MAX_AGENTS];
        self.model
            .propagate(s.x, &u, self.horizon_s, &mut pred[..n]);
        let c = centroid(&pred[..n]);
        let cost = self.score(s, &pred[..n], c, u.theta, u.alpha);
        Candidate {
            theta: u.theta,
            alpha: u.alpha,
            cost,
            grad: u.grad,
            pred,
        }
    }

    fn score(&self, s: &Setup, pred: &[Vec2], c: Vec2, theta: f64, alpha: f64) -> f64 {
        let w = &self.weights;
        let mut rel = 0.0;
        for (p, t) in pred.iter().zip(s.target) {
            rel += ((p - c) - (t - s.ct)).norm_squared();
        }
        let mut cost = w.w_com * (c - s.ct).norm_squared() + w.w_rel * rel;
        if let Some(p) = s.prev {
            let d = wrap_half(theta - p);
            cost += w.w_smooth * d * d;
            if s.elevated {
                let e = alpha - s.prev_alpha;
                cost += w.w_smooth * e * e;
            }
        }
        let (lo, hi) = (
            self.checker.r_min + w.prox_margin,
            self.checker.r_max - w.prox_margin,
        );
        let x = s.x;
        let mut pair = 0;
        for i in 0..pred.len() {
            for j in (i + 1)..pred.len() {
                let r = (pred[j] - pred[i]).norm();
                // where the separation heads if the same rate lasted `safety` more ticks: a fast
                // approach is refused before it is too late to stop (latency, model mismatch)
                let r_ahead = r + (r - s.separations[pair]) * w.safety;
                pair += 1;
                let v = (lo - r.min(r_ahead)).max(0.0) + (r.max(r_ahead) - hi).max(0.0);
                cost += w.w_prox * v * v;
                if r <= self.checker.r_min || r >= self.checker.r_max {
                    cost += w.w_prox;
                }
            }
        }
        for (i, p) in pred.iter().enumerate() {
            if let Some(near) = s.near[i] {
                // linearised clearance of the predicted position
                let cl = near.now + near.normal.dot(&(p - x[i]));
                let v = (near.margin - cl).max(0.0);
                cost += w.w_wall * v * v;
            }
        }
        cost
    }

    /// The per-axis pull displacement over the horizon per unit gradient at `theta`, `alpha`.
    fn pull_axes(&self, theta: f64, alpha: f64) -> (Vec2, Vec2) {
        let k = self.pull_coeff * self.horizon_s;
        let axis = |grad| {
            self.model
                .coil
                .actuation(&Control { theta, alpha, grad })
                .pull
        };
        let (ax, ay) = (axis([1.0, 0.0]), axis([0.0, 1.0]));
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

/// Pairs of a team of [`MAX_AGENTS`].
const MAX_PAIRS: usize = MAX_AGENTS * (MAX_AGENTS - 1) / 2;

/// The smallest wall margin (BL), even where the plan itself is closer to a wall.
const WALL_FLOOR: f64 = 0.04;

/// The least clearance (BL) the closed-form gradient keeps a predicted agent from a wall it is
/// near (half its margin if that is more).
const WALL_KEEP: f64 = 0.002;

/// How far (BL per tick of horizon) an agent can get towards a wall: agents further than
/// `wall_margin` plus this from every wall are not checked against walls at all.
const WALL_REACH: f64 = 0.3;

/// The shared inputs of one solve.
struct Setup<'a> {
    x: &'a [Vec2],
    /// The start every candidate's prediction shares (a pair under the exact flow).
    pair: Option<PairStart>,
    /// The current separation of each pair of agents, in `score`'s order.
    separations: [f64; MAX_PAIRS],
    target: &'a [Vec2],
    ct: Vec2,
    /// The field angle of the last command.
    prev: Option<f64>,
    /// The elevation of the last command (0 if none).
    prev_alpha: f64,
    /// The elevation is searched too.
    elevated: bool,
    /// Each agent near a wall: its clearance, the clearance gradient and its margin.
    near: [Option<Near>; MAX_AGENTS],
}

/// An agent near a wall.
#[derive(Clone, Copy)]
struct Near {
    /// Its clearance now (BL).
    now: f64,
    /// The unit gradient of the clearance at its position.
    normal: Vec2,
    /// The clearance below which it is penalised: `wall_margin`, or less if the target is closer.
    margin: f64,
}

/// Golden-section search of `f`'s cost over [a, b] with `iterations` shrinking steps; the
/// better of the last two candidates.
fn golden(mut a: f64, mut b: f64, iterations: usize, f: impl Fn(f64) -> Candidate) -> Candidate {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let mut fc = f(c);
    let mut fd = f(d);
    for _ in 0..iterations {
        if fc.cost < fd.cost {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    if fc.cost < fd.cost { fc } else { fd }
}

/// Wraps an angle to (−π/2, π/2]: field angles that differ by π give the same pair force.
pub fn wrap_half(a: f64) -> f64 {
    let pi = std::f64::consts::PI;
    // `rem_euclid` is a software fmod; for |a| < π fmod is `a` itself, so skip it (same bits)
    let mut w = if a.abs() < pi {
        if a < 0.0 { a + pi } else { a }
    } else {
        a.rem_euclid(pi)
    };
    if w > 0.5 * pi {
        w -= pi;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_half_is_the_euclidean_remainder_bit_for_bit() {
        let pi = std::f64::consts::PI;
        let slow = |a: f64| {
            let w = a.rem_euclid(pi);
            if w > 0.5 * pi { w - pi } else { w }
        };
        let mut a = -12.0f64;
        while a < 12.0 {
            for x in [
                a,
                a.next_up(),
                -a,
                pi,
                -pi,
                pi.next_down(),
                (-pi).next_up(),
                0.0,
                -0.0,
            ] {
                assert_eq!(wrap_half(x).to_bits(), slow(x).to_bits(), "{x}");
            }
            a += 0.0137;
        }
    }
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

    /// Two agents centred at (20, 15), `r` apart, at angle `phi`.
    fn pair_at(r: f64, phi: f64) -> [Vec2; 2] {
        LocalView::new(20.0, 15.0, r, phi).to_pair()
    }

    /// Holding an equilateral triangle: in the plane it always contracts, so the elevated
    /// search tilts the field and does much better.
    #[test]
    fn three_agents_tilt_the_field_to_hold_a_triangle() {
        let (model, checker) = setup();
        let x = [
            Vec2::new(10.0, 10.0),
            Vec2::new(12.5, 10.0),
            Vec2::new(11.25, 12.165),
        ];
        let make = |planar| {
            let w = ObcWeights {
                planar,
                ..Default::default()
            };
            ObcOptimizer::new(model.clone(), checker.clone(), 0.5, w)
        };
        let flat = make(Planar::Yes).solve(&x, &x, None, None);
        let free = make(Planar::Auto).solve(&x, &x, None, None);
        assert_eq!(flat.control.alpha, 0.0);
        assert!(free.control.alpha > 0.3, "{:?}", free.control);
        assert!(
            free.cost < 0.5 * flat.cost,
            "{} vs {}",
            free.cost,
            flat.cost
        );
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
        let x = pair_at(2.2, 0.4);
        for u in [
            Control::planar(1.0, 0.03, -0.05),
            Control::planar(-2.0, 0.06, 0.01),
        ] {
            let mut target = [Vec2::zeros(); 2];
            model.propagate(&x, &u, 1.0 / 60.0, &mut target);
            let s = opt.solve(&x, &target, None, None);
            let err: f64 = s
                .predicted
                .iter()
                .zip(&target)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max);
            // 24 grid angles refined 10 times find θ to ~4e-4 rad: ~1e-5 BL per frame, far
            // below the camera's noise
            assert!(
                err < 5e-5,
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
        let x = pair_at(2.2, 0.4);
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
        let x = pair_at(1.5, 0.0);
        let target = pair_at(1.0, 0.0);
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
        let x = LocalView::new(10.0, 0.53, 2.0, 0.0).to_pair();
        let target = [x[0] - Vec2::new(0.0, 1.0), x[1] - Vec2::new(0.0, 1.0)];
        let sol = opt.solve(&x, &target, None, None);
        for p in &sol.predicted {
            assert!(checker.collision.clearance(*p) >= 0.0, "{p:?}");
        }
    }
}

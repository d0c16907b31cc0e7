//! The convex subproblem of one SCP step: the flow linearised along the rollout, the walls,
//! the proximity range and the goal linearised and softened by slack, the cost as a
//! second-order-cone program, solved by Clarabel (an interior-point solver for conic programs,
//! pure Rust: one dependency for the path-length epigraph's cones and the control effort's
//! quadratic alike).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use magbench_env::Vec2;

use super::Rollout;
use super::linearise::EdgeJacobian;
use super::rollout::{end_disks, end_violation};
use crate::Problem;

/// Step of the central differences of a wall's clearance (BL).
const H: f64 = 1e-6;

/// A weight on the squared step (per unit of the trust region's units) that keeps the
/// subproblem strictly convex where the cost does not see a variable.
const REGULARISE: f64 = 1e-6;

/// Clarabel's duality-gap (absolute and relative) and feasibility tolerance, against its default
/// 1e-8. A step is judged by the flow's own rollout (the ratio of actual to predicted decrease),
/// not by the subproblem's optimality, so the subproblem needs only the accuracy of the
/// decreases the optimiser tells apart, `SMALLEST_DECREASE` (1e-4): a window's feasible merit is
/// its path length, a few BL for 8 edges, which a relative 1e-6 resolves to a few 1e-6. For the
/// same reason the KKT solves are not iteratively refined.
const TOLERANCE: f64 = 1e-6;

/// How close to a wall or to an end of the proximity range a waypoint must be (BL, beyond the
/// margin) for the subproblem to carry its constraint: a waypoint farther away is not expected
/// to get there in one step, and if it does, the next rollout's violation brings its
/// constraint in.
const ACTIVE: f64 = 1.0;

/// The trust region of a step.
#[derive(Debug, Clone, Copy)]
pub struct Trust {
    /// Its size: the largest change of a field angle (rad) and of a gradient command (fraction
    /// of the limit).
    pub size: f64,
    /// The coil's gradient limit (T/m).
    pub gradient_limit: f64,
}

/// A solved step.
#[derive(Debug, Clone)]
pub struct Step {
    /// The change of each edge's (θ, G_x, G_y).
    pub delta: Vec<[f64; 3]>,
    /// The model's merit before the step: the modelled cost of the rollout plus its penalised
    /// violations.
    pub now: f64,
    /// The model's merit after the step.
    pub predicted: f64,
}

/// Linear terms `(variable, coefficient)` of one constraint row, and its right-hand side.
type Row = (Vec<(usize, f64)>, f64);

/// A conic program under construction: `min ½ zᵀPz + qᵀz` over `Az + s = b`, `s` in the cones.
#[derive(Default)]
struct Program {
    q: Vec<f64>,
    p: Vec<(usize, usize, f64)>,
    zero: Vec<Row>,
    nonneg: Vec<Row>,
    socs: Vec<Vec<Row>>,
    slacks: Vec<usize>,
}

impl Program {
    /// A new variable with linear cost `cost`; its index.
    fn var(&mut self, cost: f64) -> usize {
        self.q.push(cost);
        self.q.len() - 1
    }

    /// A nonnegative slack paid `penalty` per unit; its index.
    fn slack(&mut self, penalty: f64) -> usize {
        let s = self.var(penalty);
        self.nonneg.push((vec![(s, -1.0)], 0.0));
        self.slacks.push(s);
        s
    }

    /// `Σ terms ≤ b`.
    fn le(&mut self, terms: Vec<(usize, f64)>, b: f64) {
        self.nonneg.push((terms, b));
    }

    /// `lo ≤ z_v ≤ hi`.
    fn bounds(&mut self, v: usize, lo: f64, hi: f64) {
        self.le(vec![(v, 1.0)], hi);
        self.le(vec![(v, -1.0)], -lo);
    }

    /// Solves the program; `z` when Clarabel solves it.
    fn solve(&self) -> Option<Vec<f64>> {
        let n = self.q.len();
        let mut rows = (Vec::new(), Vec::new(), Vec::new());
        let mut b = Vec::new();
        let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
        let mut push = |group: &[Row], rows: &mut (Vec<usize>, Vec<usize>, Vec<f64>)| {
            for (terms, rhs) in group {
                let r = b.len();
                for &(c, v) in terms {
                    rows.0.push(r);
                    rows.1.push(c);
                    rows.2.push(v);
                }
                b.push(*rhs);
            }
        };
        push(&self.zero, &mut rows);
        cones.push(ZeroConeT(self.zero.len()));
        push(&self.nonneg, &mut rows);
        cones.push(NonnegativeConeT(self.nonneg.len()));
        for soc in &self.socs {
            push(soc, &mut rows);
            cones.push(SecondOrderConeT(soc.len()));
        }
        let m = b.len();
        let a = CscMatrix::new_from_triplets(m, n, rows.0, rows.1, rows.2);
        let (pi, pj, pv) = self.p.iter().fold(
            (Vec::new(), Vec::new(), Vec::new()),
            |(mut i, mut j, mut v), &(r, c, x)| {
                i.push(r);
                j.push(c);
                v.push(x);
                (i, j, v)
            },
        );
        let p = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
        let settings = DefaultSettings {
            verbose: false,
            max_iter: 200,
            tol_gap_abs: TOLERANCE,
            tol_gap_rel: TOLERANCE,
            tol_feas: TOLERANCE,
            iterative_refinement_enable: false,
            ..DefaultSettings::default()
        };
        let mut solver = DefaultSolver::new(&p, &self.q, &a, &b, &cones, settings).ok()?;
        solver.solve();
        matches!(
            solver.solution.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        )
        .then(|| solver.solution.x.clone())
    }
}

/// The step of least model merit within the trust region, or `None` when the solver fails.
pub fn solve_step(
    problem: &Problem,
    rollout: &Rollout,
    model: &[EdgeJacobian],
    trust: Trust,
    margin: f64,
    penalty: f64,
) -> Option<Step> {
    let n = problem.agents();
    let dim = 2 * n;
    let k_edges = rollout.edges();
    let limit = trust.gradient_limit;
    let mut prog = Program::default();
    // δu_k = (δθ, δG_x, δG_y), then δx_1 … δx_K
    let du = |k: usize, j: usize| 3 * k + j;
    let dx = |k: usize, c: usize| 3 * k_edges + (k - 1) * dim + c;
    // (variable, weight, gradient now) of each gradient command in the control effort
    let mut weights = Vec::with_capacity(2 * k_edges);
    for k in 0..k_edges {
        let u = &rollout.controls[k];
        let effort = effort_weight(problem, rollout.durations[k]);
        weights.extend([(du(k, 1), effort, u.grad[0]), (du(k, 2), effort, u.grad[1])]);
        for j in 0..3 {
            let v = prog.var(0.0);
            debug_assert_eq!(v, du(k, j));
            let (scale, quadratic, linear) = match j {
                0 => (1.0, 0.0, 0.0),
                _ => (limit, 2.0 * effort, 2.0 * effort * u.grad[j - 1]),
            };
            prog.q[v] = linear;
            prog.p
                .push((v, v, quadratic + REGULARISE / (scale * scale)));
            let step = trust.size * scale;
            match j {
                0 => prog.bounds(v, -step, step),
                _ => {
                    let g = u.grad[j - 1];
                    prog.bounds(v, (-step).max(-limit - g), step.min(limit - g));
                }
            }
        }
    }
    for k in 1..=k_edges {
        for c in 0..dim {
            let v = prog.var(0.0);
            debug_assert_eq!(v, dx(k, c));
            prog.p.push((v, v, REGULARISE));
        }
    }
    // the flow: δx_{k+1} − A_k δx_k − B_k δu_k = 0
    for (k, jac) in model.iter().enumerate() {
        for r in 0..dim {
            let mut terms = vec![(dx(k + 1, r), 1.0)];
            if k > 0 {
                terms.extend((0..dim).map(|c| (dx(k, c), -jac.a[r * dim + c])));
            }
            terms.extend((0..3).map(|j| (du(k, j), -jac.b[r * 3 + j])));
            prog.zero.push((terms, 0.0));
        }
    }
    let checker = &problem.checker;
    let mut model_violation = 0.0;
    for k in 1..=k_edges {
        let s = &rollout.states[k];
        // walls: clearance + ∇clearance·δp ≥ margin − slack
        for (i, p) in s.iter().enumerate() {
            let c = checker.collision.clearance(*p);
            if c >= margin + ACTIVE {
                continue;
            }
            let grad = clearance_gradient(problem, *p);
            let slack = prog.slack(penalty);
            prog.le(
                vec![
                    (dx(k, 2 * i), -grad.x),
                    (dx(k, 2 * i + 1), -grad.y),
                    (slack, -1.0),
                ],
                c - margin,
            );
            model_violation += (margin - c).max(0.0);
        }
        // the proximity range: r_min + margin ≤ r + e·(δp_j − δp_i) ≤ r_max − margin
        for i in 0..n {
            for j in i + 1..n {
                let d = s[j] - s[i];
                let r = d.norm();
                let e = d / r;
                let low = r - checker.r_min - margin;
                let high = checker.r_max - margin - r;
                let along = |sign: f64| {
                    vec![
                        (dx(k, 2 * j), sign * e.x),
                        (dx(k, 2 * j + 1), sign * e.y),
                        (dx(k, 2 * i), -sign * e.x),
                        (dx(k, 2 * i + 1), -sign * e.y),
                    ]
                };
                if low < ACTIVE {
                    let slack = prog.slack(penalty);
                    let mut terms = along(-1.0);
                    terms.push((slack, -1.0));
                    prog.le(terms, low);
                }
                if high < ACTIVE {
                    let slack = prog.slack(penalty);
                    let mut terms = along(1.0);
                    terms.push((slack, -1.0));
                    prog.le(terms, high);
                }
                model_violation += (-low).max(0.0) + (-high).max(0.0);
            }
        }
    }
    // the end: ‖p_i + δp_i − g_i‖ ≤ radius + slack_i
    let end = rollout.states.last().expect("the start");
    let (centres, radius) = end_disks(problem, &rollout.end, margin);
    for (i, (p, g)) in end.iter().zip(centres).enumerate() {
        let slack = prog.slack(penalty);
        let off = p - g;
        prog.socs.push(vec![
            (vec![(slack, -1.0)], radius),
            (vec![(dx(k_edges, 2 * i), -1.0)], off.x),
            (vec![(dx(k_edges, 2 * i + 1), -1.0)], off.y),
        ]);
    }
    model_violation += end_violation(problem, &rollout.end, end, margin);
    // the path length's epigraph: t_{k,i} ≥ ‖p_{k+1,i} + δ − p_{k,i} − δ'‖
    let mut chords = Vec::new();
    if problem.objective.is_path_length() {
        for k in 0..k_edges {
            for i in 0..n {
                let t = prog.var(1.0);
                chords.push(t);
                let step = rollout.states[k + 1][i] - rollout.states[k][i];
                let mut rows = vec![(vec![(t, -1.0)], 0.0)];
                for axis in 0..2 {
                    let mut terms = vec![(dx(k + 1, 2 * i + axis), -1.0)];
                    if k > 0 {
                        terms.push((dx(k, 2 * i + axis), 1.0));
                    }
                    rows.push((terms, step[axis]));
                }
                prog.socs.push(rows);
            }
        }
    }
    debug_assert!(
        (model_violation - rollout.violation).abs() <= 1e-6 * (1.0 + rollout.violation),
        "the subproblem's violations at δ = 0 are the rollout's"
    );
    let fixed = fixed_cost(problem, rollout);
    let chords_now: f64 = if chords.is_empty() {
        0.0
    } else {
        rollout
            .states
            .windows(2)
            .flat_map(|w| w[0].iter().zip(&w[1]).map(|(p, q)| (q - p).norm()))
            .sum()
    };
    let effort_now: f64 = weights.iter().map(|&(_, w, g)| w * g * g).sum();
    let now = fixed + chords_now + effort_now + penalty * model_violation;
    let z = prog.solve()?;
    let delta = (0..k_edges)
        .map(|k| [z[du(k, 0)], z[du(k, 1)], z[du(k, 2)]])
        .collect();
    let chord_cost: f64 = chords.iter().map(|&t| z[t]).sum();
    let effort: f64 = weights
        .iter()
        .map(|&(v, w, g)| w * (g + z[v]) * (g + z[v]))
        .sum();
    let slack: f64 = prog.slacks.iter().map(|&s| z[s].max(0.0)).sum();
    Some(Step {
        delta,
        now,
        predicted: fixed + chord_cost + effort + penalty * slack,
    })
}

/// The weight of `G_x² + G_y²` in the control effort of an edge of `duration` (`d / G_max²`),
/// 0 under other objectives.
fn effort_weight(problem: &Problem, duration: f64) -> f64 {
    if problem.objective.name() == "control-effort" {
        let g = problem.model.coil.gradient_limit();
        duration / (g * g)
    } else {
        0.0
    }
}

/// The part of the rollout's cost the subproblem does not model: all of it under an objective
/// other than path length and control effort (duration: the durations are kept).
fn fixed_cost(problem: &Problem, rollout: &Rollout) -> f64 {
    if problem.objective.is_path_length() || problem.objective.name() == "control-effort" {
        0.0
    } else {
        rollout.cost
    }
}

/// The gradient of a wall's clearance at `p`, by central differences.
fn clearance_gradient(problem: &Problem, p: Vec2) -> Vec2 {
    let c = |q: Vec2| problem.checker.collision.clearance(q);
    let (ex, ey) = (Vec2::new(H, 0.0), Vec2::new(0.0, H));
    Vec2::new(c(p + ex) - c(p - ex), c(p + ey) - c(p - ey)) / (2.0 * H)
}

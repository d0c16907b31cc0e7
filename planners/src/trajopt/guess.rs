//! The optimiser's guess when no plan is given: the centroid carried along the straight line
//! from the start's centroid to the goal's. A pair under the exact flow is steered exactly
//! onto the goal (env's `steer_pair`, which moves the pair's centre on that line while its
//! shape changes); any other team is carried with its shape held as well as one field can.

use std::f64::consts::FRAC_PI_2;

use magbench_env::math::centroid;
use magbench_env::model::steer_pair;
use magbench_env::{Control, MAX_AGENTS, Vec2};

use super::{Settings, cut};
use crate::Problem;
use crate::motion::aimed;
use crate::post_process::default_max_duration;
use crate::search_settings::to_periods;

/// The angle between a field in the plane and a pair's separation at which the pair neither
/// attracts nor repels (rad): the radial dipole force goes as `1 − 3 cos²α cos²ψ` (the paper's
/// `f_r`), zero at `cos ψ = 1/√3`, the paper's 54.74° of dynamic equilibrium.
fn neutral_angle() -> f64 {
    (1.0 / 3f64.sqrt()).acos()
}

/// The separation the guess holds agents 0 and 1 at (BL): the goal's, at least [`HELD_APART`]
/// (the pair's relative motion slows as `r⁻⁴`, so that one edge's field moves it little), and
/// half a BL inside the proximity range.
fn held_separation(problem: &Problem) -> f64 {
    let goal = (problem.goal.agents[1] - problem.goal.agents[0]).norm();
    let (lo, hi) = (problem.checker.r_min + 0.5, problem.checker.r_max - 0.5);
    goal.max(HELD_APART).min(hi).max(lo)
}

/// The least separation the guess holds (BL): at 3 BL a constant field changes the separation
/// at about a fifth of its rate at 2 BL ((2/3)⁴), some 0.15 BL in a 0.25 s edge.
const HELD_APART: f64 = 3.0;

/// How far the separation may stray from [`held_separation`] before the guess pulls it back
/// (BL).
const DEADBAND: f64 = 0.25;

/// The guess for `problem`: the exact steer of a pair from the start onto the goal where it exists
/// ([`steer_onto_goal`]); else [`held_line`], followed by the exact steer from its end onto the
/// goal where that exists.
pub fn straight_line(problem: &Problem, settings: &Settings) -> (Vec<Control>, Vec<f64>) {
    if let Some(steer) = steer_onto_goal(problem, &problem.start, settings) {
        return steer;
    }
    let (mut controls, mut durations, end) = held_line(problem, settings);
    if let Some((more, longer)) = steer_onto_goal(problem, &end, settings) {
        controls.extend(more);
        durations.extend(longer);
    }
    (controls, durations)
}

/// The exact steer of a pair from `from` onto the goal centres (env's `steer_pair`), its edges
/// at most the sampling planners' longest (crate::post_process::default_max_duration) and then
/// cut to [`Settings::edge_periods`]; walls are not checked. `None` for a team other than a
/// pair under the exact flow, or when the steer finds no solution within its limits.
fn steer_onto_goal(
    problem: &Problem,
    from: &[Vec2],
    settings: &Settings,
) -> Option<(Vec<Control>, Vec<f64>)> {
    let longest = to_periods(default_max_duration(), problem.control_period);
    let limits = problem.steer_limits(longest);
    let edges = steer_pair(&problem.model, from, &problem.goal.agents, &limits, |_| {
        true
    })?;
    Some(cut(
        problem,
        edges.iter().map(|e| (e.control, e.periods as usize)),
        settings.edge_periods,
    ))
}

/// Controls and durations that carry the centroid along the straight line from the start's to
/// the goal's at half the largest centroid speed, in edges of [`Settings::edge_periods`]. Each
/// edge's field is chosen from the separation of agents 0 and 1 where the edge starts: across
/// it (repelling) when they are too close, along it (attracting) when too far, else at the
/// neutral angle on alternate sides from edge to edge, so that the transverse force, which
/// turns the pair, changes sign (the paper's way of holding a pair in place); its gradients
/// aim the centroid at the line's point at the edge's end. The guess ignores the walls and the
/// goal's shape; the optimiser makes it valid or reports that it could not.
/// Also returns where the line ends.
fn held_line(problem: &Problem, settings: &Settings) -> (Vec<Control>, Vec<f64>, Vec<Vec2>) {
    let n = problem.agents();
    let from = centroid(&problem.start);
    let to = centroid(&problem.goal.agents);
    let speed = 0.5 * problem.model.kinematics.pull_coeff * problem.model.coil.gradient_limit();
    let edge = problem.periods(settings.edge_periods as u32);
    let edges = ((to - from).norm() / speed / edge).ceil().max(1.0) as usize;
    let held = held_separation(problem);
    let mut state = [Vec2::zeros(); MAX_AGENTS];
    state[..n].copy_from_slice(&problem.start);
    let mut next = state;
    let mut controls = Vec::with_capacity(edges);
    for k in 0..edges {
        let separation = state[1] - state[0];
        let r = separation.norm();
        let psi = if r < held - DEADBAND {
            FRAC_PI_2
        } else if r > held + DEADBAND {
            0.0
        } else if k % 2 == 0 {
            neutral_angle()
        } else {
            -neutral_angle()
        };
        let field = Control::planar(separation.y.atan2(separation.x) + psi, 0.0, 0.0);
        let target = from + (to - from) * ((k + 1) as f64 / edges as f64);
        let u = aimed(problem, field, n, centroid(&state[..n]), target, edge);
        problem
            .model
            .propagate(&state[..n], &u, edge, &mut next[..n]);
        state = next;
        controls.push(u);
    }
    (controls, vec![edge; edges], state[..n].to_vec())
}

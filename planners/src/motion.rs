//! Edges: random controls, plain propagation and checked propagation through env.
//!
//! The physics is env's: [`PlanningModel::propagate_with`](magbench_env::PlanningModel) integrates,
//! [`ValidityChecker::segment_valid`](magbench_env::ValidityChecker) checks each integration step
//! exactly as `ValidityChecker::motion_valid` does (swept capsules between samples, proximity
//! range at every sample). Durations passed here are whole control periods.

use magbench_env::{Actuation, Control, MAX_AGENTS, Vec2, Vec3};
use rand::RngExt;

use crate::{Plan, Problem};

/// A uniformly random planar control: θ_B in [−π, π), each gradient command in [−G, G].
#[inline]
pub fn random_control(rng: &mut impl RngExt, gradient_limit: f64) -> Control {
    use std::f64::consts::PI;
    Control::planar(
        rng.random_range(-PI..PI),
        rng.random_range(-gradient_limit..=gradient_limit),
        rng.random_range(-gradient_limit..=gradient_limit),
    )
}

/// A uniformly random elevated control: θ_B in [−π, π), α in [0, `alpha_max`], each gradient
/// command in [−G, G]. The in-plane motion depends on α only through cos α, so α ≥ 0 loses
/// nothing.
#[inline]
pub fn random_elevated_control(
    rng: &mut impl RngExt,
    gradient_limit: f64,
    alpha_max: f64,
) -> Control {
    use std::f64::consts::PI;
    let theta = rng.random_range(-PI..PI);
    let alpha = rng.random_range(0.0..=alpha_max);
    Control {
        theta,
        alpha,
        grad: [
            rng.random_range(-gradient_limit..=gradient_limit),
            rng.random_range(-gradient_limit..=gradient_limit),
        ],
    }
}

/// Solves `start` under `u` for `duration` into `out` (no checks).
#[inline]
pub fn propagate(problem: &Problem, start: &[Vec2], u: &Control, duration: f64, out: &mut [Vec2]) {
    problem.model.propagate(start, u, duration, out);
}

/// Solves `start` under `u` for `duration` into `out` and checks the whole motion, as
/// [`propagate_checked`] does, without measuring its length (for planners that keep no costs).
#[inline]
pub fn propagate_valid(
    problem: &Problem,
    start: &[Vec2],
    u: &Control,
    duration: f64,
    out: &mut [Vec2],
) -> bool {
    match problem.model.pair_edge(start, u) {
        Some(edge) => problem.checker.edge_end_valid(&edge, duration, out),
        None => propagate_checked(problem, start, u, duration, out).is_some(),
    }
}

/// Safety margin (BL) kept below a clearance before sweeps are skipped.
const CLEARANCE_MARGIN: f64 = 1e-9;

/// Solves `start` under `u` for `duration` into `out` and checks the whole motion. Returns the
/// agents' summed path length ([`PlanningModel::path_length`](magbench_env::PlanningModel))
/// if the motion is valid.
///
/// An exact motion is checked by env's `ValidityChecker::edge_valid` (the separation's exact
/// range, conservative advancement against obstacles) and leaves its end in `out`. An RK4
/// motion is checked at every integration step and stops at the first invalid one (`out` then
/// holds that sample). Its check is `ValidityChecker::segment_valid`'s — the proximity range at every sample, each
/// agent's capsule sweep between samples — with one shortcut through env's own queries: an
/// agent whose path since its last clearance query is shorter than that clearance cannot
/// touch an obstacle (every point of its chords lies within the clear disk), so its sweeps are
/// skipped until it has travelled that far; then it is swept and its clearance re-measured.
/// The validator checks plans with `motion_valid` itself, without the shortcut.
#[inline]
pub fn propagate_checked(
    problem: &Problem,
    start: &[Vec2],
    u: &Control,
    duration: f64,
    out: &mut [Vec2],
) -> Option<f64> {
    let checker = &problem.checker;
    if let Some(edge) = problem.model.pair_edge(start, u) {
        return checker
            .edge_end_valid(&edge, duration, out)
            .then(|| edge.path_length(duration));
    }
    let n = start.len();
    let world = &checker.collision;
    let mut prev = [Vec2::zeros(); MAX_AGENTS];
    prev[..n].copy_from_slice(start);
    let mut clear = [0.0; MAX_AGENTS];
    for (c, p) in clear.iter_mut().zip(start) {
        *c = world.clearance(*p) - CLEARANCE_MARGIN;
    }
    let mut travelled = [0.0; MAX_AGENTS];
    let mut length = 0.0;
    let ok = problem.model.propagate_with(start, u, duration, out, |s| {
        if !checker.proximity_ok(s) {
            return false;
        }
        for i in 0..n {
            let step = (s[i] - prev[i]).norm();
            length += step;
            travelled[i] += step;
            if travelled[i] >= clear[i] {
                if !world.sweep_clear(prev[i], s[i]) {
                    return false;
                }
                clear[i] = world.clearance(s[i]) - CLEARANCE_MARGIN;
                travelled[i] = 0.0;
            }
            prev[i] = s[i];
        }
        true
    });
    ok.then_some(length)
}

/// `head` followed by `edges` (command, duration), each propagated by [`propagate_valid`] from
/// where the one before ends; `None` at the first invalid edge.
pub fn replay_onto(
    problem: &Problem,
    mut head: Plan,
    edges: impl IntoIterator<Item = (Control, f64)>,
) -> Option<Plan> {
    let n = problem.agents();
    let mut at = [Vec2::zeros(); MAX_AGENTS];
    at[..n].copy_from_slice(head.end());
    let mut next = at;
    for (u, d) in edges {
        if !propagate_valid(problem, &at[..n], &u, d, &mut next[..n]) {
            return None;
        }
        head.push(u, d, next[..n].to_vec());
        at = next;
    }
    Some(head)
}

/// `u` with the gradient commands, each within the coil's limit, that bring the centroid of a
/// team of `n` at `from`, moving for `duration` under `u`'s field, closest to `to`; `u`
/// unchanged when the agents' mobilities differ (the centroid then has no velocity of its
/// own). The pull is linear in the gradient commands for a given field (the coil's
/// `pull_map`); the team's relative motion does not depend on the gradients (every agent feels
/// the same pull), so this choice brings the try's end closest to a target whose centroid is
/// `to`, under either metric, among all gradients when the coil's axes pull independently (the
/// tri-axial coil); otherwise the commands are the unconstrained best, clamped.
pub fn aimed(
    problem: &Problem,
    u: Control,
    n: usize,
    from: Vec2,
    to: Vec2,
    duration: f64,
) -> Control {
    let limit = problem.model.coil.gradient_limit();
    let Some((v0, ax, ay)) = centroid_map(problem, &u, n) else {
        return u;
    };
    // the velocity wanted beyond the drift
    let want = (to - from) / duration - v0;
    let det = ax.x * ay.y - ax.y * ay.x;
    let (sx, sy) = if ax.y == 0.0 && ay.x == 0.0 || det == 0.0 || !det.is_finite() {
        // each axis on its own (the tri-axial coil: x pulls along x, y along y)
        (fraction(want.x, ax.x), fraction(want.y, ay.y))
    } else {
        (
            fraction(want.x * ay.y - want.y * ay.x, det),
            fraction(ax.x * want.y - ax.y * want.x, det),
        )
    };
    Control {
        grad: [sx * limit, sy * limit],
        ..u
    }
}

/// The centroid velocity of a team of `n` under `u`'s field with zero gradient commands (the
/// drift), and its change per full gradient command (the coil's limit) along x and along y:
/// the centroid's velocity is affine in the gradient commands for a given field. `None` when
/// the agents' mobilities differ (the centroid then has no velocity of its own).
#[inline]
pub fn centroid_map(problem: &Problem, u: &Control, n: usize) -> Option<(Vec2, Vec2, Vec2)> {
    let (coil, kinematics) = (&problem.model.coil, &problem.model.kinematics);
    let limit = coil.gradient_limit();
    let (zero, [px, py]) = coil.pull_map(u);
    let velocity = |pull: Vec3| kinematics.centroid_velocity(&Actuation { pull, ..zero }, n);
    let v0 = velocity(zero.pull)?;
    let vx = velocity(zero.pull + px * limit)?;
    let vy = velocity(zero.pull + py * limit)?;
    Some((v0, vx - v0, vy - v0))
}

/// `want / reach` within `[−1, 1]`; 0 when the axis does not reach (`reach` 0).
fn fraction(want: f64, reach: f64) -> f64 {
    let s = want / reach;
    if s.is_finite() {
        s.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rng;
    use crate::sampler::{StateSampler, valid_sample};
    use rand::SeedableRng;

    /// The shortcut never changes the verdict or the end state of env's `motion_valid`.
    #[test]
    fn checked_propagation_agrees_with_motion_valid() {
        for name in ["micro-factory", "narrow-passage"] {
            let s = magbench_env::Scenario::load(name).unwrap();
            let p = Problem::from_scenario(&s, 0, None, 0);
            let sampler = StateSampler::new(&p);
            let mut rng = Rng::seed_from_u64(5);
            let g = p.model.coil.gradient_limit();
            let (mut valid, mut invalid) = (0, 0);
            let mut x = vec![Vec2::zeros(); 2];
            let (mut a, mut b) = (vec![Vec2::zeros(); 2], vec![Vec2::zeros(); 2]);
            for k in 0..3000 {
                assert!(valid_sample(&p, 1000, &mut x, |s| sampler.uniform(&mut rng, s)));
                let u = random_control(&mut rng, g);
                let d = p.periods(1 + k % 120);
                let ours = propagate_checked(&p, &x, &u, d, &mut a);
                let env = p.checker.motion_valid(&p.model, &x, &u, d, &mut b);
                assert_eq!(ours.is_some(), env, "{name}: edge {k}");
                if env {
                    assert_eq!(a, b);
                    valid += 1;
                } else {
                    invalid += 1;
                }
            }
            assert!(
                valid > 300 && invalid > 300,
                "{name}: {valid} valid, {invalid} invalid"
            );
        }
    }
}

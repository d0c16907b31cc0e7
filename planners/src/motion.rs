//! Edges: random controls, plain propagation and checked propagation through env.
//!
//! The physics is env's: [`PlanningModel::propagate_with`](magbench_env::PlanningModel) integrates,
//! [`ValidityChecker::segment_valid`](magbench_env::ValidityChecker) checks each integration step
//! exactly as `ValidityChecker::motion_valid` does (swept capsules between samples, proximity
//! range at every sample). Durations passed here are whole control periods.

use magbench_env::{Control, MAX_AGENTS, Vec2};
use rand::RngExt;

use crate::Problem;

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

/// Integrates `start` under `u` for `duration` into `out` (no checks).
#[inline]
pub fn propagate(problem: &Problem, start: &[Vec2], u: &Control, duration: f64, out: &mut [Vec2]) {
    problem
        .model
        .propagate_with(start, u, duration, out, |_| true);
}

/// Integrates `start` under `u` for `duration` into `out`, checking every integration step.
/// Returns the agents' summed path length along the samples if the whole motion is valid, and
/// `None` at the first invalid step (`out` then holds that sample).
#[inline]
pub fn propagate_checked(
    problem: &Problem,
    start: &[Vec2],
    u: &Control,
    duration: f64,
    out: &mut [Vec2],
) -> Option<f64> {
    let n = start.len();
    let mut prev = [Vec2::zeros(); MAX_AGENTS];
    prev[..n].copy_from_slice(start);
    let mut length = 0.0;
    let checker = &problem.checker;
    let ok = problem.model.propagate_with(start, u, duration, out, |s| {
        if !checker.segment_valid(&prev[..n], s) {
            return false;
        }
        for (p, q) in prev[..n].iter_mut().zip(s) {
            length += (q - *p).norm();
            *p = *q;
        }
        true
    });
    ok.then_some(length)
}

//! Classic fixed-step fourth-order Runge–Kutta on agent positions.
//!
//! The step is the preset's `dt_s` (1/120 s by default, two steps per 60 fps camera frame).
//! A duration is covered by `floor(duration/dt)` full steps plus, if the duration is not a whole
//! number of steps, one shorter step ([`step_schedule`]). Planners quantise durations to whole
//! control periods, so plans never use the shorter step.

use crate::math::{MAX_AGENTS, Vec2};

/// Number of full steps of size `dt` in `duration`, and the length of a final partial step
/// (0 when `duration` is a whole number of steps, to within 1e-9 of a step).
pub fn step_schedule(duration: f64, dt: f64) -> (usize, f64) {
    if duration <= 0.0 {
        return (0, 0.0);
    }
    let n = (duration / dt + 1e-9).floor();
    let rest = duration - n * dt;
    (n as usize, if rest > 1e-9 * dt { rest } else { 0.0 })
}

/// One RK4 step of size `h` of `ṗ = f(p)` for the agents in `p`, in place.
#[inline]
pub fn rk4_step(f: &impl Fn(&[Vec2], &mut [Vec2]), p: &mut [Vec2], h: f64) {
    let n = p.len();
    assert!(n <= MAX_AGENTS, "at most {MAX_AGENTS} agents");
    let z = Vec2::zeros();
    let (mut k1, mut k2, mut k3, mut k4, mut y) = (
        [z; MAX_AGENTS],
        [z; MAX_AGENTS],
        [z; MAX_AGENTS],
        [z; MAX_AGENTS],
        [z; MAX_AGENTS],
    );
    f(p, &mut k1[..n]);
    for i in 0..n {
        y[i] = p[i] + k1[i] * (0.5 * h);
    }
    f(&y[..n], &mut k2[..n]);
    for i in 0..n {
        y[i] = p[i] + k2[i] * (0.5 * h);
    }
    f(&y[..n], &mut k3[..n]);
    for i in 0..n {
        y[i] = p[i] + k3[i] * h;
    }
    f(&y[..n], &mut k4[..n]);
    let h6 = h / 6.0;
    for i in 0..n {
        p[i] += (k1[i] + (k2[i] + k3[i]) * 2.0 + k4[i]) * h6;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_is_exact_for_whole_steps() {
        let dt = 1.0 / 120.0;
        for n in [1usize, 4, 37, 2400] {
            assert_eq!(step_schedule(n as f64 * dt, dt), (n, 0.0));
        }
        let (n, rest) = step_schedule(0.01, dt);
        assert_eq!(n, 1);
        assert!((rest - (0.01 - dt)).abs() < 1e-15);
    }

    #[test]
    fn rk4_integrates_exponential_to_fourth_order() {
        let f = |p: &[Vec2], v: &mut [Vec2]| v[0] = -p[0];
        let run = |h: f64| {
            let mut p = [Vec2::new(1.0, 2.0)];
            for _ in 0..(1.0 / h).round() as usize {
                rk4_step(&f, &mut p, h);
            }
            (p[0] - Vec2::new(1.0, 2.0) * (-1.0f64).exp()).norm()
        };
        let (e1, e2) = (run(0.1), run(0.05));
        assert!(e1 / e2 > 14.0 && e1 / e2 < 18.0, "order ratio {}", e1 / e2);
    }
}

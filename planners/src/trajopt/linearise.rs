//! The flow linearised along a rollout: each edge's sensitivities to its start state and to its
//! control, by central differences of the planning model's own flow.

use magbench_env::{Control, MAX_AGENTS, Vec2};

use super::Rollout;
use crate::Problem;

/// Step of the central differences in a position (BL) and in a field angle (rad).
const H: f64 = 1e-6;

/// One edge's sensitivities, row-major over the stacked coordinates `x0, y0, x1, y1, …`.
#[derive(Debug, Clone)]
pub struct EdgeJacobian {
    /// `∂x_{k+1} / ∂x_k`: `2N × 2N`.
    pub a: Vec<f64>,
    /// `∂x_{k+1} / ∂(θ, G_x, G_y)`: `2N × 3`.
    pub b: Vec<f64>,
}

/// The sensitivities of every edge of `rollout`.
pub fn jacobians(problem: &Problem, rollout: &Rollout) -> Vec<EdgeJacobian> {
    let n = problem.agents();
    let dim = 2 * n;
    let g_step = H * problem.model.coil.gradient_limit();
    let mut plus = [Vec2::zeros(); MAX_AGENTS];
    let mut minus = [Vec2::zeros(); MAX_AGENTS];
    let mut from = [Vec2::zeros(); MAX_AGENTS];
    let mut edges = Vec::with_capacity(rollout.edges());
    for (k, (u, &d)) in rollout.controls.iter().zip(&rollout.durations).enumerate() {
        let start = &rollout.states[k];
        let mut a = vec![0.0; dim * dim];
        for c in 0..dim {
            from[..n].copy_from_slice(start);
            nudge(&mut from[..n], c, H);
            problem.model.propagate(&from[..n], u, d, &mut plus[..n]);
            nudge(&mut from[..n], c, -2.0 * H);
            problem.model.propagate(&from[..n], u, d, &mut minus[..n]);
            for r in 0..dim {
                a[r * dim + c] = (coord(&plus, r) - coord(&minus, r)) / (2.0 * H);
            }
        }
        let mut b = vec![0.0; dim * 3];
        for (j, step) in [H, g_step, g_step].into_iter().enumerate() {
            let (up, down) = (moved(u, j, step), moved(u, j, -step));
            problem.model.propagate(start, &up, d, &mut plus[..n]);
            problem.model.propagate(start, &down, d, &mut minus[..n]);
            for r in 0..dim {
                b[r * 3 + j] = (coord(&plus, r) - coord(&minus, r)) / (2.0 * step);
            }
        }
        edges.push(EdgeJacobian { a, b });
    }
    edges
}

/// Coordinate `c` of the stacked state `s`.
fn coord(s: &[Vec2], c: usize) -> f64 {
    s[c / 2][c % 2]
}

/// Adds `h` to coordinate `c` of `s`.
fn nudge(s: &mut [Vec2], c: usize, h: f64) {
    s[c / 2][c % 2] += h;
}

/// `u` with its field angle (`j = 0`) or a gradient command (`j = 1, 2`) moved by `h`.
fn moved(u: &Control, j: usize, h: f64) -> Control {
    let mut v = *u;
    match j {
        0 => v.theta += h,
        _ => v.grad[j - 1] += h,
    }
    v
}

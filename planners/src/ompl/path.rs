//! OMPL's `PathControl` as a magbench [`Plan`].
//!
//! OMPL made every edge as a chain of one-period propagation steps, each checked by magbench's
//! edge check (see the module doc of [`super`]). The plan is rebuilt here from OMPL's controls
//! and step counts alone, by the same steps from the problem's start, and must land on OMPL's
//! states. Each step is one plan edge (an OMPL edge of k steps is k plan edges with the same
//! control), so the validator replays exactly what OMPL computed. Joining an OMPL edge into
//! one plan edge does not work: the one-shot motion ends a few ulps from the chain of steps,
//! the chaotic pair dynamics amplify that over the next edges, and the joined plan soon fails
//! the check where OMPL's passed (measured on open-field: RRT and SST plans of ~9k steps).

use magbench_env::{MAX_AGENTS, Vec2};

use crate::motion::propagate_valid;
use crate::validate::REPLAY_TOLERANCE;
use crate::{Plan, Problem};

use super::ffi::control;

/// Why OMPL gave no plan magbench can use.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OmplError {
    /// The C++ shim's own message (an exception OMPL raised).
    #[error("{0}")]
    Shim(String),
    /// One of OMPL's edges fails magbench's edge check when replayed.
    #[error("OMPL's edge {edge} fails magbench's edge check")]
    EdgeCheck {
        /// The edge's index.
        edge: usize,
    },
    /// Replaying one of OMPL's edges does not land on OMPL's state.
    #[error("replaying OMPL's edge {edge} ends {dev:e} BL from OMPL's state")]
    Drift {
        /// The edge's index.
        edge: usize,
        /// The largest distance of an agent from OMPL's state (BL).
        dev: f64,
    },
}

/// The plan of OMPL's `controls` (`dims` per edge: θ_B, g_x, g_y and, with 4, α) and `steps`,
/// one plan edge per propagation step, replayed from the problem's start. With `states`
/// (OMPL's waypoints, 2N per waypoint), every edge's end must match OMPL's.
pub fn from_ompl(
    problem: &Problem,
    dims: usize,
    controls: &[f64],
    steps: &[u32],
    states: Option<&[f64]>,
) -> Result<Plan, OmplError> {
    let n = problem.agents();
    let period = problem.control_period;
    let mut plan = Plan::at(&problem.start);
    plan.flow = problem.model.flow;
    let mut x = [Vec2::zeros(); MAX_AGENTS];
    x[..n].copy_from_slice(&problem.start);
    let mut next = x;
    for (edge, (u, &k)) in controls.chunks_exact(dims).zip(steps).enumerate() {
        let u = control(u);
        for _ in 0..k {
            if !propagate_valid(problem, &x[..n], &u, period, &mut next[..n]) {
                return Err(OmplError::EdgeCheck { edge });
            }
            plan.push(u, period, next[..n].to_vec());
            x = next;
        }
        if let Some(states) = states {
            let theirs = &states[2 * n * (edge + 1)..2 * n * (edge + 2)];
            let dev = x[..n]
                .iter()
                .zip(theirs.chunks_exact(2))
                .map(|(p, q)| (p - Vec2::new(q[0], q[1])).norm())
                .fold(0.0, f64::max);
            if dev.is_nan() || dev > REPLAY_TOLERANCE {
                return Err(OmplError::Drift { edge, dev });
            }
        }
    }
    Ok(plan)
}

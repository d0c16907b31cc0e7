//! The one independent plan validator.
//!
//! It trusts nothing a planner stored: it replays the plan's controls from the problem's start
//! through env's planning model (`ValidityChecker::motion_valid`, env's own code path for the
//! continuous collision and proximity check), compares every replayed waypoint with the stored
//! one, checks the controls against the coil (and the elevation against the coil's range, the
//! setup's `alpha_max`, the plan's own `alpha_max`, and 0 when the medium does not carry the
//! out-of-plane force) and the durations against the control period, and
//! confirms that the replay ends in the goal region.
//!
//! The replay uses the flow the plan records (`pair-adaptive`, `pair-exact` or `rk4`), with
//! the problem's physics and coil.
//!
//! Replay agrees with the stored states bit for bit when the plan came from this model: the
//! pair dynamics are so sensitive that a plan made with any other arithmetic (integrator, step,
//! force formula) fails here even if it was valid there.

use magbench_env::{Control, PlanningModel, Vec2};

use crate::{Plan, Problem};

/// Largest allowed distance (BL, any agent) between a replayed and a stored waypoint.
pub const REPLAY_TOLERANCE: f64 = 1e-9;

/// Why a plan is not valid for a problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// The arrays do not fit together (lengths, agent counts).
    #[error("malformed plan: {0}")]
    Malformed(String),
    /// The first state is not the problem's start.
    #[error("the plan starts {deviation:e} BL from the problem's start")]
    WrongStart {
        /// Largest agent distance (BL).
        deviation: f64,
    },
    /// The start collides or violates the proximity range.
    #[error("the start state is invalid (collision or proximity range)")]
    InvalidStart,
    /// A control is not finite, exceeds the coil's limits or tilts the field beyond the
    /// problem's largest elevation.
    #[error("edge {edge}: control {control} {reason}")]
    BadControl {
        /// Edge index.
        edge: usize,
        /// The control, printed.
        control: String,
        /// Which bound it breaks.
        reason: String,
    },
    /// A duration is not a positive whole multiple of the control period.
    #[error(
        "edge {edge}: duration {duration} s is not a positive whole multiple of the control period {period} s"
    )]
    BadDuration {
        /// Edge index.
        edge: usize,
        /// The duration (s).
        duration: f64,
        /// The control period (s).
        period: f64,
    },
    /// The motion collides or leaves the proximity range somewhere along the edge.
    #[error("edge {edge}: the motion collides or leaves the proximity range")]
    InvalidMotion {
        /// Edge index.
        edge: usize,
    },
    /// Replay does not reproduce the stored state.
    #[error("edge {edge}: replay ends {deviation:e} BL from the stored state")]
    ReplayMismatch {
        /// Edge index.
        edge: usize,
        /// Largest agent distance (BL).
        deviation: f64,
    },
    /// The replay does not end in the goal region.
    #[error("the plan ends {distance} BL from the goal (tolerance {tolerance} BL)")]
    NotInGoal {
        /// Largest agent distance from its goal centre (BL).
        distance: f64,
        /// The goal tolerance (BL).
        tolerance: f64,
    },
}

/// Why `u` is not a command a plan may hold under `model` with elevations up to `alpha_max`
/// (rad), or `None` when it is.
fn control_fault(model: &PlanningModel, u: &Control, alpha_max: f64) -> Option<String> {
    let deg = |a: f64| a.to_degrees();
    if !u.is_finite() {
        Some("is not finite".into())
    } else if model.coil.clamp(u).1 {
        Some(format!(
            "is outside the coil's limits (gradients within ±{} T/m, elevation within ±{}°)",
            model.coil.gradient_limit(),
            deg(model.coil.alpha_max())
        ))
    } else if u.alpha.abs() > alpha_max && !model.carries_fz {
        Some(format!(
            "tilts the field to α = {}°, but the medium does not carry the out-of-plane force",
            deg(u.alpha.abs())
        ))
    } else if u.alpha.abs() > alpha_max {
        Some(format!(
            "tilts the field to α = {}°, beyond the largest elevation {}° (the setup's alpha_max, and the plan's own)",
            deg(u.alpha.abs()),
            deg(alpha_max)
        ))
    } else {
        None
    }
}

/// Largest agent distance between two states; NaN if any coordinate is NaN.
fn deviation(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, |m, d| if d.is_nan() || d > m { d } else { m })
}

/// True unless `dev` is a number within the replay tolerance.
fn too_far(dev: f64) -> bool {
    dev.is_nan() || dev > REPLAY_TOLERANCE
}

/// Checks everything but the goal: shape, start, controls, durations, replay and the
/// continuous collision and proximity check along every edge. Returns the replayed end state.
pub fn validate_path(problem: &Problem, plan: &Plan) -> Result<Vec<Vec2>, PlanError> {
    let n = problem.agents();
    if plan.states.len() != plan.controls.len() + 1 || plan.controls.len() != plan.durations.len() {
        return Err(PlanError::Malformed(format!(
            "{} states, {} controls and {} durations (need states = controls + 1 = durations + 1)",
            plan.states.len(),
            plan.controls.len(),
            plan.durations.len()
        )));
    }
    if let Some(i) = plan.states.iter().position(|s| s.len() != n) {
        return Err(PlanError::Malformed(format!(
            "state {i} has {} agents, the problem {n}",
            plan.states[i].len()
        )));
    }
    let dev = deviation(&plan.states[0], &problem.start);
    if too_far(dev) {
        return Err(PlanError::WrongStart { deviation: dev });
    }
    if !problem.checker.is_valid(&problem.start) {
        return Err(PlanError::InvalidStart);
    }
    let period = problem.control_period;
    let model = problem.model.with_flow(plan.flow);
    let mut state = problem.start.clone();
    let mut next = state.clone();
    // in bulk nothing holds the agents in the plane under a tilted field: α must be 0 there
    let alpha_max = match (model.carries_fz, plan.alpha_max) {
        (false, _) => 0.0,
        (true, Some(a)) => a.min(problem.alpha_max),
        (true, None) => problem.alpha_max,
    };
    for (edge, (u, &d)) in plan.controls.iter().zip(&plan.durations).enumerate() {
        if let Some(reason) = control_fault(&model, u, alpha_max) {
            return Err(PlanError::BadControl {
                edge,
                control: format!("{u:?}"),
                reason,
            });
        }
        let k = d / period;
        if !(d.is_finite() && k.round() >= 1.0 && (k - k.round()).abs() <= 1e-9 * k.round()) {
            return Err(PlanError::BadDuration {
                edge,
                duration: d,
                period,
            });
        }
        if !problem
            .checker
            .motion_valid(&model, &state, u, d, &mut next)
        {
            return Err(PlanError::InvalidMotion { edge });
        }
        let dev = deviation(&next, &plan.states[edge + 1]);
        if too_far(dev) {
            return Err(PlanError::ReplayMismatch {
                edge,
                deviation: dev,
            });
        }
        std::mem::swap(&mut state, &mut next);
    }
    Ok(state)
}

/// Validates a plan completely: [`validate_path`], and the replay ends in the goal region.
pub fn validate_plan(problem: &Problem, plan: &Plan) -> Result<(), PlanError> {
    let end = validate_path(problem, plan)?;
    let distance = problem.goal.distance(&end);
    if !problem.goal.contains(&end) {
        return Err(PlanError::NotInGoal {
            distance,
            tolerance: problem.goal.tolerance,
        });
    }
    Ok(())
}

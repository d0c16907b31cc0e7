//! The planning setup: what every plan of a run is made under — the objective, the metric, the
//! limits, the control period, the flow and the largest field elevation — and the one rule for whether a planner's result
//! can be used.
//!
//! A run makes one [`PlanningSetup`] and hands it to every planning call: the first plan, each
//! new leg's plan and each replan in the tracking loop. So `rrt-star{objective=duration}`
//! plans every leg under duration, and a plan is in whole frames of the rig that runs it.

use magbench_env::coil::DEFAULT_ALPHA_MAX_DEG;
use magbench_env::model::Flow;
use magbench_env::{InputError, PlanningModel, Scenario, Vec2};

use crate::metric::Metric;
use crate::objective::{OBJECTIVES, objective_by_name};
use crate::validate::{PlanError, validate_path, validate_plan};
use crate::{Limits, PlannerResult, Problem};

/// The control period when no rig says otherwise (s): one frame of the presets' 60 fps camera.
pub const DEFAULT_CONTROL_PERIOD: f64 = 1.0 / 60.0;

/// Keys of a planner variant (`rrt-star{objective=duration}` in an experiment file) that set
/// the planning setup rather than the planner.
pub const SETUP_KEYS: [&str; 4] = ["objective", "metric", "flow", "alpha_max"];

/// What every plan of a run is made under.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanningSetup {
    /// The cost to minimise: `path-length` (default), `duration` or `control-effort`.
    pub objective: &'static str,
    /// The distance of nearest-neighbour queries and EXTEND.
    pub metric: Metric,
    /// When each planning call stops.
    pub limits: Limits,
    /// Every edge lasts a whole number of these (s): the frame period of the rig (or preset)
    /// that will run the plan.
    pub control_period: f64,
    /// How the planning model solves motions (`pair-exact` or `rk4`).
    pub flow: Flow,
    /// The largest field elevation |α| a plan may command (degrees, in [0, 90]); used when the
    /// planner's `planar` setting lets the field leave the plane. The tri-axial coil's whole
    /// range ([`DEFAULT_ALPHA_MAX_DEG`]) unless set.
    pub alpha_max_deg: f64,
}

impl Default for PlanningSetup {
    fn default() -> Self {
        PlanningSetup {
            objective: OBJECTIVES[0],
            metric: Metric::Positions,
            limits: Limits::default(),
            control_period: DEFAULT_CONTROL_PERIOD,
            flow: Flow::default(),
            alpha_max_deg: DEFAULT_ALPHA_MAX_DEG,
        }
    }
}

impl PlanningSetup {
    /// The problem of leg `leg` of `scenario` from `start` (the scenario's start if `None`),
    /// with the planner's random stream seeded by `seed`.
    pub fn problem(
        &self,
        scenario: &Scenario,
        leg: usize,
        start: Option<&[Vec2]>,
        seed: u64,
    ) -> Problem {
        let model = PlanningModel::new(&scenario.physics).with_flow(self.flow);
        Problem {
            scenario: scenario.name.clone(),
            world: scenario.world_for_leg(leg),
            start: start
                .map(|s| s.to_vec())
                .unwrap_or_else(|| scenario.start.clone()),
            goal: scenario.legs[leg].goal.clone(),
            objective: objective_by_name(self.objective, &model).expect("a known objective"),
            model,
            checker: scenario.checker_for_leg(leg),
            control_period: self.control_period,
            limits: self.limits,
            seed,
            metric: self.metric,
            alpha_max: self.alpha_max_deg.to_radians(),
        }
    }

    /// Sets one of the [`SETUP_KEYS`] from its text; an error names `source`, the key and the
    /// reason.
    pub fn set(&mut self, source: &str, key: &str, value: &str) -> Result<(), InputError> {
        let bad = |reason: String| InputError::new(source, key, reason);
        match key {
            "objective" => {
                self.objective = OBJECTIVES
                    .into_iter()
                    .find(|o| *o == value)
                    .ok_or_else(|| {
                        bad(format!(
                            "unknown objective {value:?} (known: {})",
                            OBJECTIVES.join(", ")
                        ))
                    })?;
            }
            "metric" => self.metric = Metric::parse(value).map_err(bad)?,
            "flow" => {
                self.flow = Flow::from_name(value).ok_or_else(|| {
                    bad(format!("unknown flow {value:?} (known: pair-exact, rk4)"))
                })?;
            }
            "alpha_max" => {
                self.alpha_max_deg = value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|a| (0.0..=90.0).contains(a))
                    .ok_or_else(|| {
                        bad(format!(
                            "{value:?} is not an elevation in degrees in [0, 90]"
                        ))
                    })?;
            }
            _ => {
                return Err(bad(format!(
                    "not a planning-setup key (known: {})",
                    SETUP_KEYS.join(", ")
                )));
            }
        }
        Ok(())
    }

    /// The same setup with control period `period` (s), the frame period of the rig that
    /// will run the plans.
    pub fn in_frames_of(self, period: f64) -> Self {
        PlanningSetup {
            control_period: period,
            ..self
        }
    }
}

/// Why a planner's result cannot be followed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unusable {
    /// The plan fails the independent validator: a planner bug, never a plan to send to a rig.
    #[error("the planner's plan is invalid: {0}")]
    Invalid(PlanError),
    /// The plan has no motion (no edge): nothing to follow.
    #[error("the planner found no motion")]
    NoMotion,
}

/// The one rule for a planner's result: the plan passes the independent validator (and a
/// solved one ends in the goal region), and it has at least one edge to follow. Planning-only
/// runs record a result without motion (a timeout); a tracking run cannot follow one.
pub fn check_result(problem: &Problem, result: &PlannerResult) -> Result<(), Unusable> {
    let verdict = if result.solved {
        validate_plan(problem, &result.plan)
    } else {
        validate_path(problem, &result.plan).map(|_| ())
    };
    verdict.map_err(Unusable::Invalid)?;
    if result.plan.edges() == 0 {
        return Err(Unusable::NoMotion);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_is_set_by_name_and_bad_ones_name_the_key() {
        let s = Scenario::load("cargo-delivery").unwrap();
        let mut setup = PlanningSetup::default();
        setup.set("x", "objective", "duration").unwrap();
        setup.set("x", "metric", "centroid-shape:1:2").unwrap();
        setup.set("x", "flow", "rk4").unwrap();
        setup.set("x", "alpha_max", "40").unwrap();
        let setup = setup.in_frames_of(1.0 / 30.0);
        for leg in 0..s.legs.len() {
            let p = setup.problem(&s, leg, None, 7);
            assert_eq!(p.objective.name(), "duration");
            assert_eq!(
                p.metric,
                Metric::CentroidShape {
                    centroid: 1.0,
                    shape: 2.0
                }
            );
            assert_eq!(p.model.flow, Flow::Rk4);
            assert_eq!(p.control_period, 1.0 / 30.0);
            assert_eq!(p.seed, 7);
            assert_eq!(p.alpha_max, 40f64.to_radians());
        }
        for (key, value) in [
            ("objective", "energy"),
            ("metric", "l1"),
            ("flow", "euler"),
            ("alpha_max", "91"),
            ("alpha_max", "-1"),
            ("range", "2"),
        ] {
            let e = PlanningSetup::default()
                .set("exp.toml", key, value)
                .unwrap_err();
            assert_eq!((e.file.as_str(), e.field.as_str()), ("exp.toml", key));
        }
        let d = PlanningSetup::default();
        let p = d.problem(&s, 0, None, 0);
        assert_eq!(
            (p.objective.name(), p.model.flow, p.control_period),
            ("path-length", Flow::PairExact, DEFAULT_CONTROL_PERIOD)
        );
    }
}

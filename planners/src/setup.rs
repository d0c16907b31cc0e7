//! The planning setup: what every plan of a run is made under — the objective, the metric, the
//! limits, the control period, the flow, the largest field elevation and the plant it is for
//! (the medium and the coil's elevation range) — and the one rule for whether a planner's
//! result can be used.
//!
//! The plant part comes from the rig that will run the plans ([`PlanningSetup::on_plant`]): a
//! preset's `[medium]` and `[coil]`, or a rig file's `coil.alpha_max_deg`. A scenario's own
//! `[medium]` wins over the preset's. Without a rig (`magbench plan`) the setup assumes the
//! default preset's plant: bulk liquid (the `realistic` preset of `magbench track`) and a
//! tri-axial coil.
//!
//! A run makes one [`PlanningSetup`] and hands it to every planning call: the first plan, each
//! new leg's plan and each replan in the tracking loop. So `rrt-star{objective=duration}`
//! plans every leg under duration, and a plan is in whole frames of the rig that runs it.

use std::sync::Arc;

use magbench_env::coil::{
    COIL_ALPHA_MAX_DEG, DEFAULT_ALPHA_MAX_DEG, Planar, TriaxialMaxwell, elevation_params,
};
use magbench_env::model::Flow;
use magbench_env::params::ParamInfo;
use magbench_env::plant::Medium;
use magbench_env::{InputError, PlanningModel, Scenario, Vec2};

use crate::distance::Distance;
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
    pub metric: Distance,
    /// When each planning call stops.
    pub limits: Limits,
    /// Every edge lasts a whole number of these (s): the frame period of the rig (or preset)
    /// that will run the plan.
    pub control_period: f64,
    /// How the planning model solves motions (`pair-adaptive`, `pair-exact` or `rk4`).
    pub flow: Flow,
    /// The largest field elevation |α| a plan may command (degrees, in [0, 90]); used when the
    /// planner's `planar` setting lets the field leave the plane. The tri-axial coil's whole
    /// range ([`DEFAULT_ALPHA_MAX_DEG`]) unless set.
    pub alpha_max_deg: f64,
    /// The medium of the plant when the scenario names none (the preset's): whether it
    /// carries the out-of-plane force decides `planar = auto` for three or more agents.
    pub medium: Medium,
    /// The coil's elevation range (degrees): a rig file's or a preset's `alpha_max_deg`.
    pub coil_alpha_max_deg: f64,
}

impl Default for PlanningSetup {
    fn default() -> Self {
        PlanningSetup {
            objective: OBJECTIVES[0],
            metric: Distance::Positions,
            limits: Limits::default(),
            control_period: DEFAULT_CONTROL_PERIOD,
            flow: Flow::default(),
            alpha_max_deg: DEFAULT_ALPHA_MAX_DEG,
            medium: Medium::Bulk,
            coil_alpha_max_deg: COIL_ALPHA_MAX_DEG,
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
        let model = self.model(scenario).with_flow(self.flow);
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

    /// The planning model of `scenario` on this setup's plant (default flow): its coil's
    /// elevation range, and whether the effective medium — the scenario's, else the
    /// setup's — carries the out-of-plane force. Trackers predict with it too.
    pub fn model(&self, scenario: &Scenario) -> PlanningModel {
        let p = &scenario.physics;
        let coil =
            TriaxialMaxwell::new(p.gradient_limit()).with_alpha_max_deg(self.coil_alpha_max_deg);
        PlanningModel::with_coil(p, Arc::new(coil)).in_medium(p, self.medium_of(scenario))
    }

    /// The medium the agents of `scenario` are in: the scenario's `[medium]`, else the
    /// setup's (the preset's).
    pub fn medium_of<'a>(&'a self, scenario: &'a Scenario) -> &'a Medium {
        scenario.medium.as_ref().unwrap_or(&self.medium)
    }

    /// The same setup for a plant in `medium` (a preset's; a scenario's own wins) with a coil
    /// that tilts the field up to `coil_alpha_max_deg`.
    pub fn on_plant(self, medium: &Medium, coil_alpha_max_deg: f64) -> Self {
        PlanningSetup {
            medium: medium.clone(),
            coil_alpha_max_deg,
            ..self
        }
    }

    /// Whether `planar` (a planner's or tracker's) fits `scenario` on this plant: `false`
    /// needs a medium that carries the out-of-plane force.
    pub fn check_planar(&self, scenario: &Scenario, planar: Planar) -> Result<(), ElevationError> {
        let medium = self.medium_of(scenario);
        planar
            .check_medium(medium.carries_fz())
            .map_err(|why| ElevationError::NoOutOfPlaneForce {
                why,
                scenario: scenario.name.clone(),
                medium: medium.kind(),
                own_medium: scenario.medium.is_some(),
            })
    }

    /// Whether an elevation bound `alpha_max_deg` (this setup's or a tracker's) is within the
    /// coil's range.
    pub fn check_alpha_max(&self, alpha_max_deg: f64) -> Result<(), ElevationError> {
        if alpha_max_deg > self.coil_alpha_max_deg {
            return Err(ElevationError::BeyondCoil {
                alpha_max_deg,
                coil_alpha_max_deg: self.coil_alpha_max_deg,
            });
        }
        Ok(())
    }

    /// Whether a planner's or tracker's elevation settings (among its `params`) fit `scenario`
    /// on this plant: `planar = false` needs a medium that carries the out-of-plane force and,
    /// where the elevation is free, its `alpha_max` — or this setup's, for a planner, which has
    /// none of its own — may not exceed the coil's range.
    pub fn check_settings(
        &self,
        scenario: &Scenario,
        params: &[ParamInfo],
    ) -> Result<(), ElevationRefused> {
        let (planar, alpha_max) = elevation_params(params);
        let Some(planar) = planar else {
            return Ok(());
        };
        self.check_planar(scenario, planar)
            .map_err(ElevationRefused::Planar)?;
        if !self.elevation(scenario, planar).0 {
            return Ok(());
        }
        match alpha_max {
            Some(a) => self.check_alpha_max(a).map_err(ElevationRefused::AlphaMax),
            None => self
                .check_alpha_max(self.alpha_max_deg)
                .map_err(ElevationRefused::SetupAlphaMax),
        }
    }

    /// Whether a team of `scenario` under `planar` may tilt the field on this plant, and why
    /// (a few words).
    pub fn elevation(&self, scenario: &Scenario, planar: Planar) -> (bool, &'static str) {
        let fz = self.medium_of(scenario).carries_fz();
        let n = scenario.agents();
        (!planar.is_planar(n, fz), planar.reason(n, fz))
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
            "metric" => self.metric = Distance::parse(value).map_err(|e| bad(e.to_string()))?,
            "flow" => {
                self.flow = Flow::from_name(value).ok_or_else(|| {
                    let known: Vec<_> = Flow::ALL.iter().map(|f| f.name()).collect();
                    bad(format!(
                        "unknown flow {value:?} (known: {})",
                        known.join(", ")
                    ))
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

/// Why an elevation setting does not fit a scenario on a plant.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElevationError {
    /// `planar = false` in a medium that carries no out-of-plane force.
    #[error(
        "{why}; scenario {scenario} is in {medium}{}",
        if *own_medium { " (its [medium])" } else { " (the plant's medium; the scenario names none)" }
    )]
    NoOutOfPlaneForce {
        /// Why the setting needs the force.
        why: &'static str,
        /// The scenario's name.
        scenario: String,
        /// The medium's kind (`bulk`, `interface`).
        medium: &'static str,
        /// The medium is the scenario's own (else the plant's).
        own_medium: bool,
    },
    /// An elevation bound beyond the coil's range.
    #[error(
        "{alpha_max_deg}° exceeds the coil's elevation range alpha_max_deg = {coil_alpha_max_deg}°"
    )]
    BeyondCoil {
        /// The bound asked for (degrees).
        alpha_max_deg: f64,
        /// The coil's range (degrees).
        coil_alpha_max_deg: f64,
    },
}

/// Which elevation setting [`PlanningSetup::check_settings`] refuses, and why.
#[derive(Debug, Clone, PartialEq)]
pub enum ElevationRefused {
    /// The planner's or tracker's `planar`.
    Planar(ElevationError),
    /// The tracker's own `alpha_max`.
    AlphaMax(ElevationError),
    /// The setup's `alpha_max` (a planner's elevation bound).
    SetupAlphaMax(ElevationError),
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
pub fn validate_result(problem: &Problem, result: &PlannerResult) -> Result<(), Unusable> {
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
                Distance::CentroidShape {
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
            ("path-length", Flow::PairAdaptive, DEFAULT_CONTROL_PERIOD)
        );
    }
}

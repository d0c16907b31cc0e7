//! The planning setup of the command line, shared by `plan`, `track` and `rig run`: the limits
//! (`--max-iters`, `--time-limit`), `--objective`, `--metric`, `--flow` and `--alpha-max`. The control period
//! is not an option of `track` and `rig run`: it is the frame period of their rig.

use clap::Args;
use magbench_env::Scenario;
use magbench_env::params::ParamInfo;
use magbench_planners::{ElevationRefused, Limits, PlanningSetup};

use super::number::count;
use crate::Error;
use crate::run::spec::{DEFAULT_TIME_LIMIT_S, ITERATIONS, time_limit};

/// The planning setup options.
#[derive(Debug, Clone, Args)]
pub struct SetupArgs {
    /// Planner limits.
    #[command(flatten)]
    pub limits: LimitArgs,
    /// Cost objective of every planning call: path-length (default), duration or
    /// control-effort.
    #[arg(long, default_value = "path-length")]
    pub objective: String,
    /// Distance metric: positions (default) or centroid-shape:W_CENTROID:W_SHAPE.
    #[arg(long, default_value = "positions")]
    pub metric: String,
    /// How the planning model solves motions: pair-adaptive (default; the exact flow for two
    /// agents under a planar field, adaptive Dormand–Prince 5(4) otherwise), pair-exact (the
    /// exact pair flow, fixed-step RK4 otherwise) or rk4 (fixed-step RK4 everywhere).
    #[arg(long, default_value = "pair-adaptive")]
    pub flow: String,
    /// Largest field elevation a plan may command (degrees, 0–90), used where the planner's
    /// `planar` setting frees the elevation (three or more agents at an interface by default),
    /// within the coil's range (the rig file's or preset's `alpha_max_deg`).
    #[arg(long, default_value = "45")]
    pub alpha_max: String,
}

impl SetupArgs {
    /// The planning setup (default control period; a rig sets its own); exit 2 on a bad value,
    /// naming the option.
    pub fn setup(&self) -> Result<PlanningSetup, Error> {
        let mut setup = PlanningSetup {
            limits: self.limits.limits()?,
            ..PlanningSetup::default()
        };
        for (key, value) in [
            ("objective", &self.objective),
            ("metric", &self.metric),
            ("flow", &self.flow),
            ("alpha_max", &self.alpha_max),
        ] {
            setup
                .set("<command line>", key, value)
                .map_err(|e| Error::arg(format!("--{}", key.replace('_', "-")), e.reason))?;
        }
        Ok(setup)
    }
}

/// Refuses, before any planning, elevation settings that `scenario` on the setup's plant cannot
/// hold, for each `(field prefix, parameters)` of `sets` (e.g. `("param", planner.params())`):
/// `planar = false` where the medium does not carry the out-of-plane force, and — where the
/// elevation is free — an `alpha_max` above the coil's range (the set's own `alpha_max`, or
/// the setup's `--alpha-max` for a set without one; `coil` says where the range comes from).
/// Exit 2 naming the option, the field and the reason.
pub fn check_elevation(
    setup: &PlanningSetup,
    scenario: &Scenario,
    sets: &[(&str, Vec<ParamInfo>)],
    coil: &str,
) -> Result<(), Error> {
    for (prefix, params) in sets {
        setup
            .check_settings(scenario, params)
            .map_err(|e| match e {
                ElevationRefused::Planar(r) => {
                    Error::arg(format!("{prefix}.planar"), r.to_string())
                }
                ElevationRefused::AlphaMax(r) => Error::arg(
                    format!("{prefix}.alpha_max"),
                    format!("{r} ({coil}); or set planar=true"),
                ),
                ElevationRefused::SetupAlphaMax(r) => {
                    Error::arg("--alpha-max", format!("{r} ({coil}); or set planar=true"))
                }
            })?;
    }
    Ok(())
}

/// `--max-iters` and `--time-limit`.
#[derive(Debug, Clone, Args)]
pub struct LimitArgs {
    /// Planner iteration limit of every planning call (200000 when neither limit is given;
    /// none when only --time-limit is).
    #[arg(long)]
    pub max_iters: Option<u64>,
    /// Planner wall-time limit of every planning call (s; default 60, at most a week). A run
    /// that reaches it depends on the machine; one that stops at --max-iters is reproducible.
    #[arg(long)]
    pub time_limit: Option<f64>,
}

impl LimitArgs {
    /// The limits: `--max-iters` (200 000 iterations when neither option is given, no
    /// iteration limit when only `--time-limit` is) and `--time-limit` (or
    /// [`DEFAULT_TIME_LIMIT_S`]); exit 2 on a bad value.
    pub fn limits(&self) -> Result<Limits, Error> {
        if let Some(n) = self.max_iters {
            count("--max-iters", &ITERATIONS, n)?;
        }
        let t = self.time_limit.unwrap_or(DEFAULT_TIME_LIMIT_S);
        let time = time_limit(t).map_err(|r| Error::rejected("--time-limit", r))?;
        let max_iterations = match (self.max_iters, self.time_limit) {
            (None, None) => Limits::default().max_iterations,
            (n, _) => n,
        };
        Ok(Limits {
            max_iterations,
            time_limit: Some(time),
        })
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn huge_zero_and_negative_limits_are_refused() {
        for t in [1e20, f64::INFINITY, f64::NAN, 0.0, -1.0, 1e300] {
            let a = LimitArgs {
                max_iters: None,
                time_limit: Some(t),
            };
            let e = a.limits().unwrap_err();
            assert_eq!(e.exit_code(), 2);
            assert!(e.to_string().contains("--time-limit"), "{e}");
        }
        let a = LimitArgs {
            max_iters: Some(0),
            time_limit: None,
        };
        assert!(a.limits().unwrap_err().to_string().contains("--max-iters"));
        let a = LimitArgs {
            max_iters: Some(u64::MAX),
            time_limit: None,
        };
        let e = a.limits().unwrap_err().to_string();
        assert!(
            e.contains("--max-iters: must be in [1, 2097152] iterations"),
            "{e}"
        );
        let a = LimitArgs {
            max_iters: Some(5),
            time_limit: Some(2.5),
        };
        let l = a.limits().unwrap();
        assert_eq!(l.max_iterations, Some(5));
        assert_eq!(l.time_limit, Some(Duration::from_millis(2500)));
    }

    #[test]
    fn without_limits_a_planning_call_gets_the_default_time_limit() {
        use clap::Parser;
        for cmd in [
            vec!["magbench", "plan", "open-field", "--planner", "sst"],
            vec!["magbench", "track", "open-field", "--tracker", "obc"],
            vec![
                "magbench",
                "plan",
                "open-field",
                "--planner",
                "sst",
                "--max-iters",
                "9",
            ],
        ] {
            let setup = match crate::cli::Args::try_parse_from(&cmd).unwrap().command {
                crate::cli::Command::Plan(a) => a.setup.setup().unwrap(),
                crate::cli::Command::Track(a) => a.setup.setup().unwrap(),
                _ => unreachable!(),
            };
            assert_eq!(
                setup.limits.time_limit,
                Some(Duration::from_secs(60)),
                "{cmd:?}"
            );
            assert!(setup.limits.max_iterations.is_some(), "{cmd:?}");
        }
    }

    #[test]
    fn setup_options_name_themselves_on_bad_values() {
        let args = |objective: &str, metric: &str, flow: &str| SetupArgs {
            limits: LimitArgs {
                max_iters: Some(7),
                time_limit: None,
            },
            objective: objective.into(),
            metric: metric.into(),
            flow: flow.into(),
            alpha_max: "45".into(),
        };
        let s = args("duration", "centroid-shape:1:2", "rk4")
            .setup()
            .unwrap();
        assert_eq!(
            (s.objective, s.flow, s.limits.max_iterations),
            ("duration", magbench_env::model::Flow::Rk4, Some(7))
        );
        for (a, option) in [
            (args("fun", "positions", "pair-exact"), "--objective"),
            (args("duration", "l1", "pair-exact"), "--metric"),
            (args("duration", "positions", "euler"), "--flow"),
        ] {
            let e = a.setup().unwrap_err();
            assert_eq!(e.exit_code(), 2);
            assert!(
                e.to_string()
                    .contains(&format!("<command line>: {option}: ")),
                "{e}"
            );
        }
    }
}

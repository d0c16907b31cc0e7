//! Trackers by name, with `key=value` parameters (from the command line or experiment files).
//!
//! Every tracker also takes the loop's parameters ([`LOOP_PARAMS`]: replanning, time limit,
//! goal hold, estimator blend). Unknown trackers, unknown parameters and bad values are
//! [`InputError`]s naming the source, the parameter and the reason.

use magbench_env::InputError;

use crate::lookahead::{Lookahead, LookaheadParams};
use crate::obc::{Obc, ObcParams};
use crate::open_loop::OpenLoop;
use crate::optimizer::ObcWeights;
use crate::run::LoopOptions;
use crate::tracker::Tracker;

/// One numeric parameter: name, default, allowed range and meaning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// The key.
    pub name: &'static str,
    /// Default value.
    pub default: f64,
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
    /// Whole numbers only.
    pub integer: bool,
    /// What it means, with its unit.
    pub doc: &'static str,
}

const fn real(
    name: &'static str,
    default: f64,
    min: f64,
    max: f64,
    doc: &'static str,
) -> ParamSpec {
    ParamSpec {
        name,
        default,
        min,
        max,
        integer: false,
        doc,
    }
}

const fn int(name: &'static str, default: f64, min: f64, max: f64, doc: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        default,
        min,
        max,
        integer: true,
        doc,
    }
}

/// Parameters of the loop, accepted by every tracker.
pub const LOOP_PARAMS: &[ParamSpec] = &[
    real(
        "replan_error",
        1.0,
        0.0,
        1e3,
        "tracking error (BL) that triggers a replan when it persists",
    ),
    real(
        "replan_after",
        2.0,
        0.0,
        1e6,
        "seconds the error must persist before a replan; 0 = never",
    ),
    int(
        "max_replans",
        5.0,
        0.0,
        1e4,
        "most error-triggered replans per run",
    ),
    real(
        "time_factor",
        3.0,
        1.0,
        1e3,
        "time limit per plan: time_factor × plan duration + time_slack",
    ),
    real("time_slack", 20.0, 0.0, 1e6, "see time_factor (s)"),
    real(
        "hold",
        0.5,
        0.0,
        1e3,
        "seconds the team must stay in a goal region to complete a leg",
    ),
    real(
        "goal_margin",
        0.05,
        0.0,
        10.0,
        "the estimate must be this far inside the goal tolerance (BL)",
    ),
    real(
        "obs_weight",
        1.0,
        0.001,
        1.0,
        "how far a measurement moves the estimator's prior (1 = all the way)",
    ),
];

/// Parameters of the OBC optimizer, shared by `obc` and `lookahead`.
const OPTIMIZER_PARAMS: &[ParamSpec] = &[
    real("w_com", 1.0, 0.0, 1e9, "weight of the centre-of-mass error"),
    real(
        "w_rel",
        1.0,
        0.0,
        1e9,
        "weight of the formation (relative position) error",
    ),
    real(
        "w_smooth",
        1e-5,
        0.0,
        1e9,
        "weight of the field-angle change (per rad²)",
    ),
    real(
        "w_prox",
        1e3,
        0.0,
        1e12,
        "weight of a predicted separation outside the safe band (per BL²)",
    ),
    real(
        "prox_margin",
        0.15,
        0.0,
        2.0,
        "safety margin inside the proximity range (BL)",
    ),
    real(
        "safety",
        2.0,
        0.0,
        100.0,
        "ticks over which a predicted separation change is extrapolated for the proximity check",
    ),
    real(
        "wall_margin",
        0.05,
        0.0,
        2.0,
        "clearance from walls below which a predicted agent is penalised (BL)",
    ),
    real(
        "w_wall",
        1.0,
        0.0,
        1e9,
        "weight of a predicted clearance below wall_margin (per BL²)",
    ),
    int(
        "grid",
        48.0,
        4.0,
        100_000.0,
        "field angles on the brute-force grid over [0, π)",
    ),
    int(
        "refine",
        12.0,
        0.0,
        100.0,
        "golden-section iterations of the local refinement",
    ),
    int(
        "horizon",
        1.0,
        1.0,
        120.0,
        "prediction horizon (control ticks)",
    ),
];

const OBC_PARAMS: &[ParamSpec] = &[
    real(
        "eps",
        0.15,
        0.0,
        1e3,
        "error (BL, RMS over agents) above which the proximity controller takes over",
    ),
    real(
        "window",
        1.0,
        0.0,
        1e4,
        "how far ahead the nearest reference sample is sought (s)",
    ),
    real(
        "back",
        1.0,
        0.0,
        1e4,
        "how far back the proximity controller seeks the nearest sample (s)",
    ),
    int(
        "feedforward",
        1.0,
        0.0,
        1.0,
        "1 = offer the plan's own control as a candidate, 0 = grid only",
    ),
    real(
        "catchup",
        2.0,
        0.0,
        100.0,
        "behind schedule, how many extra horizons ahead the target may be",
    ),
    real(
        "stall",
        0.25,
        0.0,
        1e3,
        "seconds without progress after which the progress moves on by itself",
    ),
];

const LOOKAHEAD_PARAMS: &[ParamSpec] = &[
    real(
        "gain",
        0.5,
        0.0,
        1.0,
        "gain L of eq. (6): weight of the direction back to the path",
    ),
    real(
        "lookahead",
        0.3,
        0.0,
        1e3,
        "lookahead distance along the path (BL)",
    ),
    real(
        "window",
        1.0,
        0.0,
        1e4,
        "how far ahead agents are projected onto their paths (s)",
    ),
    real(
        "stall",
        0.1,
        0.0,
        1e3,
        "seconds without progress after which the targets move on by themselves",
    ),
];

/// A tracker in the registry.
#[derive(Debug, Clone, Copy)]
pub struct TrackerInfo {
    /// Registry name.
    pub name: &'static str,
    /// One line on what it does.
    pub about: &'static str,
    own: &'static [&'static [ParamSpec]],
    /// Loop parameters whose default differs for this tracker.
    loop_defaults: &'static [(&'static str, f64)],
}

impl TrackerInfo {
    /// Every parameter it accepts, with this tracker's defaults.
    pub fn params(&self) -> Vec<ParamSpec> {
        let mut out: Vec<ParamSpec> = self.own.iter().flat_map(|g| g.iter().copied()).collect();
        for p in LOOP_PARAMS {
            let mut p = *p;
            if let Some((_, d)) = self.loop_defaults.iter().find(|(n, _)| *n == p.name) {
                p.default = *d;
            }
            out.push(p);
        }
        out
    }
}

/// The registry.
pub const TRACKERS: &[TrackerInfo] = &[
    TrackerInfo {
        name: "open-loop",
        about: "replays the plan's controls on their schedule, ignoring observations",
        own: &[],
        loop_defaults: &[("replan_after", 0.0)],
    },
    TrackerInfo {
        name: "obc",
        about: "optimization-based controller: follows the path forward, proximity control beyond eps",
        own: &[OBC_PARAMS, OPTIMIZER_PARAMS],
        loop_defaults: &[],
    },
    TrackerInfo {
        name: "lookahead",
        about: "pure pursuit (eq. 6) with per-agent moving targets, turned into commands by the OBC optimizer",
        own: &[LOOKAHEAD_PARAMS, OPTIMIZER_PARAMS],
        loop_defaults: &[],
    },
];

/// Names of the registered trackers.
pub fn tracker_names() -> Vec<&'static str> {
    TRACKERS.iter().map(|t| t.name).collect()
}

/// The registry entry of `name`.
pub fn tracker_info(name: &str) -> Option<&'static TrackerInfo> {
    TRACKERS.iter().find(|t| t.name == name)
}

/// Splits `key=value`.
pub fn parse_param(kv: &str, source: &str) -> Result<(String, String), InputError> {
    match kv.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(InputError::new(
            source,
            "param",
            format!("expected key=value, got `{kv}`"),
        )),
    }
}

/// A tracker chosen by name, with every parameter resolved (given or default) and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackerSpec {
    /// Registry name.
    pub name: String,
    /// Every parameter's value, in registry order.
    pub values: Vec<(&'static str, f64)>,
}

impl TrackerSpec {
    /// Checks `name` and `params` (`source` names the file or `<command line>` in errors).
    pub fn parse(
        name: &str,
        params: &[(String, String)],
        source: &str,
    ) -> Result<Self, InputError> {
        let info = tracker_info(name).ok_or_else(|| {
            InputError::new(
                source,
                "tracker",
                format!(
                    "unknown tracker `{name}` (known: {})",
                    tracker_names().join(", ")
                ),
            )
        })?;
        let specs = info.params();
        let mut values: Vec<(&'static str, f64)> =
            specs.iter().map(|p| (p.name, p.default)).collect();
        for (k, v) in params {
            let field = format!("params.{k}");
            let Some(idx) = specs.iter().position(|p| p.name == k) else {
                let known: Vec<&str> = specs.iter().map(|p| p.name).collect();
                return Err(InputError::new(
                    source,
                    field,
                    format!(
                        "tracker `{name}` has no parameter `{k}` (known: {})",
                        known.join(", ")
                    ),
                ));
            };
            let p = &specs[idx];
            let x: f64 = v
                .parse()
                .map_err(|_| InputError::new(source, &field, format!("`{v}` is not a number")))?;
            if !x.is_finite() || x < p.min || x > p.max {
                return Err(InputError::new(
                    source,
                    &field,
                    format!("must be in [{}, {}], got {v}", p.min, p.max),
                ));
            }
            if p.integer && x.fract() != 0.0 {
                return Err(InputError::new(
                    source,
                    &field,
                    format!("must be a whole number, got {v}"),
                ));
            }
            values[idx].1 = x;
        }
        Ok(TrackerSpec {
            name: name.to_string(),
            values,
        })
    }

    /// The value of parameter `key`.
    pub fn get(&self, key: &str) -> f64 {
        self.values
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| *v)
            .unwrap_or_else(|| panic!("no parameter {key}"))
    }

    /// The parameters that differ from their defaults, as `key=value` (for labels).
    pub fn label(&self) -> String {
        let info = tracker_info(&self.name).expect("a checked spec");
        let changed: Vec<String> = info
            .params()
            .iter()
            .zip(&self.values)
            .filter(|(p, (_, v))| p.default != *v)
            .map(|(_, (k, v))| format!("{k}={v}"))
            .collect();
        if changed.is_empty() {
            self.name.clone()
        } else {
            format!("{}{{{}}}", self.name, changed.join(","))
        }
    }

    fn weights(&self) -> ObcWeights {
        ObcWeights {
            w_com: self.get("w_com"),
            w_rel: self.get("w_rel"),
            w_smooth: self.get("w_smooth"),
            w_prox: self.get("w_prox"),
            prox_margin: self.get("prox_margin"),
            safety: self.get("safety"),
            wall_margin: self.get("wall_margin"),
            w_wall: self.get("w_wall"),
            grid: self.get("grid") as usize,
            refine: self.get("refine") as usize,
            horizon: self.get("horizon") as usize,
        }
    }

    /// A fresh tracker.
    pub fn build(&self) -> Box<dyn Tracker> {
        match self.name.as_str() {
            "open-loop" => Box::new(OpenLoop::new()),
            "obc" => Box::new(Obc::new(ObcParams {
                eps: self.get("eps"),
                window: self.get("window"),
                back: self.get("back"),
                feedforward: self.get("feedforward") != 0.0,
                catchup: self.get("catchup"),
                stall: self.get("stall"),
                weights: self.weights(),
            })),
            "lookahead" => Box::new(Lookahead::new(LookaheadParams {
                gain: self.get("gain"),
                lookahead: self.get("lookahead"),
                window: self.get("window"),
                stall: self.get("stall"),
                weights: self.weights(),
            })),
            other => unreachable!("checked tracker name {other}"),
        }
    }

    /// The loop's options.
    pub fn loop_options(&self) -> LoopOptions {
        LoopOptions {
            replan_error: self.get("replan_error"),
            replan_after: self.get("replan_after"),
            max_replans: self.get("max_replans") as usize,
            time_factor: self.get("time_factor"),
            time_slack: self.get("time_slack"),
            hold: self.get("hold"),
            goal_margin: self.get("goal_margin"),
            obs_weight: self.get("obs_weight"),
            ..LoopOptions::default()
        }
    }
}

/// A tracker and its loop options from a name and `key=value` parameters.
pub fn build_tracker(
    name: &str,
    params: &[(String, String)],
    source: &str,
) -> Result<(Box<dyn Tracker>, LoopOptions), InputError> {
    let spec = TrackerSpec::parse(name, params, source)?;
    Ok((spec.build(), spec.loop_options()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kv(k: &str, v: &str) -> (String, String) {
        (k.to_string(), v.to_string())
    }

    #[test]
    fn builds_every_tracker_with_defaults() {
        for name in tracker_names() {
            let (t, _) = build_tracker(name, &[], "<command line>").unwrap();
            assert_eq!(t.name(), name);
        }
        let open = TrackerSpec::parse("open-loop", &[], "x").unwrap();
        assert_eq!(
            open.loop_options().replan_after,
            0.0,
            "open-loop does not replan on error by default"
        );
    }

    #[test]
    fn rejects_unknown_names_params_and_bad_values() {
        let e = build_tracker("pid", &[], "<command line>").err().unwrap();
        assert!(e.to_string().contains("unknown tracker `pid`"), "{e}");
        let e = build_tracker("obc", &[kv("gain", "0.5")], "exp.toml")
            .err()
            .unwrap();
        assert_eq!(e.field, "params.gain");
        assert!(e.reason.contains("no parameter"));
        let e = build_tracker("obc", &[kv("eps", "abc")], "x")
            .err()
            .unwrap();
        assert!(e.reason.contains("not a number"));
        let e = build_tracker("lookahead", &[kv("gain", "1.5")], "x")
            .err()
            .unwrap();
        assert!(e.reason.contains("must be in"));
        let e = build_tracker("obc", &[kv("grid", "10.5")], "x")
            .err()
            .unwrap();
        assert!(e.reason.contains("whole number"));
        assert!(parse_param("eps", "x").is_err());
        assert_eq!(parse_param("eps=0.2", "x").unwrap(), kv("eps", "0.2"));
    }

    #[test]
    fn labels_show_changed_params() {
        let s = TrackerSpec::parse("obc", &[kv("eps", "0.3")], "x").unwrap();
        assert_eq!(s.label(), "obc{eps=0.3}");
        assert_eq!(s.get("eps"), 0.3);
    }
}

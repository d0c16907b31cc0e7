//! A rig's fit scored against its truth: per parameter the error (relative for factors, τ and
//! the noise; frames for the latency; degrees and BL/s for the bias and a drift), the fit's
//! own standard error in the same unit, its status, and whether it is within the
//! tolerance.
//!
//! Moments, drags and gradient gains share a scale symmetry (moments ×λ, drags ×λ², gains ×λ);
//! when the data do not fix it the fit reports them under a convention, and the truth is
//! scaled the same way before comparing: by the true moments' geometric mean under the fit's
//! convention, by the true value of the parameter that fixed the scale when one was held.

use magbench_drivers::fit::{FitReport, Kind, ScaleFit, Status};
use magbench_env::plant::DisturbancePreset;

use super::rig::Rig;

/// A scored parameter: one of the fit's, or the detection noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Param {
    /// A parameter of the fit.
    Fit(Kind),
    /// The detection noise σ (from the residuals).
    Noise,
}

impl Param {
    /// Every parameter scored for a team of `agents`, in the CSV's order.
    pub fn all(agents: usize) -> Vec<Param> {
        let mut out = vec![];
        for i in 0..agents {
            out.push(Param::Fit(Kind::Moment(i)));
            out.push(Param::Fit(Kind::Drag(i)));
        }
        out.extend(
            [
                Kind::GradientGain(0),
                Kind::GradientGain(1),
                Kind::FieldBias,
                Kind::Drift(0),
                Kind::Drift(1),
                Kind::FieldTau,
                Kind::GradientTau,
                Kind::Latency,
            ]
            .map(Param::Fit),
        );
        out.push(Param::Noise);
        out
    }

    /// The name in reports (the fit's own).
    pub fn name(&self) -> String {
        match self {
            Param::Fit(k) => k.name(),
            Param::Noise => "camera.noise.sigma_bl".into(),
        }
    }

    /// Whether the error is relative (else absolute, in [`Param::unit`]).
    pub fn relative(&self) -> bool {
        match self {
            Param::Fit(k) => k.is_log(),
            Param::Noise => true,
        }
    }

    /// The unit of the error.
    pub fn unit(&self) -> &'static str {
        match self {
            Param::Fit(Kind::Latency) => "frames",
            Param::Fit(Kind::FieldBias) => "deg",
            Param::Fit(Kind::Drift(_)) => "BL/s",
            _ => "relative",
        }
    }

    /// The tolerance on the error: the fit's own ([`Kind::tolerance`]) for a fitted
    /// parameter, 20% for the detection noise.
    pub fn tolerance(&self) -> f64 {
        match self {
            Param::Fit(k) => k.tolerance(),
            Param::Noise => 0.2,
        }
    }

    /// The rig's true value, before any scale convention.
    pub fn truth(&self, p: &DisturbancePreset) -> f64 {
        let f = &p.fitted;
        match self {
            Param::Fit(Kind::Moment(i)) => f.moment[*i],
            Param::Fit(Kind::Drag(i)) => f.drag[*i],
            Param::Fit(Kind::GradientGain(a)) => f.gradient_gain.map_or(1.0, |g| g[*a]),
            Param::Fit(Kind::FieldBias) => f.field_bias_deg.unwrap_or(0.0),
            Param::Fit(Kind::Drift(a)) => f.drift_bl_s.map_or(0.0, |d| d[*a]),
            Param::Fit(Kind::FieldTau) => p.coil_lag.field_tau_ms,
            Param::Fit(Kind::GradientTau) => p.coil_lag.gradient_tau_ms,
            Param::Fit(Kind::Latency) => p.camera.nominal_latency_frames(),
            Param::Noise => p.camera.noise.sigma_bl,
        }
    }

    /// The power of the scale λ in this parameter ([`Kind::scale_power`]; 0 for the noise).
    fn scale_power(&self) -> i32 {
        match self {
            Param::Fit(k) => k.scale_power(),
            Param::Noise => 0,
        }
    }
}

/// What the rig's fit did with a parameter.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Fitted.
    Fitted,
    /// Written at an estimate whose standard error is above the fit's threshold, because the
    /// data reject the base's value (the fit's reason).
    Imprecise(String),
    /// Not identified by the data (the fit's reason).
    NotIdentified(String),
    /// The rig's excitation or fit failed (why).
    RigFailed(String),
}

impl Verdict {
    /// The status column.
    pub fn status(&self) -> &'static str {
        match self {
            Verdict::Fitted => "fitted",
            Verdict::Imprecise(_) => "imprecise",
            Verdict::NotIdentified(_) => "not identified",
            Verdict::RigFailed(_) => "rig failed",
        }
    }

    /// The reason column.
    pub fn reason(&self) -> &str {
        match self {
            Verdict::Fitted => "",
            Verdict::Imprecise(r) | Verdict::NotIdentified(r) | Verdict::RigFailed(r) => r,
        }
    }
}

/// One parameter of one rig, scored.
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// The parameter.
    pub param: Param,
    /// The true value.
    pub truth: f64,
    /// The true value under the fit's scale convention (what the fitted value estimates).
    pub compared: f64,
    /// The value the fit wrote (the base's when not identified), when it ran.
    pub fitted: Option<f64>,
    /// Error of the value written against `compared`, in [`Param::unit`].
    pub error: Option<f64>,
    /// The fit's standard error, in the same unit, when fitted or imprecise.
    pub se: Option<f64>,
    /// Fitted, imprecise, not identified, or the rig failed.
    pub verdict: Verdict,
    /// Whether the error of a value the fit wrote (fitted or imprecise) is within
    /// [`Param::tolerance`].
    pub within: Option<bool>,
}

/// Standard errors within which an error counts as covered by the fit's own uncertainty: the
/// half-width of a two-sided 95% interval of a normal estimate (1.96), rounded to 2.
pub const COVERAGE_SE: f64 = 2.0;

impl Score {
    /// The error in units of the fit's own standard error, for a value the fit wrote (fitted
    /// or imprecise) with a positive standard error.
    pub fn error_in_se(&self) -> Option<f64> {
        match (&self.verdict, self.error, self.se) {
            (Verdict::Fitted | Verdict::Imprecise(_), Some(e), Some(se)) if se > 0.0 => {
                Some(e / se)
            }
            _ => None,
        }
    }

    /// Whether the error is within [`COVERAGE_SE`] of the fit's standard errors: what an
    /// honest standard error gives on about 95% of values.
    pub fn covered(&self) -> Option<bool> {
        self.error_in_se().map(|z| z.abs() <= COVERAGE_SE)
    }

    /// Whether the fit claims the value to its tolerance: written (fitted or imprecise) with a
    /// standard error the fit's own rule claims to it ([`Kind::claimed`], the one its report
    /// states; the noise, which the fit does not judge so, by the same rule against its 20%).
    pub fn claimed(&self) -> bool {
        let claims = |se: f64| match self.param {
            Param::Fit(k) => k.claimed(se),
            Param::Noise => 2.0 * se <= self.param.tolerance(),
        };
        matches!(self.verdict, Verdict::Fitted | Verdict::Imprecise(_))
            && self.se.is_some_and(claims)
    }

    /// Whether the value is within its tolerance, or the fit's own output says the data cannot
    /// tell it that well (not identified, or a standard error above [`Score::claimed`]'s);
    /// `false` for a rig that failed.
    pub fn within_or_unclaimed(&self) -> bool {
        match self.verdict {
            Verdict::RigFailed(_) => false,
            _ => self.within == Some(true) || !self.claimed(),
        }
    }
}

/// The scale λ the fit's moments, drags and gains are relative to, and how it was fixed.
pub fn scale(fit: &FitReport, truth: &DisturbancePreset) -> (f64, String) {
    let f = &truth.fitted;
    match fit.scale {
        ScaleFit::Identified(_) => (1.0, "absolute (scale identified)".into()),
        ScaleFit::Convention(_) => {
            let n = f.moment.len().max(1) as f64;
            let g = (f.moment.iter().map(|m| m.ln()).sum::<f64>() / n).exp();
            (g, "moments' geometric mean = 1".into())
        }
        ScaleFit::Held => {
            let held = fit.params.iter().find(|p| {
                matches!(
                    p.kind,
                    Kind::Moment(_) | Kind::Drag(_) | Kind::GradientGain(_)
                ) && p.status.is_held()
            });
            match held {
                Some(p) => {
                    let q = Param::Fit(p.kind);
                    let v = (q.truth(truth) / p.value).powf(1.0 / q.scale_power() as f64);
                    (v, format!("{} held at {}", p.name, p.value))
                }
                None => (1.0, "absolute".into()),
            }
        }
    }
}

/// Every parameter of `rig` scored against its fit.
pub fn scores(rig: &Rig, fit: &FitReport, agents: usize) -> Vec<Score> {
    let (lambda, _) = scale(fit, &rig.truth);
    Param::all(agents)
        .into_iter()
        .map(|param| {
            let truth = param.truth(&rig.truth);
            let compared = truth / lambda.powi(param.scale_power());
            let (value, se, verdict) = match param {
                Param::Noise => match fit.noise {
                    Some(s) => (Some(s), fit.noise_se.map(|e| e / s), Verdict::Fitted),
                    None => (
                        Some(fit.preset.camera.noise.sigma_bl),
                        None,
                        Verdict::NotIdentified(
                            "not seen in the residuals' lag-1 covariance".into(),
                        ),
                    ),
                },
                Param::Fit(kind) => match fit.params.iter().find(|p| p.kind == kind) {
                    Some(p) => {
                        let value = match kind {
                            Kind::Latency => fit.latency,
                            _ => p.value,
                        };
                        let verdict = match p.status {
                            Status::Fitted => Verdict::Fitted,
                            Status::Held => Verdict::NotIdentified("held".into()),
                            Status::Unidentified(s) => Verdict::NotIdentified(format!(
                                "standard error {} above the fit's threshold {}",
                                shown(param, s),
                                shown(param, kind.identified_below_in_unit())
                            )),
                            Status::Imprecise(s) => Verdict::Imprecise(format!(
                                "standard error {} above the fit's threshold {}; the data reject the base's value",
                                shown(param, s),
                                shown(param, kind.identified_below_in_unit())
                            )),
                            Status::ScaleImprecise(s) => Verdict::Imprecise(format!(
                                "standard error {} through the scale's, above the fit's threshold {}",
                                shown(param, s),
                                shown(param, kind.identified_below_in_unit())
                            )),
                            Status::TradesOff(s) => Verdict::Imprecise(format!(
                                "standard error {} with the values set aside free, above the fit's threshold {}",
                                shown(param, s),
                                shown(param, kind.identified_below_in_unit())
                            )),
                        };
                        (Some(value), p.se, verdict)
                    }
                    None => (
                        None,
                        None,
                        Verdict::NotIdentified("not a parameter of this fit".into()),
                    ),
                },
            };
            let error = value.map(|v| {
                if param.relative() {
                    v / compared - 1.0
                } else {
                    v - compared
                }
            });
            let within = match (&verdict, error) {
                (Verdict::Fitted | Verdict::Imprecise(_), Some(e)) => {
                    Some(e.abs() <= param.tolerance())
                }
                _ => None,
            };
            Score {
                param,
                truth,
                compared,
                fitted: value,
                error,
                se,
                verdict,
                within,
            }
        })
        .collect()
}

/// Every parameter of a rig that failed, with the reason.
pub fn failed(rig: &Rig, agents: usize, why: &str) -> Vec<Score> {
    Param::all(agents)
        .into_iter()
        .map(|param| {
            let truth = param.truth(&rig.truth);
            Score {
                param,
                truth,
                compared: truth,
                fitted: None,
                error: None,
                se: None,
                verdict: Verdict::RigFailed(why.to_string()),
                within: None,
            }
        })
        .collect()
}

/// An error or a standard error of `param` as text: a percentage when relative.
pub fn shown(param: Param, v: f64) -> String {
    if param.relative() {
        format!("{:.1}%", 100.0 * v)
    } else {
        format!("{v:.3} {}", param.unit())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn score(verdict: Verdict, error: f64, se: f64) -> Score {
        Score {
            param: Param::Fit(Kind::Drag(0)),
            truth: 1.0,
            compared: 1.0,
            fitted: Some(1.0 + error),
            error: Some(error),
            se: Some(se),
            verdict,
            within: Some(error.abs() <= 0.1),
        }
    }

    #[test]
    fn a_miss_counts_against_the_goal_only_when_the_fit_claimed_the_tolerance() {
        // tolerance 10%: claimed up to a standard error of 5%
        let claimed_miss = score(Verdict::Fitted, 0.12, 0.05);
        assert!(claimed_miss.claimed() && !claimed_miss.within_or_unclaimed());
        let loose_miss = score(Verdict::Fitted, 0.12, 0.051);
        assert!(!loose_miss.claimed() && loose_miss.within_or_unclaimed());
        let hit = score(Verdict::Imprecise("wide".into()), 0.02, 0.2);
        assert!(hit.within_or_unclaimed());
        let held = score(Verdict::NotIdentified("held".into()), 0.3, 0.01);
        assert!(!held.claimed() && held.within_or_unclaimed());
        assert!(!score(Verdict::RigFailed("touched".into()), 0.0, 0.01).within_or_unclaimed());
    }

    #[test]
    fn an_error_is_covered_within_two_of_its_own_standard_errors() {
        let s = score(Verdict::Fitted, -0.05, 0.02);
        assert_eq!(s.error_in_se(), Some(-2.5));
        assert_eq!(s.covered(), Some(false));
        let s = score(Verdict::Imprecise("wide".into()), 0.05, 0.03);
        assert_eq!(s.covered(), Some(true));
        // a value the fit did not write, or one without a standard error, is not counted
        assert_eq!(
            score(Verdict::NotIdentified("held".into()), 0.5, 0.1).covered(),
            None
        );
        assert_eq!(score(Verdict::Fitted, 0.01, 0.0).covered(), None);
    }
}

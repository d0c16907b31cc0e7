//! What a fit found, and the preset file it writes: the fitted values in the preset's own
//! format, their standard errors, the held-out check and the warnings as comments.

use std::fmt::Write as _;

use magbench_env::plant::DisturbancePreset;

use super::contact::StuckFrames;
use super::model::{Kind, Model, SegmentTrace};
use super::problem::Problem;
use super::{MIN_HELD_OUT, SAME_PREDICTION_BL, stuck_summary};

/// Whether a parameter was fitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Status {
    /// Fitted; its standard error is below its threshold.
    Fitted,
    /// Held at the base value by request (`--hold`).
    Held,
    /// Held at the base value because the data do not identify it (standard error, in the
    /// preset's unit as [`ParamFit::se`]) and do not reject the base's value.
    Unidentified(f64),
    /// Held at its estimate, which is written: its standard error (as above) exceeds the
    /// threshold, but the data reject the base's value (held there, the residuals rise as for
    /// a value more than [`super::REJECTS_BASE_SE`] standard errors away).
    Imprecise(f64),
    /// A moment, drag or gain fitted and written whose standard error (as above) exceeds the
    /// threshold only through the uncertainty of the moment/drag/gain scale: the scale fitted,
    /// the parameter identified relative to the others but not absolutely; or the scale held
    /// by an anchor (the convention, or a value the fit set aside), the parameter identified
    /// with the anchor held but not relative to it.
    ScaleImprecise(f64),
    /// Fitted and written, but its standard error (as above) exceeds the threshold with the
    /// parameters the fit set aside (unidentified or imprecise) free as well: it trades off
    /// against a value the data do not fix.
    TradesOff(f64),
}

impl Status {
    /// Whether the preset carries the fit's value (fitted or imprecise) rather than the
    /// base's.
    pub fn is_written(&self) -> bool {
        matches!(
            self,
            Status::Fitted
                | Status::Imprecise(_)
                | Status::ScaleImprecise(_)
                | Status::TradesOff(_)
        )
    }

    /// Whether the fit held the parameter (by request, or set aside at the base's value or
    /// at its estimate), so that a held moment, drag or gain fixes the scale.
    pub fn is_held(&self) -> bool {
        matches!(
            self,
            Status::Held | Status::Unidentified(_) | Status::Imprecise(_)
        )
    }
}

/// One parameter's result, in the preset's units.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamFit {
    /// What it is.
    pub kind: Kind,
    /// Its name in reports.
    pub name: String,
    /// The value written (the base value when neither fitted nor imprecise).
    pub value: f64,
    /// Standard error in the preset's unit (relative for factors and τ), when fitted or
    /// imprecise.
    pub se: Option<f64>,
    /// Fitted or why not.
    pub status: Status,
}

/// How the moment/drag/gain scale (moments ×λ, drags ×λ², gains ×λ) was settled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ScaleFit {
    /// The data identify it: the standard error of `ln λ`.
    Identified(f64),
    /// The data do not (standard error of `ln λ` shown; infinite when no term of the model
    /// breaks the symmetry): the geometric mean of the moment factors is held at the base's,
    /// 1, and moments, drags and gains are relative to it.
    Convention(f64),
    /// A moment, drag or gain was held (`--hold`, unidentified or imprecise), which fixes it.
    Held,
}

/// The check on segments left out of the fit: prediction error (residual RMS per coordinate,
/// each segment's start state fitted) under the fitted preset and under the base, over the
/// held-out segments both predicted (a prediction that touched a wall or stuck is not
/// compared).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeldOut {
    /// Segments held out.
    pub segments: usize,
    /// Held-out segments predicted under both presets, on which they are compared.
    pub compared: usize,
    /// RMS error of the fitted preset's predictions (BL); NaN when none was compared.
    pub fitted_rms: f64,
    /// RMS error of the base preset's predictions (BL); NaN when none was compared.
    pub base_rms: f64,
    /// Largest difference between the two presets' residuals (BL); NaN when none was compared.
    pub max_difference: f64,
}

impl HeldOut {
    /// The check from each held-out segment's residuals under the fitted preset and under the
    /// base (`None`: the prediction touched a wall or stuck), in the same order.
    pub fn compare(fitted: &[Option<Vec<f64>>], base: &[Option<Vec<f64>>]) -> Self {
        let (mut sf, mut sb, mut n, mut diff, mut compared) = (0.0, 0.0, 0usize, 0.0f64, 0);
        for (f, b) in fitted.iter().zip(base) {
            let (Some(f), Some(b)) = (f, b) else {
                continue;
            };
            compared += 1;
            for (u, v) in f.iter().zip(b) {
                // a missed detection is 0 under both
                if *u != 0.0 || *v != 0.0 {
                    sf += u * u;
                    sb += v * v;
                    n += 1;
                    diff = diff.max((u - v).abs());
                }
            }
        }
        let nan = |v: f64| if n == 0 { f64::NAN } else { v };
        Self {
            segments: fitted.len(),
            compared,
            fitted_rms: nan((sf / n.max(1) as f64).sqrt()),
            base_rms: nan((sb / n.max(1) as f64).sqrt()),
            max_difference: nan(diff),
        }
    }

    /// Why the check cannot tell the fitted preset from the base, when it cannot: fewer than
    /// [`MIN_HELD_OUT`] segments compared, errors that are not finite, or predictions that
    /// agree to within [`SAME_PREDICTION_BL`].
    pub fn undecided(&self) -> Option<String> {
        if self.compared < MIN_HELD_OUT {
            return Some(format!(
                "only {} of the {} held-out segments were predicted under both presets (a prediction that touches a wall or sticks is not compared); a comparison needs {MIN_HELD_OUT}",
                self.compared, self.segments
            ));
        }
        if !self.fitted_rms.is_finite() || !self.base_rms.is_finite() {
            return Some(format!(
                "the prediction errors are not finite numbers ({} fitted, {} base)",
                self.fitted_rms, self.base_rms
            ));
        }
        // NaN compares false: a NaN difference is not "the same"
        (self.max_difference <= SAME_PREDICTION_BL).then(|| {
            format!(
                "the fitted preset and the base predict the {} compared segments alike (residuals within {SAME_PREDICTION_BL:e} BL, RMS {:.4} BL): the fit changed nothing they test",
                self.compared, self.fitted_rms
            )
        })
    }

    /// The RMS errors (fitted, base) when the check can compare them.
    pub fn rms(&self) -> Option<(f64, f64)> {
        self.undecided()
            .is_none()
            .then_some((self.fitted_rms, self.base_rms))
    }

    /// Whether the fitted preset predicts the held-out segments better than the base (false
    /// when the check cannot tell).
    pub fn fitted_better(&self) -> bool {
        self.rms().is_some_and(|(f, b)| f < b)
    }

    /// The check as one line of the report.
    pub fn line(&self) -> String {
        match self.undecided() {
            Some(why) => format!(
                "held-out check           cannot tell the fitted preset from the base: {why}"
            ),
            None => format!(
                "held-out check           prediction RMS {:.4} BL fitted against {:.4} BL base, on {} of the {} segments left out of the fit",
                self.fitted_rms, self.base_rms, self.compared, self.segments
            ),
        }
    }
}

/// The result of `magbench calibrate`.
#[derive(Debug, Clone)]
pub struct FitReport {
    /// Every parameter.
    pub params: Vec<ParamFit>,
    /// The latency written (frames): fitted or imprecise, else the base's.
    pub latency: f64,
    /// The largest latency the fit could take (frames, `--max-latency`).
    pub max_latency: usize,
    /// (latency in frames, mean squared residual in BL²) of the quick fit at each start of the
    /// latency ([`super::LATENCY_START_STEP`] apart).
    pub latency_table: Vec<(f64, f64)>,
    /// Detection noise σ (BL per coordinate), when the residuals show it.
    pub noise: Option<f64>,
    /// The standard error of [`FitReport::noise`] (BL).
    pub noise_se: Option<f64>,
    /// How the moment/drag/gain scale was settled.
    pub scale: ScaleFit,
    /// The check on held-out segments.
    pub held_out: HeldOut,
    /// Seconds of log.
    pub seconds: f64,
    /// Per run, the frames found stuck in contact and left out of the fit and of the held-out
    /// check.
    pub stuck: Vec<StuckFrames>,
    /// Residual RMS per agent (BL) at the optimum.
    pub rms_per_agent: Vec<f64>,
    /// Segments and residuals fitted.
    pub segments: usize,
    /// Residuals fitted.
    pub residuals: usize,
    /// The fitted preset.
    pub preset: DisturbancePreset,
    /// Predicted against observed motion under the fitted preset: the segments of the first
    /// run within its first [`TRACE_S`] seconds.
    pub traces: Vec<SegmentTrace>,
}

/// How much of the first run [`FitReport::traces`] shows (s).
pub const TRACE_S: f64 = 10.0;

/// Assembles the report of a finished fit.
#[allow(clippy::too_many_arguments)]
pub(super) fn build(
    model: &Model,
    base: &DisturbancePreset,
    p: &Problem<'_>,
    se: &[f64],
    free: &[bool],
    set_aside: &[(usize, Status)],
    latency_table: Vec<(f64, f64)>,
    noise: Option<(f64, f64)>,
    scale: ScaleFit,
    held_out: HeldOut,
    seconds: f64,
    stuck: Vec<StuckFrames>,
) -> FitReport {
    let x = p.x();
    let params: Vec<ParamFit> = model
        .kinds
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let se_unit = |s: f64| match k {
                Kind::FieldBias => s.to_degrees(),
                _ => s,
            };
            // standard errors in the preset's unit
            let status = if free[i] {
                Status::Fitted
            } else {
                match set_aside.iter().find(|u| u.0 == i).map(|u| u.1) {
                    Some(Status::Unidentified(s)) => Status::Unidentified(se_unit(s)),
                    Some(Status::Imprecise(s)) => Status::Imprecise(se_unit(s)),
                    Some(Status::ScaleImprecise(s)) => Status::ScaleImprecise(se_unit(s)),
                    Some(Status::TradesOff(s)) => Status::TradesOff(se_unit(s)),
                    _ => Status::Held,
                }
            };
            let se_i = match status {
                Status::Fitted => Some(se_unit(se[i])),
                Status::Imprecise(s) | Status::ScaleImprecise(s) | Status::TradesOff(s) => Some(s),
                Status::Held | Status::Unidentified(_) => None,
            };
            let value = match k {
                Kind::Latency => x[i].clamp(0.0, model.max_latency as f64),
                _ => k.value(x[i]),
            };
            ParamFit {
                kind: *k,
                name: k.name(),
                value,
                se: se_i,
                status,
            }
        })
        .collect();
    let mut preset = base.clone();
    let fit = |pred: &dyn Fn(&Kind) -> bool| -> Option<Vec<f64>> {
        let sel: Vec<&ParamFit> = params.iter().filter(|q| pred(&q.kind)).collect();
        (!sel.is_empty() && sel.iter().all(|q| q.status.is_written()))
            .then(|| sel.iter().map(|q| q.value).collect())
    };
    let f = &mut preset.fitted;
    f.enabled = true;
    f.moment = fit(&|k| matches!(k, Kind::Moment(_))).unwrap_or_default();
    f.drag = fit(&|k| matches!(k, Kind::Drag(_))).unwrap_or_default();
    f.gradient_gain = fit(&|k| matches!(k, Kind::GradientGain(_))).map(|v| [v[0], v[1]]);
    f.field_bias_deg = fit(&|k| matches!(k, Kind::FieldBias)).map(|v| v[0]);
    f.drift_bl_s = fit(&|k| matches!(k, Kind::Drift(_))).map(|v| [v[0], v[1]]);
    if let Some(v) = fit(&|k| matches!(k, Kind::FieldTau)) {
        preset.coil_lag.field_tau_ms = v[0];
    }
    if let Some(v) = fit(&|k| matches!(k, Kind::GradientTau)) {
        preset.coil_lag.gradient_tau_ms = v[0];
    }
    if let Some(v) = fit(&|k| matches!(k, Kind::Latency)) {
        preset.camera.latency.enabled = v[0] > 0.0 || preset.camera.latency.enabled;
        preset.camera.latency.frames = v[0];
    }
    let latency = preset.camera.nominal_latency_frames();
    if let Some((s, _)) = noise {
        preset.camera.noise.enabled = true;
        preset.camera.noise.sigma_bl = s;
    }
    let predict = model.preset_at(model.predict_base(), x);
    let t0 = model
        .runs
        .first()
        .and_then(|r| r.frames.first())
        .map_or(0.0, |f| f.t);
    let traces = p
        .segments()
        .iter()
        .filter(|s| s.run == 0 && model.runs[0].frames[s.start].t < t0 + TRACE_S)
        .map(|s| model.predict(&predict, s).0)
        .collect();
    FitReport {
        traces,
        params,
        latency,
        max_latency: model.max_latency,
        latency_table,
        noise: noise.map(|n| n.0),
        noise_se: noise.map(|n| n.1),
        scale,
        held_out,
        seconds,
        stuck,
        rms_per_agent: p.rms_per_agent(),
        segments: p.segments().len(),
        residuals: model.residual_count(p.segments()),
        preset,
    }
}

impl FitReport {
    /// Seconds of the logs found stuck in contact and left out.
    pub fn excluded_seconds(&self) -> f64 {
        self.stuck.iter().map(|s| s.seconds).sum()
    }

    /// The geometric mean of the fitted moment factors (the common-mode moment scale) and its
    /// standard error (relative), when every agent's moment was fitted.
    pub fn moment_scale(&self) -> Option<(f64, f64)> {
        let m: Vec<&ParamFit> = self
            .params
            .iter()
            .filter(|p| matches!(p.kind, Kind::Moment(_)))
            .collect();
        if m.is_empty() || m.iter().any(|p| p.status != Status::Fitted) {
            return None;
        }
        let n = m.len() as f64;
        let g = (m.iter().map(|p| p.value.ln()).sum::<f64>() / n).exp();
        // errors taken as independent: the SE of a mean of logs
        let se = (m.iter().map(|p| p.se.unwrap_or(0.0).powi(2)).sum::<f64>()).sqrt() / n;
        Some((g, se))
    }

    /// One line per parameter ([`param_line`]), for the terminal and the preset's comments.
    pub fn lines(&self) -> Vec<String> {
        let mut out: Vec<String> = self.params.iter().map(param_line).collect();
        if let Some((g, s)) = self.moment_scale() {
            out.push(format!(
                "{:<24} {:>10.4}  ± {:.1}%  (geometric mean of the moments)",
                "moment_scale",
                g,
                100.0 * s
            ));
        }
        if !self.latency_table.is_empty() {
            out.push(format!(
                "{:<24} {:>10}  latency started from quick fits every half frame, mean squared residual: {}",
                "",
                "",
                self.latency_table
                    .iter()
                    .map(|(l, m)| format!("{l}: {m:.3e} BL²"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        out.push(match self.scale {
            ScaleFit::Identified(s) => format!(
                "{:<24} {:>10}  ± {:.1}%  identified by the data (moments ×λ, drags ×λ², gains ×λ)",
                "scale λ", "1", 100.0 * s
            ),
            ScaleFit::Convention(s) => format!(
                "{:<24} {:>10}  {}: fixed by convention, the moments' geometric mean = 1; moments, drags and gains are relative to it, and so are their standard errors (identified: m_i/√d_i, g/√d_i)",
                "scale λ",
                "-",
                if s.is_finite() {
                    format!("not identified by the data (± {:.0}%)", 100.0 * s)
                } else {
                    "a symmetry of the model (no hydrodynamic interaction, capillary attraction or magnet lag)".into()
                }
            ),
            ScaleFit::Held => format!(
                "{:<24} {:>10}  fixed by a held moment, drag or gain; the others, and their standard errors, are relative to it",
                "scale λ", "-"
            ),
        });
        out.push(match (self.noise, self.noise_se) {
            (Some(s), Some(e)) => format!(
                "{:<24} {:>10.4}  ± {e:.1e}  from the residuals' lag-1 covariance",
                "camera.noise.sigma_bl", s
            ),
            (Some(s), None) => format!(
                "{:<24} {:>10.4}  from the residuals' lag-1 covariance",
                "camera.noise.sigma_bl", s
            ),
            (None, _) => format!(
                "{:<24} {:>10}  not seen in the residuals: left at the base value",
                "camera.noise.sigma_bl", "-"
            ),
        });
        out.push(format!(
            "residual RMS per agent   {} BL over {} segments ({} residuals)",
            self.rms_per_agent
                .iter()
                .map(|r| format!("{r:.4}"))
                .collect::<Vec<_>>()
                .join(", "),
            self.segments,
            self.residuals
        ));
        if self.excluded_seconds() > 0.0 {
            out.push(format!(
                "excluded                 {}: left out of the fit and of the held-out check",
                stuck_summary(&self.stuck, true)
            ));
        }
        out.push(self.held_out.line());
        out.push(
            "left at the base value, never fitted: camera.noise bias (absorbed in the positions), camera.latency jitter, misses and swaps, field jitter, axis gains and skew, cross-talk, ambient field, flow, Brownian motion, hydrodynamics and capillary (physics, not parameters), magnet lag (from the moments)"
                .into(),
        );
        for w in self.warnings() {
            out.push(format!("warning: {w}"));
        }
        out
    }

    /// What the output cannot be trusted for, each with what to change: predictions on held-out
    /// segments no better than the base's or a held-out check that cannot tell, parameters the
    /// data did not identify, a latency fitted at its bound, a scale fixed by convention, a
    /// noise the residuals did not show.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = vec![];
        let h = &self.held_out;
        match (h.undecided(), h.rms()) {
            (Some(why), _) => w.push(format!(
                "the held-out check cannot tell the fitted preset from the base, so nothing shows that the fit predicts better; do not use it; check that --scenario and --base match the rig, then excite longer or harder. Why: {why}"
            )),
            (None, Some((f, b))) if !h.fitted_better() => w.push(format!(
                "the fitted preset predicts the held-out segments no better than the base ({f:.4} against {b:.4} BL): do not use it; check that --scenario and --base match the rig, then excite longer or harder"
            )),
            _ => {}
        }
        for p in &self.params {
            match p.status {
                Status::Unidentified(_) => w.push(format!(
                    "{} was not identified and keeps the base value: {}",
                    p.name,
                    advice(p.kind)
                )),
                Status::Imprecise(_) => w.push(format!(
                    "{} is imprecise: the estimate written is less certain than the fit's threshold asks, though the data reject the base's value; to pin it down: {}",
                    p.name,
                    advice(p.kind)
                )),
                Status::ScaleImprecise(_) => w.push(format!(
                    "{} is imprecise through the moment/drag/gain scale, which the data fix too loosely: measure one of the three (a gradient gain with a gaussmeter) and --hold it",
                    p.name
                )),
                Status::TradesOff(_) => w.push(format!(
                    "{} is imprecise: it trades off against what the data do not fix ({}); pin that down (its warning says how) or --hold it at a measured value",
                    p.name,
                    set_aside_names(&self.params),
                )),
                Status::Fitted | Status::Held => {}
            }
        }
        w.extend(latency_at_bound(&self.params, self.max_latency));
        if let ScaleFit::Convention(_) = self.scale {
            w.push("the common scale of moments, drags and gains is not in the data (no hydrodynamic interaction, capillary attraction or magnet lag strong enough to break it): the absolute values rest on the convention; measure one (a gradient gain with a gaussmeter) and --hold it".into());
        }
        if self.noise.is_none() {
            w.push("the detection noise was not seen in the residuals and keeps the base value: the process noise hides it; image a resting team to measure it".into());
        }
        w
    }

    /// The fitted preset as a file: the report as comments, then the preset's TOML.
    pub fn preset_file(&self, sources: &[String]) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# Fitted by `magbench calibrate` to {}.",
            sources.join(", ")
        );
        let _ = writeln!(
            s,
            "# Values with standard errors (from the Jacobian at the optimum, each segment's start"
        );
        let _ = writeln!(
            s,
            "# state profiled out; white detection noise assumed). [fitted] replaces the"
        );
        let _ = writeln!(s, "# per-run draws of the values it gives.");
        for l in self.lines() {
            let _ = writeln!(s, "#   {l}");
        }
        s.push_str(&self.preset.to_toml());
        s
    }
}

/// What to change so that a parameter of this kind is identified.
fn advice(k: Kind) -> &'static str {
    match k {
        Kind::Moment(_) | Kind::Drag(_) => {
            "run longer, with the agents far enough apart to move independently (rig excite's separation band)"
        }
        Kind::GradientGain(_) => {
            "run longer or with stronger gradient steps (rig excite pulls at 70% of the limit)"
        }
        Kind::FieldBias | Kind::Drift(_) => "run longer",
        Kind::FieldTau | Kind::GradientTau => {
            "its steps and chirps must move the agents by more than the detection noise within a few τ: a stronger field or gradient, a camera with less noise or more frames per second, a longer run"
        }
        Kind::Latency => {
            "the excitation's steps must show when motion starts: a camera with less noise or more frames per second, a longer run"
        }
    }
}

/// The warning for a latency fitted at a bound of its range: 0 frames, where the data would
/// take less latency than none, or `max_latency`, where they may take more than the fit can
/// predict. There the standard error comes from one side only, and the latency trades off
/// against the coils' τ (both delay the response), so neither is known as well as printed.
fn latency_at_bound(params: &[ParamFit], max_latency: usize) -> Option<String> {
    let p = params.iter().find(|p| p.kind == Kind::Latency)?;
    if !p.status.is_written() {
        return None;
    }
    let one_side = "its standard error is taken on one side only, and there the latency trades off against the coils' τ (both delay the response), so neither is known as well as printed";
    if p.value <= Kind::Latency.lowest() {
        Some(format!(
            "{} came out at its lower bound, 0 frames: {one_side}; if the camera's delay is known (from its timestamps), --hold {} at it",
            p.name, p.name
        ))
    } else if p.value >= max_latency as f64 {
        Some(format!(
            "{} came out at its upper bound, {max_latency} frames (--max-latency): the camera may be later than that; {one_side}; fit again with a larger --max-latency",
            p.name
        ))
    } else {
        None
    }
}

/// A parameter's line in the report; a value fitted but not claimed to its tolerance
/// ([`Kind::claimed`]) says so.
fn param_line(p: &ParamFit) -> String {
    let se = |s: f64| match p.kind {
        k if k.is_log() => format!("± {:.1}%", 100.0 * s),
        Kind::Latency => format!("± {s:.2} frames"),
        Kind::FieldBias => format!("± {s:.3}°"),
        _ => format!("± {s:.2e}"),
    };
    match p.status {
        Status::Fitted => {
            let s = p.se.unwrap_or(f64::NAN);
            let claim = match p.kind.claimed(s) {
                true => String::new(),
                false => format!(
                    ", but not to {} (two standard errors exceed it)",
                    tolerance(p.kind)
                ),
            };
            format!("{:<24} {:>10.4}  {}  fitted{claim}", p.name, p.value, se(s))
        }
        Status::Held => format!(
            "{:<24} {:>10}  held at the base value (--hold)",
            p.name, "-"
        ),
        Status::Unidentified(s) => format!(
            "{:<24} {:>10}  not identified by the data (standard error {}): left at the base value",
            p.name,
            "-",
            se(s)
        ),
        Status::Imprecise(s) => format!(
            "{:<24} {:>10.4}  {}  imprecise: the standard error is above the fit's threshold ({}), but the data reject the base's value (held there, the residuals rise as much as for a value more than {} standard errors away), so the estimate is written",
            p.name,
            p.value,
            se(s),
            se(p.kind.identified_below_in_unit()),
            super::REJECTS_BASE_SE
        ),
        Status::TradesOff(s) => format!(
            "{:<24} {:>10.4}  {}  imprecise through the values set aside: fitted, but with the parameters the data do not fix free as well its standard error is above the fit's threshold ({})",
            p.name,
            p.value,
            se(s),
            se(p.kind.identified_below_in_unit())
        ),
        Status::ScaleImprecise(s) => format!(
            "{:<24} {:>10.4}  {}  imprecise through the scale: fitted, but the uncertainty of the moment/drag/gain scale (below) puts its standard error above the fit's threshold ({})",
            p.name,
            p.value,
            se(s),
            se(p.kind.identified_below_in_unit())
        ),
    }
}

/// The names of the parameters the fit set aside (not identified, or imprecise and held at
/// the estimate), joined by commas.
fn set_aside_names(params: &[ParamFit]) -> String {
    params
        .iter()
        .filter(|p| matches!(p.status, Status::Unidentified(_) | Status::Imprecise(_)))
        .map(|p| p.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A parameter's tolerance as the report writes it: `±5%`, `±0.5 frames`, `±0.5°`,
/// `±0.005 BL/s`.
fn tolerance(k: Kind) -> String {
    let t = k.tolerance();
    match k {
        k if k.is_log() => format!("±{:.0}%", 100.0 * t),
        Kind::Latency => format!("±{t} frames"),
        Kind::FieldBias => format!("±{t}°"),
        _ => format!("±{t} BL/s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn latency(value: f64, status: Status) -> ParamFit {
        ParamFit {
            kind: Kind::Latency,
            name: Kind::Latency.name(),
            value,
            se: Some(0.04),
            status,
        }
    }

    #[test]
    fn a_latency_fitted_at_either_bound_is_warned_of_and_one_inside_is_not() {
        let w = latency_at_bound(&[latency(0.0, Status::Fitted)], 4).unwrap();
        assert!(w.contains("lower bound") && w.contains("--hold camera.latency.frames"));
        assert!(latency_at_bound(&[latency(0.3, Status::Fitted)], 4).is_none());
        assert!(latency_at_bound(&[latency(0.0, Status::Held)], 4).is_none());
        let w = latency_at_bound(&[latency(4.0, Status::Fitted)], 4).unwrap();
        assert!(w.contains("upper bound, 4 frames") && w.contains("larger --max-latency"));
        assert!(latency_at_bound(&[latency(3.9, Status::Fitted)], 4).is_none());
    }

    #[test]
    fn a_value_fitted_coarser_than_its_tolerance_says_so() {
        let gain = |se| ParamFit {
            kind: Kind::GradientGain(0),
            name: Kind::GradientGain(0).name(),
            value: 1.02,
            se: Some(se),
            status: Status::Fitted,
        };
        // tolerance 5%: claimed up to a standard error of 2.5%
        assert!(param_line(&gain(0.02)).ends_with("fitted"));
        let coarse = param_line(&gain(0.04));
        assert!(coarse.contains("fitted, but not to ±5%"), "{coarse}");
        let mut bias = latency(0.3, Status::Fitted);
        bias.kind = Kind::FieldBias;
        bias.se = Some(0.3);
        assert!(param_line(&bias).contains("not to ±0.5°"));
    }
}

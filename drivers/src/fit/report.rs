//! What a fit found, and the preset file it writes: the fitted values in the preset's own
//! format, their standard errors and the fit's residuals as comments.

use std::fmt::Write as _;

use magbench_env::plant::DisturbancePreset;

use super::model::{Kind, Model, SegmentTrace};
use super::problem::Problem;

/// Whether a parameter was fitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Status {
    /// Fitted; its standard error is below its threshold.
    Fitted,
    /// Held at the base value by request (`--hold`).
    Held,
    /// Held at the base value because the data do not identify it (standard error shown).
    Unidentified(f64),
}

/// One parameter's result, in the preset's units.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamFit {
    /// What it is.
    pub kind: Kind,
    /// Its name in reports.
    pub name: String,
    /// The value written (the base value when not fitted).
    pub value: f64,
    /// Standard error in the preset's unit (relative for factors and τ), when fitted.
    pub se: Option<f64>,
    /// Fitted or why not.
    pub status: Status,
}

/// The result of `magbench calibrate`.
#[derive(Debug, Clone)]
pub struct FitReport {
    /// Every parameter.
    pub params: Vec<ParamFit>,
    /// The latency chosen (frames), and the mean squared residual of each candidate.
    pub latency: usize,
    /// (latency, mean squared residual in BL²) per candidate.
    pub latency_table: Vec<(usize, f64)>,
    /// Detection noise σ (BL per coordinate), when the residuals show it.
    pub noise: Option<f64>,
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
    unidentified: &[(usize, f64)],
    latency: usize,
    latency_table: Vec<(usize, f64)>,
    noise: Option<f64>,
) -> FitReport {
    let x = p.x();
    let params: Vec<ParamFit> = model
        .kinds
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let status = if free[i] {
                Status::Fitted
            } else {
                match unidentified.iter().find(|u| u.0 == i) {
                    Some(u) => Status::Unidentified(u.1),
                    None => Status::Held,
                }
            };
            let fitted = status == Status::Fitted;
            let se_unit = |s: f64| match k {
                Kind::FieldBias => s.to_degrees(),
                _ => s,
            };
            ParamFit {
                kind: *k,
                name: k.name(),
                value: k.value(x[i]),
                se: fitted.then(|| se_unit(se[i])),
                status,
            }
        })
        .collect();
    let mut preset = base.clone();
    let fit = |pred: &dyn Fn(&Kind) -> bool| -> Option<Vec<f64>> {
        let sel: Vec<&ParamFit> = params.iter().filter(|q| pred(&q.kind)).collect();
        (!sel.is_empty() && sel.iter().all(|q| q.status == Status::Fitted))
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
    preset.camera.latency.enabled = latency > 0 || preset.camera.latency.enabled;
    preset.camera.latency.frames = latency as f64;
    if let Some(s) = noise {
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
        .map(|s| model.predict(&predict, s, latency).0)
        .collect();
    FitReport {
        traces,
        params,
        latency,
        latency_table,
        noise,
        rms_per_agent: p.rms_per_agent(),
        segments: p.segments().len(),
        residuals: model.residual_count(p.segments()),
        preset,
    }
}

impl FitReport {
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

    /// One line per parameter, for the terminal and the preset's comments.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![];
        for p in &self.params {
            let se = |s: f64| match p.kind {
                k if k.is_log() => format!("± {:.1}%", 100.0 * s),
                Kind::FieldBias => format!("± {s:.3}°"),
                _ => format!("± {s:.2e}"),
            };
            out.push(match p.status {
                Status::Fitted => format!(
                    "{:<24} {:>10.4}  {}  fitted",
                    p.name,
                    p.value,
                    se(p.se.unwrap_or(f64::NAN))
                ),
                Status::Held => format!("{:<24} {:>10}  held at the base value (--hold)", p.name, "-"),
                Status::Unidentified(s) => format!(
                    "{:<24} {:>10}  not identified by the data (standard error {}): left at the base value",
                    p.name,
                    "-",
                    se(s)
                ),
            });
        }
        if let Some((g, s)) = self.moment_scale() {
            out.push(format!(
                "{:<24} {:>10.4}  ± {:.1}%  (geometric mean of the moments)",
                "moment_scale",
                g,
                100.0 * s
            ));
        }
        out.push(format!(
            "{:<24} {:>10}  search over whole frames, mean squared residual per candidate: {}",
            "camera.latency.frames",
            self.latency,
            self.latency_table
                .iter()
                .map(|(l, m)| format!("{l}: {m:.3e} BL²"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
        out.push(match self.noise {
            Some(s) => format!(
                "{:<24} {:>10.4}  from the residuals' lag-1 covariance",
                "camera.noise.sigma_bl", s
            ),
            None => format!(
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
        out.push(
            "left at the base value, never fitted: camera.noise bias (absorbed in the positions), camera.latency jitter, misses and swaps, field jitter, axis gains and skew, cross-talk, ambient field, flow, Brownian motion, hydrodynamics and capillary (physics, not parameters), magnet lag (from the moments), gradient coil τ"
                .into(),
        );
        out
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

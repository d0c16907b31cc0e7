//! The benchmark's outputs: `calibration-bench.csv` (one row per rig × parameter) and the
//! Markdown summary (per parameter: rigs within tolerance, fitted, imprecise, not identified,
//! failed).

use std::fmt::Write as _;
use std::path::Path;

use magbench_drivers::fit::HeldOut;

use super::rig::Rig;
use super::score::{COVERAGE_SE, Param, Score, Verdict, shown};

/// One rig's result: its scores and the fit's held-out check.
pub struct RigResult {
    /// The rig.
    pub rig: Rig,
    /// Every parameter scored.
    pub scores: Vec<Score>,
    /// How the moment/drag/gain scale was compared (empty when the rig failed).
    pub scale: String,
    /// The fit's held-out check, when fitted.
    pub held_out: Option<HeldOut>,
    /// Tracking RMS error (BL) under the truth, the fitted preset and the base, when fitted
    /// (or why it could not be measured).
    pub tracking: Option<Result<[f64; 3], String>>,
}

impl RigResult {
    /// Whether the rig failed: nothing was fitted.
    pub fn failed(&self) -> bool {
        matches!(
            self.scores.first().map(|s| &s.verdict),
            Some(Verdict::RigFailed(_))
        )
    }

    /// The held-out prediction RMS (BL) of the fitted and the base preset, when fitted and the
    /// held-out check could compare them.
    pub fn held_out_rms(&self) -> Option<(f64, f64)> {
        self.held_out.and_then(|h| h.rms())
    }

    /// The tracking errors under the truth, the fitted preset and the base, when measured.
    pub fn tracked(&self) -> Option<[f64; 3]> {
        self.tracking
            .as_ref()
            .and_then(|t| t.as_ref().ok())
            .copied()
    }
}

/// Largest relative difference of the tracking error under the fitted preset from that under
/// the truth.
pub const TRACKING_TOLERANCE: f64 = 0.1;

/// A number for the CSV: empty when absent, else full precision.
fn cell(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| format!("{v}"))
}

/// Writes `calibration-bench.csv` into `dir`: rig, seed, medium, hydrodynamics, parameter,
/// true value, the true value under the fit's scale convention, the fitted value, its error
/// and the error's unit, the fit's standard error, the error in standard errors, status,
/// reason, tolerance, within it,
/// the scale convention, the held-out prediction RMS of the fitted and the base preset (empty
/// when the held-out check cannot compare them), and
/// the tracking RMS error under the truth, the fitted preset and the base.
pub fn write_csv(dir: &Path, results: &[RigResult]) -> Result<(), String> {
    let path = dir.join("calibration-bench.csv");
    let err = |e: csv::Error| format!("{}: {e}", path.display());
    let mut w = csv::Writer::from_path(&path).map_err(err)?;
    w.write_record([
        "rig",
        "seed",
        "medium",
        "hydrodynamics",
        "parameter",
        "true",
        "true_compared",
        "fitted",
        "error",
        "error_unit",
        "standard_error",
        "error_in_se",
        "status",
        "reason",
        "tolerance",
        "within_tolerance",
        "scale",
        "held_out_fitted_rms_bl",
        "held_out_base_rms_bl",
        "tracking_rms_truth_bl",
        "tracking_rms_fitted_bl",
        "tracking_rms_base_bl",
    ])
    .map_err(err)?;
    for r in results {
        for s in &r.scores {
            let within = s.within.map_or(String::new(), |b| b.to_string());
            w.write_record([
                r.rig.index.to_string(),
                r.rig.seed.to_string(),
                r.rig.medium_name().into(),
                r.rig.hydrodynamics().to_string(),
                s.param.name(),
                format!("{}", s.truth),
                format!("{}", s.compared),
                cell(s.fitted),
                cell(s.error),
                s.param.unit().into(),
                cell(s.se),
                cell(s.error_in_se()),
                s.verdict.status().into(),
                s.verdict.reason().into(),
                format!("{}", s.param.tolerance()),
                within,
                r.scale.clone(),
                cell(r.held_out_rms().map(|h| h.0)),
                cell(r.held_out_rms().map(|h| h.1)),
                cell(r.tracked().map(|t| t[0])),
                cell(r.tracked().map(|t| t[1])),
                cell(r.tracked().map(|t| t[2])),
            ])
            .map_err(err)?;
        }
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}

/// The per-rig table's cell of a fit's held-out check, as `calibrate` reports it: better, no
/// better (each with the two prediction RMS) or cannot tell; `–` when nothing was fitted.
fn held_out_cell(h: Option<&HeldOut>) -> String {
    match (h, h.and_then(HeldOut::rms)) {
        (None, _) => "–".into(),
        (Some(_), None) => "cannot tell".into(),
        (Some(h), Some((f, b))) if h.fitted_better() => format!("better ({f:.4} < {b:.4} BL)"),
        (Some(_), Some((f, b))) => format!("no better ({f:.4} ≥ {b:.4} BL)"),
    }
}

/// The Markdown summary: one row per parameter with its tolerance, the rigs whose written value
/// (fitted or imprecise) is within it, fitted, imprecise, not identified and failed, the
/// largest error of a fitted value, the written values whose error is within
/// [`COVERAGE_SE`] of their own standard errors (of those with one), and the rigs whose value
/// is within tolerance or not claimed to it ([`Score::within_or_unclaimed`]);
/// then per rig the held-out check and the tracking errors under the truth, the fitted preset
/// and the base, with how many fits `calibrate` warns not to use; then one line per failed rig
/// with its reason.
pub fn summary(results: &[RigResult], params: &[Param]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| parameter | tolerance | within tolerance | fitted | imprecise | not identified | rig failed | largest fitted error | error within {COVERAGE_SE} SE | within tolerance or not claimed |"
    );
    let _ = writeln!(
        s,
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let (mut covered, mut with_se) = (0, 0);
    for (k, p) in params.iter().enumerate() {
        let col: Vec<&Score> = results.iter().map(|r| &r.scores[k]).collect();
        let count = |f: &dyn Fn(&Score) -> bool| col.iter().filter(|s| f(s)).count();
        let fitted = count(&|s| s.verdict == Verdict::Fitted);
        let within = count(&|s| s.within == Some(true));
        let imprecise = count(&|s| matches!(s.verdict, Verdict::Imprecise(_)));
        let unident = count(&|s| matches!(s.verdict, Verdict::NotIdentified(_)));
        let failed = count(&|s| matches!(s.verdict, Verdict::RigFailed(_)));
        let worst = col
            .iter()
            .filter(|s| s.verdict == Verdict::Fitted)
            .filter_map(|s| s.error)
            .map(f64::abs)
            .max_by(f64::total_cmp);
        let cov = count(&|s| s.covered() == Some(true));
        let se = count(&|s| s.covered().is_some());
        let goal = count(&|s| s.within_or_unclaimed());
        covered += cov;
        with_se += se;
        let _ = writeln!(
            s,
            "| {} | {} | {within} of {n} | {fitted} | {imprecise} | {unident} | {failed} | {} | {cov} of {se} | {goal} of {n} |",
            p.name(),
            shown(*p, p.tolerance()),
            worst.map_or("–".into(), |w| shown(*p, w)),
            n = col.len(),
        );
    }
    let _ = writeln!(
        s,
        "\nErrors within {COVERAGE_SE} of the fit's own standard errors: {covered} of {with_se} values written with one (about 95% if the standard errors are right). A value is claimed to its tolerance when the fit wrote it with a standard error of at most the tolerance over {COVERAGE_SE}; the last column counts the rigs where it is within tolerance or not so claimed.",
    );
    let _ = writeln!(
        s,
        "\n| rig | medium | hydrodynamics | held-out check | tracking RMS, truth (BL) | fitted (BL) | base (BL) | fitted against truth |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut close = 0;
    let mut tracked = 0;
    let mut warned = 0;
    for r in results {
        // calibrate warns against a fit whose held-out predictions are no better, or untested
        if r.held_out.is_some_and(|h| !h.fitted_better()) {
            warned += 1;
        }
        let row = match &r.tracking {
            None => "| – | – | – | rig failed |".to_string(),
            Some(Err(e)) => format!("| – | – | – | {e} |"),
            Some(Ok([t, f, b])) => {
                tracked += 1;
                let d = f / t - 1.0;
                if d.abs() <= TRACKING_TOLERANCE {
                    close += 1;
                }
                format!("| {t:.4} | {f:.4} | {b:.4} | {:+.1}% |", 100.0 * d)
            }
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} {row}",
            r.rig.index,
            r.rig.medium_name(),
            if r.rig.hydrodynamics() { "on" } else { "off" },
            held_out_cell(r.held_out.as_ref()),
        );
    }
    let _ = writeln!(
        s,
        "\nTracking error under the fitted preset within {:.0}% of the truth's: {close} of {tracked} rigs fitted ({} drawn).",
        100.0 * TRACKING_TOLERANCE,
        results.len()
    );
    let fitted = results.iter().filter(|r| !r.failed()).count();
    let _ = writeln!(
        s,
        "Fits that `calibrate` warns not to use (held-out predictions no better than the base's, or a check that cannot tell): {warned} of {fitted} rigs fitted; their parameters are scored above like the others."
    );
    let failed: Vec<&RigResult> = results.iter().filter(|r| r.failed()).collect();
    if !failed.is_empty() {
        let _ = writeln!(s, "\nRigs that failed:\n");
    }
    for r in failed {
        let _ = writeln!(
            s,
            "- rig {} ({}, hydrodynamics {}): {}",
            r.rig.index,
            r.rig.medium_name(),
            if r.rig.hydrodynamics() { "on" } else { "off" },
            r.scores[0].verdict.reason()
        );
    }
    s
}

//! `magbench calibrate`: fits a preset's parameters to logged rig runs.
//!
//! The logs are cut into segments of a few consecutive frames; each segment is predicted by
//! env's [`magbench_env::plant::Plant`] under the logged commands from a start state of its
//! own (multiple shooting), and Levenberg–Marquardt (the `levenberg-marquardt` crate)
//! minimises the squared differences to what was seen, the first frame included. The start
//! states are free parameters profiled out by variable projection (the `starts` module):
//! predicting from the first observation instead carries its detection noise into every later
//! frame and biases the moments and drags along their common scale.
//! The parameters ([`model::Kind`]): per-agent moment and drag factors, each gradient axis's
//! gain, the field-angle bias, a uniform drift, the field and gradient axes' time constants
//! when the base preset has coil dynamics, and the camera latency, a continuous number of
//! frames fitted jointly with the rest: frame `k` shows the plant `L` frame periods before
//! its capture, so between two frames the prediction runs the command of `⌊L⌋ + 1` frames
//! back for the fraction `L − ⌊L⌋` of the period and then that of `⌊L⌋` frames back (the
//! frames interpolated). Its starting value is the best of quick fits every half frame.
//! The detection noise comes from the residuals: for one-frame predictions
//! `e_k = n_{k+1} − n_k + w_k`, so white detection noise of σ gives consecutive residuals the
//! covariance −σ² while the process noise `w` gives none.
//!
//! Standard errors come from the Jacobian and the residuals at the optimum: the larger of
//! `σ_r² (JᵀJ)⁻¹` and the same clustered by segment (`(JᵀJ)⁻¹ (Σ_s J_sᵀ r_s r_sᵀ J_s)
//! (JᵀJ)⁻¹`), since a segment's prediction errors share the process noise and any model error
//! since its start, so they are not white. Moment, drag and
//! gradient gain share one scale symmetry (moments ×λ, drags ×λ², gains ×λ leave every force
//! the same) that only the terms which do not scale with the agent's own drag or moment break
//! (hydrodynamic interaction, capillary attraction, the magnet's rotation lag). The fit
//! measures the standard error of `ln λ`; above [`SCALE_IDENTIFIED_BELOW`] it fixes the scale
//! by a stated convention — the geometric mean of the moment factors is the base's, 1 — and
//! reports it ([`ScaleFit`]); the ratios `m_i/√d_i` and `g_a/√d_i` are what the data then
//! identify. The scale's uncertainty reaches the moments, drags and gains' standard errors
//! both ways. With the scale fitted, one above its threshold only through the scale's (its
//! contrast with the moments' geometric mean identified) is kept at its estimate and reported
//! imprecise through the scale ([`Status::ScaleImprecise`]), not held at the base, which would
//! fix the scale by an unmeasured value. With the scale held by an anchor (the convention, or
//! a moment, drag or gain set aside), a term that breaks the symmetry only weakly bends the
//! direction the data do not see away from the scale alone, so the anchor, held where the data
//! do not confirm it, moves the other values with it: their standard errors are then at least
//! those of their contrasts with the anchor from the data alone, and one above its threshold is
//! reported imprecise through the scale. A parameter whose standard error exceeds its threshold
//! ([`model::Kind::identified_below`]) is not fitted to noise: the worst one is held and the
//! fit repeated, until every parameter left is identified. It is held at the base value unless
//! the data reject that value: refitted with it there, the residuals' sum of squares rises by
//! more than it would for a value [`REJECTS_BASE_SE`] standard errors away (a likelihood-ratio
//! test, [`base_likelihood_ratio`]). Then it is held at the estimate, reported imprecise:
//! holding it at the base would make the parameters it trades off against (the latency
//! against the coils' τ) make up the difference. What it trades off against still depends on
//! where it is held, so every value left fitted takes the larger of its standard error and its
//! standard error with the set-aside parameters free as well ([`trade_offs`]); one above its
//! threshold only through them is written and reported imprecise through them
//! ([`Status::TradesOff`]).
//!
//! Frames in which the team is stuck in contact (found from the observed positions, the
//! [`contact`] module) are left out of the fit and of the held-out check, and the report says
//! how many seconds; a log with too little left ([`MIN_SEGMENTS`]) is refused.
//!
//! Every fifth segment is held out of the fit; the report gives the prediction error of the
//! fitted preset and of the base on those both predict ([`HeldOut`]), says so when the check
//! cannot tell them apart (too few compared, or the same predictions), and warns when the fit
//! predicts no better than the base, when the check cannot tell, or when it left a parameter
//! unidentified or imprecise.

mod anchor;
pub mod contact;
pub mod error;
pub mod log;
pub mod model;
mod problem;
pub mod report;
mod starts;

use magbench_env::plant::DisturbancePreset;
use magbench_env::{InputError, Scenario};
use rayon::prelude::*;

use self::model::{Segment, frame_period};

pub use self::contact::StuckFrames;
pub use self::error::FitError;
pub use self::log::{LoggedFrame, LoggedRun, read_log};
pub use self::model::{Kind, Model, SegmentTrace};
pub use self::report::{FitReport, HeldOut, ParamFit, ScaleFit, Status, TRACE_S};

use self::anchor::{Anchor, contrasts, relative_standard_errors, scale_power};
use self::problem::{Problem, solve};

/// Options of a fit.
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// Frames per segment.
    pub segment_frames: usize,
    /// Largest latency (frames) the fit may take; quick fits start it every
    /// [`LATENCY_START_STEP`] from 0 to this.
    pub max_latency: usize,
    /// Names of parameters held at the base value (e.g. `gradient_gain.x`).
    pub hold: Vec<String>,
    /// Whether each segment's start state is fitted (profiled out, see the `starts` module)
    /// rather than taken as observed.
    pub free_starts: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            segment_frames: SEGMENT_FRAMES,
            max_latency: 4,
            hold: vec![],
            free_starts: true,
        }
    }
}

/// Frames per segment by default (1.33 s at 60 fps). A segment's start state is fitted with
/// it, and what the linearisation in that start leaves is a bias of second order in the
/// detection noise, about the same in every segment, while what a segment says of the
/// parameters grows with its length; a longer segment also has fewer start states (2 per agent
/// each) to share the data with. The benchmark's segment table (`cargo xtask measure --only
/// calibration-bench-segments`, docs/calibration.md) compares 40, 60 and 80 frames on its
/// three benchmarks: 60 and 80 score about as many values within tolerance, 60 more errors
/// within two standard errors. One long run at the top of the benchmark's noise compares
/// them on a single rig (`cargo xtask measure --only calibration-segments`). A longer segment
/// needs a longer log ([`MIN_SEGMENTS`] of them: 33 s at 60 fps).
pub const SEGMENT_FRAMES: usize = 80;

/// Frames of each segment the latency's quick fits predict. They start from the base's coils
/// and run 3 iterations; over whole segments a base whose coils are far from the rig's leaves
/// errors that 3 iterations do not remove, and the quick fits then rank the latencies by those
/// (on rig 7 of the calibration benchmark, 40-frame segments chose 2 frames, true 3.79;
/// their first 20 frames chose 3.5).
pub const QUICK_SEGMENT_FRAMES: usize = 20;

/// Largest standard error of `ln λ`, the common scale of moments, drags and gains, at which
/// the data fix it (as for any factor, [`model::Kind::identified_below`]); above it the
/// convention holds the moments' geometric mean at 1.
pub const SCALE_IDENTIFIED_BELOW: f64 = 0.1;

/// The distance in standard errors whose rise of the residuals' sum of squares
/// ([`base_likelihood_ratio`], this squared) rejects the base's value of an unidentified
/// parameter: it is then held at its estimate (reported imprecise) rather than at the base.
/// Two standard errors: a test at about 5% (χ² with one degree of freedom, 3.84).
pub const REJECTS_BASE_SE: f64 = 2.0;

/// One segment in this many is held out of the fit for the check of its predictions.
pub const HOLD_OUT_EVERY: usize = 5;

/// Fewest held-out segments predicted under both the fitted preset and the base for the
/// held-out check to compare them: a prediction error from fewer says little.
pub const MIN_HELD_OUT: usize = 5;

/// Fewest segments a fit takes: [`MIN_HELD_OUT`] held out and, with one in
/// [`HOLD_OUT_EVERY`] held out, 20 fitted (every one of the excitation's 4 field-angle blocks
/// seen about 5 times).
pub const MIN_SEGMENTS: usize = MIN_HELD_OUT * HOLD_OUT_EVERY;

/// Largest difference (BL) between the fitted preset's and the base's held-out residuals at
/// which the two predict the same: a micro body length, far below any camera's detection
/// noise.
pub const SAME_PREDICTION_BL: f64 = 1e-6;

/// Largest share of frames a log may lose in gaps: beyond it the consecutive stretches the fit
/// predicts are the exception, not the run.
pub const MAX_LOST_SHARE: f64 = 0.5;

/// Room (BL) around the scenario's workspace an observation may fall in (detection error and
/// an agent's radius); beyond it the log is of another workspace.
pub const WORKSPACE_MARGIN_BL: f64 = 1.0;

/// Checks that every run can be a run of `scenario`: its agent count, positions within the
/// workspace, time and frame order, not mostly gaps. Agents stuck in contact are not a reason
/// to refuse a run: [`contact`] finds those frames and the fit leaves them out.
fn check_runs(scenario: &Scenario, runs: &[LoggedRun]) -> Result<(), InputError> {
    let (w, h) = (scenario.world.width, scenario.world.height);
    let m = WORKSPACE_MARGIN_BL;
    for run in runs {
        let f = &run.frames;
        if let Some(fr) = f.iter().find(|fr| fr.agents.len() != scenario.agents()) {
            return Err(InputError::new(
                &run.source,
                format!("frame {}", fr.frame),
                format!(
                    "{} agents, the scenario {} has {}",
                    fr.agents.len(),
                    scenario.name,
                    scenario.agents()
                ),
            ));
        }
        for fr in f {
            if let Some(p) = fr
                .agents
                .iter()
                .flatten()
                .find(|p| p.x < -m || p.y < -m || p.x > w + m || p.y > h + m)
            {
                return Err(InputError::new(
                    &run.source,
                    format!("frame {}", fr.frame),
                    format!(
                        "an agent observed at ({:.2}, {:.2}) BL, outside {}'s {w} × {h} BL workspace: a log of another scenario or rig?",
                        p.x, p.y, scenario.name
                    ),
                ));
            }
        }
        if let Some(k) =
            (1..f.len()).find(|&k| f[k].frame <= f[k - 1].frame || f[k].t <= f[k - 1].t)
        {
            return Err(InputError::new(
                &run.source,
                format!("frame {}", f[k].frame),
                format!(
                    "frame index or time does not increase (frame {} at {} s after frame {} at {} s)",
                    f[k].frame,
                    f[k].t,
                    f[k - 1].frame,
                    f[k - 1].t
                ),
            ));
        }
        let span = f.last().map_or(0, |l| l.frame - f[0].frame) + 1;
        let lost = span.saturating_sub(f.len() as u64);
        if lost as f64 > MAX_LOST_SHARE * span as f64 {
            return Err(InputError::new(
                &run.source,
                "frame",
                format!(
                    "gaps: {lost} of {span} frames missing (more than {:.0}%)",
                    100.0 * MAX_LOST_SHARE
                ),
            ));
        }
    }
    Ok(())
}

/// `x` moved along the scale direction `dir` until the mean of the ln moment factors
/// (`moments`) is 0, the convention's value; the same forces as `x`.
fn onto_convention(x: &[f64], dir: &[f64], moments: &[usize]) -> Vec<f64> {
    let mean = |v: &[f64]| moments.iter().map(|&i| v[i]).sum::<f64>() / moments.len() as f64;
    let t = mean(x) / mean(dir);
    x.iter().zip(dir).map(|(a, d)| a - t * d).collect()
}

/// The moment factors' indices among `kinds`: the scale convention holds their mean.
fn moment_indices(kinds: &[Kind]) -> Vec<usize> {
    (0..kinds.len())
        .filter(|&i| matches!(kinds[i], Kind::Moment(_)))
        .collect()
}

/// Whether the fit holds the moment/drag/gain scale by the convention.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ScaleState {
    /// Held for the first fit; not yet measured.
    Undecided,
    /// The data fix it: fitted without the convention.
    Free,
    /// The data do not fix it: held by the convention.
    Held,
    /// No term of the model breaks it ([`scale_is_symmetry`]): held by the convention.
    Symmetry,
}

/// Largest change of a prediction (BL) under a step of [`SYMMETRY_STEP`] along the scale
/// below which the scale is a symmetry of the model: a thousandth of the least detection
/// noise of a rig (0.005 BL), so no data see it.
const SYMMETRY_BL: f64 = 5e-6;

/// The step along the scale (in ln λ) that [`scale_is_symmetry`] takes.
const SYMMETRY_STEP: f64 = 0.1;

/// Whether moving `x` by [`SYMMETRY_STEP`] along the scale direction `dir` changes no
/// prediction of `segs` by more than [`SYMMETRY_BL`]: a model with no hydrodynamic
/// interaction, capillary attraction or magnet lag has the scale as an exact symmetry, and a
/// standard error computed along it measures only the finite differences' rounding and the
/// integrator's tolerance.
fn scale_is_symmetry(model: &model::Model, segs: &[Segment], x: &[f64], dir: &[f64]) -> bool {
    let base = model.predict_base();
    let moved: Vec<f64> = x
        .iter()
        .zip(dir)
        .map(|(a, d)| a + SYMMETRY_STEP * d)
        .collect();
    let (a, b) = (model.preset_at(base, x), model.preset_at(base, &moved));
    segs.par_iter().all(|s| {
        let start = model.observed_start(s);
        let (ra, bad_a) = model.segment_rows(&a, s, &start);
        let (rb, bad_b) = model.segment_rows(&b, s, &start);
        let worst = ra
            .iter()
            .zip(&rb)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        bad_a == bad_b && worst <= SYMMETRY_BL
    })
}

/// The direction of the moment/drag/gain scale symmetry in the fitted coordinates (ln moment
/// +1, ln drag +2, ln gain +1 per unit of ln λ), or `None` when one of them is held.
fn scale_direction(kinds: &[Kind], free: &[bool]) -> Option<Vec<f64>> {
    let v: Vec<f64> = kinds.iter().map(scale_power).collect();
    v.iter()
        .zip(free)
        .all(|(v, f)| *v == 0.0 || *f)
        .then_some(v)
}

/// Spacing of the latencies the quick fits start from (frames). A prediction depends on the
/// latency through the moments its commands switch, so the cost has a kink at every whole
/// frame where a local search can stop; starting at every half frame puts a start inside
/// each whole frame's span as well as on its edges.
pub const LATENCY_START_STEP: f64 = 0.5;

/// The latencies the quick fits start from: 0 to `max_latency` frames every
/// [`LATENCY_START_STEP`].
fn latency_starts(max_latency: usize) -> Vec<f64> {
    let n = (max_latency as f64 / LATENCY_START_STEP).round() as usize;
    (0..=n).map(|k| k as f64 * LATENCY_START_STEP).collect()
}

/// The segments of `segs` that `x` predicts at every latency of `latencies` (parameter `lat`):
/// a segment whose prediction touches a wall or sticks at one of them is left out, so that
/// every start of the fit is compared on the same segments (a failed prediction costs
/// [`problem::FAILED_PREDICTION_BL`] a row).
fn usable_segments(
    model: &Model,
    segs: Vec<Segment>,
    x: &[f64],
    lat: usize,
    latencies: &[f64],
    free_starts: bool,
) -> Vec<Segment> {
    let mut keep = vec![true; segs.len()];
    for &l in latencies {
        let mut x = x.to_vec();
        x[lat] = l;
        let none = vec![false; x.len()];
        let p = Problem::new(model, segs.clone(), x, none, free_starts);
        for (k, r) in p.segment_residuals().iter().enumerate() {
            keep[k] &= r.is_some();
        }
    }
    segs.into_iter()
        .zip(keep)
        .filter_map(|(s, k)| k.then_some(s))
        .collect()
}

/// Fits `base` to `runs` of `scenario`.
pub fn calibrate(
    scenario: &Scenario,
    base: &DisturbancePreset,
    runs: Vec<LoggedRun>,
    opts: &FitOptions,
) -> Result<FitReport, FitError> {
    check_runs(scenario, &runs)?;
    let stuck: Vec<StuckFrames> = runs.iter().map(contact::stuck_frames).collect();
    let sources = runs
        .iter()
        .map(|r| r.source.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let seconds: f64 = runs
        .iter()
        .map(|r| r.frames.len() as f64 * frame_period(&r.frames))
        .sum();
    let runs: Vec<LoggedRun> = runs
        .into_iter()
        .zip(&stuck)
        .map(|(mut r, s)| {
            let mut k = 0;
            r.frames.retain(|_| {
                k += 1;
                !s.stuck[k - 1]
            });
            r
        })
        .collect();
    let model = Model::new(scenario, base, runs, opts.max_latency);
    let x0 = model.base_point(base);
    let user_held: Vec<bool> = model
        .kinds
        .iter()
        .map(|k| opts.hold.contains(&k.name()))
        .collect();
    let mut free: Vec<bool> = user_held.iter().map(|h| !h).collect();
    let all = model.segments(opts.segment_frames);
    let excluded: f64 = stuck.iter().map(|s| s.seconds).sum();
    if all.len() < MIN_SEGMENTS && excluded > 0.0 {
        return Err(InputError::new(
            &sources,
            "frames",
            format!(
                "too little usable data: {}; {} segments of up to {} frames remain, a fit needs {MIN_SEGMENTS} ({MIN_HELD_OUT} held out, {} fitted); excite again keeping the agents apart (at an interface, capillary attraction may beat the separation loop)",
                // the error names the file already; more than one run, each is named
                stuck_summary(&stuck, stuck.len() > 1),
                all.len(),
                opts.segment_frames,
                MIN_SEGMENTS - MIN_HELD_OUT
            ),
        )
        .into());
    }
    if all.is_empty() {
        return Err(FitError::NoSegments(sources));
    }
    if all.len() < MIN_SEGMENTS {
        return Err(InputError::new(
            &sources,
            "",
            format!(
                "too short to fit: {} segments of up to {} frames with every agent seen, the field on and the coils settled ({seconds:.1} s logged); a fit needs {MIN_SEGMENTS} (a longer run)",
                all.len(),
                opts.segment_frames
            ),
        )
        .into());
    }
    let held: Vec<Segment> = all
        .iter()
        .enumerate()
        .filter(|(k, _)| k % HOLD_OUT_EVERY == HOLD_OUT_EVERY - 1)
        .map(|(_, s)| *s)
        .collect();
    let lat = model
        .kinds
        .iter()
        .position(|k| *k == Kind::Latency)
        .expect("the latency is a parameter");
    let starts: Vec<f64> = if free[lat] {
        latency_starts(opts.max_latency)
    } else {
        vec![x0[lat]]
    };
    let fitted: Vec<Segment> = all
        .iter()
        .enumerate()
        .filter(|(k, _)| k % HOLD_OUT_EVERY != HOLD_OUT_EVERY - 1)
        .map(|(_, s)| *s)
        .collect();
    let segs = usable_segments(&model, fitted, &x0, lat, &starts, opts.free_starts);
    if segs.is_empty() {
        return Err(FitError::NoSegments(sources));
    }
    // the latency's start: a quick fit at each of `starts`, least mean squared residual wins
    let quick_segs: Vec<Segment> = segs
        .iter()
        .map(|s| Segment {
            len: s.len.min(QUICK_SEGMENT_FRAMES),
            ..*s
        })
        .collect();
    let mut latency_table = vec![];
    let mut x_start = x0.clone();
    if free[lat] {
        let mut best = f64::INFINITY;
        for &l in &starts {
            let mut x = x0.clone();
            x[lat] = l;
            let mut quick = free.clone();
            quick[lat] = false;
            let p = Problem::new(&model, quick_segs.clone(), x, quick, opts.free_starts);
            let (p, _) = solve(p, 3);
            let ms = p.mean_square();
            latency_table.push((l, ms));
            if ms < best {
                best = ms;
                x_start = p.x().to_vec();
            }
        }
    }
    let moments = moment_indices(&model.kinds);
    let mut scale;
    // The convention holds the scale in the first fit, so that a search along a direction the
    // data do not see cannot run off; the data alone then say whether they fix it there. If
    // they do, the fit is redone without the convention (and falls back to it, from that
    // fit moved back onto the convention, should the scale's standard error then exceed the
    // threshold).
    let mut scale_state = match scale_direction(&model.kinds, &free) {
        Some(d) if scale_is_symmetry(&model, &segs, &x_start, &d) => ScaleState::Symmetry,
        _ => ScaleState::Undecided,
    };
    // the parameters held because their standard error exceeds the threshold, and how
    let mut set_aside = vec![];
    let (problem, se) = loop {
        let dir = scale_direction(&model.kinds, &free);
        let pinned = dir.is_some() && scale_state != ScaleState::Free;
        let mut p = Problem::new(
            &model,
            segs.clone(),
            x_start.clone(),
            free.clone(),
            opts.free_starts,
        );
        if pinned {
            p.pin_scale(moments.clone());
        }
        let (mut p, _) = solve(p, 20);
        if let Some(d) = dir.as_deref() {
            let s = p.data_standard_error_along(d);
            // a NaN or infinite error is not identified either
            let identified = s.partial_cmp(&SCALE_IDENTIFIED_BELOW)
                != Some(std::cmp::Ordering::Greater)
                && s.is_finite();
            match (scale_state, identified) {
                (ScaleState::Undecided, true) => {
                    scale_state = ScaleState::Free;
                    x_start = p.x().to_vec();
                    continue;
                }
                (ScaleState::Free, false) => {
                    scale_state = ScaleState::Held;
                    x_start = onto_convention(p.x(), d, &moments);
                    continue;
                }
                (ScaleState::Free, true) => scale = ScaleFit::Identified(s),
                (ScaleState::Symmetry, _) => scale = ScaleFit::Convention(f64::INFINITY),
                (_, _) => {
                    scale_state = ScaleState::Held;
                    scale = ScaleFit::Convention(s);
                }
            }
        } else {
            scale = ScaleFit::Held;
        }
        // with the scale fitted, a moment, drag or gain is judged by its standard error
        // relative to the others: one above its threshold only through the scale's is kept
        // and reported imprecise through the scale
        let (fitted, combos) = match scale {
            ScaleFit::Identified(_) => contrasts(&model.kinds, &free, &Anchor::Convention),
            _ => (vec![], vec![]),
        };
        let ses = p.standard_errors_with(&combos);
        let (se, relative_se) = (ses.params, ses.combos);
        let relative: Vec<(usize, f64)> = fitted.into_iter().zip(relative_se).collect();
        let judged = |i: usize| relative.iter().find(|r| r.0 == i).map_or(se[i], |r| r.1);
        let worst = model
            .kinds
            .iter()
            .enumerate()
            .filter(|(i, _)| free[*i])
            .map(|(i, k)| (i, judged(i) / k.identified_below()))
            .filter(|(_, ratio)| ratio.is_nan() || *ratio > 1.0)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((i, _)) => {
                free[i] = false;
                let mut at_base = p.x().to_vec();
                at_base[i] = x0[i];
                let mut q = Problem::new(
                    &model,
                    segs.clone(),
                    at_base,
                    free.clone(),
                    opts.free_starts,
                );
                // pinned as the next fit will be
                let next_dir = scale_direction(&model.kinds, &free);
                if next_dir.is_some() && scale_state != ScaleState::Free {
                    q.pin_scale(moments.clone());
                }
                let (q, _) = solve(q, 20);
                let lr = base_likelihood_ratio(&p, &q, ses.white[i] / se[i]);
                if lr > REJECTS_BASE_SE * REJECTS_BASE_SE {
                    x_start = p.x().to_vec();
                    set_aside.push((i, Status::Imprecise(se[i])));
                } else {
                    x_start = q.x().to_vec();
                    set_aside.push((i, Status::Unidentified(se[i])));
                }
            }
            None => {
                let through_scale = relative.iter().map(|r| r.0);
                set_aside_through_scale(
                    &model.kinds,
                    &se,
                    through_scale,
                    &mut free,
                    &mut set_aside,
                );
                break (p, se);
            }
        }
    };
    let mut se = se;
    let anchor = match scale {
        ScaleFit::Convention(s) if s.is_finite() => Some(Anchor::Convention),
        ScaleFit::Held => Anchor::set_aside(&model.kinds, &user_held, &set_aside),
        _ => None,
    };
    if let Some(anchor) = anchor {
        let relative =
            relative_standard_errors(&model, &segs, &problem, &free, &anchor, opts.free_starts);
        for &(i, s) in &relative {
            if s > se[i] || s.is_nan() {
                se[i] = s;
            }
        }
        let through_scale = relative.iter().map(|r| r.0);
        set_aside_through_scale(&model.kinds, &se, through_scale, &mut free, &mut set_aside);
    }
    let pin = scale_state != ScaleState::Free;
    trade_offs(&model, &problem, pin, &mut se, &mut free, &mut set_aside);
    let noise = problem.detection_noise();
    let check = |x: &[f64]| {
        Problem::new(
            &model,
            held.clone(),
            x.to_vec(),
            vec![false; x.len()],
            opts.free_starts,
        )
        .segment_residuals()
    };
    let held_out = HeldOut::compare(&check(problem.x()), &check(&x0));
    Ok(report::build(
        &model,
        base,
        &problem,
        &se,
        &free,
        &set_aside,
        latency_table,
        noise,
        scale,
        held_out,
        seconds,
        stuck,
    ))
}

/// The likelihood-ratio statistic of a parameter held at the base's value: the rise of the
/// residuals' sum of squares from `free` (the fit with it free) to `held` (refitted with it at
/// the base), over the residual variance at `free`, times `white_over_used²`, the ratio of the
/// parameter's white-residual variance to the one reported (the larger of it and the
/// segment-clustered one), which scales the statistic to the residuals' correlation within a
/// segment (1 when either is not finite). Unlike a distance in standard errors, it does not
/// depend on the coordinates a parameter is fitted in: a coil's τ fitted as ln τ, a few
/// milliseconds with a standard error of a few, is as far from a base of 14 ms as the data
/// say, not as the logarithm's slope at the estimate says (Gregory and Veall, "Formulating
/// Wald tests of nonlinear restrictions", Econometrica 53(6), 1985).
fn base_likelihood_ratio(free: &Problem, held: &Problem, white_over_used: f64) -> f64 {
    let (ssr_free, variance) = free.sum_of_squares();
    let (ssr_held, _) = held.sum_of_squares();
    let scale = if white_over_used.is_finite() && white_over_used > 0.0 {
        white_over_used * white_over_used
    } else {
        1.0
    };
    (ssr_held - ssr_free) / variance * scale
}

/// Every fitted parameter's standard error made at least its standard error with the
/// parameters the fit set aside (unidentified or imprecise) free as well, at `problem`'s
/// optimum (with the scale convention's row when `pin` and the scale is then a direction of
/// the free ones): a value held where the data do not confirm it moves the values it trades
/// off against (the latency against a coil's τ), and their uncertainty then includes its
/// own. This is the consider covariance of Schmidt's filter, the held parameters' variance
/// the data's (Tapley, Schutz and Born, "Statistical Orbit Determination", 2004, ch. 6). One
/// whose standard error then exceeds its threshold is reported imprecise through them
/// ([`Status::TradesOff`]); its estimate is written.
fn trade_offs(
    model: &Model,
    problem: &Problem,
    pin: bool,
    se: &mut [f64],
    free: &mut [bool],
    set_aside: &mut Vec<(usize, Status)>,
) {
    let mut joint = free.to_vec();
    for (i, status) in set_aside.iter() {
        if matches!(status, Status::Unidentified(_) | Status::Imprecise(_)) {
            joint[*i] = true;
        }
    }
    if joint == free {
        return;
    }
    let mut q = Problem::new(
        model,
        problem.segments().to_vec(),
        problem.x().to_vec(),
        joint.clone(),
        problem.free_starts(),
    );
    if pin && scale_direction(&model.kinds, &joint).is_some() {
        q.pin_scale(moment_indices(&model.kinds));
    }
    let with_held = q.standard_errors_with(&[]).params;
    for i in 0..se.len() {
        let larger = with_held[i] > se[i];
        if !free[i] || !larger {
            continue;
        }
        se[i] = with_held[i];
        let identified = se[i] <= model.kinds[i].identified_below();
        if !identified {
            free[i] = false;
            set_aside.push((i, Status::TradesOff(se[i])));
        }
    }
}

/// Each moment, drag or gain of `params` whose standard error exceeds its threshold only
/// through the scale's: held (its estimate written) and reported imprecise through the scale.
fn set_aside_through_scale(
    kinds: &[Kind],
    se: &[f64],
    params: impl Iterator<Item = usize>,
    free: &mut [bool],
    set_aside: &mut Vec<(usize, Status)>,
) {
    for i in params {
        let identified = se[i] <= kinds[i].identified_below();
        if !identified {
            free[i] = false;
            set_aside.push((i, Status::ScaleImprecise(se[i])));
        }
    }
}

/// What was left out as stuck in contact, per run: seconds of seconds (of which file, with
/// `name_files`), stretches and the band.
pub fn stuck_summary(stuck: &[StuckFrames], name_files: bool) -> String {
    stuck
        .iter()
        .filter(|s| s.stretches > 0)
        .map(|s| {
            format!(
                "{:.1} s of {:.1} s{} excluded, the agents stuck in contact ({} stretch{} of at least {} frames with an observed separation within {:.3} BL of contact and not rising)",
                s.seconds,
                s.run_seconds,
                if name_files {
                    format!(" of {}", s.source)
                } else {
                    String::new()
                },
                s.stretches,
                if s.stretches == 1 { "" } else { "es" },
                contact::STUCK_FRAMES,
                s.margin_bl
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

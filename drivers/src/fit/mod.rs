//! `magbench calibrate`: fits a preset's parameters to logged rig runs.
//!
//! The logs are cut into segments of a few consecutive frames; each segment is predicted by
//! env's [`magbench_env::plant::Plant`] under the logged commands from a start state of its
//! own (multiple shooting), and Levenberg–Marquardt (the `levenberg-marquardt` crate)
//! minimises the squared differences to what was seen, the first frame included. The start
//! states are free parameters profiled out by variable projection (the `starts` module):
//! predicting from the first observation instead carries its detection noise into every later
//! frame and biases the moments and drags along their common scale. The parameters
//! ([`model::Kind`]): per-agent moment and drag factors, each gradient axis's gain, the
//! field-angle bias, a uniform drift and, when the base preset has coil dynamics, the field
//! axes' time constant. The camera latency is a discrete search over whole frames (a quick fit
//! from the observed starts for each; the least mean squared residual wins); the detection
//! noise comes from the residuals: for one-frame predictions `e_k = n_{k+1} − n_k + w_k`, so
//! white detection noise of σ gives consecutive residuals the covariance −σ² while the process
//! noise `w` gives none.
//!
//! Standard errors come from the Jacobian at the optimum, `σ_r² (JᵀJ)⁻¹`. A parameter whose
//! standard error exceeds its threshold ([`model::Kind::identified_below`]) is not fitted to
//! noise: the worst one is held at the base value and the fit repeated, until every parameter
//! left is identified. Moment, drag and gradient gain share one scale symmetry (moments ×λ,
//! drags ×λ², gains ×λ leave every force the same) that only the terms which do not scale with
//! the agent's own drag or moment break (hydrodynamic interaction, capillary attraction, the
//! magnet's rotation lag); without them one of the three is held.

pub mod error;
pub mod log;
pub mod model;
mod problem;
pub mod report;
mod starts;

use magbench_env::plant::DisturbancePreset;
use magbench_env::{InputError, Scenario};

pub use self::error::FitError;
pub use self::log::{LoggedFrame, LoggedRun, read_log};
pub use self::model::{Kind, Model, SegmentTrace};
pub use self::report::{FitReport, ParamFit, Status, TRACE_S};

use self::problem::{Problem, solve};

/// Options of a fit.
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// Frames per segment.
    pub segment_frames: usize,
    /// Latencies tried (frames): 0 to this.
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
            segment_frames: 20,
            max_latency: 4,
            hold: vec![],
            free_starts: true,
        }
    }
}

/// Fits `base` to `runs` of `scenario`.
pub fn calibrate(
    scenario: &Scenario,
    base: &DisturbancePreset,
    runs: Vec<LoggedRun>,
    opts: &FitOptions,
) -> Result<FitReport, FitError> {
    for run in &runs {
        if let Some(f) = run
            .frames
            .iter()
            .find(|f| f.agents.len() != scenario.agents())
        {
            return Err(InputError::new(
                &run.source,
                format!("frame {}", f.frame),
                format!(
                    "{} agents, the scenario {} has {}",
                    f.agents.len(),
                    scenario.name,
                    scenario.agents()
                ),
            )
            .into());
        }
    }
    let sources = runs
        .iter()
        .map(|r| r.source.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let model = Model::new(scenario, base, runs);
    let x0 = model.base_point(base);
    let mut free: Vec<bool> = model
        .kinds
        .iter()
        .map(|k| !opts.hold.contains(&k.name()))
        .collect();
    // latency: the quick fit of each candidate, least mean squared residual wins
    let mut latency_table = vec![];
    for l in 0..=opts.max_latency {
        let segs = model.segments(opts.segment_frames, l);
        if segs.is_empty() {
            continue;
        }
        let p = Problem::new(&model, segs, l, x0.clone(), free.clone(), false);
        let (p, _) = solve(p, 3);
        latency_table.push((l, p.mean_square()));
    }
    let &(latency, _) = latency_table
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or(FitError::NoSegments(sources))?;
    let segs = model.segments(opts.segment_frames, latency);
    let mut unidentified = vec![];
    let (problem, se) = loop {
        let p = Problem::new(
            &model,
            segs.clone(),
            latency,
            x0.clone(),
            free.clone(),
            opts.free_starts,
        );
        let (p, _) = solve(p, 20);
        let se = p.standard_errors();
        let worst = model
            .kinds
            .iter()
            .enumerate()
            .filter(|(i, _)| free[*i])
            .map(|(i, k)| (i, se[i] / k.identified_below()))
            .filter(|(_, ratio)| ratio.is_nan() || *ratio > 1.0)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((i, _)) => {
                free[i] = false;
                unidentified.push((i, se[i]));
            }
            None => break (p, se),
        }
    };
    let noise = problem.detection_noise();
    Ok(report::build(
        &model,
        base,
        &problem,
        &se,
        &free,
        &unidentified,
        latency,
        latency_table,
        noise,
    ))
}

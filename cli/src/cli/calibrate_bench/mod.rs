//! `magbench calibrate bench`: `calibrate` evaluated over a family of random rigs, so that every
//! change to the fit is measured on rigs nobody tuned it for.
//!
//! Each rig's preset is drawn (seeded) from documented ranges ([`ranges::Ranges`]); the rig —
//! env's plant and camera, stepped frame by frame (`SimRig`) — is driven by `rig excite`'s
//! trajectory and its log fitted by `calibrate` from a base that knows only the rig's medium
//! and hydrodynamic switch ([`rig::base`]). Each fitted parameter is scored against its truth
//! ([`score`]), and OBC tracks one plan under the truth, the fitted preset and the base
//! ([`tracking`]); the rows, a summary and a figure go to `--out` ([`report`]). Rigs run in
//! parallel on `--threads` workers; every rig's draws depend on its index and the seed only,
//! so the output does not depend on the number of threads.

pub mod ranges;
pub mod report;
pub mod rig;
pub mod score;
pub mod tracking;

use std::path::PathBuf;

use clap::Args;
use rayon::prelude::*;

use magbench_drivers::fit::FitOptions;
use magbench_env::Scenario;
use magbench_env::input::Bound;

use self::ranges::Ranges;
use self::report::RigResult;
use self::rig::Outcome;
use self::score::Param;
use self::tracking::Tracking;
use super::calibrate::SEGMENT_FRAMES;
use super::calibrate_bench_plot::BenchFigure;
use super::number::{checked, count};
use crate::Error;
use crate::output::{outln, prepare_dir};
use crate::registry::Registry;

/// `magbench calibrate bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Output folder: calibration-bench.csv, calibration-bench.md, the figure, and per rig its
    /// true preset, rig log and fitted preset (rigs/rig-N/).
    #[arg(long)]
    pub out: PathBuf,
    /// Rigs drawn.
    #[arg(long, default_value_t = 20)]
    pub rigs: usize,
    /// Seed of the draws (the same seed and ranges give the same rigs and output).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Seconds of excitation per rig.
    #[arg(long, default_value_t = 90.0)]
    pub duration: f64,
    /// The ranges the rigs are drawn from (TOML; keys as in docs/calibration.md, each
    /// optional); default the ranges docs/calibration.md gives.
    #[arg(long)]
    pub ranges: Option<PathBuf>,
    /// Worker threads (default: one per core); the output does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// The scenario the rigs run (an open map: segments whose prediction touches a wall are
    /// dropped).
    #[arg(long, default_value = "open-field")]
    pub scenario: String,
    /// Frames per segment each fit predicts (`calibrate --segment-frames`).
    #[arg(long, default_value_t = magbench_drivers::fit::SEGMENT_FRAMES)]
    pub segment_frames: usize,
}

/// Rigs one benchmark may draw.
const RIGS: Bound = Bound::closed(
    1.0,
    1000.0,
    " rigs",
    "each rig is an excitation and a fit of tens of seconds",
);

/// Seconds of excitation per rig.
const DURATION: Bound = Bound::above(
    0.0,
    3600.0,
    " s",
    "an hour of rig time per rig; the fit's work grows with the log",
);

/// Runs `magbench calibrate bench`.
pub fn run(a: BenchArgs, registry: &Registry) -> Result<(), Error> {
    count("--rigs", &RIGS, a.rigs as u64)?;
    checked("--duration", &DURATION, a.duration)?;
    count("--segment-frames", &SEGMENT_FRAMES, a.segment_frames as u64)?;
    let threads = super::number::threads(a.threads)?;
    let ranges = match &a.ranges {
        Some(p) => Ranges::load(p)?,
        None => Ranges::default(),
    };
    let scenario = Scenario::load(&a.scenario)?;
    prepare_dir(&a.out, "--out")?;
    let agents = scenario.agents();
    let rigs = rig::draw(&ranges, a.seed, a.rigs, agents);
    let tracking = Tracking::plan(registry, &rig::interface())?;
    let opts = FitOptions {
        segment_frames: a.segment_frames,
        max_latency: ranges.max_latency(),
        ..FitOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Failed(format!("thread pool: {e}")))?;
    let started = std::time::Instant::now();
    let results: Vec<Result<RigResult, String>> = pool.install(|| {
        rigs.par_iter()
            .map(|r| {
                let dir = a.out.join("rigs").join(format!("rig-{}", r.index));
                let outcome =
                    std::panic::catch_unwind(|| rig::run(r, &scenario, a.duration, &opts, &dir))
                        .unwrap_or_else(|p| {
                            let msg = p
                                .downcast_ref::<String>()
                                .cloned()
                                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                                .unwrap_or_default();
                            Ok(Outcome::Failed(format!("the run panicked: {msg}")))
                        })?;
                Ok(match outcome {
                    Outcome::Fitted(fit) => {
                        let (_, scale) = score::scale(&fit, &r.truth);
                        let rms = |f: &str| tracking.rms(registry, &dir.join(f), r.interface());
                        let tracked =
                            (|| Ok([rms("truth.toml")?, rms("fitted.toml")?, rms("base.toml")?]))();
                        RigResult {
                            rig: r.clone(),
                            scores: score::scores(r, &fit, agents),
                            scale,
                            held_out: Some(fit.held_out),
                            tracking: Some(tracked),
                        }
                    }
                    Outcome::Failed(why) => RigResult {
                        rig: r.clone(),
                        scores: score::failed(r, agents, &why),
                        scale: String::new(),
                        held_out: None,
                        tracking: None,
                    },
                })
            })
            .collect()
    });
    let results = results
        .into_iter()
        .collect::<Result<Vec<_>, _>>()
        .map_err(Error::Failed)?;
    let params = Param::all(agents);
    report::write_csv(&a.out, &results).map_err(Error::Failed)?;
    let table = report::summary(&results, &params);
    let md = a.out.join("calibration-bench.md");
    std::fs::write(&md, &table).map_err(|e| Error::Failed(format!("{}: {e}", md.display())))?;
    outln!(
        "{} rigs of {} s on {}, seed {}, segments of {} frames, {threads} threads, in {:.0} s",
        a.rigs,
        a.duration,
        scenario.name,
        a.seed,
        a.segment_frames,
        started.elapsed().as_secs_f64()
    );
    outln!();
    for l in table.lines() {
        outln!("{l}");
    }
    outln!();
    outln!(
        "rows         {}",
        a.out.join("calibration-bench.csv").display()
    );
    outln!("summary      {}", md.display());
    let stem = a.out.join("calibration-bench");
    for f in crate::plot::save(&BenchFigure::new(&results, &params), &stem)? {
        outln!("figure       {}", f.display());
    }
    Ok(())
}

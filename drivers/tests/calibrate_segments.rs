//! How the segment length weighs on the fit at strong detection noise: one excitation run
//! under a preset with 3 frames of latency at each of two detection noises, 0.03 BL and the
//! calibration benchmark's top, 0.08 BL, fitted with segments of 20, 40, 60 and 80 frames, each
//! from the observed starts and with the start states free. Predicting from a noisy first
//! observation biases the fit by an amount that grows with the segment's length; the free
//! start states remove that first-order bias, and what remains, of second order in the noise,
//! shrinks as the segments grow.
//!
//! The rig is env's plant and camera (`SimRig`) stepped frame by frame: no sockets, no sleeps,
//! no wall clock. It prints each fit's latency and errors as a Markdown table (a value the fit
//! writes imprecise marked so, a held one "not fitted", the worst error over the fitted ones, "–"
//! when none is),
//! which `cargo xtask measure --only calibration-segments` keeps for docs/calibration.md.

mod common;

use common::NOISY_LATENCY as LATENCY;
use magbench_drivers::fit::{FitOptions, Kind, SEGMENT_FRAMES, Status, calibrate, read_log};
use magbench_env::plant::DisturbancePreset;

/// Seconds of excitation.
const EXCITE_S: f64 = 240.0;

/// The detection noises (BL): the strongest of tests/calibrate_noise_bias.rs, and the top of
/// `magbench calibrate bench`'s range.
const NOISES: [f64; 2] = [0.03, 0.08];

/// Two runs, sixteen fits (segments of 20, 40, 60 and 80 frames, observed and free starts).
#[test]
#[ignore = "several minutes in a debug build; run with --ignored"]
fn segment_length_from_the_observed_starts_and_with_free_starts() {
    let mut header = false;
    let worst_free_default: Vec<f64> = NOISES
        .iter()
        .map(|&noise| {
            let mut t = common::noisy();
            t.camera.noise.sigma_bl = noise;
            fits(&t, &mut header)
        })
        .collect();
    // the default fit (free starts) at the strongest noise of tests/calibrate_noise_bias.rs,
    // within its tolerance; at the top of the benchmark's range this run's default fit is
    // reported, not asserted: it leaves drag[0] unidentified and moment[0] 25% off
    // (docs/calibration.md, on the segment's length)
    assert!(
        worst_free_default[0] <= 0.10,
        "{} BL, {SEGMENT_FRAMES} frames, free starts: worst error {}",
        NOISES[0],
        worst_free_default[0]
    );
}

/// The eight fits of one excitation run under `t`, printed as table rows (after the header
/// unless `header` says it is out); the worst error of the default fit.
fn fits(t: &DisturbancePreset, header: &mut bool) -> f64 {
    let noise = t.camera.noise.sigma_bl;
    let dir = tempfile::tempdir().unwrap();
    let (scenario, path) = common::excite_open_field(t, EXCITE_S, dir.path());
    let n = scenario.agents();
    let mut base = DisturbancePreset::ideal();
    base.hydrodynamics.enabled = true;
    let f = &t.fitted;
    let mut worst_free_default = f64::INFINITY;
    for segment_frames in [20, 40, 60, 80] {
        for free_starts in [false, true] {
            let run = read_log(&path, n).unwrap();
            let opts = FitOptions {
                segment_frames,
                free_starts,
                ..FitOptions::default()
            };
            let fit = calibrate(&scenario, &base, vec![run], &opts).unwrap();
            let mut cells = vec![];
            let mut worst: Option<f64> = None;
            for p in &fit.params {
                let truth = match p.kind {
                    Kind::Moment(i) => f.moment[i],
                    Kind::Drag(i) => f.drag[i],
                    Kind::GradientGain(a) => f.gradient_gain.unwrap()[a],
                    _ => continue,
                };
                let e = p.value / truth - 1.0;
                let cell = match p.status {
                    Status::Fitted => {
                        worst = Some(worst.unwrap_or(0.0).max(e.abs()));
                        format!("{:+.1}%", 100.0 * e)
                    }
                    s if s.is_written() => format!("{:+.1}% (imprecise)", 100.0 * e),
                    _ => "not fitted".into(),
                };
                cells.push((p.name.clone(), cell));
            }
            if !*header {
                let names: Vec<&str> = cells.iter().map(|(n, _)| n.as_str()).collect();
                println!(
                    "| noise (BL) | segment (frames) | start states | latency chosen (true {LATENCY}) | {} | worst |",
                    names.join(" | ")
                );
                println!("|{}", " --- |".repeat(names.len() + 5));
                *header = true;
            }
            let starts = if free_starts { "free" } else { "observed" };
            let errors: Vec<&str> = cells.iter().map(|(_, c)| c.as_str()).collect();
            println!(
                "| {noise} | {segment_frames} | {starts} | {:.2} | {} | {} |",
                fit.latency,
                errors.join(" | "),
                worst.map_or("–".into(), |w| format!("{:.1}%", 100.0 * w))
            );
            // the observed starts are the comparison: their bias may move the latency too
            assert!(
                !free_starts || (fit.latency - LATENCY as f64).abs() <= 0.5,
                "{noise} BL, {segment_frames} frames, {starts} starts: latency {}",
                fit.latency
            );
            if segment_frames == SEGMENT_FRAMES && free_starts {
                // no value fitted is no value within tolerance
                worst_free_default = worst.unwrap_or(f64::INFINITY);
            }
        }
    }
    worst_free_default
}

//! On a rig whose plant has no hydrodynamic interaction, capillary attraction or magnet lag,
//! moments ×λ, drags ×λ² and gradient gains ×λ leave every prediction the same: the fit holds
//! the scale by the convention without testing it, and fits the rest. The rig is rig 7 of
//! `magbench calibrate bench` at seed 0 (bulk liquid, 0.033 BL of detection noise, 3.79 frames
//! of latency, a 3.7 ms gradient coil). A standard error tested along an exact symmetry
//! measures only the integrator's tolerance and can pass for identified, and with the scale
//! left free the search runs the moments off (to 10¹¹ on this rig); the latency's quick fits,
//! over whole 40-frame segments, choose 2 frames here.
//!
//! The rig is env's plant and camera (`SimRig`) stepped frame by frame, with the benchmark's
//! seed: no sockets, no sleeps, no wall clock.

use crate::common;

use magbench_drivers::fit::{FitOptions, FitReport, Kind, ScaleFit, Status, calibrate, read_log};
use magbench_env::plant::DisturbancePreset;

/// The seed `calibrate bench` drew for its rig 7 (plant, camera and excitation).
const SEED: u64 = 24_044_858;

/// The rig's fit under `opts`, and its truth.
fn fit(opts: &FitOptions) -> (FitReport, DisturbancePreset) {
    let truth = common::fixture("bulk-rig-truth.toml");
    let base = common::fixture("bulk-rig-base.toml");
    let dir = tempfile::tempdir().unwrap();
    let alpha_max = truth.coil.alpha_max_deg.to_radians();
    let (scenario, path) = common::excite_seeded(&truth, 90.0, SEED, alpha_max, dir.path());
    let run = read_log(&path, scenario.agents()).unwrap();
    let fit = calibrate(&scenario, &base, vec![run], opts).unwrap();
    (fit, truth)
}

#[test]
fn a_scale_no_term_breaks_is_held_by_the_convention_and_the_rest_is_fitted() {
    let (fit, truth) = fit(&FitOptions::default());
    assert_eq!(fit.scale, ScaleFit::Convention(f64::INFINITY));
    let true_latency = truth.camera.latency.frames;
    assert!(
        (fit.latency - true_latency).abs() < 0.5,
        "latency {} frames, true {true_latency}",
        fit.latency
    );
    // the truth under the convention: the true moments' geometric mean is 1
    let f = &truth.fitted;
    let lambda = (f.moment.iter().map(|m| m.ln()).sum::<f64>() / f.moment.len() as f64).exp();
    let get = |k: Kind| fit.params.iter().find(|p| p.kind == k).unwrap().value;
    for i in 0..2 {
        let m = get(Kind::Moment(i)) / (f.moment[i] / lambda) - 1.0;
        assert!(m.abs() < 0.10, "moment[{i}] off by {m}");
        let g = get(Kind::GradientGain(i)) / (f.gradient_gain.unwrap()[i] / lambda) - 1.0;
        assert!(g.abs() < 0.05, "gradient gain {i} off by {g}");
    }
}

/// The camera is 3.79 frames late; a fit that may take at most 3 puts the latency at that
/// bound, with a finite standard error (fitted, or written as imprecise), and warns that the
/// camera may be later: a search that ran past the bound would find the prediction unchanged
/// there, a derivative of 0 and an infinite standard error, and hold the base's 2 frames as
/// "not identified".
#[test]
fn a_camera_later_than_the_search_allows_is_fitted_at_the_bound_and_warned_of() {
    let (fit, _) = fit(&FitOptions {
        max_latency: 3,
        ..FitOptions::default()
    });
    let latency = fit.params.iter().find(|p| p.kind == Kind::Latency).unwrap();
    assert!(
        matches!(latency.status, Status::Fitted | Status::Imprecise(_))
            && latency.se.is_some_and(f64::is_finite),
        "{latency:?}"
    );
    assert_eq!(latency.value, 3.0);
    let warnings = fit.warnings();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("upper bound, 3 frames") && w.contains("--max-latency")),
        "{warnings:?}"
    );
}

//! A fit must not gain by losing segments. On this rig (rig 13 of `magbench calibrate bench`
//! at seed 0: an interface without hydrodynamic interaction, 3.74 frames of latency, coils of
//! 22 and 28 ms), quick fits at the longer latencies could once drive every prediction into a
//! wall or into contact, score a mean squared residual of 0 and start the fit there; the
//! latency and both coils then came out "not identified". A failed prediction now costs
//! every row, and the fit compares only segments the base predicts at every latency.
//!
//! The rig is env's plant and camera (`SimRig`) stepped frame by frame, with the benchmark's
//! seed: no sockets, no sleeps, no wall clock.

use crate::common;

use magbench_drivers::fit::{FitOptions, Kind, Status, calibrate, read_log};

/// The seed `calibrate bench` drew for its rig 13 (plant, camera and excitation).
const SEED: u64 = 148_078_453;

#[test]
fn no_start_of_the_fit_wins_by_losing_segments() {
    let truth = common::fixture("interface-rig-truth.toml");
    let base = common::fixture("interface-rig-base.toml");
    let dir = tempfile::tempdir().unwrap();
    let alpha_max = truth.coil.alpha_max_deg.to_radians();
    let (scenario, path) = common::excite_seeded(&truth, 90.0, SEED, alpha_max, dir.path());
    let run = read_log(&path, scenario.agents()).unwrap();
    let fit = calibrate(&scenario, &base, vec![run], &FitOptions::default()).unwrap();
    for (l, ms) in &fit.latency_table {
        assert!(*ms > 1e-5, "the quick fit at {l} frames scored {ms:e} BL²");
    }
    let get = |k: Kind| fit.params.iter().find(|p| p.kind == k).unwrap();
    let latency = get(Kind::Latency);
    assert_eq!(latency.status, Status::Fitted, "{latency:?}");
    let true_latency = truth.camera.latency.frames;
    assert!(
        (fit.latency - true_latency).abs() < 0.5,
        "latency {} frames, true {true_latency}",
        fit.latency
    );
    for k in [Kind::FieldTau, Kind::GradientTau] {
        assert_eq!(get(k).status, Status::Fitted, "{:?}", get(k));
    }
}

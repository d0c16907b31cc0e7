//! A fitted value that trades off against one the fit set aside is reported imprecise through
//! it. On this rig (rig 12 of `magbench calibrate bench --seed 1`: bulk liquid with
//! hydrodynamic interaction, 2.24 frames of latency, a 6.9 ms field coil and a 27 ms gradient
//! coil) neither coil's τ is identified, and both are held at the base's (6 and 14 ms). The
//! latency is then seen through the gradient coil's delay, 13 ms short, and comes out 0.74
//! frames late with a standard error of 0.23 frames, claimed to ½ frame; with the two τ free
//! its standard error is 0.43 frames.
//!
//! The rig is env's plant and camera (`SimRig`) stepped frame by frame, with the benchmark's
//! seed: no sockets, no sleeps, no wall clock.

use crate::common;

use magbench_drivers::fit::{FitOptions, Kind, Status, calibrate, read_log};

/// The seed `calibrate bench --seed 1` drew for its rig 12 (plant, camera and excitation).
const SEED: u64 = 291_523_587;

#[test]
fn a_latency_that_trades_off_against_an_unidentified_coil_is_reported_imprecise_through_it() {
    let truth = common::fixture("seed1-rig12-truth.toml");
    let base = common::fixture("bulk-hydro-rig-base.toml");
    let dir = tempfile::tempdir().unwrap();
    let alpha_max = truth.coil.alpha_max_deg.to_radians();
    let (scenario, path) = common::excite_seeded(&truth, 90.0, SEED, alpha_max, dir.path());
    let run = read_log(&path, scenario.agents()).unwrap();
    let fit = calibrate(&scenario, &base, vec![run], &FitOptions::default()).unwrap();
    let get = |k: Kind| fit.params.iter().find(|p| p.kind == k).unwrap();
    let tau = get(Kind::GradientTau);
    assert!(matches!(tau.status, Status::Unidentified(_)), "{tau:?}");
    let latency = get(Kind::Latency);
    let Status::TradesOff(se) = latency.status else {
        panic!("{latency:?}")
    };
    assert_eq!(latency.se, Some(se));
    assert!(!Kind::Latency.claimed(se), "{latency:?}");
    assert!(se > Kind::Latency.identified_below_in_unit(), "{latency:?}");
    // its estimate is written
    assert_eq!(fit.preset.camera.latency.frames, latency.value);
    let warning = fit
        .warnings()
        .into_iter()
        .find(|w| w.starts_with("camera.latency.frames is imprecise: it trades off"));
    let warning = warning.unwrap_or_else(|| panic!("{:?}", fit.warnings()));
    assert!(warning.contains("coil_lag.gradient_tau_ms"), "{warning}");
    assert!(
        fit.lines()
            .iter()
            .any(|l| l.starts_with("camera.latency.frames") && l.contains("imprecise through")),
        "{:?}",
        fit.lines()
    );
}

//! `calibrate` on logs of a team stuck in contact, and its held-out check when the check cannot
//! tell the fitted preset from the base. A stuck stretch found in the observed positions is left
//! out of the fit and said so, or the log is refused naming the file and the reason when too
//! little is left; a check that cannot compare says so instead of printing numbers. The logs
//! come from env's plant and camera stepped frame by frame (`SimRig`: no sockets, no wall
//! clock).

use crate::common;

use std::sync::OnceLock;

use magbench_drivers::fit::model::Model;
use magbench_drivers::fit::{FitError, FitOptions, HeldOut, LoggedRun, calibrate, read_log};
use magbench_env::plant::DisturbancePreset;
use magbench_env::{Scenario, Vec2};

/// Seconds of excitation of the shared log: with 6 s stuck, enough for the 25 segments of 80
/// frames a fit takes.
const EXCITE_S: f64 = 60.0;

/// The base of the fits: the hydrodynamic-only preset of the walkthrough.
fn base() -> DisturbancePreset {
    let mut b = DisturbancePreset::ideal();
    b.hydrodynamics.enabled = true;
    b
}

/// [`EXCITE_S`] seconds of excitation on open-field under the noisy preset, read back.
fn log() -> (Scenario, LoggedRun) {
    static LOG: OnceLock<(Scenario, LoggedRun)> = OnceLock::new();
    LOG.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let (scenario, path) = common::excite_open_field(&common::noisy(), EXCITE_S, dir.path());
        let run = read_log(&path, scenario.agents()).unwrap();
        (scenario, run)
    })
    .clone()
}

/// `run` with agent 1 seen touching agent 0 (1 BL along x, with 0.03 BL of pseudo-random
/// detection noise per coordinate) from `from_s` seconds into the run: a stuck team.
fn stuck_from(run: &LoggedRun, from_s: f64) -> LoggedRun {
    let mut run = run.clone();
    let t0 = run.frames[0].t;
    for f in &mut run.frames {
        if f.t - t0 < from_s {
            continue;
        }
        let jitter = |c: u64| 0.03 * (((f.frame * 7 + c * 13) % 11) as f64 / 5.0 - 1.0);
        if let (Some(a), Some(_)) = (f.agents[0], f.agents[1]) {
            f.agents[1] = Some(a + Vec2::new(1.0 + jitter(0), jitter(1)));
        }
    }
    run
}

#[test]
fn a_team_stuck_for_the_last_part_is_left_out_of_the_fit_and_said_so() {
    let (scenario, run) = log();
    let stuck_s = 6.0;
    let run = stuck_from(&run, EXCITE_S - stuck_s);
    let fit = calibrate(&scenario, &base(), vec![run], &FitOptions::default())
        .unwrap_or_else(|e| panic!("refused: {e}"));
    let lines = fit.lines().join("\n");
    let excluded = fit.excluded_seconds();
    // the stretch starts where the pair was put at contact, give or take the frames around it
    assert!(
        (excluded - stuck_s).abs() <= 0.5,
        "excluded {excluded} s of the {stuck_s} s stuck:\n{lines}"
    );
    assert_eq!(fit.stuck.len(), 1);
    assert!(fit.stuck[0].stretches >= 1, "{:?}", fit.stuck[0]);
    assert!(lines.contains("excluded"), "{lines}");
    assert!(lines.contains("stuck in contact"), "{lines}");
    assert!(lines.contains("rig-log.csv"), "{lines}");
}

#[test]
fn a_team_stuck_for_most_of_the_log_is_refused_naming_the_file_and_the_reason() {
    let (scenario, run) = log();
    let run = stuck_from(&run, 4.0);
    match calibrate(&scenario, &base(), vec![run], &FitOptions::default()) {
        Err(FitError::Input(e)) => {
            assert!(e.file.contains("rig-log.csv"), "{e}");
            assert_eq!(e.field, "frames", "{e}");
            assert!(e.reason.contains("too little usable data"), "{e}");
            assert!(e.reason.contains("stuck in contact"), "{e}");
            assert!(e.reason.contains("a fit needs 25"), "{e}");
        }
        Err(e) => panic!("not an input error: {e}"),
        Ok(f) => panic!("a fit was made: {:?}", f.lines()),
    }
}

#[test]
fn a_fit_that_changes_nothing_has_a_held_out_check_that_says_it_cannot_tell() {
    let (scenario, run) = log();
    // every parameter held at the base: the fitted preset predicts what the base does
    let hold = Model::new(&scenario, &base(), vec![run.clone()], 4)
        .kinds
        .iter()
        .map(|k| k.name())
        .collect();
    let opts = FitOptions {
        hold,
        ..FitOptions::default()
    };
    let fit = calibrate(&scenario, &base(), vec![run], &opts).unwrap();
    let h = fit.held_out;
    assert!(h.compared >= 5, "{h:?}");
    assert!(h.rms().is_none(), "{h:?}");
    assert!(!h.fitted_better(), "{h:?}");
    let why = h.undecided().expect("the check cannot tell");
    assert!(why.contains("alike"), "{why}");
    let lines = fit.lines().join("\n");
    assert!(
        lines.contains("held-out check           cannot tell the fitted preset from the base"),
        "{lines}"
    );
    assert!(!lines.contains("prediction RMS"), "{lines}");
    assert!(
        fit.warnings()
            .iter()
            .any(|w| w.contains("held-out check cannot tell")),
        "{:?}",
        fit.warnings()
    );
}

#[test]
fn a_held_out_check_compares_only_segments_both_presets_predicted() {
    let seg = |v: f64| Some(vec![v, -v, 0.0, v]);
    // no segment predicted under both: nothing to compare, not an RMS of 0
    let none = HeldOut::compare(&[None, seg(0.1), None], &[seg(0.1), None, None]);
    assert_eq!(none.compared, 0);
    assert!(
        none.fitted_rms.is_nan() && none.base_rms.is_nan(),
        "{none:?}"
    );
    let why = none.undecided().unwrap();
    assert!(why.contains("only 0 of the 3"), "{why}");
    assert!(none.line().contains("cannot tell"), "{}", none.line());
    // too few compared
    let few = HeldOut::compare(&vec![seg(0.1); 4], &vec![seg(0.2); 4]);
    assert!(few.undecided().unwrap().contains("only 4 of the 4"));
    // enough, and different: a comparison
    let f: Vec<_> = (0..6).map(|_| seg(0.1)).collect();
    let b: Vec<_> = (0..6).map(|_| seg(0.2)).collect();
    let h = HeldOut::compare(&f, &b);
    assert_eq!(h.undecided(), None);
    assert!(h.fitted_better());
    let (fr, br) = h.rms().unwrap();
    assert!(
        (fr - 0.1).abs() < 1e-12 && (br - 0.2).abs() < 1e-12,
        "{h:?}"
    );
    assert!(h.line().contains("on 6 of the 6 segments"), "{}", h.line());
    // the base better: no comparison is missing, the fitted preset is simply worse
    let worse = HeldOut::compare(&b, &f);
    assert!(worse.rms().is_some() && !worse.fitted_better());
}

//! `calibrate` on logs it cannot fit: a log of another workspace, a number that is not one, a
//! log mostly gaps, a stuck team, a log too short. Each is an input error naming the file and the reason,
//! never a fit. The logs come from env's plant and camera stepped frame by frame (`SimRig`: no
//! sockets, no wall clock).

use crate::common;

use std::path::Path;

use magbench_drivers::fit::{FitError, FitOptions, calibrate, read_log};
use magbench_env::plant::DisturbancePreset;
use magbench_env::{InputError, Scenario};

/// The base of the fits: the hydrodynamic-only preset of the walkthrough.
fn base() -> DisturbancePreset {
    let mut b = DisturbancePreset::ideal();
    b.hydrodynamics.enabled = true;
    b
}

/// The input error of fitting the log at `path`, which must be one.
fn refused(
    scenario: &Scenario,
    path: &Path,
    edit: impl FnOnce(&mut magbench_drivers::fit::LoggedRun),
) -> InputError {
    let mut run = read_log(path, scenario.agents()).unwrap();
    edit(&mut run);
    match calibrate(scenario, &base(), vec![run], &FitOptions::default()) {
        Err(FitError::Input(e)) => e,
        Err(e) => panic!("not an input error: {e}"),
        Ok(f) => panic!("a fit was made: {:?}", f.lines()),
    }
}

#[test]
fn a_log_too_short_to_fit_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (scenario, path) = common::excite_open_field(&common::noisy(), 3.0, dir.path());
    let e = refused(&scenario, &path, |_| {});
    assert!(e.file.contains("rig-log.csv"), "{e}");
    assert!(e.reason.contains("too short"), "{e}");
}

#[test]
fn a_log_of_another_workspace_mostly_gaps_or_not_a_number_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (scenario, path) = common::excite_open_field(&common::noisy(), 12.0, dir.path());
    // another rig's workspace: every observation 100 BL further along x
    let e = refused(&scenario, &path, |r| {
        for f in &mut r.frames {
            for p in f.agents.iter_mut().flatten() {
                p.x += 100.0;
            }
        }
    });
    assert!(e.file.contains("rig-log.csv"), "{e}");
    assert!(e.reason.contains("outside"), "{e}");
    // a stuck pair: agent 1 touching agent 0 throughout
    let e = refused(&scenario, &path, |r| {
        for f in &mut r.frames {
            if let Some(a) = f.agents[0] {
                f.agents[1] = Some(a + magbench_env::Vec2::new(0.95, 0.0));
            }
        }
    });
    assert!(e.reason.contains("contact"), "{e}");
    // two frames in three lost
    let e = refused(&scenario, &path, |r| {
        let mut k = 0;
        r.frames.retain(|_| {
            k += 1;
            k % 3 == 0
        });
    });
    assert!(e.reason.contains("gaps"), "{e}");
    // a NaN in a position
    let text = std::fs::read_to_string(&path).unwrap();
    let head = text.lines().next().unwrap();
    let x0 = head.split(',').position(|c| c == "x0_bl").unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let k = (0..lines.len())
        .filter(|&k| lines[k].contains(",observation,"))
        .nth(5)
        .unwrap();
    let mut cells: Vec<String> = lines[k].split(',').map(String::from).collect();
    cells[x0] = "NaN".into();
    lines[k] = cells.join(",");
    let bad = dir.path().join("nan.csv");
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let e = read_log(&bad, scenario.agents()).unwrap_err();
    assert!(e.file.contains("nan.csv"), "{e}");
    assert!(e.reason.contains("not a finite number"), "{e}");
}

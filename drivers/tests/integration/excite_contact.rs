//! The excitation keeps a pair apart on a rig that reacts slowly. On this rig (rig 12 of
//! `magbench calibrate bench` at seed 0: an interface without hydrodynamic interaction,
//! 2.82 frames of latency, coils of 15 and 35 ms) the separation loop once repelled for a few
//! frames, saw the observed separation back above the band's lower edge before the rig had
//! acted on the repulsion, attracted again, and the pair touched at 5.5 s and stuck: the rest
//! of the log was a stuck team. A repulsion now holds for the slowest reaction the loop
//! allows for.
//!
//! The rig is env's plant and camera (`SimRig`) stepped frame by frame, with the benchmark's
//! seed: no sockets, no sleeps, no wall clock.

use crate::common;

use magbench_drivers::excite::{ExciteSetup, excite};
use magbench_drivers::watch::Watched;
use magbench_env::Scenario;
use magbench_trackers::SimRig;

/// The seed `calibrate bench` drew for its rig 12 (plant, camera and excitation).
const SEED: u64 = 2_001_733_016;

#[test]
fn a_slow_rig_at_an_interface_is_excited_without_its_pair_touching() {
    let truth = common::fixture("capillary-rig-truth.toml");
    let scenario = Scenario::load("open-field").unwrap();
    let mut sim = SimRig::new(&scenario, &truth, SEED);
    let world = (scenario.world.width, scenario.world.height);
    let mut watched = Watched::new(&mut sim, world);
    let setup = ExciteSetup {
        duration: 30.0,
        seed: SEED,
        gradient_limit: scenario.physics.gradient_limit(),
        alpha_max: truth.coil.alpha_max_deg.to_radians(),
        world: scenario.world.clone(),
    };
    let report = excite(&mut watched, &setup, None).unwrap();
    assert!(report.separation_overrides > 0, "{report:?}");
    assert_eq!(watched.touched_at, None, "{report:?}");
    assert_eq!(watched.left_at, None, "{report:?}");
}

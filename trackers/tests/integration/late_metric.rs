//! The path error is a distance to the planned path, not to a time-indexed point: a run that
//! follows the path exactly but late scores zero (and so does the team-synchronous error); the
//! time-indexed error sees the delay.

use crate::common;

use common::*;
use magbench_env::plant::Observation;
use magbench_env::{Control, PlanningModel, Vec2};
use magbench_trackers::{
    GroundTruth, LoopOptions, Mission, Reference, Rig, RigError, Trackers, track,
};

/// A rig whose agents move along the reference exactly, at half the planned pace and after a
/// one-second pause, whatever it is commanded.
struct LateRig {
    reference: Reference,
    frame: usize,
}

impl LateRig {
    fn positions(&self) -> Vec<Vec2> {
        // one integration sample (1/120 s of plan) per frame (1/60 s): half pace
        let k = self.frame.saturating_sub(60);
        self.reference.state(k).to_vec()
    }
}

impl Rig for LateRig {
    fn frame_period(&self) -> f64 {
        FRAME
    }
    fn observe(&mut self) -> Result<Observation, RigError> {
        let o = Observation {
            t: self.frame as f64 * FRAME,
            agents: self.positions().into_iter().map(Some).collect(),
        };
        self.frame += 1;
        Ok(o)
    }
    fn command(&mut self, _u: &Control) -> Result<(), RigError> {
        Ok(())
    }
    fn stop(&mut self) -> Result<(), RigError> {
        Ok(())
    }
    fn ground_truth(&self) -> Option<GroundTruth> {
        Some(GroundTruth {
            positions: self.reference.state(self.frame.saturating_sub(61)).to_vec(),
            wall_contacts: 0,
            agent_contact: false,
        })
    }
}

#[test]
fn error_is_zero_on_a_late_run_along_the_path() {
    let s = scenario("open-field");
    let model = PlanningModel::new(&s.physics);
    let plan = random_plan(&model, &s.checker_for_leg(0), &s.start, 12, 9);
    let reference = Reference::from_plan(&plan, &model);
    let mut rig = LateRig {
        reference: reference.clone(),
        frame: 0,
    };
    let spec = Trackers::builtin().spec("obc", &[], "test").unwrap();
    let opts = LoopOptions {
        time_factor: 2.5,
        time_slack: 2.0,
        replan_after: 0.0,
        ..spec.loop_options()
    };
    let out = track(
        &mut rig,
        spec.build().as_mut(),
        Mission::with_plan(&s, plan.clone()),
        &opts,
    );
    let m = &out.metrics;
    // observed and true positions both lie on the path, in step: path and team-synchronous
    // errors vanish, the time-indexed error does not
    assert!(m.rms_error_true_bl.unwrap() < 1e-12, "{m:?}");
    assert!(m.rms_error_sync_bl < 1e-9, "{m:?}");
    assert!(m.rms_error_time_bl > 0.1, "{m:?}");
    assert!(
        m.ticks > 60 + reference.len(),
        "the run covered the whole path, late"
    );
    assert!(
        m.rms_error_bl < 1e-12 && m.max_error_bl < 1e-12,
        "rms {:e}, max {:e}",
        m.rms_error_bl,
        m.max_error_bl
    );
    // the same run measured against the time-indexed reference is far off
    let timed = out
        .ticks
        .iter()
        .map(|t| (t.position(0) - reference.point(reference.index_at(t.t), 0)).norm())
        .fold(0.0, f64::max);
    assert!(timed > 0.5, "a time-indexed error would be {timed} BL");
}

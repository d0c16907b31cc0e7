//! A missed detection never crashes a tracker: it holds or predicts.

use crate::common;

use common::*;
use magbench_env::plant::{DisturbancePreset, Observation};
use magbench_env::{Control, PlanningModel};
use magbench_trackers::{GroundTruth, Mission, Rig, RigError, SimRig, Trackers, track};

/// Wraps a rig and blinds its camera: agent 1 is missed on frames 30–59, both agents on
/// frames 100–119, every 7th frame loses agent 0, and frame 150 fails outright (recoverable).
struct Blind<R: Rig> {
    inner: R,
    frame: usize,
}

impl<R: Rig> Rig for Blind<R> {
    fn frame_period(&self) -> f64 {
        self.inner.frame_period()
    }
    fn observe(&mut self) -> Result<Observation, RigError> {
        let mut o = self.inner.observe()?;
        let k = self.frame;
        self.frame += 1;
        if k == 150 {
            return Err(RigError::Recoverable("frame dropped".into()));
        }
        if (30..60).contains(&k) {
            o.agents[1] = None;
        }
        if (100..120).contains(&k) {
            o.agents.iter_mut().for_each(|a| *a = None);
        }
        if k % 7 == 3 {
            o.agents[0] = None;
        }
        Ok(o)
    }
    fn command(&mut self, u: &Control) -> Result<(), RigError> {
        assert!(u.is_finite(), "a tracker sent a non-finite command {u:?}");
        self.inner.command(u)
    }
    fn stop(&mut self) -> Result<(), RigError> {
        self.inner.stop()
    }
    fn latency(&self) -> f64 {
        self.inner.latency()
    }
    fn ground_truth(&self) -> Option<GroundTruth> {
        self.inner.ground_truth()
    }
}

#[test]
fn missed_detections_do_not_crash_any_tracker() {
    let s = scenario("open-field");
    let model = PlanningModel::new(&s.physics);
    let plan = random_plan(&model, &s.checker_for_leg(0), &s.start, 8, 21);
    for name in Trackers::builtin().names() {
        let spec = Trackers::builtin().spec(name, &[], "test").unwrap();
        let mut rig = Blind {
            inner: SimRig::new(&s, &DisturbancePreset::realistic(), 5),
            frame: 0,
        };
        let mut opts = spec.loop_options();
        opts.time_slack = 1.0;
        let out = track(
            &mut rig,
            spec.build().as_mut(),
            Mission::with_plan(&s, plan.clone()),
            &opts,
        );
        let m = &out.metrics;
        assert!(
            m.ticks > 160,
            "{name}: ran past the blind frames ({} ticks, {:?})",
            m.ticks,
            m.status
        );
        assert!(
            m.missed_detections >= 30 + 40 + 20,
            "{name}: {} misses counted",
            m.missed_detections
        );
        assert_eq!(m.rig_faults, 1, "{name}");
        for t in &out.ticks {
            assert!(
                t.estimate
                    .iter()
                    .all(|p| p.x.is_finite() && p.y.is_finite()),
                "{name}: estimate at {}",
                t.t
            );
        }
        if name != "open-loop" {
            // holding or predicting through the gaps keeps the team on its path
            assert!(!m.agent_contact, "{name}: agents touched");
            assert!(
                m.max_error_bl < 0.5,
                "{name}: max error {} BL",
                m.max_error_bl
            );
        }
    }
}

//! The loop stops the rig (zero field) on every exit path: a normal end, a fatal rig fault on
//! observe or on command, a cancel, and a panic in the tracker.

use crate::common;

use std::cell::Cell;
use std::rc::Rc;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use common::*;
use magbench_env::plant::{DisturbancePreset, Observation};
use magbench_env::{Control, PlanningModel};
use magbench_trackers::{
    GroundTruth, LoopOptions, Mission, Rig, RigError, RunStatus, SimRig, Tick, Tracker,
    TrackerContext, TrackerStatus, track,
};

/// A simulated rig that counts stops and can fail on the n-th observe or command.
struct Counting {
    inner: SimRig,
    stops: Rc<Cell<usize>>,
    fail_observe_at: Option<usize>,
    fail_command_at: Option<usize>,
    observes: usize,
    commands: usize,
}

impl Rig for Counting {
    fn frame_period(&self) -> f64 {
        self.inner.frame_period()
    }
    fn observe(&mut self) -> Result<Observation, RigError> {
        self.observes += 1;
        if Some(self.observes) == self.fail_observe_at {
            return Err(RigError::Fatal("camera unplugged".into()));
        }
        self.inner.observe()
    }
    fn command(&mut self, u: &Control) -> Result<(), RigError> {
        self.commands += 1;
        if Some(self.commands) == self.fail_command_at {
            return Err(RigError::Fatal("coil driver not answering".into()));
        }
        self.inner.command(u)
    }
    fn stop(&mut self) -> Result<(), RigError> {
        self.stops.set(self.stops.get() + 1);
        self.inner.stop()
    }
    fn ground_truth(&self) -> Option<GroundTruth> {
        self.inner.ground_truth()
    }
}

/// A tracker that panics on its 10th command. Until then it holds the field across the pair
/// (ψ = 90°, repulsion), so the agents cannot touch and end the run first, whatever the
/// preset draws.
struct Panicky(usize);

impl magbench_env::params::ParamSet for Panicky {}

impl Tracker for Panicky {
    fn name(&self) -> &str {
        "panicky"
    }
    fn reset(&mut self, _ctx: &TrackerContext) {}
    fn command(&mut self, _ctx: &TrackerContext, _tick: &Tick) -> Control {
        self.0 += 1;
        assert!(self.0 < 10, "tracker bug");
        Control::planar(std::f64::consts::FRAC_PI_2, 0.0, 0.0)
    }
    fn status(&self) -> TrackerStatus {
        TrackerStatus::default()
    }
}

fn rig(
    s: &magbench_env::Scenario,
    stops: &Rc<Cell<usize>>,
    obs: Option<usize>,
    cmd: Option<usize>,
) -> Counting {
    Counting {
        inner: SimRig::new(s, &DisturbancePreset::realistic(), 1),
        stops: stops.clone(),
        fail_observe_at: obs,
        fail_command_at: cmd,
        observes: 0,
        commands: 0,
    }
}

#[test]
fn the_rig_is_stopped_on_every_exit_path() {
    let s = scenario("open-field");
    let model = PlanningModel::new(&s.physics);
    let plan = random_plan(&model, &s.checker_for_leg(0), &s.start, 4, 2);
    let opts = LoopOptions {
        time_slack: 0.5,
        ..Default::default()
    };
    let obc = || {
        magbench_trackers::Trackers::builtin()
            .spec("obc", &[], "t")
            .unwrap()
            .build()
    };

    // normal end (time limit)
    let stops = Rc::new(Cell::new(0));
    let out = track(
        &mut rig(&s, &stops, None, None),
        obc().as_mut(),
        Mission::with_plan(&s, plan.clone()),
        &opts,
    );
    assert_eq!(out.metrics.status, RunStatus::Timeout);
    assert!(stops.get() >= 1);

    // fatal fault on observe, and on command
    for (o, c, what) in [
        (Some(30), None, "camera unplugged"),
        (None, Some(30), "coil driver"),
    ] {
        let stops = Rc::new(Cell::new(0));
        let out = track(
            &mut rig(&s, &stops, o, c),
            obc().as_mut(),
            Mission::with_plan(&s, plan.clone()),
            &opts,
        );
        assert_eq!(out.metrics.status, RunStatus::RigFault);
        assert!(
            out.message.as_deref().unwrap_or("").contains(what),
            "{:?}",
            out.message
        );
        assert!(stops.get() >= 1, "stopped after {what}");
    }

    // cancel (Ctrl-C)
    let stops = Rc::new(Cell::new(0));
    let cancel = Arc::new(AtomicBool::new(true));
    let opts_c = LoopOptions {
        cancel: Some(cancel),
        ..opts.clone()
    };
    let out = track(
        &mut rig(&s, &stops, None, None),
        obc().as_mut(),
        Mission::with_plan(&s, plan.clone()),
        &opts_c,
    );
    assert_eq!(out.metrics.status, RunStatus::Cancelled);
    assert!(stops.get() >= 1);

    // a panic inside the tracker: the guard stops the rig while unwinding
    let stops = Rc::new(Cell::new(0));
    let mut r = rig(&s, &stops, None, None);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        track(
            &mut r,
            &mut Panicky(0),
            Mission::with_plan(&s, plan.clone()),
            &opts,
        )
    }));
    assert!(result.is_err(), "the panic propagates");
    assert_eq!(stops.get(), 1, "stopped once, while unwinding");
}

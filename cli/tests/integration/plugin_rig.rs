//! A rig added from outside the workspace, as a plugin adds one: `Cli::new().rig::<R>(name)`,
//! then `track --rig-type NAME` and `rig run --rig-type NAME` run through it, and the
//! registry's unknown-name error lists it.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use magbench::Cli;
use magbench::prelude::*;
use magbench_env::World;
use magbench_env::plant::{DisturbancePreset, Observation};

/// Frames the plugin's rigs have delivered, over every run of this test binary.
static FRAMES: AtomicUsize = AtomicUsize::new(0);

/// A plugin's rig: env's simulated plant under a built-in preset named by its argument, that
/// counts its frames.
struct Counting {
    preset: DisturbancePreset,
}

impl RigKind for Counting {
    fn load(arg: &str, option: &str) -> Result<Self, OpenError> {
        let preset = DisturbancePreset::by_name(arg).ok_or_else(|| {
            InputError::new("<command line>", option, format!("no preset {arg:?}"))
        })?;
        Ok(Counting { preset })
    }
}

impl RigDescription for Counting {
    fn frame_period(&self) -> f64 {
        1.0 / self.preset.camera.fps
    }

    fn plant(&self) -> RigPlant {
        RigPlant {
            medium: self.preset.medium.clone(),
            coil_alpha_max_deg: self.preset.coil.alpha_max_deg,
            coil_source: "counting".into(),
        }
    }

    fn open(
        &self,
        scenario: &Scenario,
        seed: u64,
        _log_dir: Option<&Path>,
    ) -> Result<Box<dyn RunRig>, OpenError> {
        Ok(Box::new(CountingRun {
            sim: SimRig::new(scenario, &self.preset, seed),
            label: format!("counting:{}", self.preset.name),
        }))
    }
}

/// The counting rig opened for one run.
struct CountingRun {
    sim: SimRig,
    label: String,
}

impl Rig for CountingRun {
    fn frame_period(&self) -> f64 {
        self.sim.frame_period()
    }
    fn observe(&mut self) -> Result<Observation, RigError> {
        FRAMES.fetch_add(1, Ordering::SeqCst);
        self.sim.observe()
    }
    fn command(&mut self, u: &Control) -> Result<(), RigError> {
        self.sim.command(u)
    }
    fn stop(&mut self) -> Result<(), RigError> {
        self.sim.stop()
    }
    fn latency(&self) -> f64 {
        self.sim.latency()
    }
    fn set_world(&mut self, w: &World) -> Result<(), RigError> {
        self.sim.set_world(w)
    }
    fn ground_truth(&self) -> Option<GroundTruth> {
        self.sim.ground_truth()
    }
}

impl RunRig for CountingRun {
    fn label(&self) -> String {
        self.label.clone()
    }
    fn as_rig(&mut self) -> &mut dyn Rig {
        self
    }
}

/// The `metrics.json` a run wrote into `dir`.
fn metrics(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("metrics.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn a_plugin_rig_runs_track_and_rig_run() {
    let cli = Cli::new().rig::<Counting>("counting");
    assert_eq!(
        cli.registry().rigs().names(),
        ["simulated", "coil", "counting"]
    );
    let dir = tempfile::tempdir().unwrap();
    let (track_out, rig_out) = (dir.path().join("track"), dir.path().join("rig"));
    let before = FRAMES.load(Ordering::SeqCst);
    cli.run_args([
        "magbench",
        "track",
        "open-field",
        "--tracker",
        "obc",
        "--max-iters",
        "20000",
        "--rig-type",
        "counting",
        "--preset",
        "ideal",
        "--out",
        track_out.to_str().unwrap(),
    ])
    .unwrap_or_else(|e| panic!("track: {e}"));
    let m = metrics(&track_out);
    assert_eq!(m["preset"], "counting:ideal", "{m}");
    let after_track = FRAMES.load(Ordering::SeqCst);
    assert!(after_track > before, "the loop observed through the plugin");
    cli.run_args([
        "magbench",
        "rig",
        "run",
        "--rig-type",
        "counting",
        "--rig",
        "realistic",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--tracker",
        "obc",
        "--max-iters",
        "20000",
        "--out",
        rig_out.to_str().unwrap(),
    ])
    .unwrap_or_else(|e| panic!("rig run: {e}"));
    let m = metrics(&rig_out);
    assert_eq!(m["preset"], "counting:realistic", "{m}");
    assert!(FRAMES.load(Ordering::SeqCst) > after_track);
}

#[test]
fn rig_names_resolve_in_the_registry_given() {
    let args = [
        "magbench",
        "track",
        "open-field",
        "--tracker",
        "obc",
        "--rig-type",
        "counting",
    ];
    // the built-in registry does not know the plugin's rig: the option, and the known names
    let e = Cli::new().run_args(args).err().unwrap();
    assert_eq!(e.exit_code(), 2);
    let text = e.to_string();
    assert!(
        text.contains("unknown rig \"counting\"") && text.contains("simulated, coil"),
        "{text}"
    );
    // the plugin's own bad input names the option that gave it
    let e = Cli::new()
        .rig::<Counting>("counting")
        .run_args([
            "magbench",
            "rig",
            "run",
            "--rig-type",
            "counting",
            "--rig",
            "stormy",
            "open-field",
            "--planner",
            "goal-zoom-rrt",
            "--tracker",
            "obc",
        ])
        .err()
        .unwrap();
    assert_eq!(e.exit_code(), 2);
    assert!(
        e.to_string().contains("--rig") && e.to_string().contains("stormy"),
        "{e}"
    );
}

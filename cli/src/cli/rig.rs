//! `magbench rig emulate|check|redetect|run`: physical runs on a coil-and-camera rig, and the
//! emulator that stands in for one.

use magbench_env::input::Bound;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use clap::{Args, Subcommand};
use magbench_drivers::emulator::faults::{FAULT_SYNTAX, FaultPlan};
use magbench_drivers::emulator::render::RenderParams;
use magbench_drivers::emulator::{self, DeviceEndpoint, EmulatorConfig};
use magbench_drivers::rigfile::{CoilEndpoint, RigConfig};
use magbench_drivers::rigs::preset_named;
use magbench_drivers::{HardwareError, HardwareRig, check, interrupt, redetect};
use magbench_env::Scenario;

use super::plan_and_track::{TrackRun, tracker_spec};
use super::setup::SetupArgs;
use crate::Error;
use crate::output::{emit, outln, prepare_dir, prepare_file};
use crate::registry::Registry;

/// Rig subcommands.
#[derive(Debug, Subcommand)]
pub enum RigCmd {
    /// Play the device side of a rig: the coil protocol, env's plant, rendered camera frames.
    Emulate(Box<EmulateArgs>),
    /// Bring-up test: turn the pair in place at the magic angle in closed loop, report frames,
    /// detections and control-loop latency.
    Check(CheckArgs),
    /// Rerun the detector on recorded frames (and report its error when the truth is recorded).
    Redetect(RedetectArgs),
    /// Run a scenario on the rig: observe the start, plan from it, track in closed loop at the
    /// camera rate, log everything, stop with zero field, print the metrics of `magbench track`.
    Run(Box<RunArgs>),
    /// Drive the rig through an identification trajectory for `magbench calibrate`: field
    /// angles through 0°, ±54.74° and 90° to the separation, gradient steps on both axes,
    /// elevation steps; logs as `rig run` does.
    Excite(ExciteArgs),
}

/// `magbench rig excite`.
#[derive(Debug, Args)]
pub struct ExciteArgs {
    /// The rig file.
    #[arg(long, conflicts_with = "preset", required_unless_present = "preset")]
    pub rig: Option<PathBuf>,
    /// Instead of a rig: env's simulated plant and camera under this preset.
    #[arg(long)]
    pub preset: Option<String>,
    /// Scenario (workspace and start): open-field or another map with room to move.
    pub scenario: String,
    /// Folder for rig-log.csv.
    #[arg(long)]
    pub out: PathBuf,
    /// Seconds of excitation.
    #[arg(long, default_value_t = 120.0)]
    pub duration: f64,
    /// Seed of the block order (and of the simulated plant).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// `magbench rig run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The rig's description: for a `coil` rig, its rig file; for another rig type, what that
    /// type reads.
    #[arg(long)]
    pub rig: String,
    /// The rig type, by its registry name: `coil` (a coil-and-camera rig or its emulator),
    /// `simulated` (--rig is then a disturbance preset) or a plugin's.
    #[arg(long, default_value = "coil")]
    pub rig_type: String,
    /// A built-in scenario name or a scenario file.
    pub scenario: String,
    /// The planner of the first plan and of every replan: a name or a label such as
    /// `goal-zoom-rrt{k=5}`.
    #[arg(long)]
    pub planner: String,
    /// The tracker: a name (open-loop, obc, lookahead, formation, mppi or a plugin's; see
    /// `track --list`) or a label with parameters as experiment files write it, `obc{time_slack=5}`.
    #[arg(long)]
    pub tracker: String,
    /// Seed of the planner.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// A tracker or loop parameter, key=value (repeatable). Added to those of a --tracker
    /// label; a key in both is refused.
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// A planner parameter, key=value (repeatable). Added to those of a --planner label; a key
    /// in both is refused.
    #[arg(long = "planner-param", value_name = "KEY=VALUE")]
    pub planner_params: Vec<String>,
    /// Planner limits, objective, metric and flow of every planning call.
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Folder for rig-log.csv (every observation, command, fault), ticks.csv, metrics.json,
    /// plans.json, plan.json, the world plot and a GIF of the run.
    #[arg(long, default_value = "rig-run")]
    pub out: PathBuf,
    /// Print one JSON object on stdout instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// `magbench rig emulate`.
#[derive(Debug, Args)]
pub struct EmulateArgs {
    /// The rig file being emulated (calibration, limits, camera, pixel map).
    #[arg(long)]
    pub rig: PathBuf,
    /// Scenario (world and start positions): a built-in name or a file.
    pub scenario: String,
    /// Serve the coil link on a pseudo-terminal linked at PATH (opened by the host as a serial port).
    #[arg(long, conflicts_with = "listen")]
    pub port: Option<PathBuf>,
    /// Serve the coil link on TCP ADDR (default 127.0.0.1:0, a free port).
    #[arg(long)]
    pub listen: Option<String>,
    /// Frame stream TCP address.
    #[arg(long, default_value = "127.0.0.1:0")]
    pub camera_listen: String,
    /// Faults to inject, e.g. `drop=0.05,corrupt=0.02`.
    #[arg(long, default_value = "", help = format!("Faults to inject: {FAULT_SYNTAX}"))]
    pub faults: String,
    /// Disturbance preset of the plant: ideal, realistic, hardware or a preset file.
    #[arg(long, default_value = "realistic")]
    pub preset: String,
    /// Seed of the plant, the frames and the faults.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Device time runs this many times faster than wall time.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Stop after this much device time (s).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Lockstep: after each frame wait (up to 50 ms) for the host's command before advancing
    /// one frame. As fast as the host's loop and immune to machine load; --speed is ignored.
    #[arg(long)]
    pub lockstep: bool,
    /// Event log (CSV).
    #[arg(long, default_value = "emulator-log.csv")]
    pub log: PathBuf,
    /// Also record every frame and the true positions to this folder.
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Write a copy of the rig file with the live endpoints here, once ready.
    #[arg(long)]
    pub write_rig: Option<PathBuf>,
    /// Sensor noise (grey levels).
    #[arg(long, default_value_t = 3.0)]
    pub noise: f64,
    /// Optical blur, Gaussian σ (pixels).
    #[arg(long, default_value_t = 1.0)]
    pub blur: f64,
    /// Frames show the agents as the preset's camera sees them: late by its latency, displaced
    /// by its detection noise and bias (the detector's pixel error comes on top).
    #[arg(long)]
    pub preset_camera: bool,
}

/// `magbench rig check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The rig file.
    #[arg(long)]
    pub rig: PathBuf,
    /// Scenario whose start tells where the agents are (identities are assigned by it).
    pub scenario: String,
    /// Seconds of frames to run.
    #[arg(long, default_value_t = 5.0)]
    pub duration: f64,
    /// Folder for the CSV log of every observation, command and fault.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `magbench rig redetect`.
#[derive(Debug, Args)]
pub struct RedetectArgs {
    /// The rig file (pixel map and detector parameters).
    #[arg(long)]
    pub rig: PathBuf,
    /// Folder of recorded frames (`frames.csv` + PGM/PNG, or just images).
    pub frames: PathBuf,
    /// Scenario whose start primes the agents' identities (needed without recorded truth).
    #[arg(long)]
    pub scenario: Option<String>,
    /// CSV of the detections.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs a rig subcommand (`rig run` with the planners and trackers of `registry`).
pub fn run(cmd: RigCmd, registry: &Registry) -> Result<(), Error> {
    match cmd {
        RigCmd::Emulate(a) => emulate(*a),
        RigCmd::Check(a) => check_cmd(a),
        RigCmd::Redetect(a) => redetect_cmd(a),
        RigCmd::Run(a) => run_cmd(*a, registry),
        RigCmd::Excite(a) => excite_cmd(a),
    }
}

fn excite_cmd(a: ExciteArgs) -> Result<(), Error> {
    use magbench_drivers::excite::{ExciteSetup, excite, log_for};
    let scenario = Scenario::load(&a.scenario)?;
    option("--duration", RUN_DURATION, a.duration)?;
    prepare_dir(&a.out, "--out")?;
    let log = a.out.join("rig-log.csv");
    let mut setup = ExciteSetup {
        duration: a.duration,
        seed: a.seed,
        gradient_limit: scenario.physics.gradient_limit(),
        alpha_max: 0.0,
        world: scenario.world.clone(),
    };
    let rep = match (&a.rig, &a.preset) {
        (Some(rig), _) => {
            let (cfg, mut hw) = open_rig(rig, &scenario, Some(&log))?;
            outln!("rig: {}", hw.describe());
            setup.alpha_max = cfg.coil.alpha_max_deg.to_radians();
            excite(&mut hw, &setup, None)
        }
        (None, Some(p)) => {
            let preset = preset_named(p, "--preset")?;
            setup.alpha_max = preset.coil.alpha_max_deg.to_radians();
            let mut sim = magbench_trackers::SimRig::new(&scenario, &preset, a.seed);
            let mut l = log_for(&log, scenario.agents())
                .map_err(|e| Error::Failed(format!("{}: {e}", log.display())))?;
            excite(&mut sim, &setup, Some(&mut l))
        }
        (None, None) => return Err(Error::arg("--rig", "give --rig or --preset")),
    }
    .map_err(|e| Error::Failed(e.to_string()))?;
    outln!(
        "frames       {} over {:.2} s ({} detections missed)",
        rep.frames,
        rep.duration_s,
        rep.missed
    );
    outln!("commands     {}", rep.commands);
    outln!(
        "separation   {:.3} to {:.3} BL ({} frames held by the separation loop, {} by the centre-of-mass loop)",
        rep.separation_range.0,
        rep.separation_range.1,
        rep.separation_overrides,
        rep.com_overrides
    );
    outln!("log          {}", log.display());
    Ok(())
}

fn emulate(a: EmulateArgs) -> Result<(), Error> {
    let rig = RigConfig::load(&a.rig)?;
    let rig_text = std::fs::read_to_string(&a.rig)?;
    let scenario = Scenario::load(&a.scenario)?;
    let faults = FaultPlan::parse(&a.faults)
        .map_err(|r| Error::Input(r.under("--faults").in_file("<command line>")))?;
    let preset = preset_named(&a.preset, "--preset")?;
    option(
        "--speed",
        Bound::above(
            0.0,
            100.0,
            " × real time",
            "faster than 100× the emulated camera's frames outrun the renderer",
        ),
        a.speed,
    )?;
    option(
        "--noise",
        Bound::closed(0.0, 255.0, " grey levels", "an 8-bit image's range"),
        a.noise,
    )?;
    magbench_drivers::rigfile::BLUR_PX
        .check("--blur", a.blur)
        .map_err(|r| Error::arg("--blur", r.reason))?;
    if let Some(d) = a.duration {
        option("--duration", RUN_DURATION, d)?;
    }
    prepare_file(&a.log, "--log")?;
    if let Some(d) = &a.record {
        prepare_dir(d, "--record")?;
    }
    if let Some(f) = &a.write_rig {
        prepare_file(f, "--write-rig")?;
    }
    let endpoint = match (&a.port, &a.listen) {
        (Some(p), _) => DeviceEndpoint::Pty(p.clone()),
        (None, Some(l)) => DeviceEndpoint::Tcp(l.clone()),
        (None, None) => DeviceEndpoint::Tcp("127.0.0.1:0".into()),
    };
    let write_rig = a.write_rig.clone();
    let baud = match &rig.coil.endpoint {
        CoilEndpoint::Serial { baud, .. } => *baud,
        CoilEndpoint::Tcp(_) => 115_200,
    };
    let on_ready = Box::new(move |coil: &str, camera: &str| {
        let ep = match coil.split_once(' ') {
            Some(("serial", p)) => CoilEndpoint::Serial {
                path: p.to_string(),
                baud,
            },
            Some((_, addr)) => CoilEndpoint::Tcp(addr.to_string()),
            None => CoilEndpoint::Tcp(coil.to_string()),
        };
        if let Some(path) = &write_rig {
            match RigConfig::with_endpoints(&rig_text, &ep, Some(camera)) {
                Ok(text) => {
                    let tmp = path.with_extension("tmp");
                    if std::fs::write(&tmp, text)
                        .and_then(|_| std::fs::rename(&tmp, path))
                        .is_err()
                    {
                        eprintln!("error: cannot write {}", path.display());
                    }
                }
                Err(e) => eprintln!("error: {e}"),
            }
        }
        let _ = emit(&format!("coil: {coil}\ncamera: {camera}\nready\n"));
    });
    let stop = Arc::new(AtomicBool::new(false));
    let cfg = EmulatorConfig {
        rig,
        scenario,
        endpoint,
        camera_listen: a.camera_listen,
        faults,
        preset,
        render: RenderParams {
            noise: a.noise,
            blur_px: a.blur,
            ..RenderParams::default()
        },
        preset_camera: a.preset_camera,
        seed: a.seed,
        clock: magbench_drivers::clock::wall(),
        speed: a.speed,
        lockstep: a.lockstep,
        duration: a.duration,
        log: a.log,
        record: a.record,
        on_ready,
        on_event: None,
    };
    emulator::run(cfg, stop).map_err(|e| Error::Failed(e.to_string()))
}

fn open_rig(
    rig_path: &Path,
    scenario: &Scenario,
    log: Option<&Path>,
) -> Result<(RigConfig, HardwareRig), Error> {
    let rig = RigConfig::load(rig_path)?;
    let field = rig.coil.field_mt.unwrap_or(scenario.physics.field_mt);
    let abort = interrupt::interrupt_flag().map_err(HardwareError::from)?;
    let hw = HardwareRig::open(&rig, field, &scenario.start, abort, log)?;
    Ok((rig, hw))
}

fn check_cmd(a: CheckArgs) -> Result<(), Error> {
    let scenario = Scenario::load(&a.scenario)?;
    option("--duration", RUN_DURATION, a.duration)?;
    let log = match &a.out {
        Some(d) => {
            prepare_dir(d, "--out")?;
            Some(d.join("rig-log.csv"))
        }
        None => None,
    };
    let (_, mut hw) = open_rig(&a.rig, &scenario, log.as_deref())?;
    outln!("rig: {}", hw.describe());
    let r = check::spin_check(&mut hw, a.duration)?;
    outln!(
        "frames       {} ({} dropped, {} stuck) over {:.2} s",
        r.frames,
        r.dropped_frames,
        r.stuck_frames,
        r.duration_s
    );
    outln!("detections   {} missed", r.missed_detections);
    outln!("commands     {} ({} faults logged)", r.commands, r.faults);
    outln!(
        "pair         turned {:.1}°, separation {:.3} → {:.3} BL",
        r.turned_deg,
        r.separation.0,
        r.separation.1
    );
    match r.latency_ms {
        Some((m, p99)) => {
            outln!("latency      frame arrival → command sent: median {m:.3} ms, p99 {p99:.3} ms")
        }
        None => outln!("latency      no command followed a frame"),
    }
    if let Some(l) = log {
        outln!("log          {}", l.display());
    }
    Ok(())
}

fn redetect_cmd(a: RedetectArgs) -> Result<(), Error> {
    let rig = RigConfig::load(&a.rig)?;
    if let Some(f) = &a.out {
        prepare_file(f, "--out")?;
    }
    let prior = match &a.scenario {
        Some(s) => Some(Scenario::load(s)?.start),
        None => None,
    };
    if a.frames.join("frames.csv").exists() {
        magbench_drivers::camera::read_index(&a.frames)?;
    }
    let r = redetect::redetect(&rig, &a.frames, prior.as_deref(), a.out.as_deref())?;
    outln!("frames       {}", r.frames);
    outln!("detections   {} ({} missed)", r.detections, r.missed);
    if let Some((rms, max)) = r.error_px {
        outln!("error        RMS {rms:.4} px, max {max:.4} px (against the recorded truth)");
    }
    outln!("detect time  {:.3} ms per frame", r.mean_detect_ms);
    Ok(())
}

fn run_cmd(a: RunArgs, registry: &Registry) -> Result<(), Error> {
    let scenario = Scenario::load(&a.scenario)?;
    let tracker = tracker_spec(registry, &a.tracker, &a.params)?;
    let setup = a.setup.setup()?;
    super::plan_and_track::run(TrackRun {
        registry,
        scenario: &scenario,
        rig: registry.rigs().load(&a.rig_type, &a.rig, "--rig")?,
        planner: Some(a.planner),
        planner_params: &a.planner_params,
        plan: None,
        force: false,
        tracker,
        seed: a.seed,
        setup,
        out: Some(a.out),
        gif: false,
        json: a.json,
    })
}

/// How long `rig excite` and `rig check` may drive a rig: a day, so that no accepted duration
/// runs unbounded.
const RUN_DURATION: Bound = Bound::above(
    0.0,
    86_400.0,
    " s",
    "a day bounds a rig session and its log",
);

/// A command-line number checked against its bound, refused naming the option.
fn option(name: &str, bound: Bound, v: f64) -> Result<f64, Error> {
    bound.check(name, v).map_err(|r| Error::arg(name, r.reason))
}

//! `magbench rig emulate|check|replay|run`: physical runs on a coil-and-camera rig, and the
//! emulator that stands in for one.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use clap::{Args, Subcommand};
use magbench_drivers::emulator::faults::{FAULT_SYNTAX, FaultPlan};
use magbench_drivers::emulator::render::RenderParams;
use magbench_drivers::emulator::{self, DeviceEndpoint, EmulatorConfig};
use magbench_drivers::rigfile::{CoilEndpoint, RigConfig};
use magbench_drivers::{HardwareRig, check, interrupt, replay, stats};
use magbench_env::plant::DisturbancePreset;
use magbench_env::{Scenario, Vec2};
use magbench_planners::{Limits, Problem};
use magbench_trackers::{Mission, RunStatus, TrackerSpec};
use serde_json::{Value, json};

use crate::CliError;

/// Rig subcommands.
#[derive(Debug, Subcommand)]
pub enum RigCmd {
    /// Play the device side of a rig: the coil protocol, env's plant, rendered camera frames.
    Emulate(Box<EmulateArgs>),
    /// Bring-up test: turn the pair in place at the magic angle in closed loop, report frames,
    /// detections and control-loop latency.
    Check(CheckArgs),
    /// Rerun the detector on recorded frames (and report its error when the truth is recorded).
    Replay(ReplayArgs),
    /// Run a scenario on the rig: observe the start, plan from it, track in closed loop at the
    /// camera rate, log everything, stop with zero field, print the metrics of `magbench track`.
    Run(Box<RunArgs>),
}

/// `magbench rig run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The rig file.
    #[arg(long)]
    pub rig: PathBuf,
    /// A built-in scenario name or a scenario file.
    pub scenario: String,
    /// The planner of the first plan and of every replan.
    #[arg(long)]
    pub planner: String,
    /// The tracker: open-loop, obc or lookahead.
    #[arg(long)]
    pub tracker: String,
    /// Seed of the planner.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// A tracker or loop parameter, key=value (repeatable).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// A planner parameter, key=value (repeatable).
    #[arg(long = "planner-param", value_name = "KEY=VALUE")]
    pub planner_params: Vec<String>,
    /// Planner iteration limit of every planning call.
    #[arg(long)]
    pub max_iters: Option<u64>,
    /// Planner time limit of every planning call (s).
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Folder for rig-log.csv (every observation, command, fault), ticks.csv, metrics.json and
    /// plans.json.
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
    /// Disturbance preset of the plant (ideal or realistic).
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

/// `magbench rig replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
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

/// Runs a rig subcommand.
pub fn run(cmd: RigCmd) -> Result<(), CliError> {
    match cmd {
        RigCmd::Emulate(a) => emulate(*a),
        RigCmd::Check(a) => check_cmd(a),
        RigCmd::Replay(a) => replay_cmd(a),
        RigCmd::Run(a) => run_cmd(*a),
    }
}

fn emulate(a: EmulateArgs) -> Result<(), CliError> {
    let rig = RigConfig::load(&a.rig)?;
    let rig_text = std::fs::read_to_string(&a.rig)?;
    let scenario = Scenario::load(&a.scenario)?;
    let faults = FaultPlan::parse(&a.faults).map_err(|r| CliError::arg("--faults", r))?;
    let preset = DisturbancePreset::by_name(&a.preset).ok_or_else(|| {
        CliError::arg(
            "--preset",
            format!(
                "unknown preset {:?}; use {}",
                a.preset,
                DisturbancePreset::NAMES.join(" or ")
            ),
        )
    })?;
    if !(a.speed.is_finite() && a.speed > 0.0 && a.speed <= 100.0) {
        return Err(CliError::arg(
            "--speed",
            format!("must be in (0, 100], got {}", a.speed),
        ));
    }
    if !(a.noise.is_finite() && a.noise >= 0.0 && a.blur.is_finite() && a.blur >= 0.0) {
        return Err(CliError::arg("--noise/--blur", "must be finite and ≥ 0"));
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
        println!("coil: {coil}");
        println!("camera: {camera}");
        println!("ready");
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
        seed: a.seed,
        speed: a.speed,
        lockstep: a.lockstep,
        duration: a.duration,
        log: a.log,
        record: a.record,
        on_ready,
    };
    emulator::run(cfg, stop).map_err(CliError::Failed)
}

fn open_rig(
    rig_path: &Path,
    scenario: &Scenario,
    log: Option<&Path>,
) -> Result<(RigConfig, HardwareRig), CliError> {
    let rig = RigConfig::load(rig_path)?;
    let field = rig.coil.field_mt.unwrap_or(scenario.physics.field_mt);
    let hw = HardwareRig::open(
        &rig,
        field,
        &scenario.start,
        interrupt::interrupt_flag(),
        log,
    )
    .map_err(|e| CliError::Failed(e.to_string()))?;
    Ok((rig, hw))
}

fn check_cmd(a: CheckArgs) -> Result<(), CliError> {
    let scenario = Scenario::load(&a.scenario)?;
    if !(a.duration.is_finite() && a.duration > 0.0) {
        return Err(CliError::arg(
            "--duration",
            format!("must be > 0, got {}", a.duration),
        ));
    }
    let log = match &a.out {
        Some(d) => {
            std::fs::create_dir_all(d)?;
            Some(d.join("rig-log.csv"))
        }
        None => None,
    };
    let (_, mut hw) = open_rig(&a.rig, &scenario, log.as_deref())?;
    println!("rig: {}", hw.describe());
    let r = check::spin_check(&mut hw, a.duration).map_err(|e| CliError::Failed(e.to_string()))?;
    println!(
        "frames       {} ({} dropped, {} stuck) over {:.2} s",
        r.frames, r.dropped_frames, r.stuck_frames, r.duration_s
    );
    println!("detections   {} missed", r.missed_detections);
    println!("commands     {} ({} faults logged)", r.commands, r.faults);
    println!(
        "pair         turned {:.1}°, separation {:.3} → {:.3} BL",
        r.turned_deg, r.separation.0, r.separation.1
    );
    match r.latency_ms {
        Some((m, p99)) => {
            println!("latency      frame arrival → command sent: median {m:.3} ms, p99 {p99:.3} ms")
        }
        None => println!("latency      no command followed a frame"),
    }
    if let Some(l) = log {
        println!("log          {}", l.display());
    }
    Ok(())
}

fn replay_cmd(a: ReplayArgs) -> Result<(), CliError> {
    let rig = RigConfig::load(&a.rig)?;
    let prior = match &a.scenario {
        Some(s) => Some(Scenario::load(s)?.start),
        None => None,
    };
    let r = replay::replay(&rig, &a.frames, prior.as_deref(), a.out.as_deref())
        .map_err(CliError::Failed)?;
    println!("frames       {}", r.frames);
    println!("detections   {} ({} missed)", r.detections, r.missed);
    if let Some((rms, max)) = r.error_px {
        println!("error        RMS {rms:.4} px, max {max:.4} px (against the recorded truth)");
    }
    println!("detect time  {:.3} ms per frame", r.mean_detect_ms);
    Ok(())
}

fn kv_list(list: &[String]) -> Result<Vec<(String, String)>, CliError> {
    list.iter()
        .map(|kv| {
            magbench_trackers::registry::parse_param(kv, "<command line>").map_err(CliError::from)
        })
        .collect()
}

/// Frames with both agents seen that make up the observed start.
const START_FRAMES: usize = 10;

/// The start as the rig sees it: the mean of the first frames in which every agent is found.
fn observe_start(hw: &mut HardwareRig, agents: usize) -> Result<Vec<Vec2>, CliError> {
    let mut sum = vec![Vec2::zeros(); agents];
    let (mut n, mut frames) = (0, 0);
    while n < START_FRAMES {
        let o = hw.observe().map_err(|e| CliError::Failed(e.to_string()))?;
        frames += 1;
        if frames > 120 {
            return Err(CliError::Failed(format!(
                "the detector found every agent in only {n} of {frames} frames at the start; check the rig's [detector] and [pixels] calibration (magbench rig replay helps)"
            )));
        }
        if o.agents.iter().all(|a| a.is_some()) {
            for (s, a) in sum.iter_mut().zip(&o.agents) {
                *s += a.expect("checked");
            }
            n += 1;
        }
    }
    Ok(sum.into_iter().map(|s| s / n as f64).collect())
}

fn run_cmd(a: RunArgs) -> Result<(), CliError> {
    let scenario = Scenario::load(&a.scenario)?;
    let rig = RigConfig::load(&a.rig)?;
    let spec = TrackerSpec::parse(&a.tracker, &kv_list(&a.params)?, "<command line>")?;
    let mut planner =
        magbench_planners::registry::create(&a.planner, &kv_list(&a.planner_params)?)?;
    if let Some(t) = a.time_limit
        && !(t.is_finite() && t > 0.0)
    {
        return Err(CliError::arg(
            "--time-limit",
            format!("must be a number of seconds > 0, got {t}"),
        ));
    }
    let limits = (a.max_iters.is_some() || a.time_limit.is_some()).then(|| Limits {
        max_iterations: a.max_iters,
        time_limit: a.time_limit.map(std::time::Duration::from_secs_f64),
    });
    std::fs::create_dir_all(&a.out)?;
    let field = rig.coil.field_mt.unwrap_or(scenario.physics.field_mt);
    let abort = interrupt::interrupt_flag();
    let mut hw = HardwareRig::open(
        &rig,
        field,
        &scenario.start,
        abort.clone(),
        Some(&a.out.join("rig-log.csv")),
    )
    .map_err(|e| CliError::Failed(e.to_string()))?;
    eprintln!("rig: {}", hw.describe());

    // observe the start, and plan from it (the field is zero meanwhile)
    let start = observe_start(&mut hw, scenario.agents())?;
    let offset = start
        .iter()
        .zip(&scenario.start)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    eprintln!(
        "observed start: {} (at most {offset:.3} BL from the scenario's start)",
        start
            .iter()
            .map(|p| format!("({:.3}, {:.3})", p.x, p.y))
            .collect::<Vec<_>>()
            .join(" ")
    );
    let checker = scenario.checker_for_leg(0);
    if !checker.is_valid(&start) {
        let _ = hw.stop();
        return Err(CliError::Failed(
            "the observed start is in collision or outside the proximity range; place the agents at the scenario's start".into(),
        ));
    }
    let mut problem = Problem::from_scenario(&scenario, 0, Some(&start), a.seed);
    if let Some(l) = limits {
        problem.limits = l;
    }
    let result = planner.solve(&problem);
    eprintln!(
        "plan: {} in {:.2} s ({} edges, {:.1} s long)",
        if result.solved {
            "solved"
        } else if result.approximate {
            "approximate"
        } else {
            "not found"
        },
        result.time_s,
        result.plan.edges(),
        result.plan.durations.iter().sum::<f64>()
    );
    if !(result.solved || result.approximate) || result.plan.edges() == 0 {
        let _ = hw.stop();
        return Err(CliError::Failed(format!(
            "{} found no plan from the observed start",
            a.planner
        )));
    }
    let solved = result.solved;
    let mission = Mission {
        scenario: &scenario,
        plan: Some(result.plan),
        plan_time_s: result.time_s,
        plan_solved: solved,
        planner: Some(planner.as_mut()),
        limits,
        seed: a.seed,
    };
    let mut tracker = spec.build();
    let mut opts = spec.loop_options();
    opts.record_ticks = true;
    opts.cancel = Some(abort);
    let out = magbench_trackers::track(&mut hw, tracker.as_mut(), mission, &opts);
    let stopped = hw.stop();
    let stats = hw.stats().clone();
    drop(hw);

    let lat = |q: f64| stats::percentile(&stats.latencies_ms, q);
    let mut v = json!({
        "scenario": scenario.name,
        "planner": a.planner,
        "tracker": spec.name,
        "tracker_label": spec.label(),
        "seed": a.seed,
        "preset": format!("rig:{}", rig.name),
        "solved": solved,
    });
    if let (Value::Object(o), Value::Object(m)) = (
        &mut v,
        serde_json::to_value(&out.metrics).expect("metrics serialize"),
    ) {
        o.extend(m);
        o.insert(
            "per_agent".into(),
            serde_json::to_value(&out.per_agent).expect("serialize"),
        );
        o.insert("message".into(), json!(out.message));
        o.insert(
            "observed_start".into(),
            json!(start.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>()),
        );
        o.insert(
            "rig".into(),
            json!({
                "frames": stats.frames,
                "dropped_frames": stats.dropped_frames,
                "skipped_frames": stats.skipped_frames,
                "stuck_frames": stats.stuck_frames,
                "missed_detections": stats.missed_detections,
                "commands": stats.commands,
                "clamped_commands": stats.clamped_commands,
                "faults": stats.faults,
                "latency_median_ms": lat(0.5),
                "latency_p99_ms": lat(0.99),
            }),
        );
    }
    std::fs::write(
        a.out.join("metrics.json"),
        serde_json::to_string_pretty(&v).expect("json"),
    )?;
    let ticks = std::fs::File::create(a.out.join("ticks.csv"))?;
    magbench_trackers::write_ticks_csv(std::io::BufWriter::new(ticks), &out.ticks)
        .map_err(|e| CliError::Failed(e.to_string()))?;
    let plans: Vec<Value> = out
        .plans
        .iter()
        .map(|p| json!({"leg": p.leg, "start_t_s": p.start_t, "reason": p.reason, "solved": p.solved, "planning_time_s": p.planning_time_s, "plan": p.plan}))
        .collect();
    std::fs::write(
        a.out.join("plans.json"),
        serde_json::to_string_pretty(&plans).expect("json"),
    )?;
    if a.json {
        println!(
            "{}",
            serde_json::to_string(&v).map_err(|e| CliError::Failed(e.to_string()))?
        );
    } else {
        print!("{}", super::track::summary_text(&v));
        println!(
            "rig           {} frames ({} dropped, {} skipped while planning or busy, {} stuck), {} missed detections, {} commands ({} clamped), {} faults",
            stats.frames,
            stats.dropped_frames,
            stats.skipped_frames,
            stats.stuck_frames,
            stats.missed_detections,
            stats.commands,
            stats.clamped_commands,
            stats.faults
        );
        if let (Some(m), Some(p)) = (lat(0.5), lat(0.99)) {
            println!("latency       frame arrival → command sent: median {m:.3} ms, p99 {p:.3} ms");
        }
        println!("log           {}", a.out.join("rig-log.csv").display());
    }
    if out.metrics.status == RunStatus::RigFault {
        return Err(CliError::Failed(format!(
            "rig fault: {}",
            out.message.unwrap_or_else(|| "unknown".into())
        )));
    }
    if let Err(e) = stopped {
        return Err(CliError::Failed(format!("stopping the rig: {e}")));
    }
    Ok(())
}

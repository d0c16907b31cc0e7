//! One rig of the benchmark: its true preset drawn from the ranges, the base preset the fit
//! starts from, and the run — `rig excite` on env's plant and camera (`SimRig`), then
//! `calibrate` on its log.

use std::path::Path;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use magbench_drivers::excite::{ExciteSetup, excite, log_for};
use magbench_drivers::fit::{FitError, FitOptions, FitReport, calibrate, read_log};
use magbench_env::Scenario;
use magbench_env::plant::{DisturbancePreset, Fitted, Medium};
use magbench_trackers::SimRig;

use super::ranges::Ranges;
use magbench_drivers::watch::Watched;

/// One drawn rig: its true preset and the seed of its plant, camera and excitation.
#[derive(Debug, Clone)]
pub struct Rig {
    /// Index in the benchmark (0-based).
    pub index: usize,
    /// Seed of the plant's and camera's draws and of the excitation's block order.
    pub seed: u64,
    /// The rig's preset, which the fit does not see.
    pub truth: DisturbancePreset,
}

impl Rig {
    /// Whether the agents sit at a liquid–air interface.
    pub fn interface(&self) -> bool {
        matches!(self.truth.medium, Medium::Interface(_))
    }

    /// Whether the agents interact hydrodynamically.
    pub fn hydrodynamics(&self) -> bool {
        self.truth.hydrodynamics.enabled
    }

    /// The medium's name in the outputs: `interface` or `bulk`.
    pub fn medium_name(&self) -> &'static str {
        if self.interface() {
            "interface"
        } else {
            "bulk"
        }
    }
}

/// The `hardware` preset's interface (water–air, its contact angle), for rigs at one; its
/// agent-to-agent spread of contact angles is left out (it acts through per-run draws the
/// fit does not model).
pub fn interface() -> Medium {
    let hw = DisturbancePreset::by_name("hardware").expect("the hardware preset is built in");
    match hw.medium {
        Medium::Interface(mut i) => {
            i.contact_angle_spread_deg = 0.0;
            Medium::Interface(i)
        }
        Medium::Bulk => unreachable!("the hardware preset is at an interface"),
    }
}

/// Seed of the field biases' stream, mixed with the benchmark's seed.
const BIAS_STREAM: u64 = 0xB1A5;

/// `count` rigs of `agents` agents drawn from `ranges`, seeded by `seed`: the same seed and
/// ranges give the same rigs. Each rig is `ideal` with its medium (at an interface, with
/// capillary attraction), hydrodynamic interaction,
/// coil time constants (no slew limit), camera latency and detection noise, and per-agent
/// moments, drags, gradient gains and coil frame rotation (field bias) as `[fitted]` values
/// (no drift). The field biases come from a stream of their own, so the other values of a
/// seed's rigs do not depend on the bias's range.
pub fn draw(ranges: &Ranges, seed: u64, count: usize, agents: usize) -> Vec<Rig> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut biases = ChaCha8Rng::seed_from_u64(seed ^ BIAS_STREAM);
    (0..count)
        .map(|index| {
            let mut u = |r: [f64; 2]| uniform(&mut rng, r);
            let mut p = DisturbancePreset::ideal();
            p.name = format!("rig-{index}");
            p.description = format!("calibration benchmark rig {index} (seed {seed})");
            p.coil_lag.enabled = true;
            p.coil_lag.field_tau_ms = u(ranges.field_tau_ms);
            p.coil_lag.gradient_tau_ms = u(ranges.gradient_tau_ms);
            p.coil_lag.field_slew_mt_per_s = 0.0;
            p.coil_lag.gradient_slew_mt_per_m_per_s = 0.0;
            let latency = u(ranges.latency_frames);
            p.camera.latency.enabled = latency > 0.0;
            p.camera.latency.frames = latency;
            p.camera.latency.jitter_frames = 0.0;
            p.camera.noise.enabled = true;
            p.camera.noise.sigma_bl = u(ranges.noise_bl);
            p.fitted = Fitted {
                enabled: true,
                moment: (0..agents).map(|_| u(ranges.moment)).collect(),
                drag: (0..agents).map(|_| u(ranges.drag)).collect(),
                gradient_gain: Some([u(ranges.gradient_gain), u(ranges.gradient_gain)]),
                field_bias_deg: Some(uniform(&mut biases, ranges.field_bias_deg)),
                drift_bl_s: Some([0.0, 0.0]),
            };
            let share = |s: f64, x: f64| x < s;
            if share(ranges.interface_share, u([0.0, 1.0])) {
                p.medium = interface();
                p.capillary.enabled = true;
            }
            p.hydrodynamics.enabled = share(ranges.hydrodynamics_share, u([0.0, 1.0]));
            let rig_seed = rng.random_range(0..u32::MAX as u64);
            Rig {
                index,
                seed: rig_seed,
                truth: p,
            }
        })
        .collect()
}

/// A value drawn uniformly from `[low, high]` (`low` when the range is one value).
fn uniform(rng: &mut ChaCha8Rng, [lo, hi]: [f64; 2]) -> f64 {
    match lo < hi {
        true => rng.random_range(lo..=hi),
        false => lo,
    }
}

/// The preset the fit starts from: what a lab knows of its rig — the medium, capillary
/// attraction at an interface and whether the agents interact — with the `hardware` preset's numbers for the coils (6 and 14 ms) and the
/// camera (2 frames, 0.02 BL), and no fitted values.
pub fn base(rig: &Rig) -> DisturbancePreset {
    let hw = DisturbancePreset::by_name("hardware").expect("the hardware preset is built in");
    let mut p = DisturbancePreset::ideal();
    p.name = "base".into();
    p.description =
        "ideal with the rig's medium and hydrodynamic switch, hardware's coils and camera".into();
    p.medium = rig.truth.medium.clone();
    p.hydrodynamics.enabled = rig.truth.hydrodynamics.enabled;
    p.capillary.enabled = rig.truth.capillary.enabled;
    p.coil_lag = hw.coil_lag.clone();
    p.coil_lag.field_slew_mt_per_s = 0.0;
    p.coil_lag.gradient_slew_mt_per_m_per_s = 0.0;
    p.camera.latency.enabled = true;
    p.camera.latency.frames = hw.camera.latency.frames;
    p.camera.noise.enabled = true;
    p.camera.noise.sigma_bl = hw.camera.noise.sigma_bl;
    p
}

/// How a rig's run ended.
pub enum Outcome {
    /// Excited and fitted.
    Fitted(Box<FitReport>),
    /// The excitation failed or `calibrate` refused the log: why.
    Failed(String),
}

/// Excites `rig` for `duration` seconds on `scenario` (env's plant and camera, stepped frame
/// by frame), logs it to `dir/rig-log.csv`, writes `dir/truth.toml`, `dir/base.toml` and, when
/// the fit succeeds,
/// `dir/fitted.toml`, and fits `base` to the log. I/O failures are errors; a failed
/// excitation (an error, agents that touched and stuck where `calibrate` did not find it) or a
/// refused log is an [`Outcome::Failed`] saying what `calibrate` made of the log; a log whose
/// stuck stretch `calibrate` found and left out is fitted on the rest.
pub fn run(
    rig: &Rig,
    scenario: &Scenario,
    duration: f64,
    opts: &FitOptions,
    dir: &Path,
) -> Result<Outcome, String> {
    let io = |e: std::io::Error| format!("{}: {e}", dir.display());
    std::fs::create_dir_all(dir).map_err(io)?;
    std::fs::write(dir.join("truth.toml"), rig.truth.to_toml()).map_err(io)?;
    let path = dir.join("rig-log.csv");
    let n = scenario.agents();
    let mut sim = SimRig::new(scenario, &rig.truth, rig.seed);
    let mut log = log_for(&path, n).map_err(io)?;
    let setup = ExciteSetup {
        duration,
        seed: rig.seed,
        gradient_limit: scenario.physics.gradient_limit(),
        alpha_max: rig.truth.coil.alpha_max_deg.to_radians(),
        world: scenario.world.clone(),
    };
    let world = (scenario.world.width, scenario.world.height);
    let mut watched = Watched::new(&mut sim, world);
    let excited = excite(&mut watched, &setup, Some(&mut log));
    let touched = watched.touched_at;
    let left = watched.left_at;
    drop(log);
    if let Err(e) = excited {
        return Ok(Outcome::Failed(format!("excitation failed: {e}")));
    }
    if let Some(t) = left {
        return Ok(Outcome::Failed(format!(
            "excitation failed: the plant's agents left the {} × {} BL workspace at {t:.2} s (true positions; the simulated plant diverged)",
            world.0, world.1
        )));
    }
    let base = base(rig);
    std::fs::write(dir.join("base.toml"), base.to_toml()).map_err(io)?;
    let fitted = read_log(&path, n)
        .map_err(FitError::Input)
        .and_then(|run| calibrate(scenario, &base, vec![run], opts));
    let fit = match fitted {
        Ok(mut fit) => {
            fit.preset.name = "fitted".into();
            fit.preset.description = format!("base fitted to rig {}", rig.index);
            let text = fit.preset_file(&[path.display().to_string()]);
            std::fs::write(dir.join("fitted.toml"), text).map_err(io)?;
            fit
        }
        Err(e) => {
            let why = match e {
                FitError::Input(e) => e.reason,
                e => e.to_string(),
            };
            let excitation = touched.map_or(String::new(), |t| stuck(t, duration) + "; ");
            return Ok(Outcome::Failed(format!(
                "{excitation}calibrate refused the log: {why}"
            )));
        }
    };
    // a stuck stretch calibrate found and left out is a fit of the rest of the log
    Ok(match touched {
        Some(t) if fit.excluded_seconds() == 0.0 => Outcome::Failed(format!(
            "{}; calibrate found no stuck stretch in the log and fitted all of it ({})",
            stuck(t, duration),
            fit.held_out.line()
        )),
        _ => Outcome::Fitted(Box::new(fit)),
    })
}

/// Why an excitation whose pair touched at `t` of `duration` seconds failed.
fn stuck(t: f64, duration: f64) -> String {
    format!(
        "excitation failed: the agents touched at {t:.1} s of {duration} s (true positions) and stuck, so the rest of the log is a stuck team"
    )
}

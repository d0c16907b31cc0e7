//! `magbench rig excite`: an identification trajectory for `magbench calibrate`.
//!
//! Blocks of [`BLOCK_S`] seconds, each with a field angle relative to the pair's separation
//! (ψ), a gradient and an elevation. ψ visits the singular angles in turn — 0° (strongest
//! attraction, no turn), ±54.74° (no radial force, fastest turn), 90° (repulsion) — and in
//! every eight blocks one sweeps ψ through the whole half turn and one is a chirp.
//!
//! Steps and chirps are what make the coils' lag and the camera's latency visible. Each block
//! starts with a step of ψ and of the gradient: after a step a latency `L` delays the motion
//! by `L` frame periods and then the agents move as before, while a coil of time constant τ
//! rounds the step off over a few τ — the first frames after each step tell the two apart,
//! and the blocks hold their command long enough ([`BLOCK_S`] ≫ τ) for the fit's segments
//! to start from settled coils. A chirp block sweeps the frequency of a square wave from
//! [`CHIRP_F0_HZ`] to [`CHIRP_F1_HZ`]: on even chirp blocks ψ alternates ±[`CHIRP_PSI_DEG`]°
//! about the block's ψ, on odd ones the gradient reverses. A first-order coil passes a
//! frequency `f` with the gain `1/√(1 + (2πfτ)²)` and a latency shifts its phase by `2πfL`
//! without changing its gain, so the amplitude of the response across the sweep measures τ
//! and its phase the sum; 10 Hz is 2πfτ = 1.6 for a 25 ms coil and 6 frames a cycle at
//! 60 fps. Gradient blocks pull along x or y at
//! [`GRADIENT_FRACTION`] of the coil's limit, and with a z coil some blocks tilt the field by
//! ±[`ALPHA_STEP_DEG`]°; the order of the blocks is drawn from the seed. Two closed loops keep
//! the run usable: on the separation of agents 0 and 1 (below [`R_MIN`] BL, or the higher edge
//! at which the rig's attraction seen so far would bring the pair to contact within
//! [`REACTION_S`], or when the pair approaches fast enough to touch within it (the
//! [`Approach`] guard), the field turns to ψ = 90° and repels, for at least [`REACTION_S`];
//! beyond the band's upper edge,
//! [`R_MAX`] or as much above the raised lower edge, it turns to ψ = 0 and attracts), and on the centre of
//! mass (a gradient never pulls it further from the workspace's centre once it is more than
//! a quarter of the workspace away). Every observation and command goes to the rig's log as
//! `rig run` writes it.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use magbench_env::plant::Observation;
use magbench_env::{Control, Vec2, World};
use magbench_trackers::{Rig, RigError};

use crate::check::MAGIC_ANGLE;
use crate::rig_log::RigLog;

/// Length of one block of the trajectory (s).
pub const BLOCK_S: f64 = 0.5;
/// Below this separation (BL) the field repels (the lowest edge of the band; [`Approach`]
/// raises it on a rig whose attraction is strong).
pub const R_MIN: f64 = 1.7;
/// Beyond this separation (BL) the field attracts.
pub const R_MAX: f64 = 3.2;
/// The slowest reaction of a rig the separation loop allows for (s), from the ranges of the
/// calibration benchmark's rigs: a frame seen up to 4 frames late at 60 fps (67 ms), the
/// command sent after the frame (17 ms), and the field coil turned to within e⁻² of the new
/// angle (2τ at τ = 40 ms: 80 ms).
pub const REACTION_S: f64 = 4.0 / 60.0 + 1.0 / 60.0 + 2.0 * 0.040;
/// Frames over which [`Approach`] measures the pair's approach: at 60 fps a tenth of a second,
/// over which a detection noise of 0.08 BL gives κ̂ a standard deviation of about 20 BL⁵/s at
/// 2.5 BL.
pub const APPROACH_FRAMES: usize = 6;
/// Gradient steps, as a fraction of the coil's gradient limit.
pub const GRADIENT_FRACTION: f64 = 0.7;
/// Elevation steps (degrees), where the coil can tilt the field.
pub const ALPHA_STEP_DEG: f64 = 35.0;
/// A chirp's first frequency (Hz): one cycle per block, below any coil's corner (≥ 4 Hz for
/// τ ≤ 40 ms).
pub const CHIRP_F0_HZ: f64 = 2.0;
/// A chirp's last frequency (Hz): above the corner of a 16 ms coil, and 6 frames a cycle at
/// 60 fps (a square wave sampled by the camera still shows it).
pub const CHIRP_F1_HZ: f64 = 10.0;
/// Amplitude of a field-angle chirp about the block's ψ (degrees): the torque and the pair's
/// force change by tens of percent, the pair stays within one regime.
pub const CHIRP_PSI_DEG: f64 = 30.0;

/// What the trajectory needs to know about the rig.
#[derive(Debug, Clone)]
pub struct ExciteSetup {
    /// Seconds of excitation.
    pub duration: f64,
    /// Seed of the block order.
    pub seed: u64,
    /// Largest gradient the coil makes (T/m).
    pub gradient_limit: f64,
    /// Largest elevation (radians): 0 for a planar coil set.
    pub alpha_max: f64,
    /// The workspace (its centre and size steer the centre-of-mass loop).
    pub world: World,
}

/// What a block's command does within it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Chirp {
    /// Holds (a step at the block's start).
    None,
    /// ψ alternates ±[`CHIRP_PSI_DEG`] about the block's ψ at a rising frequency.
    Psi,
    /// The gradient reverses at a rising frequency.
    Gradient,
}

/// One block: ψ (or a sweep), gradient, elevation.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Block {
    /// ψ (radians), or `None` for a sweep from −90° to 90°.
    psi: Option<f64>,
    /// A chirp within the block.
    chirp: Chirp,
    /// Gradient axis (0 = x, 1 = y) and sign, or none.
    grad: Option<(usize, f64)>,
    /// Elevation (radians).
    alpha: f64,
}

/// What an excitation run did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExciteReport {
    /// Observations received.
    pub frames: u64,
    /// Commands sent.
    pub commands: u64,
    /// Agent detections missing.
    pub missed: u64,
    /// Frames in which the separation loop overrode the block's ψ.
    pub separation_overrides: u64,
    /// Frames in which the centre-of-mass loop reversed a gradient.
    pub com_overrides: u64,
    /// Smallest and largest separation of agents 0 and 1 seen (BL).
    pub separation_range: (f64, f64),
    /// Observed time span (s).
    pub duration_s: f64,
}

/// The separation loop's guard against a fast approach. Under the strongest attraction (ψ = 0)
/// a pair's separation follows `r⁵ = r₀⁵ − 10κt` (docs/physics.md), whatever the rig's moments
/// and drags, which only scale κ. The guard estimates κ from the pair's last
/// [`APPROACH_FRAMES`] observed separations, `κ̂ = (r_old⁵ − r_new⁵)/(10Δt)`, and reports a
/// pair that at that rate would touch (r = 1) within [`REACTION_S`] of its last observation.
/// It also keeps the largest κ̂ seen below [`KAPPA_WITHIN_BL`] (the rig's attraction at its
/// strongest, where the detection noise matters least) and raises the band's lower edge to
/// the separation from which that attraction needs [`REACTION_S`] to bring the pair to
/// contact, `(1 + 10 κ_max REACTION_S)^{1/5}`, never below [`R_MIN`]; the upper edge keeps
/// the band's width. The run starts by repelling until the pair has reached the band's upper
/// edge (and the guard has its frames), or for at most [`START_S`], so that the first
/// attraction starts from the farthest separation and the guard sees the rig's attraction
/// before the pair is close.
#[derive(Debug, Clone, Default)]
pub struct Approach {
    /// The last observed separations, oldest first: (time s, separation BL).
    seen: std::collections::VecDeque<(f64, f64)>,
    /// The largest κ̂ seen (BL⁵/s).
    kappa_max: f64,
    /// Whether the pair has reached the band's upper edge once (or [`START_S`] has passed).
    started: bool,
    /// When the first separation was observed (s).
    first: Option<f64>,
    /// Until when the loop keeps repelling (s): [`REACTION_S`] after the last frame that
    /// called for it.
    repel_until: Option<f64>,
}

/// Longest repulsion at the run's start (s): two blocks. Repelling from 2 BL, a pair of the
/// benchmark's strongest rigs (κ ≈ 58 BL⁵/s: moments +30%, drags −30% on the default physics'
/// 24 BL⁵/s) reaches 3.2 BL in about 1 s (`r⁵ = r₀⁵ + 5κt`); a weaker pair, still closer by
/// then, also attracts more slowly.
pub const START_S: f64 = 2.0 * BLOCK_S;

/// Separations (BL) below which both ends of a window must lie for its κ̂ to count toward
/// the largest: the noise of κ̂ grows as r⁴ (5r⁴σ√2/(10Δt): 13 BL⁵/s at 2.2 BL for σ = 0.08 BL).
pub const KAPPA_WITHIN_BL: f64 = 2.2;

impl Approach {
    /// Records separation `r` observed at `t` and returns true when the pair would touch
    /// within [`REACTION_S`] at the approach rate of the last [`APPROACH_FRAMES`] frames, and
    /// from the run's start until the pair first reaches the band's upper edge with the
    /// guard's frames seen (the loop repels).
    pub fn too_fast(&mut self, t: f64, r: f64) -> bool {
        self.seen.push_back((t, r));
        if self.seen.len() > APPROACH_FRAMES + 1 {
            self.seen.pop_front();
        }
        let full = self.seen.len() == APPROACH_FRAMES + 1;
        let first = *self.first.get_or_insert(t);
        self.started |= full && (r >= self.r_max() || t - first >= START_S);
        let (&(t0, r0), &(t1, r1)) = match (self.seen.front(), self.seen.back()) {
            (Some(a), Some(b)) if self.started && b.0 > a.0 => (a, b),
            _ => return true,
        };
        let kappa = (r0.powi(5) - r1.powi(5)) / (10.0 * (t1 - t0));
        if r0 < KAPPA_WITHIN_BL && r1 < KAPPA_WITHIN_BL {
            self.kappa_max = self.kappa_max.max(kappa);
        }
        kappa > 0.0 && (r1.powi(5) - 1.0) < 10.0 * kappa * REACTION_S
    }

    /// Records separation `r` observed at `t` and returns whether the loop repels: below the
    /// band's lower edge ([`Approach::r_min`]), when the pair approaches too fast
    /// ([`Approach::too_fast`]), and for [`REACTION_S`] after the last frame that called for
    /// either, because until then the rig has not yet acted on the repulsion and the pair's
    /// observed separation says nothing of it.
    pub fn repels(&mut self, t: f64, r: f64) -> bool {
        let now = self.too_fast(t, r) || r < self.r_min();
        if now {
            self.repel_until = Some(t + REACTION_S);
        }
        now || self.repel_until.is_some_and(|until| t < until)
    }

    /// Below this separation (BL) the loop repels.
    pub fn r_min(&self) -> f64 {
        (1.0 + 10.0 * self.kappa_max * REACTION_S)
            .powf(0.2)
            .max(R_MIN)
    }

    /// Beyond this separation (BL) the loop attracts.
    pub fn r_max(&self) -> f64 {
        self.r_min() + (R_MAX - R_MIN)
    }
}

/// The block sequence of a run.
fn blocks(setup: &ExciteSetup) -> Vec<Block> {
    let n = (setup.duration / BLOCK_S).ceil().max(1.0) as usize;
    let psis = [
        Some(0.0),
        Some(MAGIC_ANGLE),
        Some(std::f64::consts::FRAC_PI_2),
        Some(-MAGIC_ANGLE),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(setup.seed);
    let tilt = setup.alpha_max.min(ALPHA_STEP_DEG.to_radians());
    (0..n)
        .map(|k| {
            let psi = if k % 8 == 3 {
                None
            } else {
                psis[(k + k / 4) % 4]
            };
            let chirp = match (k % 8, (k / 8) % 2) {
                (7, 0) => Chirp::Psi,
                (7, _) => Chirp::Gradient,
                _ => Chirp::None,
            };
            let grad = match (chirp, rng.random_range(0..5)) {
                (Chirp::Gradient, g) => Some((g % 2, 1.0)),
                (_, 0) => None,
                (_, g) => Some(((g - 1) % 2, if g <= 2 { 1.0 } else { -1.0 })),
            };
            let alpha = if tilt > 0.0 && rng.random_range(0..3) == 0 {
                if rng.random_bool(0.5) { tilt } else { -tilt }
            } else {
                0.0
            };
            Block {
                psi,
                chirp,
                grad,
                alpha,
            }
        })
        .collect()
}

/// Drives `rig` through the identification trajectory, then zeroes the field. `log`, when
/// given, receives every observation and command (for a rig that does not log itself).
pub fn excite(
    rig: &mut dyn Rig,
    setup: &ExciteSetup,
    mut log: Option<&mut RigLog>,
) -> Result<ExciteReport, RigError> {
    let plan = blocks(setup);
    let centre = Vec2::new(setup.world.width, setup.world.height) * 0.5;
    let reach = Vec2::new(setup.world.width, setup.world.height) * 0.25;
    let mut rep = ExciteReport {
        separation_range: (f64::INFINITY, 0.0),
        ..Default::default()
    };
    let mut u = Control::default();
    let mut have_command = false;
    let (mut t0, mut t) = (None, 0.0);
    let mut frame = 0u64;
    let mut approach = Approach::default();
    let result = (|| -> Result<(), RigError> {
        loop {
            let obs: Observation = rig.observe()?;
            let start = *t0.get_or_insert(obs.t);
            t = obs.t - start;
            if t >= setup.duration {
                return Ok(());
            }
            rep.frames += 1;
            rep.missed += obs.agents.iter().filter(|a| a.is_none()).count() as u64;
            if let Some(l) = log.as_deref_mut() {
                l.observation(obs.t, frame, &obs.agents);
            }
            let loops = Loops {
                centre,
                reach,
                approach: &mut approach,
            };
            if let Some(c) = next_command(&obs, t, &plan, setup, loops, &mut rep) {
                u = c;
                have_command = true;
            }
            if have_command {
                rig.command(&u)?;
                rep.commands += 1;
                if let Some(l) = log.as_deref_mut() {
                    l.command_without_currents(obs.t, Some(frame), &u);
                }
            }
            frame += 1;
        }
    })();
    let stopped = rig.stop();
    if let Some(l) = log {
        l.stop(t, "stop: excitation finished; field zeroed");
        l.flush();
    }
    result?;
    stopped?;
    rep.duration_s = t;
    Ok(rep)
}

/// What the two closed loops keep between frames: the workspace's centre and the reach of
/// the centre-of-mass loop, and the separation loop's [`Approach`] guard.
struct Loops<'a> {
    centre: Vec2,
    reach: Vec2,
    approach: &'a mut Approach,
}

/// The command for the frame `obs` at time `t` of the run; `None` when agents 0 and 1 were not
/// both found (the previous command holds).
fn next_command(
    obs: &Observation,
    t: f64,
    plan: &[Block],
    setup: &ExciteSetup,
    loops: Loops,
    rep: &mut ExciteReport,
) -> Option<Control> {
    let Loops {
        centre,
        reach,
        approach,
    } = loops;
    let (Some(a), Some(b)) = (obs.agents.first().copied()?, obs.agents.get(1).copied()?) else {
        return None;
    };
    let d = b - a;
    let (r, phi) = (d.norm(), d.y.atan2(d.x));
    rep.separation_range = (rep.separation_range.0.min(r), rep.separation_range.1.max(r));
    let k = ((t / BLOCK_S) as usize).min(plan.len() - 1);
    let block = plan[k];
    let s = (t / BLOCK_S).fract();
    let wave = square_chirp(s * BLOCK_S);
    let mut psi = match block.psi {
        Some(p) if block.chirp == Chirp::Psi => p + wave * CHIRP_PSI_DEG.to_radians(),
        Some(p) => p,
        None => (s - 0.5) * std::f64::consts::PI,
    };
    if approach.repels(obs.t, r) {
        psi = std::f64::consts::FRAC_PI_2;
        rep.separation_overrides += 1;
    } else if r > approach.r_max() {
        psi = 0.0;
        rep.separation_overrides += 1;
    }
    let theta = phi + psi;
    let mut grad = [0.0; 2];
    if let Some((axis, sign)) = block.grad {
        let found: Vec<Vec2> = obs.agents.iter().flatten().copied().collect();
        let com = found.iter().sum::<Vec2>() / found.len() as f64;
        // the pull along the axis is G·m̂: its direction follows the field's component
        let m = if axis == 0 { theta.cos() } else { theta.sin() } * block.alpha.cos();
        let sign = if block.chirp == Chirp::Gradient {
            sign * wave
        } else {
            sign
        };
        let g = sign * GRADIENT_FRACTION * setup.gradient_limit;
        let mut pull = g * m;
        let off = com[axis] - centre[axis];
        if off.abs() > reach[axis] && pull * off > 0.0 {
            pull = -pull;
            rep.com_overrides += 1;
        }
        grad[axis] = if m.abs() < 1e-9 { 0.0 } else { pull / m };
    }
    Some(Control {
        theta,
        alpha: block.alpha,
        grad,
    })
}

/// The chirp's square wave (±1) at `t` seconds into its block: the sign of
/// `sin 2π(f₀t + (f₁ − f₀)t²/(2T))`, its frequency rising linearly from [`CHIRP_F0_HZ`] to
/// [`CHIRP_F1_HZ`] over the block's [`BLOCK_S`].
fn square_chirp(t: f64) -> f64 {
    let phase = CHIRP_F0_HZ * t + (CHIRP_F1_HZ - CHIRP_F0_HZ) * t * t / (2.0 * BLOCK_S);
    if (phase.fract()) < 0.5 { 1.0 } else { -1.0 }
}

/// A rig that does not log itself, with a log that receives what [`excite`] does.
pub fn log_for(path: &std::path::Path, agents: usize) -> std::io::Result<RigLog> {
    RigLog::create(path, agents, std::time::Instant::now())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(alpha_max: f64) -> ExciteSetup {
        ExciteSetup {
            duration: 20.0,
            seed: 3,
            gradient_limit: 0.085,
            alpha_max,
            world: World {
                width: 40.0,
                height: 30.0,
                obstacles: vec![],
            },
        }
    }

    #[test]
    fn blocks_visit_every_singular_angle_both_gradient_axes_and_tilt_only_with_a_z_coil() {
        let b = blocks(&setup(std::f64::consts::FRAC_PI_2));
        for psi in [0.0, MAGIC_ANGLE, std::f64::consts::FRAC_PI_2, -MAGIC_ANGLE] {
            assert!(b.iter().any(|x| x.psi == Some(psi)), "ψ = {psi}");
        }
        assert!(b.iter().any(|x| x.psi.is_none()), "a sweep");
        for axis in 0..2 {
            for s in [1.0, -1.0] {
                assert!(b.iter().any(|x| x.grad == Some((axis, s))), "{axis} {s}");
            }
        }
        assert!(b.iter().any(|x| x.alpha != 0.0));
        assert!(
            b.iter().any(|x| x.chirp == Chirp::Psi),
            "a field-angle chirp"
        );
        assert!(
            b.iter()
                .any(|x| x.chirp == Chirp::Gradient && x.grad.is_some()),
            "a gradient chirp"
        );
        assert!(blocks(&setup(0.0)).iter().all(|x| x.alpha == 0.0));
    }

    #[test]
    fn the_separation_loop_overrides_the_block() {
        let s = setup(0.0);
        let plan = vec![Block {
            psi: Some(0.0),
            chirp: Chirp::None,
            grad: None,
            alpha: 0.0,
        }];
        let mut rep = ExciteReport::default();
        let c = Vec2::new(20.0, 15.0);
        fn loops(c: Vec2, approach: &mut Approach) -> Loops<'_> {
            Loops {
                centre: c,
                reach: c,
                approach,
            }
        }
        // a guard that has seen the pair hold still at 2.5 BL
        let mut approach = approach_tests::running();
        for k in 0..APPROACH_FRAMES {
            approach.too_fast(k as f64 / 60.0, 2.5);
        }
        let t = APPROACH_FRAMES as f64 / 60.0;
        let mut command = |r: f64, t: f64| {
            let obs = Observation {
                t,
                agents: vec![Some(c), Some(Vec2::new(c.x + r, c.y))],
            };
            next_command(&obs, 0.0, &plan, &s, loops(c, &mut approach), &mut rep).unwrap()
        };
        let u = command(2.5, t);
        assert_eq!(u.theta, 0.0, "the block's ψ");
        let u = command(1.5, t + 1.0 / 60.0);
        assert!(
            (u.theta - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "repel"
        );
        assert_eq!(rep.separation_overrides, 1);
    }
}

#[cfg(test)]
mod approach_tests {
    use super::*;

    /// A guard past the run's start (the pair has reached the band's upper edge once).
    pub(super) fn running() -> Approach {
        Approach {
            started: true,
            ..Approach::default()
        }
    }

    /// The first time (s) at which the guard reports a pair attracted at ψ = 0 from `r0` BL
    /// with constant κ (BL⁵/s), seen at 60 fps, or `None` before contact.
    fn first_alarm(r0: f64, kappa: f64) -> Option<f64> {
        let mut a = running();
        (0..)
            .map(|k| k as f64 / 60.0)
            .map(|t| (t, r0.powi(5) - 10.0 * kappa * t))
            .take_while(|&(_, r5)| r5 > 1.0)
            .filter(|&(t, r5)| a.too_fast(t, r5.powf(0.2)) && t > APPROACH_FRAMES as f64 / 60.0)
            .map(|(t, _)| t)
            .next()
    }

    #[test]
    fn a_fast_approach_is_reported_at_least_the_reaction_time_before_contact() {
        for kappa in [24.0, 60.0, 120.0] {
            let r0: f64 = 3.2;
            let contact = (r0.powi(5) - 1.0) / (10.0 * kappa);
            let alarm = first_alarm(r0, kappa).expect("reported before contact");
            assert!(
                contact - alarm >= REACTION_S - 1.0 / 60.0,
                "κ {kappa}: alarm at {alarm:.3} s, contact at {contact:.3} s"
            );
        }
    }

    #[test]
    fn a_strong_attraction_raises_the_band_to_where_it_needs_the_reaction_time() {
        let mut a = running();
        assert_eq!((a.r_min(), a.r_max()), (R_MIN, R_MAX));
        // κ = 20 BL⁵/s from 2.15 BL, seen for a tenth of a second (to 1.92 BL)
        let kappa = 20.0;
        for k in 0..=APPROACH_FRAMES {
            let t = k as f64 / 60.0;
            a.too_fast(t, (2.15f64.powi(5) - 10.0 * kappa * t).powf(0.2));
        }
        let edge = (1.0 + 10.0 * kappa * REACTION_S).powf(0.2);
        assert!((a.r_min() - edge).abs() < 1e-9, "{} vs {edge}", a.r_min());
        assert!((a.r_max() - a.r_min() - (R_MAX - R_MIN)).abs() < 1e-12);
        // contact from the raised edge takes the reaction time
        let contact = (a.r_min().powi(5) - 1.0) / (10.0 * kappa);
        assert!((contact - REACTION_S).abs() < 1e-9);
    }

    #[test]
    fn a_run_starts_by_repelling_until_the_pair_reaches_the_band_s_upper_edge() {
        let mut a = Approach::default();
        let r = |k: usize| 2.0 + 0.1 * k as f64;
        let alarms: Vec<bool> = (0..16).map(|k| a.too_fast(k as f64 / 60.0, r(k))).collect();
        let first_clear = alarms.iter().position(|x| !x).expect("released");
        assert!(r(first_clear) >= R_MAX, "released at {} BL", r(first_clear));
        assert!(r(first_clear - 1) < R_MAX);
    }

    #[test]
    fn a_repulsion_holds_for_the_reaction_time_after_the_last_frame_that_called_for_it() {
        // a guard that has seen the pair hold still at 2.5 BL, in the band, for longer than
        // the reaction time (its first frame, without a rate, repels)
        let mut a = running();
        let frame = 1.0 / 60.0;
        let settled = 2 * (REACTION_S / frame) as usize;
        for k in 0..settled {
            a.repels(k as f64 * frame, 2.5);
        }
        assert!(!a.repels(settled as f64 * frame, 2.5));
        // one frame below the band's lower edge, then back in the band
        let t = (settled + 1) as f64 * frame;
        assert!(a.repels(t, R_MIN - 0.1));
        let held: Vec<bool> = (1..=12)
            .map(|k| a.repels(t + k as f64 * frame, 2.5))
            .collect();
        let released = held.iter().position(|x| !x).expect("released") + 1;
        assert!(held[..released - 1].iter().all(|&x| x));
        assert!(
            (released as f64 * frame - REACTION_S).abs() <= frame,
            "released {released} frames after the call, {:.1} frames of reaction",
            REACTION_S / frame
        );
    }

    #[test]
    fn a_slow_approach_and_a_separation_are_not_reported() {
        // κ = 0.5 BL⁵/s from 2.5 BL: contact after 19 s
        let alarms = |a: &mut Approach, r: &dyn Fn(f64) -> f64| -> Vec<usize> {
            (0..20)
                .filter(|&k| {
                    let t = k as f64 / 60.0;
                    a.too_fast(t, r(t))
                })
                .collect()
        };
        // a running guard's first frame has no rate yet
        let first = vec![0];
        // κ = 0.5 BL⁵/s from 2.5 BL: contact after 19 s
        let slow = alarms(&mut running(), &|t| (2.5f64.powi(5) - 5.0 * t).powf(0.2));
        assert_eq!(slow, first, "only the frame before a rate is known");
        let apart = alarms(&mut running(), &|t| 1.8 + 6.0 * t);
        assert_eq!(apart, first);
    }
}

#[cfg(test)]
mod chirp_tests {
    use super::*;

    #[test]
    fn the_square_chirp_switches_faster_towards_the_end_of_its_block() {
        let frames: Vec<f64> = (0..30).map(|k| square_chirp(k as f64 / 60.0)).collect();
        let switches = |w: &[f64]| w.windows(2).filter(|p| p[0] != p[1]).count();
        assert!(
            switches(&frames[15..]) > switches(&frames[..15]),
            "{frames:?}"
        );
    }
}

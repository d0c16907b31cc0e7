//! `magbench rig check`: a closed-loop bring-up test of a rig without a plan.
//!
//! Each frame it reads the pair's heading φ from the detections and commands the field at
//! θ_B = φ + 54.7356°, where the radial force vanishes (cos²ψ = 1/3): the pair turns in place
//! at constant separation; a proportional term on ψ (larger ψ repels, smaller attracts) holds
//! the separation measured in the first frame against latency and field-angle error. A rig whose calibration, detector and protocol all work turns the
//! pair steadily; the report gives frame, detection and latency figures.

use magbench_env::{Control, Vec2};

use crate::hardware::{HardwareError, HardwareRig};
use crate::stats::percentile;

/// What a check run measured.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    /// Observations received.
    pub frames: u64,
    /// Frames the camera dropped.
    pub dropped_frames: u64,
    /// Stuck frames.
    pub stuck_frames: u64,
    /// Missing agent detections.
    pub missed_detections: u64,
    /// Commands sent.
    pub commands: u64,
    /// Faults logged.
    pub faults: u64,
    /// Observed time span (s).
    pub duration_s: f64,
    /// Frame arrival → command sent: median and 99th percentile (ms).
    pub latency_ms: Option<(f64, f64)>,
    /// Net rotation of the pair's heading (degrees).
    pub turned_deg: f64,
    /// Separation at the start and at the end (BL).
    pub separation: (f64, f64),
}

/// The magic angle: the radial pair force vanishes at ψ = acos(1/√3).
pub const MAGIC_ANGLE: f64 = 0.955_316_618_124_509_2;

/// ψ correction per BL of separation error (rad/BL).
pub const SEPARATION_GAIN: f64 = 1.0;

/// Turns the pair at the magic angle for `duration` seconds of frames, then zeroes the field.
pub fn spin_check(rig: &mut HardwareRig, duration: f64) -> Result<CheckReport, HardwareError> {
    rig.reset_clock();
    let mut u = Control::default();
    let (mut phi0, mut phi_prev, mut turned) = (None, 0.0, 0.0);
    let (mut r0, mut r1) = (f64::NAN, f64::NAN);
    let mut t = 0.0;
    let mut sent_any = false;
    while t < duration {
        let obs = rig.observe()?;
        t = obs.t;
        if let [Some(a), Some(b)] = obs.agents[..2] {
            let d: Vec2 = b - a;
            let phi = d.y.atan2(d.x);
            if phi0.is_none() {
                phi0 = Some(phi);
                phi_prev = phi;
                r0 = d.norm();
            }
            turned += magbench_env::math::wrap_angle(phi - phi_prev);
            phi_prev = phi;
            r1 = d.norm();
            let psi = MAGIC_ANGLE + (SEPARATION_GAIN * (r0 - d.norm())).clamp(-0.5, 0.5);
            u = Control::planar(phi + psi, 0.0, 0.0);
            sent_any = true;
        }
        if sent_any {
            rig.command(&u)?;
        }
    }
    rig.stop()?;
    let s = rig.stats();
    let latency_ms = percentile(&s.latencies_ms, 0.5).zip(percentile(&s.latencies_ms, 0.99));
    Ok(CheckReport {
        frames: s.frames,
        dropped_frames: s.dropped_frames,
        stuck_frames: s.stuck_frames,
        missed_detections: s.missed_detections,
        commands: s.commands,
        faults: s.faults,
        duration_s: t,
        latency_ms,
        turned_deg: turned.to_degrees(),
        separation: (r0, r1),
    })
}

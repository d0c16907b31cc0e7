//! The coil driver's arithmetic: a [`Control`] to channel currents, within limits, and back.

use magbench_env::Control;

use crate::calibration::{Calibration, FieldVector};
use crate::rigfile::CoilConfig;

/// Why a command was changed before it was sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ClampFlags {
    /// Some channel exceeded its current limit: the whole current vector was scaled down.
    pub current: bool,
    /// Some channel would have changed faster than the slew limit: the step was scaled down.
    pub slew: bool,
}

impl ClampFlags {
    /// True when anything was clamped.
    pub fn any(&self) -> bool {
        self.current || self.slew
    }
}

/// Currents ready to send, the field they realise and what was clamped.
#[derive(Debug, Clone, PartialEq)]
pub struct CoilCommand {
    /// Channel currents (A), within the limits.
    pub currents: Vec<f64>,
    /// The field and gradient these currents produce (T, T/m).
    pub field: FieldVector,
    /// What was clamped to get here.
    pub clamped: ClampFlags,
}

/// Turns coil commands into currents through the rig calibration, never beyond the limits.
///
/// Limits keep directions: when a channel would exceed its current limit, the whole current
/// vector is scaled by the same factor (field direction and gradient ratio kept, magnitudes
/// reduced); when a channel would change faster than the slew limit, the whole change is scaled.
/// Both are flagged. A stop ([`CoilDriver::zero`]) is never slew-limited.
#[derive(Debug, Clone)]
pub struct CoilDriver {
    calibration: Calibration,
    limits: Vec<f64>,
    slew: f64,
    field_t: f64,
    last: Vec<f64>,
}

impl CoilDriver {
    /// A driver for the rig's coil with field magnitude `field_mt` (mT).
    pub fn new(cfg: &CoilConfig, field_mt: f64) -> Self {
        let n = cfg.calibration.channels();
        Self {
            calibration: cfg.calibration.clone(),
            limits: cfg.current_limit_a.clone(),
            slew: cfg.slew_a_per_s,
            field_t: field_mt * 1e-3,
            last: vec![0.0; n],
        }
    }

    /// Number of channels.
    pub fn channels(&self) -> usize {
        self.limits.len()
    }

    /// The field magnitude commanded (T).
    pub fn field_t(&self) -> f64 {
        self.field_t
    }

    /// The currents last returned (what the device should be applying).
    pub fn last_currents(&self) -> &[f64] {
        &self.last
    }

    /// The field vector a command asks for: `B b̂(θ, α)` and the gradients.
    pub fn field_vector(&self, u: &Control) -> FieldVector {
        let (b, [gx, gy]) = (self.field_t, u.grad);
        let (ca, sa) = (u.alpha.cos(), u.alpha.sin());
        [
            b * ca * u.theta.cos(),
            b * ca * u.theta.sin(),
            b * sa,
            gx,
            gy,
        ]
    }

    /// Currents for `u`, `dt` seconds after the previous command; `None` for a non-finite
    /// command (which must not be sent).
    pub fn command(&mut self, u: &Control, dt: f64) -> Option<CoilCommand> {
        if !u.is_finite() {
            return None;
        }
        let mut i = self.calibration.currents(&self.field_vector(u));
        let mut clamped = ClampFlags::default();
        let over = i
            .iter()
            .zip(&self.limits)
            .map(|(x, l)| x.abs() / l)
            .fold(0.0, f64::max);
        if over > 1.0 {
            i.iter_mut().for_each(|x| *x /= over);
            clamped.current = true;
        }
        let step = self.slew * dt.max(0.0);
        let worst = i
            .iter()
            .zip(&self.last)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        if worst > step {
            let k = step / worst;
            for (x, y) in i.iter_mut().zip(&self.last) {
                *x = y + (*x - y) * k;
            }
            clamped.slew = true;
        }
        self.last.clone_from(&i);
        Some(CoilCommand {
            field: self.calibration.field(&i),
            currents: i,
            clamped,
        })
    }

    /// All currents zero (never slew-limited).
    pub fn zero(&mut self) -> CoilCommand {
        self.last.iter_mut().for_each(|x| *x = 0.0);
        CoilCommand {
            currents: self.last.clone(),
            field: [0.0; 5],
            clamped: ClampFlags::default(),
        }
    }
}

/// The coil command a field vector amounts to, and its field magnitude (T).
pub fn control_of_field(q: &FieldVector) -> (Control, f64) {
    let b = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
    let theta = q[1].atan2(q[0]);
    let alpha = if b > 0.0 {
        (q[2] / b).clamp(-1.0, 1.0).asin()
    } else {
        0.0
    };
    (
        Control {
            theta,
            alpha,
            grad: [q[3], q[4]],
        },
        b,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigfile::RigConfig;

    fn driver() -> CoilDriver {
        let rig =
            RigConfig::parse(include_str!("../../rigs/emulator.toml"), "emulator.toml").unwrap();
        CoilDriver::new(&rig.coil, 5.0)
    }

    #[test]
    fn a_command_within_limits_round_trips() {
        let mut d = driver();
        let u = Control {
            theta: 2.1,
            alpha: 0.1,
            grad: [0.05, -0.03],
        };
        let c = d.command(&u, 1.0).unwrap();
        assert!(!c.clamped.any());
        let (back, b) = control_of_field(&c.field);
        assert!((back.theta - 2.1).abs() < 1e-12 && (back.alpha - 0.1).abs() < 1e-12);
        assert!((back.grad[0] - 0.05).abs() < 1e-15 && (b - 5e-3).abs() < 1e-15);
    }

    #[test]
    fn over_limit_is_scaled_and_flagged_keeping_direction() {
        let mut d = driver();
        // 0.2 T/m needs 10 A on an 8 A channel
        let c = d.command(&Control::planar(0.7, 0.2, 0.1), 1.0).unwrap();
        assert!(c.clamped.current && !c.clamped.slew);
        assert!(c.currents.iter().all(|x| x.abs() <= 8.0 + 1e-12));
        assert!((c.currents[3] - 8.0).abs() < 1e-12);
        let (back, _) = control_of_field(&c.field);
        assert!(
            (back.theta - 0.7).abs() < 1e-12 && (back.grad[0] / back.grad[1] - 2.0).abs() < 1e-12
        );
    }

    #[test]
    fn slew_limits_the_step_and_zero_is_immediate() {
        let mut d = driver();
        // 5 A in 1 ms at 1000 A/s: only 1 A allowed
        let c = d.command(&Control::planar(0.0, 0.0, 0.0), 0.001).unwrap();
        assert!(c.clamped.slew && (c.currents[0] - 1.0).abs() < 1e-12);
        assert_eq!(d.zero().currents, vec![0.0; 5]);
        assert!(
            d.command(
                &Control {
                    theta: f64::NAN,
                    ..Default::default()
                },
                1.0
            )
            .is_none()
        );
    }
}

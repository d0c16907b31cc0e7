//! The plant stepper: env's [`Plant`] advanced frame by frame under the currents the coil
//! driver has in force, piecewise at every change (never other physics than env's).

use magbench_env::Vec2;
use magbench_env::plant::Plant;

use super::coil::Change;
use crate::calibration::Calibration;
use crate::coil_driver::control_of_field;

/// The plant and the currents driving it.
pub struct PlantStepper {
    plant: Plant,
    calibration: Calibration,
    /// Field magnitude (T) below which the agents are not driven (the field is off).
    field_on: f64,
    in_force: Vec<f64>,
    t: f64,
}

impl PlantStepper {
    /// Steps `plant` under currents mapped to fields by `calibration`; a field weaker than
    /// `field_on` (T) leaves the agents alone.
    pub fn new(plant: Plant, calibration: Calibration, field_on: f64) -> Self {
        let channels = calibration.channels();
        Self {
            plant,
            calibration,
            field_on,
            in_force: vec![0.0; channels],
            t: 0.0,
        }
    }

    /// Integrates from the last frame to device time `t`, through the current `changes`
    /// that happened meanwhile, in order (one stamped before the last frame counts from it).
    pub fn advance_to(&mut self, t: f64, changes: Vec<Change>) {
        let mut seg_start = self.t;
        for c in changes {
            let tc = c.t.clamp(seg_start, t);
            self.advance(seg_start, tc);
            seg_start = tc;
            self.in_force = c.currents;
        }
        self.advance(seg_start, t);
        self.t = t;
    }

    fn advance(&mut self, a: f64, b: f64) {
        if b > a {
            let (u, field) = control_of_field(&self.calibration.field(&self.in_force));
            if field >= self.field_on {
                self.plant.run(&u, b - a);
            }
        }
    }

    /// The currents in force (A).
    pub fn in_force(&self) -> &[f64] {
        &self.in_force
    }

    /// The true agent positions (BL).
    pub fn positions(&self) -> &[Vec2] {
        self.plant.positions()
    }

    /// True once two agents have touched and stuck.
    pub fn stuck(&self) -> bool {
        self.plant.stuck()
    }
}

//! The simulated rig: env's [`Plant`] observed through env's [`Camera`].

use std::sync::Arc;

use magbench_env::collision::CollisionWorld;
use magbench_env::plant::{AGENT_RADIUS_BL, Camera, DisturbancePreset, Observation, Plant};
use magbench_env::{Coil, Control, PhysicalParams, Scenario, TriaxialMaxwell, Vec2, World};

use crate::rig::{GroundTruth, Rig, RigError};

/// A [`Rig`] over the simulated plant and camera of a [`DisturbancePreset`].
///
/// Frame `k` is at `t = k·T` (`T` = the camera's frame period). [`Rig::observe`] advances the
/// plant by one frame under the command in force, captures the frame, and returns the
/// observation the camera delivers now: the agents as they were one (jittering) latency ago,
/// stamped with the nominal latency (the camera has been running on the agents at rest before
/// the run, so there is one from the first call on). [`Rig::latency`] is the nominal latency:
/// all the estimator is told. Commands go to the plant at once; with the coil-dynamics term
/// the field then follows them with its lag. The map is centred in the coil. Without a field
/// (before the first command and after [`Rig::stop`]) the plant is not advanced: with zero
/// field only the slow flow and Brownian motion would move the agents, which the simulation
/// leaves out.
#[derive(Debug, Clone)]
pub struct SimRig {
    plant: Plant,
    camera: Camera,
    period: f64,
    latency: f64,
    frame: u64,
    command: Option<Control>,
    stopped: bool,
    agent_radius: f64,
}

impl SimRig {
    /// The rig of `scenario` (its physics, world, start and medium, if it sets one) under
    /// `preset`, drawn with `seed`.
    pub fn new(scenario: &Scenario, preset: &DisturbancePreset, seed: u64) -> Self {
        Self::from_parts(
            &scenario.physics,
            &scenario.world,
            &scenario.plant_preset(preset),
            seed,
            &scenario.start,
        )
    }

    /// The rig of a physical preset and a world with the tri-axial coil, whose elevation range
    /// is the preset's (`[coil] alpha_max_deg`), agents at `start`.
    pub fn from_parts(
        params: &PhysicalParams,
        world: &World,
        preset: &DisturbancePreset,
        seed: u64,
        start: &[Vec2],
    ) -> Self {
        let coil: Arc<dyn Coil> = Arc::new(
            TriaxialMaxwell::new(params.gradient_limit())
                .with_alpha_max_deg(preset.coil.alpha_max_deg),
        );
        let plant = Plant::in_world(params, coil, world, preset, seed, start);
        let camera = Camera::new(preset.camera.clone(), seed);
        let (period, latency) = (camera.frame_period(), camera.nominal_latency());
        Self {
            plant,
            camera,
            period,
            latency,
            frame: 0,
            command: None,
            stopped: false,
            agent_radius: AGENT_RADIUS_BL,
        }
    }

    /// The simulated plant (true state, drawn disturbances).
    pub fn plant(&self) -> &Plant {
        &self.plant
    }
}

impl Rig for SimRig {
    fn frame_period(&self) -> f64 {
        self.period
    }

    fn observe(&mut self) -> Result<Observation, RigError> {
        if let (true, Some(u), false) = (self.frame > 0, self.command, self.stopped) {
            self.plant.run(&u, self.period);
        }
        let t = self.frame as f64 * self.period;
        self.frame += 1;
        let obs = self.camera.capture(t, self.plant.positions());
        obs.ok_or_else(|| RigError::Fatal("the simulated camera delivered no frame".into()))
    }

    fn command(&mut self, u: &Control) -> Result<(), RigError> {
        if self.stopped {
            return Err(RigError::Fatal("command after stop".into()));
        }
        if !u.is_finite() {
            return Err(RigError::Recoverable(format!(
                "non-finite command {u:?} ignored"
            )));
        }
        self.command = Some(*u);
        Ok(())
    }

    fn stop(&mut self) -> Result<(), RigError> {
        self.stopped = true;
        self.command = None;
        Ok(())
    }

    fn latency(&self) -> f64 {
        self.latency
    }

    fn set_world(&mut self, world: &World) -> Result<(), RigError> {
        self.plant
            .set_collision(Arc::new(CollisionWorld::new(world, self.agent_radius)));
        Ok(())
    }

    fn ground_truth(&self) -> Option<GroundTruth> {
        Some(GroundTruth {
            positions: self.plant.positions().to_vec(),
            wall_contacts: self.plant.wall_contacts(),
            agent_contact: self.plant.stuck(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn world() -> World {
        World {
            width: 30.0,
            height: 20.0,
            obstacles: vec![],
        }
    }

    #[test]
    fn latency_one_frame_delivers_previous_capture() {
        let start = [Vec2::new(10.0, 10.0), Vec2::new(12.5, 10.0)];
        let mut rig = SimRig::from_parts(
            &PhysicalParams::default(),
            &world(),
            &DisturbancePreset::realistic(),
            4,
            &start,
        );
        assert!((rig.latency() - rig.frame_period()).abs() < 1e-15);
        let o0 = rig.observe().unwrap();
        assert!(
            (o0.t + rig.frame_period()).abs() < 1e-12,
            "pre-rolled frame at −T"
        );
        rig.command(&Control::planar(0.0, 0.0, 0.08)).unwrap();
        let o1 = rig.observe().unwrap();
        assert!(o1.t.abs() < 1e-12);
        rig.stop().unwrap();
        rig.stop().unwrap();
        assert!(rig.command(&Control::default()).is_err());
    }

    #[test]
    fn ideal_rig_sees_the_truth_now() {
        let start = [Vec2::new(10.0, 10.0), Vec2::new(12.5, 10.0)];
        let mut rig = SimRig::from_parts(
            &PhysicalParams::default(),
            &world(),
            &DisturbancePreset::ideal(),
            4,
            &start,
        );
        rig.observe().unwrap();
        rig.command(&Control::planar(1.0, 0.05, 0.05)).unwrap();
        let o = rig.observe().unwrap();
        let truth = rig.ground_truth().unwrap().positions;
        for (a, b) in o.agents.iter().zip(&truth) {
            assert_eq!(a.unwrap(), *b);
        }
        assert_ne!(truth[0], start[0], "the plant moved under the command");
    }

    #[test]
    fn hardware_rig_tells_the_nominal_latency() {
        let start = [Vec2::new(10.0, 10.0), Vec2::new(12.5, 10.0)];
        let rig = SimRig::from_parts(
            &PhysicalParams::default(),
            &world(),
            &DisturbancePreset::hardware(),
            4,
            &start,
        );
        assert!((rig.latency() - 2.0 * rig.frame_period()).abs() < 1e-15);
    }

    #[test]
    fn the_coil_holds_the_elevation_to_the_presets_range() {
        let start = [
            Vec2::new(10.0, 10.0),
            Vec2::new(12.5, 10.0),
            Vec2::new(11.25, 12.165),
        ];
        let p = PhysicalParams::default();
        let tilted = |deg: f64| Control {
            alpha: deg.to_radians(),
            ..Control::planar(0.3, 0.02, 0.01)
        };
        let run = |range: f64, u: Control| {
            let mut preset = DisturbancePreset::ideal();
            preset.coil.alpha_max_deg = range;
            let mut rig = SimRig::from_parts(&p, &world(), &preset, 4, &start);
            rig.observe().unwrap();
            rig.command(&u).unwrap();
            for _ in 0..30 {
                rig.observe().unwrap();
            }
            rig.ground_truth().unwrap().positions
        };
        // a 60° command on a coil that tilts 20° moves the team as a 20° one does
        assert_eq!(run(20.0, tilted(60.0)), run(90.0, tilted(20.0)));
        assert_ne!(run(90.0, tilted(60.0)), run(90.0, tilted(20.0)));
    }

    #[test]
    fn the_map_is_centred_in_the_coil() {
        let mut preset = DisturbancePreset::ideal();
        preset.nonuniform_field.enabled = true;
        // agent 0 at the map's centre, agent 1 5 BL to its right
        let start = [Vec2::new(15.0, 10.0), Vec2::new(20.0, 10.0)];
        let p = PhysicalParams::default();
        let mut rig = SimRig::from_parts(&p, &world(), &preset, 4, &start);
        rig.observe().unwrap();
        rig.command(&Control::planar(FRAC_PI_2, p.gradient_limit(), 0.0))
            .unwrap();
        rig.observe().unwrap();
        let b = rig.plant().fields().unwrap();
        let angle = |v: &magbench_env::Vec3| v.y.atan2(v.x);
        assert!((angle(&b[0]) - FRAC_PI_2).abs() < 1e-4, "{}", angle(&b[0]));
        // 2.5 mm × 85 mT/m = 0.21 mT across 5 mT: bent by 2.4°
        let bend = (FRAC_PI_2 - angle(&b[1])).to_degrees();
        assert!((bend - 2.43).abs() < 0.02, "{bend}°");
    }
}

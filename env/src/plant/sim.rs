//! The plant: integrates the true (perturbed) physics, handles walls and sticking.

use std::sync::Arc;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::DisturbancePreset;
use crate::coil::{Coil, Control};
use crate::collision::CollisionWorld;
use crate::math::{MAX_AGENTS, Vec2};
use crate::model::{Kinematics, PairEdge, rk4_step, step_schedule};
use crate::physics::PhysicalParams;

/// The simulated plant of one run.
///
/// A noiseless plant of two identical agents (no jitter, no Brownian motion, equal moment and
/// drag factors: the `ideal` preset) follows each constant command exactly, like the planning
/// model: while the command stays the same it is the exact flow from where that command began
/// ([`PairEdge`]), sampled every integration step for contacts. So a plan followed open loop
/// is reproduced bit for bit. Every other plant integrates, each integration step: RK4 of the
/// perturbed kinematics under the commanded field (with the run's field-angle bias and a fresh
/// jitter), then a Brownian increment `√(2D dt)·N(0,1)`, then wall handling — an agent that overlaps a wall or obstacle slides along its surface
/// (it is projected back into contact; never through) and a new contact counts as one wall
/// contact event. When two agents touch (r ≤ 1 BL) they stick: the run is failed and frozen.
#[derive(Debug, Clone)]
pub struct Plant {
    kinematics: Kinematics,
    coil: Arc<dyn Coil>,
    collision: Arc<CollisionWorld>,
    dt: f64,
    rng: ChaCha8Rng,
    angle_bias: f64,
    jitter: f64,
    diffusion: f64,
    positions: Vec<Vec2>,
    time: f64,
    stuck: bool,
    touching_wall: Vec<bool>,
    wall_contacts: usize,
    /// The noiseless pair case: constant commands are followed exactly.
    exact: bool,
    /// The exact constant-command motion in progress.
    segment: Option<Segment>,
}

/// A constant command the noiseless plant is following exactly: `runs` calls of [`Plant::run`]
/// of `run` seconds each under `command` (as applied, bias included) from the edge's start.
#[derive(Debug, Clone)]
struct Segment {
    edge: PairEdge,
    command: Control,
    run: f64,
    runs: u32,
}

impl Plant {
    /// A plant for one run: disturbances drawn from `preset` with `seed`, agents at `start`.
    pub fn new(
        params: &PhysicalParams,
        coil: Arc<dyn Coil>,
        collision: Arc<CollisionWorld>,
        preset: &DisturbancePreset,
        seed: u64,
        start: &[Vec2],
    ) -> Self {
        assert!(start.len() <= MAX_AGENTS);
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x9147_A11E_0000_0001);
        let mut kinematics = Kinematics::nominal(params);
        let spread = |s: f64, rng: &mut ChaCha8Rng| {
            if s > 0.0 {
                rng.random_range(1.0 - s..=1.0 + s)
            } else {
                1.0
            }
        };
        for i in 0..start.len() {
            kinematics.moment[i] = spread(preset.moment_spread, &mut rng);
            kinematics.mobility[i] = 1.0 / spread(preset.drag_spread, &mut rng);
        }
        if preset.drift_speed_bl_s > 0.0 {
            let speed = rng.random_range(0.0..=preset.drift_speed_bl_s);
            let dir = rng.random_range(0.0..std::f64::consts::TAU);
            kinematics.flow = Vec2::new(dir.cos(), dir.sin()) * speed;
        }
        let normal = |rng: &mut ChaCha8Rng| -> f64 { StandardNormal.sample(rng) };
        let angle_bias = preset.field_angle_bias_deg.to_radians() * normal(&mut rng);
        let exact = start.len() == 2
            && preset.field_angle_jitter_deg == 0.0
            && !preset.brownian
            && kinematics.moment[0] == kinematics.moment[1]
            && kinematics.mobility[0] == kinematics.mobility[1];
        Self {
            kinematics,
            coil,
            collision,
            dt: params.dt_s,
            rng,
            angle_bias,
            jitter: preset.field_angle_jitter_deg.to_radians(),
            diffusion: if preset.brownian {
                params.diffusion()
            } else {
                0.0
            },
            positions: start.to_vec(),
            time: 0.0,
            stuck: false,
            touching_wall: vec![false; start.len()],
            wall_contacts: 0,
            exact,
            segment: None,
        }
    }

    /// True agent positions (BL).
    pub fn positions(&self) -> &[Vec2] {
        &self.positions
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// True once two agents have touched and stuck (a failed run).
    pub fn stuck(&self) -> bool {
        self.stuck
    }

    /// Number of wall contact events so far.
    pub fn wall_contacts(&self) -> usize {
        self.wall_contacts
    }

    /// The integration step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The run's drawn kinematics (mismatch factors and flow), for logs.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }

    /// Switches the map (the obstacles of a new leg).
    pub fn set_collision(&mut self, collision: Arc<CollisionWorld>) {
        self.collision = collision;
    }

    /// Advances by `duration` under `u`, with the planning model's step schedule.
    pub fn run(&mut self, u: &Control, duration: f64) {
        if self.exact && !self.stuck && self.run_exact(u, duration) {
            return;
        }
        self.run_steps(u, duration, 0);
    }

    /// RK4 steps of the schedule of `duration`, from step `from` on.
    fn run_steps(&mut self, u: &Control, duration: f64, from: usize) {
        let (steps, rest) = step_schedule(duration, self.dt);
        for k in 0..steps + usize::from(rest > 0.0) {
            if k >= from {
                self.step_by(u, if k < steps { self.dt } else { rest });
            }
        }
    }

    /// [`Plant::run`] of the noiseless pair: the exact flow of the constant command, continued
    /// from where the command began, sampled at the integration steps for agent and wall
    /// contacts. False when no closed form applies (the caller integrates instead).
    fn run_exact(&mut self, u: &Control, duration: f64) -> bool {
        let (u, _) = self.coil.clamp(u);
        let applied = Control {
            theta: u.theta + self.angle_bias,
            ..u
        };
        let continuing = self
            .segment
            .as_ref()
            .is_some_and(|s| s.command == applied && s.run == duration);
        if !continuing {
            let act = self.coil.actuation(&applied);
            let Some(edge) = self.kinematics.pair_edge(&self.positions, &act) else {
                self.segment = None;
                return false;
            };
            self.segment = Some(Segment {
                edge,
                command: applied,
                run: duration,
                runs: 0,
            });
        }
        let seg = self.segment.as_mut().expect("a segment was just set");
        seg.runs += 1;
        let (edge, t1) = (seg.edge, seg.runs as f64 * duration);
        let t0 = t1 - duration;
        let (steps, rest) = step_schedule(duration, self.dt);
        let samples = steps + usize::from(rest > 0.0);
        for k in 1..=samples {
            self.time += if k <= steps { self.dt } else { rest };
            let mut before = [Vec2::zeros(); 2];
            before.copy_from_slice(&self.positions);
            let t = if k == samples {
                t1
            } else {
                t0 + k as f64 * self.dt
            };
            edge.at(t, &mut self.positions);
            if self.contact_during_step(&before) {
                self.segment = None;
                return true;
            }
            if self.slide_along_walls() {
                // the agents left the exact curve: integrate the rest of this run
                self.segment = None;
                self.run_steps(&u, duration, k);
                return true;
            }
        }
        true
    }

    /// Projects agents that overlap a wall or obstacle back into contact, counting new
    /// contacts; true when any agent was moved.
    fn slide_along_walls(&mut self) -> bool {
        let mut moved = false;
        for (i, p) in self.positions.iter_mut().enumerate() {
            match self.collision.push_out(*p) {
                Some(q) => {
                    *p = q;
                    moved = true;
                    if !self.touching_wall[i] {
                        self.wall_contacts += 1;
                    }
                    self.touching_wall[i] = true;
                }
                None => self.touching_wall[i] = false,
            }
        }
        moved
    }

    /// Advances one integration step under `u`.
    pub fn step(&mut self, u: &Control) {
        self.step_by(u, self.dt);
    }

    fn step_by(&mut self, u: &Control, h: f64) {
        self.segment = None;
        self.time += h;
        if self.stuck {
            return;
        }
        let (u, _) = self.coil.clamp(u);
        let mut applied = u;
        if self.angle_bias != 0.0 || self.jitter > 0.0 {
            let j: f64 = if self.jitter > 0.0 {
                StandardNormal.sample(&mut self.rng)
            } else {
                0.0
            };
            applied.theta += self.angle_bias + self.jitter * j;
        }
        let act = self.coil.actuation(&applied);
        let kin = &self.kinematics;
        let n = self.positions.len();
        let mut before = [Vec2::zeros(); MAX_AGENTS];
        before[..n].copy_from_slice(&self.positions);
        rk4_step(
            &|p: &[Vec2], v: &mut [Vec2]| kin.velocities(p, &act, v),
            &mut self.positions,
            h,
        );
        if self.contact_during_step(&before[..n]) {
            return;
        }
        if self.diffusion > 0.0 {
            let s = (2.0 * self.diffusion * h).sqrt();
            for p in &mut self.positions {
                let (nx, ny): (f64, f64) = (
                    StandardNormal.sample(&mut self.rng),
                    StandardNormal.sample(&mut self.rng),
                );
                *p += Vec2::new(nx, ny) * s;
            }
        }
        self.slide_along_walls();
        self.contact_during_step(&before[..n]);
    }

    /// Detects agents touching during the last step: a pair whose relative position passed
    /// within 1 BL of contact anywhere along the step's chord (a fast attraction can carry an
    /// integration step past r = 1). The touching pair is left in contact, stuck.
    fn contact_during_step(&mut self, before: &[Vec2]) -> bool {
        let n = self.positions.len();
        for i in 0..n {
            for j in (i + 1)..n {
                let (d0, d1) = (before[j] - before[i], self.positions[j] - self.positions[i]);
                let seg = d1 - d0;
                let t = if seg.norm_squared() > 0.0 {
                    (-d0.dot(&seg) / seg.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                if (d0 + seg * t).norm() <= 1.0 || !d1.norm().is_finite() {
                    let mid = (before[i] + before[j]) * 0.5;
                    let dir = if d0.norm() > 0.0 {
                        d0 / d0.norm()
                    } else {
                        Vec2::new(1.0, 0.0)
                    };
                    self.positions[..n].copy_from_slice(before);
                    self.positions[i] = mid - dir * 0.5;
                    self.positions[j] = mid + dir * 0.5;
                    self.stuck = true;
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::PlanningModel;
    use crate::physics::LocalView;
    use crate::world::World;

    fn open_world() -> Arc<CollisionWorld> {
        Arc::new(CollisionWorld::new(
            &World {
                width: 40.0,
                height: 30.0,
                obstacles: vec![],
            },
            0.5,
        ))
    }

    #[test]
    fn ideal_plant_is_the_planning_model_bit_for_bit() {
        let p = PhysicalParams::default();
        let model = PlanningModel::new(&p);
        let start = LocalView {
            xc: 20.0,
            yc: 15.0,
            r: 2.5,
            phi: 0.2,
        }
        .to_pair();
        let mut plant = Plant::new(
            &p,
            model.coil.clone(),
            open_world(),
            &DisturbancePreset::ideal(),
            3,
            &start,
        );
        // ψ ≈ 55° then ψ ≈ 90°: the pair rotates, then separates; it never touches
        let controls = [
            Control::planar(1.16, 0.05, 0.02),
            Control::planar(1.8, -0.08, 0.0),
        ];
        let mut s = start;
        for u in &controls {
            let mut out = [Vec2::zeros(); 2];
            model.propagate_with(&s, u, 0.75, &mut out, |_| true);
            s = out;
            plant.run(u, 0.75);
        }
        assert!(!plant.stuck());
        let diff: f64 = plant
            .positions()
            .iter()
            .zip(&s)
            .map(|(a, b)| (a - b).norm())
            .sum();
        assert_eq!(plant.positions(), &s[..], "difference {diff:e}");
    }

    #[test]
    fn attraction_makes_agents_stick() {
        let p = PhysicalParams::default();
        let start = LocalView {
            xc: 20.0,
            yc: 15.0,
            r: 1.4,
            phi: 0.0,
        }
        .to_pair();
        let coil: Arc<dyn Coil> = Arc::new(crate::coil::TriaxialMaxwell::new(p.gradient_limit()));
        let mut plant = Plant::new(
            &p,
            coil,
            open_world(),
            &DisturbancePreset::ideal(),
            1,
            &start,
        );
        plant.run(&Control::planar(0.0, 0.0, 0.0), 1.0);
        assert!(plant.stuck());
    }

    #[test]
    fn pulling_into_a_wall_slides_and_counts_one_contact() {
        let p = PhysicalParams::default();
        let start = LocalView {
            xc: 2.0,
            yc: 15.0,
            r: 2.0,
            phi: std::f64::consts::FRAC_PI_2,
        }
        .to_pair();
        let coil: Arc<dyn Coil> = Arc::new(crate::coil::TriaxialMaxwell::new(p.gradient_limit()));
        let mut plant = Plant::new(
            &p,
            coil,
            open_world(),
            &DisturbancePreset::ideal(),
            1,
            &start,
        );
        // field along −x pulls toward the left wall (θ = π, G_x > 0 gives F_x < 0)
        plant.run(
            &Control::planar(std::f64::consts::PI, p.gradient_limit(), 0.0),
            8.0,
        );
        for q in plant.positions() {
            assert!(q.x >= 0.5 - 1e-9, "agent passed through the wall: {q:?}");
        }
        assert_eq!(
            plant.wall_contacts(),
            2,
            "each agent touched once and stayed"
        );
    }
}

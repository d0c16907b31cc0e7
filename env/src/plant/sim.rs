//! The plant: integrates the true (perturbed) physics, handles walls and sticking.

use std::sync::Arc;

use rand_chacha::ChaCha8Rng;

use super::dynamics::{Advance, Dynamics, State};
use super::field::CoilOutput;
use super::streams::{Stream, normal, stream};
use super::{DisturbancePreset, Walls};
use crate::coil::{Coil, Control};
use crate::collision::CollisionWorld;
use crate::math::{MAX_AGENTS, Vec2, Vec3, centroid};
use crate::model::{Kinematics, PairEdge, step_schedule};
use crate::physics::PhysicalParams;
use crate::world::World;

/// Agent radius (BL): an agent is one body length across.
pub const AGENT_RADIUS_BL: f64 = 0.5;

/// The simulated plant of one run.
///
/// A noiseless plant of two identical agents (the `ideal` preset; a field bias and a uniform
/// drift may be on) follows each constant command exactly, like the planning model: while the
/// command stays the same it is the exact flow from where that command began ([`PairEdge`]),
/// sampled every integration step for contacts. So a plan followed open loop is reproduced
/// bit for bit. Every other plant integrates, each integration step `h` (the physical preset's
/// `dt_s`, or the shorter rest of a duration): the coil's outputs follow the command (with the
/// run's field bias and a fresh jitter) through the coil dynamics, and RK4 advances positions
/// and moments through the [`Dynamics`] of every term (in sub-steps with the magnet-lag
/// term); then a Brownian increment `√(2D h)·N(0,1)`, then wall handling — an agent that
/// overlaps a wall or obstacle slides along its surface (it is projected back into contact;
/// never through) and a new contact counts as one wall contact event. Under virtual walls
/// (`walls = "virtual"`) the agents pass through walls and obstacles, and each new overlap
/// still counts as one wall contact event. When two agents touch
/// (r ≤ 1 BL) they stick: the run is failed and frozen.
///
/// The run starts with the field switched on: at the first command the coil is settled on it
/// and every moment is aligned with the field its agent feels.
#[derive(Debug, Clone)]
pub struct Plant {
    kinematics: Kinematics,
    dynamics: Dynamics,
    coil: Arc<dyn Coil>,
    collision: Arc<CollisionWorld>,
    dt: f64,
    jitter_rng: ChaCha8Rng,
    brownian_rng: ChaCha8Rng,
    diffusion: f64,
    n: usize,
    state: State,
    /// The coil's outputs now; `None` before the first command.
    coil_out: Option<CoilOutput>,
    /// Where the coil is centred (BL), before the run's placement offset.
    centre: Vec2,
    time: f64,
    stuck: bool,
    touching_wall: Vec<bool>,
    wall_contacts: usize,
    /// Whether walls stop the agents or only count their contacts.
    walls: Walls,
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
    /// The coil is centred on the agents' centroid until [`Plant::set_coil_centre`] says
    /// otherwise.
    pub fn new(
        params: &PhysicalParams,
        coil: Arc<dyn Coil>,
        collision: Arc<CollisionWorld>,
        preset: &DisturbancePreset,
        seed: u64,
        start: &[Vec2],
    ) -> Self {
        let n = start.len();
        assert!((1..=MAX_AGENTS).contains(&n), "1 to {MAX_AGENTS} agents");
        let dynamics = Dynamics::draw(preset, params, n, seed);
        let mut kinematics = Kinematics::in_medium(params, preset.medium.drag());
        kinematics.moment = dynamics.factors.moment;
        kinematics.mobility = dynamics.factors.mobility;
        kinematics.flow = dynamics.flow.drift;
        let exact = n == 2
            && dynamics.is_exact_pair()
            && !preset.brownian.enabled
            && kinematics.moment[0] == kinematics.moment[1]
            && kinematics.mobility[0] == kinematics.mobility[1];
        let mut state = State {
            p: [Vec2::zeros(); MAX_AGENTS],
            m: [Vec3::zeros(); MAX_AGENTS],
        };
        state.p[..n].copy_from_slice(start);
        let centre = centroid(start);
        Self {
            kinematics,
            dynamics,
            coil,
            collision,
            dt: preset.medium.step(params.dt_s),
            jitter_rng: stream(seed, Stream::FieldJitter),
            brownian_rng: stream(seed, Stream::Brownian),
            diffusion: if preset.brownian.enabled {
                params.diffusion_in(preset.medium.drag())
            } else {
                0.0
            },
            n,
            state,
            coil_out: None,
            centre,
            time: 0.0,
            stuck: false,
            touching_wall: vec![false; n],
            wall_contacts: 0,
            walls: preset.walls,
            exact,
            segment: None,
        }
    }

    /// A plant for one run in `world` (its collision geometry for agents of radius 0.5 BL),
    /// with the map centred in the coil: what every simulated rig (the tracking loop's and the
    /// emulator's) runs.
    pub fn in_world(
        params: &PhysicalParams,
        coil: Arc<dyn Coil>,
        world: &World,
        preset: &DisturbancePreset,
        seed: u64,
        start: &[Vec2],
    ) -> Self {
        let collision = Arc::new(CollisionWorld::new(world, AGENT_RADIUS_BL));
        let mut plant = Self::new(params, coil, collision, preset, seed, start);
        plant.set_coil_centre(Vec2::new(world.width, world.height) * 0.5);
        plant
    }

    /// Centres the coil on `centre` (BL; the run's placement offset comes on top): the map's
    /// centre for a map centred in the coil.
    pub fn set_coil_centre(&mut self, centre: Vec2) {
        self.centre = centre;
    }

    /// True agent positions (BL).
    pub fn positions(&self) -> &[Vec2] {
        &self.state.p[..self.n]
    }

    /// Unit moment directions, with the magnet-lag term, once the field is on.
    pub fn moments(&self) -> Option<&[Vec3]> {
        (self.dynamics.tracks_moments() && self.coil_out.is_some()).then(|| &self.state.m[..self.n])
    }

    /// The field (T) each agent feels now; `None` before the first command.
    pub fn fields(&self) -> Option<Vec<Vec3>> {
        let c = self.coil_out?;
        let (b, _) = self.dynamics.fields(&c, self.centre, &self.state);
        Some(b[..self.n].to_vec())
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

    /// The run's drawn dynamics (agent factors, field model, flow), for logs.
    pub fn dynamics(&self) -> &Dynamics {
        &self.dynamics
    }

    /// True when constant commands are followed by the exact pair flow.
    pub fn is_exact(&self) -> bool {
        self.exact
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

    /// Integration steps of the schedule of `duration`, from step `from` on.
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
            theta: u.theta + self.dynamics.field.bias,
            ..u
        };
        let continuing = self
            .segment
            .as_ref()
            .is_some_and(|s| s.command == applied && s.run == duration);
        if !continuing {
            let act = self.coil.actuation(&applied);
            let Some(edge) = self.kinematics.pair_edge(self.positions(), &act) else {
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
            before.copy_from_slice(self.positions());
            let t = if k == samples {
                t1
            } else {
                t0 + k as f64 * self.dt
            };
            edge.at(t, &mut self.state.p[..2]);
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

    /// Projects agents that overlap a wall or obstacle back into contact (physical walls; virtual
    /// walls leave them where they are), counting new contacts; true when any agent was moved.
    fn slide_along_walls(&mut self) -> bool {
        let mut moved = false;
        let physical = self.walls == Walls::Physical;
        for (i, p) in self.state.p[..self.n].iter_mut().enumerate() {
            match self.collision.push_out(*p) {
                Some(q) => {
                    if physical {
                        *p = q;
                        moved = true;
                    }
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
        let t0 = self.time;
        self.time += h;
        if self.stuck {
            return;
        }
        let (u, _) = self.coil.clamp(u);
        let jitter = self.dynamics.field.jitter_sample(&mut self.jitter_rng);
        let target = self.dynamics.field.target(&u, jitter);
        let c0 = match self.coil_out {
            Some(c) => c,
            None => {
                if self.dynamics.tracks_moments() {
                    self.dynamics
                        .align_moments(&mut self.state, &target, self.centre);
                }
                target
            }
        };
        let n = self.n;
        let mut before = [Vec2::zeros(); MAX_AGENTS];
        before[..n].copy_from_slice(self.positions());
        let advance = self
            .dynamics
            .advance(&mut self.state, t0, &c0, &target, self.centre, h);
        self.coil_out = Some(self.dynamics.coil_at(&c0, &target, h));
        if advance == Advance::Contact {
            self.stick_closest_pair();
            return;
        }
        if self.contact_during_step(&before[..n]) {
            return;
        }
        if self.diffusion > 0.0 {
            let s = (2.0 * self.diffusion * h).sqrt();
            for p in &mut self.state.p[..n] {
                let (nx, ny) = (
                    normal(&mut self.brownian_rng),
                    normal(&mut self.brownian_rng),
                );
                *p += Vec2::new(nx, ny) * s;
            }
        }
        self.slide_along_walls();
        self.contact_during_step(&before[..n]);
    }

    /// Leaves the closest pair in contact about its midpoint, stuck: the end of a step whose
    /// integration reached contact, with the state at the last instant before it.
    fn stick_closest_pair(&mut self) {
        let p = &mut self.state.p[..self.n];
        let mut closest = (0, 1, f64::INFINITY);
        for i in 0..p.len() {
            for j in (i + 1)..p.len() {
                let d = (p[j] - p[i]).norm();
                if d < closest.2 {
                    closest = (i, j, d);
                }
            }
        }
        let (i, j, d) = closest;
        let mid = (p[i] + p[j]) * 0.5;
        let dir = if d > 0.0 {
            (p[j] - p[i]) / d
        } else {
            Vec2::new(1.0, 0.0)
        };
        p[i] = mid - dir * 0.5;
        p[j] = mid + dir * 0.5;
        self.stuck = true;
    }

    /// Detects agents touching during the last step: a pair whose relative position passed
    /// within 1 BL of contact anywhere along the step's chord (a fast attraction can carry an
    /// integration step past r = 1). The touching pair is left in contact, stuck.
    fn contact_during_step(&mut self, before: &[Vec2]) -> bool {
        let n = self.n;
        let positions = &mut self.state.p;
        for i in 0..n {
            for j in (i + 1)..n {
                let (d0, d1) = (before[j] - before[i], positions[j] - positions[i]);
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
                    positions[..n].copy_from_slice(before);
                    positions[i] = mid - dir * 0.5;
                    positions[j] = mid + dir * 0.5;
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
        let start = LocalView::new(20.0, 15.0, 2.5, 0.2).to_pair();
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
        let start = LocalView::new(20.0, 15.0, 1.4, 0.0).to_pair();
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

    /// Pairs 1.02–1.6 BL apart in the bulk with the field 0–0.6 rad off their separation: a
    /// plant step of 1/120 s can carry the r⁻⁴ attraction past contact. The integrated plant (a
    /// lagging coil keeps it off the exact flow) must end each step apart or in contact, stuck,
    /// never thrown across the workspace.
    #[test]
    fn a_fast_attraction_ends_in_contact_not_thrown_apart() {
        let p = PhysicalParams::default();
        let coil: Arc<dyn Coil> = Arc::new(crate::coil::TriaxialMaxwell::new(p.gradient_limit()));
        let mut preset = DisturbancePreset::ideal();
        preset.coil_lag.enabled = true;
        preset.coil_lag.field_tau_ms = 25.0;
        let centre = Vec2::new(20.0, 15.0);
        let mut bad = vec![];
        for r0 in (0..30).map(|k| 1.02 + 0.02 * k as f64) {
            for psi in (0..13).map(|k| 0.05 * k as f64) {
                let start = LocalView::new(centre.x, centre.y, r0, psi).to_pair();
                let mut plant = Plant::new(&p, coil.clone(), open_world(), &preset, 1, &start);
                assert!(!plant.is_exact());
                plant.step(&Control::planar(0.0, 0.0, 0.0));
                let q = plant.positions();
                let r = (q[1] - q[0]).norm();
                let moved = (q[0] - start[0]).norm().max((q[1] - start[1]).norm());
                let ok = if plant.stuck() {
                    (r - 1.0).abs() < 1e-9 && moved < 0.5
                } else {
                    r > 1.0 && moved < 0.5
                };
                if !ok {
                    bad.push(format!(
                        "r0 {r0:.2} ψ {psi:.2}: r {r:.3e}, moved {moved:.3e}, stuck {}",
                        plant.stuck()
                    ));
                }
            }
        }
        assert!(bad.is_empty(), "{}", bad.join("\n"));
    }

    /// A pair 2 BL from the left wall under `preset`, pulled toward it for 8 s (field along −x:
    /// θ = π, G_x > 0 gives F_x < 0).
    fn pulled_into_the_left_wall(preset: &DisturbancePreset) -> Plant {
        let p = PhysicalParams::default();
        let start = LocalView::new(2.0, 15.0, 2.0, std::f64::consts::FRAC_PI_2).to_pair();
        let coil: Arc<dyn Coil> = Arc::new(crate::coil::TriaxialMaxwell::new(p.gradient_limit()));
        let mut plant = Plant::new(&p, coil, open_world(), preset, 1, &start);
        plant.run(
            &Control::planar(std::f64::consts::PI, p.gradient_limit(), 0.0),
            8.0,
        );
        plant
    }

    #[test]
    fn pulling_into_a_wall_slides_and_counts_one_contact() {
        let plant = pulled_into_the_left_wall(&DisturbancePreset::ideal());
        for q in plant.positions() {
            assert!(q.x >= 0.5 - 1e-9, "agent passed through the wall: {q:?}");
        }
        assert_eq!(
            plant.wall_contacts(),
            2,
            "each agent touched once and stayed"
        );
    }

    #[test]
    fn virtual_walls_let_agents_through_and_count_the_contact() {
        let plant = pulled_into_the_left_wall(&DisturbancePreset {
            walls: Walls::Virtual,
            ..DisturbancePreset::ideal()
        });
        for q in plant.positions() {
            assert!(q.x < 0.5, "agent stopped at a virtual wall: {q:?}");
        }
        assert_eq!(plant.wall_contacts(), 2, "each agent crossed once");
    }
}

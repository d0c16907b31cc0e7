//! The deterministic planning model (the seed's eq. 3 over the vector physics).
//!
//! Replaying a plan's controls through this model from the plan's start reproduces its states
//! bit for bit. The pair dynamics are extremely sensitive (a 1e-9 BL start error grew to
//! 4–53 BL on long mazes in another implementation), so any other path of code — another
//! integrator, step or force formula — only agrees approximately, and tracking needs closed loop.

use std::sync::Arc;

use super::{Kinematics, Propagator, rk4_step, step_schedule};
use crate::coil::{Coil, Control, TriaxialMaxwell};
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::PhysicalParams;

/// Nominal kinematics + coil + fixed step: what planners and the OBC predict with.
#[derive(Debug, Clone)]
pub struct PlanningModel {
    /// The velocity field (nominal factors).
    pub kinematics: Kinematics,
    /// The coil that realises controls.
    pub coil: Arc<dyn Coil>,
    /// Integration step (s).
    pub dt: f64,
}

impl PlanningModel {
    /// The planning model of a preset with the default tri-axial coil.
    pub fn new(p: &PhysicalParams) -> Self {
        Self::with_coil(p, Arc::new(TriaxialMaxwell::new(p.gradient_limit())))
    }

    /// The planning model of a preset with a given coil.
    pub fn with_coil(p: &PhysicalParams, coil: Arc<dyn Coil>) -> Self {
        Self {
            kinematics: Kinematics::nominal(p),
            coil,
            dt: p.dt_s,
        }
    }

    /// Agent velocities (BL/s) at `p` under `u`.
    pub fn velocities(&self, p: &[Vec2], u: &Control, v: &mut [Vec2]) {
        let act = self.coil.actuation(u);
        self.kinematics.velocities(p, &act, v);
    }

    /// Integrates under a constant control, visiting each sample; see [`Propagator`].
    #[inline]
    pub fn propagate_with(
        &self,
        start: &[Vec2],
        u: &Control,
        duration: f64,
        out: &mut [Vec2],
        mut visit: impl FnMut(&[Vec2]) -> bool,
    ) -> bool {
        let n = start.len();
        assert!(n <= MAX_AGENTS && out.len() == n);
        out.copy_from_slice(start);
        let act = self.coil.actuation(u);
        let f = |p: &[Vec2], v: &mut [Vec2]| self.kinematics.velocities(p, &act, v);
        let (steps, rest) = step_schedule(duration, self.dt);
        for _ in 0..steps {
            rk4_step(&f, out, self.dt);
            if !visit(out) {
                return false;
            }
        }
        if rest > 0.0 {
            rk4_step(&f, out, rest);
            if !visit(out) {
                return false;
            }
        }
        true
    }
}

impl PlanningModel {
    /// Integrates `start` under each `(controls[i], durations[i])` into `ends[i]` (first N
    /// entries), advancing the independent integrations step by step together so that the CPU
    /// overlaps them (about 3× faster than one at a time for two agents). Each end equals
    /// [`PlanningModel::propagate_with`]'s for that pair bit for bit: same steps, same arithmetic.
    pub fn propagate_many(
        &self,
        start: &[Vec2],
        controls: &[Control],
        durations: &[f64],
        ends: &mut [[Vec2; MAX_AGENTS]],
    ) {
        let n = start.len();
        let k = controls.len();
        assert!(n <= MAX_AGENTS && durations.len() == k && ends.len() >= k);
        let acts: Vec<_> = controls.iter().map(|u| self.coil.actuation(u)).collect();
        let schedules: Vec<_> = durations
            .iter()
            .map(|&d| step_schedule(d, self.dt))
            .collect();
        let most = schedules.iter().map(|s| s.0).max().unwrap_or(0);
        for e in ends[..k].iter_mut() {
            e[..n].copy_from_slice(start);
        }
        for step in 0..most {
            for i in 0..k {
                if step < schedules[i].0 {
                    let act = &acts[i];
                    let f = |p: &[Vec2], v: &mut [Vec2]| self.kinematics.velocities(p, act, v);
                    rk4_step(&f, &mut ends[i][..n], self.dt);
                }
            }
        }
        for i in 0..k {
            let rest = schedules[i].1;
            if rest > 0.0 {
                let act = &acts[i];
                let f = |p: &[Vec2], v: &mut [Vec2]| self.kinematics.velocities(p, act, v);
                rk4_step(&f, &mut ends[i][..n], rest);
            }
        }
    }
}

impl Propagator for PlanningModel {
    fn propagate_visit(
        &self,
        start: &[Vec2],
        u: &Control,
        duration: f64,
        out: &mut [Vec2],
        visit: &mut dyn FnMut(&[Vec2]) -> bool,
    ) -> bool {
        self.propagate_with(start, u, duration, out, visit)
    }

    fn step(&self) -> f64 {
        self.dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::LocalView;

    #[test]
    fn replay_is_bit_exact() {
        let m = PlanningModel::new(&PhysicalParams::default());
        let start = LocalView {
            xc: 10.0,
            yc: 8.0,
            r: 2.0,
            phi: 0.3,
        }
        .to_pair();
        let u = Control::planar(1.2, 0.05, -0.02);
        let (mut a, mut b) = ([Vec2::zeros(); 2], [Vec2::zeros(); 2]);
        m.propagate(&start, &u, 0.5, &mut a);
        m.propagate(&start, &u, 0.5, &mut b);
        assert_eq!(a, b);
    }

    #[test]
    fn propagate_many_matches_one_at_a_time_bit_for_bit() {
        let m = PlanningModel::new(&PhysicalParams::default());
        let start = LocalView {
            xc: 10.0,
            yc: 8.0,
            r: 2.0,
            phi: 0.3,
        }
        .to_pair();
        let controls: Vec<_> = (0..7)
            .map(|i| Control::planar(0.9 * i as f64 - 3.0, 0.01 * i as f64, -0.02))
            .collect();
        let durations = [0.5, 1.0 / 60.0, 0.25, 0.01, 0.0, 0.3, 1.0 / 7.0];
        let mut ends = [[Vec2::zeros(); MAX_AGENTS]; 7];
        m.propagate_many(&start, &controls, &durations, &mut ends);
        for i in 0..7 {
            let mut one = [Vec2::zeros(); 2];
            m.propagate(&start, &controls[i], durations[i], &mut one);
            assert_eq!(&ends[i][..2], &one[..], "try {i}");
        }
    }

    #[test]
    fn magic_angle_holds_separation() {
        let m = PlanningModel::new(&PhysicalParams::default());
        let v = LocalView {
            xc: 10.0,
            yc: 8.0,
            r: 2.0,
            phi: 0.0,
        };
        let magic = (1.0f64 / 3.0).sqrt().acos();
        let mut out = [Vec2::zeros(); 2];
        // over a short time the separation barely changes while the pair rotates
        m.propagate(
            &v.to_pair(),
            &Control::planar(magic, 0.0, 0.0),
            0.02,
            &mut out,
        );
        let w = LocalView::from_pair(out[0], out[1]);
        assert!((w.r - 2.0).abs() < 1e-3, "r moved to {}", w.r);
        assert!(w.phi > 0.0, "pair rotates toward the field");
    }
}

//! The deterministic planning model (the seed's eq. 3 over the vector physics).
//!
//! [`Flow::PairAdaptive`] (the default) moves two identical agents under a planar command by the
//! exact flow ([`super::pair_flow`]) and everything else (three or more agents, an elevated
//! field, unequal agents) by adaptive Dormand–Prince 5(4) ([`super::dp5_solve`]);
//! [`Flow::PairExact`] integrates everything else by classic RK4 at the fixed step, and
//! [`Flow::Rk4`] uses RK4 everywhere. A plan records its flow, and replay uses it.
//!
//! Replaying a plan's controls through this model from the plan's start reproduces its states
//! bit for bit. The pair dynamics are extremely sensitive (a 1e-9 BL start error grew to
//! 4–53 BL on long mazes in another implementation), so any other path of code — another
//! integrator, step or force formula — only agrees approximately, and tracking needs closed loop.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::pair_flow::{PairEdge, PairStart};
use super::{
    Dp5Grid, ErrorBudget, Kinematics, Propagator, TeamField, dp5_solve, dp5_solve_many, rk4_step,
    step_schedule,
};
use crate::coil::{Actuation, Coil, Control, TriaxialMaxwell};
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::PhysicalParams;

/// How the planning model solves a motion under a constant command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Flow {
    /// The exact flow for two identical agents under a planar command; adaptive Dormand–Prince
    /// 5(4) otherwise ([`super::dp5_solve`], tolerance [`super::TOLERANCE_BL`]).
    #[default]
    PairAdaptive,
    /// The exact flow for two identical agents under a planar command; RK4 at the fixed step
    /// otherwise.
    PairExact,
    /// Classic RK4 at the fixed step for every motion.
    Rk4,
}

impl Flow {
    /// Every flow, in the order the command line lists them.
    pub const ALL: [Flow; 3] = [Flow::PairAdaptive, Flow::PairExact, Flow::Rk4];

    /// The name used in plan files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Flow::PairAdaptive => "pair-adaptive",
            Flow::PairExact => "pair-exact",
            Flow::Rk4 => "rk4",
        }
    }

    /// The flow of a name, if known.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Whether two identical agents under a planar command move by the exact pair flow.
    #[inline]
    pub fn pair_exact(self) -> bool {
        self != Flow::Rk4
    }

    /// Whether integrated motions are solved adaptively (else by RK4 at the fixed step).
    #[inline]
    pub fn adaptive(self) -> bool {
        self == Flow::PairAdaptive
    }
}

/// Nominal kinematics + coil + flow: what planners and the OBC predict with.
#[derive(Debug, Clone)]
pub struct PlanningModel {
    /// The velocity field (nominal factors).
    pub kinematics: Kinematics,
    /// The coil that realises controls.
    pub coil: Arc<dyn Coil>,
    /// Integration step of RK4, and the sampling step of visits under every flow (s).
    pub dt: f64,
    /// How motions are solved.
    pub flow: Flow,
    /// Whether the agents' medium carries the out-of-plane force f_z (a liquid–air interface,
    /// the seed's set-up), so that a field tilted out of the plane keeps them in it; false in
    /// bulk liquid, where only α = 0 keeps the planar model true. True unless set
    /// ([`PlanningModel::in_medium`]).
    pub carries_fz: bool,
    /// The proximity range `[r_min, r_max]` (BL) the adaptive integrator's error budget is
    /// derived for ([`PlanningModel::error_budget`]).
    pub separation: [f64; 2],
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
            flow: Flow::default(),
            carries_fz: true,
            separation: [p.r_min, p.r_max],
        }
    }

    /// The adaptive integrator's error budget for a team of `n`: its fastest relative speed is
    /// that of an agent with `n − 1` neighbours at `r_min`, each pushing with the aligned
    /// dipole force's largest magnitude `2 c_F s_i s_j μ_i / r⁴`; its slowest charged speed is a
    /// lone pair's at `r_max` with the force's smallest magnitude (√0.8 of `c_F / r⁴`).
    pub fn error_budget(&self, n: usize) -> ErrorBudget {
        let k = &self.kinematics;
        let (mut hi, mut lo) = (0.0f64, f64::INFINITY);
        for i in 0..n {
            for j in (0..n).filter(|&j| j != i) {
                let c = k.force_coeff * k.moment[i] * k.moment[j] * k.mobility[i];
                hi = hi.max(c);
                lo = lo.min(c);
            }
        }
        let [r_min, r_max] = self.separation;
        ErrorBudget::new(
            2.0 * (n.max(2) - 1) as f64 * hi / r_min.powi(4),
            0.8f64.sqrt() * lo.min(hi) / r_max.powi(4),
            r_min,
        )
    }

    /// The sample spacing and error budget of an adaptive motion of a team of `n`.
    #[inline]
    fn dp5_grid(&self, n: usize) -> Dp5Grid {
        Dp5Grid {
            dt: self.dt,
            budget: self.error_budget(n),
        }
    }

    /// The same model for agents of `p` in `medium`: its drag ([`crate::plant::Medium::drag`],
    /// so that a plan at an interface has the interface's time scale, as the plant does), its
    /// integration step ([`crate::plant::Medium::step`], the plant's too) and whether it carries
    /// the out-of-plane force. The coil and flow are kept.
    pub fn in_medium(self, p: &PhysicalParams, medium: &crate::plant::Medium) -> Self {
        Self {
            kinematics: Kinematics {
                moment: self.kinematics.moment,
                mobility: self.kinematics.mobility,
                flow: self.kinematics.flow,
                ..Kinematics::in_medium(p, medium.drag())
            },
            dt: medium.step(p.dt_s),
            carries_fz: medium.carries_fz(),
            ..self
        }
    }

    /// The same model with another flow.
    pub fn with_flow(&self, flow: Flow) -> Self {
        Self {
            flow,
            ..self.clone()
        }
    }

    /// The exact motion from `start` under `u`, when the flow uses the pair flow and the
    /// closed form applies: two agents with equal moment and mobility factors and an in-plane
    /// field. The uniform background flow and the pull then only move the centre of mass.
    #[inline]
    pub fn pair_edge(&self, start: &[Vec2], u: &Control) -> Option<PairEdge> {
        if !self.flow.pair_exact() || start.len() != 2 {
            return None;
        }
        self.kinematics.pair_edge(start, &self.coil.actuation(u))
    }

    /// The end of the motion from `start` under `u` for `duration` seconds, into `out`; equal
    /// bit for bit to the last sample of [`PlanningModel::propagate_with`].
    #[inline]
    pub fn propagate(&self, start: &[Vec2], u: &Control, duration: f64, out: &mut [Vec2]) {
        match self.pair_edge(start, u) {
            Some(edge) => edge.at(duration, out),
            None => {
                self.solve(
                    start,
                    &self.coil.actuation(u),
                    duration,
                    out,
                    false,
                    &mut |_| true,
                );
            }
        }
    }

    /// The agents' summed path length from `start` under `u` for `duration` (BL): along the
    /// exact curve (Gauss–Legendre quadrature) for an exact motion, along the polyline through
    /// the integration samples otherwise. Planners and `plan_cost` both measure with this.
    pub fn path_length(&self, start: &[Vec2], u: &Control, duration: f64) -> f64 {
        if let Some(edge) = self.pair_edge(start, u) {
            return edge.path_length(duration);
        }
        let n = start.len();
        let mut prev = [Vec2::zeros(); MAX_AGENTS];
        prev[..n].copy_from_slice(start);
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let mut length = 0.0;
        self.propagate_integrated(start, u, duration, &mut out[..n], &mut |s| {
            for (p, q) in prev[..n].iter_mut().zip(s) {
                length += (q - *p).norm();
                *p = *q;
            }
            true
        });
        length
    }

    /// Agent velocities (BL/s) at `p` under `u`.
    pub fn velocities(&self, p: &[Vec2], u: &Control, v: &mut [Vec2]) {
        let act = self.coil.actuation(u);
        self.kinematics.velocities(p, &act, v);
    }

    /// Solves the motion under a constant control, visiting a sample every step `dt` and at
    /// the end; see [`Propagator`]. An exact motion is evaluated at each sample time from the
    /// start (nothing accumulates), an RK4 motion is integrated step by step, an adaptive one
    /// is read from the dense output of the step containing each sample.
    #[inline]
    pub fn propagate_with(
        &self,
        start: &[Vec2],
        u: &Control,
        duration: f64,
        out: &mut [Vec2],
        mut visit: impl FnMut(&[Vec2]) -> bool,
    ) -> bool {
        let Some(edge) = self.pair_edge(start, u) else {
            return self.propagate_integrated(start, u, duration, out, &mut visit);
        };
        let (steps, rest) = step_schedule(duration, self.dt);
        let samples = steps + usize::from(rest > 0.0);
        for k in 1..=samples {
            let t = if k == samples {
                duration
            } else {
                k as f64 * self.dt
            };
            edge.at(t, out);
            if !visit(out) {
                return false;
            }
        }
        if samples == 0 {
            out.copy_from_slice(start);
        }
        true
    }

    /// The integrated motion (RK4 or adaptive, by the flow), visiting each sample.
    fn propagate_integrated(
        &self,
        start: &[Vec2],
        u: &Control,
        duration: f64,
        out: &mut [Vec2],
        visit: &mut dyn FnMut(&[Vec2]) -> bool,
    ) -> bool {
        self.integrate(start, &self.coil.actuation(u), duration, out, visit)
    }

    /// The end of the motion from `start` under the field and pull `act` (what the coil makes
    /// of a command) for `duration` seconds, into `out`: [`PlanningModel::propagate`] for a
    /// caller that already holds the actuation of its command.
    #[inline]
    pub fn propagate_actuated(
        &self,
        start: &[Vec2],
        act: &Actuation,
        duration: f64,
        out: &mut [Vec2],
    ) {
        let edge = (self.flow.pair_exact() && start.len() == 2)
            .then(|| self.kinematics.pair_edge(start, act))
            .flatten();
        match edge {
            Some(edge) => edge.at(duration, out),
            None => {
                self.solve(start, act, duration, out, false, &mut |_| true);
            }
        }
    }

    /// The shared start of many motions from `start`, when the flow uses the pair flow and
    /// `start` is a pair: pass it to [`PlanningModel::propagate_from`].
    #[inline]
    pub fn pair_start(&self, start: &[Vec2]) -> Option<PairStart> {
        (self.flow.pair_exact() && start.len() == 2)
            .then(|| PairStart::new(start))
            .flatten()
    }

    /// [`PlanningModel::propagate_actuated`] from `start`, with `prepared` its
    /// [`PlanningModel::pair_start`]: the same result, less work per command.
    #[inline]
    pub fn propagate_from(
        &self,
        start: &[Vec2],
        prepared: Option<&PairStart>,
        act: &Actuation,
        duration: f64,
        out: &mut [Vec2],
    ) {
        match prepared.and_then(|s| self.kinematics.pair_edge_from(s, act)) {
            Some(edge) => edge.at(duration, out),
            None => self.propagate_actuated(start, act, duration, out),
        }
    }

    /// The motion under `act` solved by the flow's integrator, visiting a sample at every
    /// whole step `dt` and at the end.
    fn integrate(
        &self,
        start: &[Vec2],
        act: &Actuation,
        duration: f64,
        out: &mut [Vec2],
        visit: &mut dyn FnMut(&[Vec2]) -> bool,
    ) -> bool {
        self.solve(start, act, duration, out, true, visit)
    }

    /// [`PlanningModel::integrate`], visiting only when `visits` (the end is the same bits
    /// either way). Its callbacks are trait objects and it is not inlined, so the integrators'
    /// code for every team size is compiled once, in this crate, not again in each crate whose
    /// closures call it (docs/layout.md, "Build time").
    fn solve(
        &self,
        start: &[Vec2],
        act: &Actuation,
        duration: f64,
        out: &mut [Vec2],
        visits: bool,
        visit: &mut dyn FnMut(&[Vec2]) -> bool,
    ) -> bool {
        let n = start.len();
        assert!(n <= MAX_AGENTS && out.len() == n);
        if self.flow.adaptive() {
            let field = TeamField::new(&self.kinematics, act, n);
            let f = |p: &[Vec2], v: &mut [Vec2]| field.velocities(p, v);
            return dp5_solve(&f, start, duration, self.dp5_grid(n), out, visits, visit).0;
        }
        let f = |p: &[Vec2], v: &mut [Vec2]| self.kinematics.velocities(p, act, v);
        out.copy_from_slice(start);
        let (steps, rest) = step_schedule(duration, self.dt);
        for _ in 0..steps {
            rk4_step(&f, out, self.dt);
            if visits && !visit(out) {
                return false;
            }
        }
        if rest > 0.0 {
            rk4_step(&f, out, rest);
            if visits && !visit(out) {
                return false;
            }
        }
        true
    }
}

impl PlanningModel {
    /// Solves `start` under each `(controls[i], durations[i])` into `ends[i]` (first N
    /// entries). Exact motions are evaluated directly, the others by
    /// [`PlanningModel::solve_many`]. Each end equals [`PlanningModel::propagate`]'s bit for
    /// bit.
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
        let mut integrated = Vec::new();
        for i in 0..k {
            match self.pair_edge(start, &controls[i]) {
                Some(edge) => edge.at(durations[i], &mut ends[i][..n]),
                None => integrated.push(i),
            }
        }
        if integrated.is_empty() {
            return;
        }
        self.solve_many(
            start,
            controls,
            durations,
            integrated,
            |_| true,
            |i, end| ends[i][..n].copy_from_slice(end),
        );
    }

    /// Solves `start` under `(controls[i], durations[i])` for each `i` that `order` yields, by
    /// the flow's integrator (never the exact pair flow), and hands each end to `done(i, end)`.
    /// Adaptive motions are solved a few side by side ([`dp5_solve_many`]) in `order`'s order,
    /// `order` pulled as lanes free, and a motion for which `wanted(i)` turns false — asked
    /// before it starts and after each of its steps — is dropped without an end. RK4 motions
    /// are all drawn from `order` first and advance step by step together, so that the CPU
    /// overlaps them (about 3× faster than one at a time for two agents). Each end equals
    /// [`PlanningModel::propagate_actuated`]'s bit for bit.
    #[inline]
    pub fn solve_many(
        &self,
        start: &[Vec2],
        controls: &[Control],
        durations: &[f64],
        order: impl IntoIterator<Item = usize>,
        wanted: impl Fn(usize) -> bool,
        mut done: impl FnMut(usize, &[Vec2]),
    ) {
        let mut order = order.into_iter();
        self.solve_each(start, controls, durations, &mut order, &wanted, &mut done);
    }

    /// [`PlanningModel::solve_many`] with trait-object callbacks, compiled once, in this crate
    /// (as [`PlanningModel::solve`]).
    fn solve_each(
        &self,
        start: &[Vec2],
        controls: &[Control],
        durations: &[f64],
        order: &mut dyn Iterator<Item = usize>,
        wanted: &dyn Fn(usize) -> bool,
        done: &mut dyn FnMut(usize, &[Vec2]),
    ) {
        let n = start.len();
        let k = controls.len();
        assert!(n <= MAX_AGENTS && durations.len() == k);
        let acts: Vec<_> = controls.iter().map(|u| self.coil.actuation(u)).collect();
        if self.flow.adaptive() {
            let fields: Vec<_> = acts
                .iter()
                .map(|act| {
                    let field = TeamField::new(&self.kinematics, act, n);
                    move |p: &[Vec2], v: &mut [Vec2]| field.velocities(p, v)
                })
                .collect();
            dp5_solve_many(
                &fields,
                start,
                durations,
                self.dp5_grid(n),
                order,
                wanted,
                done,
            );
            return;
        }
        let motions: Vec<usize> = order.into_iter().filter(|&i| wanted(i)).collect();
        let schedules: Vec<_> = motions
            .iter()
            .map(|&i| step_schedule(durations[i], self.dt))
            .collect();
        let most = schedules.iter().map(|s| s.0).max().unwrap_or(0);
        let mut ends = vec![[Vec2::zeros(); MAX_AGENTS]; motions.len()];
        for e in &mut ends {
            e[..n].copy_from_slice(start);
        }
        for step in 0..most {
            for (m, &i) in motions.iter().enumerate() {
                if step < schedules[m].0 {
                    let act = &acts[i];
                    let f = |p: &[Vec2], v: &mut [Vec2]| self.kinematics.velocities(p, act, v);
                    rk4_step(&f, &mut ends[m][..n], self.dt);
                }
            }
        }
        for (m, &i) in motions.iter().enumerate() {
            let rest = schedules[m].1;
            if rest > 0.0 {
                let act = &acts[i];
                let f = |p: &[Vec2], v: &mut [Vec2]| self.kinematics.velocities(p, act, v);
                rk4_step(&f, &mut ends[m][..n], rest);
            }
            done(i, &ends[m][..n]);
        }
    }
}

impl Propagator for PlanningModel {
    fn propagate(&self, start: &[Vec2], u: &Control, duration: f64, out: &mut [Vec2]) {
        PlanningModel::propagate(self, start, u, duration, out);
    }

    fn closed_form(&self, start: &[Vec2], u: &Control) -> Option<PairEdge> {
        self.pair_edge(start, u)
    }

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

    /// A pair centred at (10, 8), 2 apart, at angle `phi`.
    fn pair_view(phi: f64) -> LocalView {
        LocalView::new(10.0, 8.0, 2.0, phi)
    }

    #[test]
    fn replay_is_bit_exact() {
        let m = PlanningModel::new(&PhysicalParams::default());
        let start = pair_view(0.3).to_pair();
        let u = Control::planar(1.2, 0.05, -0.02);
        let (mut a, mut b) = ([Vec2::zeros(); 2], [Vec2::zeros(); 2]);
        m.propagate(&start, &u, 0.5, &mut a);
        m.propagate(&start, &u, 0.5, &mut b);
        assert_eq!(a, b);
    }

    #[test]
    fn propagate_many_matches_one_at_a_time_bit_for_bit() {
        let m = PlanningModel::new(&PhysicalParams::default());
        let start = pair_view(0.3).to_pair();
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
        let v = pair_view(0.0);
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

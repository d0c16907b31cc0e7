//! The plant's equations of motion with every term of a preset.
//!
//! State: each agent's position `P_i` (BL) and, with the magnet-lag term, the unit direction
//! `m̂_i` of its moment (otherwise `m̂_i` is the direction of the field it feels). The coil's
//! five outputs follow their command exactly in closed form ([`super::coil_lag`]). Per agent:
//!
//! ```text
//! B_i   = A B_coil + B_ambient + ∇B (P_i − x_c)               (field it feels, T)
//! F_i   = k_pull s_i ∇B m̂_i + Σ_k F_k,i + Σ_j c_F s_i s_j F̂(m̂_j, m̂_i, P_i − P_j) + Σ_j F_cap,ij
//! Ṗ_i   = μ_i F_i + Σ_{j≠i} M_RP(P_i − P_j) F_j + u_flow(P_i, t) + Σ_k u_k,i
//! dm̂_i/dt = (s_i μ_i / (τ₀ B₀)) (B_i − (B_i·m̂_i) m̂_i)
//! ```
//!
//! with forces in velocity units of a nominal agent (BL/s), `s_i`, `μ_i` the agent's moment
//! and mobility factors, `F̂` the general dipole–dipole force ([`crate::physics::dipole`]) in
//! the plane, `M_RP` the Rotne–Prager coupling, `F_k,i` and `u_k,i` the force and velocity
//! of each term `k` that contributes through [`super::Term::draw`], and τ₀ the nominal
//! rotation time. With every
//! term off this is exactly the planning model's kinematics. Integration: classic RK4, in
//! `n` equal sub-steps of each plant step, `n` the smallest with a sub-step under the fastest
//! rotation time at 1.5 B₀ (one sub-step without the magnet-lag term). A sub-step whose
//! stages would carry a pair within contact is halved until the pair touches, where the plant
//! leaves it stuck: the r⁻⁴ force is never evaluated at r ≤ 1.

use std::sync::Arc;

use nalgebra::Matrix3;

use super::DisturbancePreset;
use super::capillary::CapillaryLaw;
use super::coil_lag::AxisResponse;
use super::field::{CoilOutput, FieldModel};
use super::flow::FlowField;
use super::heterogeneity::AgentFactors;
use super::hydrodynamics::rotne_prager;
use super::magnet_lag::rotation_time;
use super::pinning::PinningLaw;
use super::term::Contribution;
use crate::math::{MAX_AGENTS, Vec2, Vec3};
use crate::physics::PhysicalParams;
use crate::physics::dipole::dipole_force;

/// Positions and moment directions of the team.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Positions (BL).
    pub p: [Vec2; MAX_AGENTS],
    /// Unit moment directions (used with the magnet-lag term).
    pub m: [Vec3; MAX_AGENTS],
}

impl State {
    const ZERO: Self = Self {
        p: [Vec2::new(0.0, 0.0); MAX_AGENTS],
        m: [Vec3::new(0.0, 0.0, 0.0); MAX_AGENTS],
    };

    /// `self + k·d` over the first `n` agents.
    fn plus(&self, d: &State, k: f64, n: usize) -> State {
        let mut s = *self;
        for i in 0..n {
            s.p[i] += d.p[i] * k;
            s.m[i] += d.m[i] * k;
        }
        s
    }
}

/// How many times a sub-step is split in halves before a pair is taken to have touched: a
/// plant step of 1/120 s ends in pieces of 1/(120·2¹⁰) s ≈ 8 µs, over which a nominal pair in
/// the bulk with the default physics, approaching at its contact speed 2κ ≈ 48 BL/s
/// ([`crate::physics::PhysicalParams::kappa`]), moves under 0.001 BL.
pub const MAX_HALVINGS: u32 = 10;

/// How an integration step ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Advance {
    /// No pair reached contact.
    Clear,
    /// A pair reached contact (r ≤ 1 BL) during the step.
    Contact,
}

/// What stays fixed over one plant step: its start time, the coil's outputs at its start, the
/// target they follow and the coil's centre.
struct Span<'a> {
    t0: f64,
    c0: &'a CoilOutput,
    u: &'a CoilOutput,
    centre: Vec2,
}

/// True when, moving in a straight line from `a` to `b`, some pair of the first `n` agents
/// comes within contact (centre distance ≤ 1 BL), or `b` is not finite.
fn reaches_contact(a: &State, b: &State, n: usize) -> bool {
    for i in 0..n {
        if !(b.p[i].x.is_finite() && b.p[i].y.is_finite()) {
            return true;
        }
        for j in (i + 1)..n {
            let (d0, d1) = (a.p[j] - a.p[i], b.p[j] - b.p[i]);
            let seg = d1 - d0;
            let len2 = seg.norm_squared();
            let t = if len2 > 0.0 {
                (-d0.dot(&seg) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            if (d0 + seg * t).norm_squared() <= 1.0 {
                return true;
            }
        }
    }
    false
}

/// The drawn equations of motion of one run.
#[derive(Debug, Clone)]
pub struct Dynamics {
    n: usize,
    force_coeff: f64,
    pull_coeff: f64,
    /// The drawn per-agent factors.
    pub factors: AgentFactors,
    /// The drawn field model.
    pub field: FieldModel,
    axes: [AxisResponse; 5],
    /// Rotation rate per tesla of each agent, s_i μ_i/(τ₀ B₀) (1/(T·s)); `None` without the
    /// magnet-lag term.
    rotation: Option<[f64; MAX_AGENTS]>,
    hydrodynamics: bool,
    capillary: Option<CapillaryLaw>,
    /// How far each moment tilts out of the plane at a pinning interface.
    pinning: Option<PinningLaw>,
    /// The drawn background flow.
    pub flow: FlowField,
    /// The contributions of the terms drawn through [`super::Term::draw`].
    contributions: Vec<Arc<dyn Contribution>>,
}

impl Dynamics {
    /// Draws the dynamics of `n` agents for the run seeded with `seed`.
    pub fn draw(preset: &DisturbancePreset, p: &PhysicalParams, n: usize, seed: u64) -> Self {
        let mut factors = preset.heterogeneity.draw(&preset.medium, n, seed);
        for i in 0..n {
            if let Some(m) = preset.fitted.moment_of(i) {
                factors.moment[i] = m;
            }
            if let Some(m) = preset.fitted.mobility_of(i) {
                factors.mobility[i] = m;
            }
        }
        let field = FieldModel::draw(preset, p, seed);
        let (fa, ga) = (
            preset.coil_lag.field_axis(),
            preset.coil_lag.gradient_axis(),
        );
        let drag = preset.medium.drag();
        let rotation = preset.magnet_lag.enabled.then(|| {
            let tau0 = rotation_time(p, drag.rotation);
            let mut r = [0.0; MAX_AGENTS];
            for (i, ri) in r.iter_mut().enumerate().take(n) {
                *ri = factors.moment[i] * factors.mobility[i] / (tau0 * field.b0);
            }
            r
        });
        let capillary = match (preset.capillary.enabled, preset.medium.interface()) {
            (true, Some(iface)) => Some(CapillaryLaw::new(iface, p, drag, &factors, n)),
            _ => None,
        };
        let pinning = PinningLaw::new(&preset.medium, p, &factors, n);
        let contributions = preset.contributions(p, &factors, n, seed);
        Self {
            n,
            force_coeff: p.force_coeff_in(drag),
            pull_coeff: p.pull_coeff_in(drag),
            factors,
            field,
            axes: [fa, fa, fa, ga, ga],
            rotation,
            hydrodynamics: preset.hydrodynamics.enabled,
            capillary,
            pinning,
            flow: FlowField::draw(&preset.drift, &preset.flow, seed)
                .with_drift(preset.fitted.drift()),
            contributions,
        }
    }

    /// True when the motion is the planning model's up to a field bias and a uniform drift:
    /// no jitter, an exact and instant coil, aligned moments, no pair term beyond the dipole
    /// force, a uniform steady flow.
    pub fn is_exact_pair(&self) -> bool {
        self.field.jitter == 0.0
            && self.field.is_exact()
            && self.axes.iter().all(AxisResponse::is_instant)
            && self.rotation.is_none()
            && !self.hydrodynamics
            && self.capillary.is_none()
            && self.flow.is_uniform()
            && self.contributions.is_empty()
    }

    /// True with the magnet-lag term: the state's moment directions are integrated.
    pub fn tracks_moments(&self) -> bool {
        self.rotation.is_some()
    }

    /// The coil outputs `t` seconds after they were `c0`, under the constant target `u`.
    pub fn coil_at(&self, c0: &CoilOutput, u: &CoilOutput, t: f64) -> CoilOutput {
        std::array::from_fn(|k| self.axes[k].at(c0[k], u[k], t))
    }

    /// The field (T) each agent of `s` feels under coil outputs `c`, and the gradient tensor.
    pub fn fields(
        &self,
        c: &CoilOutput,
        centre: Vec2,
        s: &State,
    ) -> ([Vec3; MAX_AGENTS], Matrix3<f64>) {
        let (b, g) = self.field.realise(c);
        let mut out = [Vec3::zeros(); MAX_AGENTS];
        for (o, p) in out.iter_mut().zip(&s.p[..self.n]) {
            *o = self.field.at(&b, &g, centre, *p);
        }
        (out, g)
    }

    /// The field (T) each agent's moment turns toward: the field it feels, with its elevation
    /// limited by the contact line's pinning at an interface ([`super::pinning`]); and the
    /// gradient tensor.
    pub fn moment_fields(
        &self,
        c: &CoilOutput,
        centre: Vec2,
        s: &State,
    ) -> ([Vec3; MAX_AGENTS], Matrix3<f64>) {
        let (mut b, g) = self.fields(c, centre, s);
        if let Some(pin) = &self.pinning {
            for (i, bi) in b[..self.n].iter_mut().enumerate() {
                *bi = pin.limit(i, *bi, s.m[i]);
            }
        }
        (b, g)
    }

    /// The rates of state `s` at time `t` under coil outputs `c`, coil centred on `centre`.
    pub fn rates(&self, t: f64, c: &CoilOutput, centre: Vec2, s: &State) -> State {
        let n = self.n;
        let (b, g) = self.moment_fields(c, centre, s);
        let f = &self.factors;
        let mut d = State::ZERO;
        let mut m = [Vec3::zeros(); MAX_AGENTS];
        for i in 0..n {
            match &self.rotation {
                Some(rate) => {
                    m[i] = s.m[i];
                    d.m[i] = (b[i] - m[i] * b[i].dot(&m[i])) * rate[i];
                }
                None => m[i] = b[i].try_normalize(0.0).unwrap_or(s.m[i]),
            }
        }
        // forces, in velocity units of a nominal agent
        let mut force = [Vec2::zeros(); MAX_AGENTS];
        for i in 0..n {
            let pull = g * m[i] * (self.pull_coeff * f.moment[i]);
            force[i] = Vec2::new(pull.x, pull.y);
        }
        for c in &self.contributions {
            for (i, fi) in force[..n].iter_mut().enumerate() {
                *fi += c.force(i, s.p[i], t);
            }
        }
        for i in 0..n {
            for j in (i + 1)..n {
                let r = s.p[j] - s.p[i];
                let fd = dipole_force(m[i], m[j], Vec3::new(r.x, r.y, 0.0))
                    * (self.force_coeff * f.moment[i] * f.moment[j]);
                let mut fj = Vec2::new(fd.x, fd.y);
                if let Some(cap) = &self.capillary {
                    fj += cap.pair(i, j, r);
                }
                force[j] += fj;
                force[i] -= fj;
            }
        }
        for i in 0..n {
            let mut v = force[i] * f.mobility[i] + self.flow.at(s.p[i], t);
            for c in &self.contributions {
                v += c.velocity(i, s.p[i], t);
            }
            if self.hydrodynamics {
                for (j, (pj, fj)) in s.p[..n].iter().zip(&force[..n]).enumerate() {
                    if j != i {
                        v += rotne_prager(s.p[i] - pj, *fj);
                    }
                }
            }
            d.p[i] = v;
        }
        d
    }

    /// Number of RK4 sub-steps for a plant step of `h` seconds.
    pub fn substeps(&self, h: f64) -> usize {
        match &self.rotation {
            Some(rate) => {
                let fastest = rate[..self.n].iter().fold(0.0f64, |a, r| a.max(*r));
                ((h * fastest * 1.5 * self.field.b0).ceil() as usize).max(1)
            }
            None => 1,
        }
    }

    /// Advances `s` by `h` seconds from time `t0` with the coil starting at `c0` under the
    /// target `u`, in RK4 sub-steps. A sub-step whose stages would carry a pair within contact
    /// (r ≤ 1 BL, where the r⁻⁴ force has no meaning) is split in halves, down to
    /// [`MAX_HALVINGS`] times; [`Advance::Contact`] when the pair still reaches contact, with `s`
    /// at the last state before it.
    pub fn advance(
        &self,
        s: &mut State,
        t0: f64,
        c0: &CoilOutput,
        u: &CoilOutput,
        centre: Vec2,
        h: f64,
    ) -> Advance {
        let k = self.substeps(h);
        let dh = h / k as f64;
        let span = Span { t0, c0, u, centre };
        for q in 0..k {
            if self.advance_span(s, &span, q as f64 * dh, dh, 0) == Advance::Contact {
                return Advance::Contact;
            }
        }
        Advance::Clear
    }

    /// Advances `s` from `a` to `a + dh` seconds into the step: one RK4 sub-step, or two halves
    /// when its stages reach contact.
    fn advance_span(&self, s: &mut State, span: &Span, a: f64, dh: f64, depth: u32) -> Advance {
        if let Some(next) = self.rk4(s, span, a, dh) {
            *s = next;
            return Advance::Clear;
        }
        if depth == MAX_HALVINGS {
            return Advance::Contact;
        }
        let half = 0.5 * dh;
        match self.advance_span(s, span, a, half, depth + 1) {
            Advance::Clear => self.advance_span(s, span, a + half, half, depth + 1),
            contact => contact,
        }
    }

    /// One classic RK4 sub-step from `a` to `a + dh` seconds into the step; `None` when a
    /// stage or the result reaches contact (or is not finite), before the rates are evaluated
    /// there.
    fn rk4(&self, s: &State, span: &Span, a: f64, dh: f64) -> Option<State> {
        let n = self.n;
        let at = |x: f64| self.coil_at(span.c0, span.u, x);
        let (c_a, c_m, c_b) = (at(a), at(a + 0.5 * dh), at(a + dh));
        let (t, centre) = (span.t0 + a, span.centre);
        let clear = |x: State| (!reaches_contact(s, &x, n)).then_some(x);
        let k1 = self.rates(t, &c_a, centre, s);
        let k2 = self.rates(
            t + 0.5 * dh,
            &c_m,
            centre,
            &clear(s.plus(&k1, 0.5 * dh, n))?,
        );
        let k3 = self.rates(
            t + 0.5 * dh,
            &c_m,
            centre,
            &clear(s.plus(&k2, 0.5 * dh, n))?,
        );
        let k4 = self.rates(t + dh, &c_b, centre, &clear(s.plus(&k3, dh, n))?);
        let h6 = dh / 6.0;
        let mut next = *s;
        for i in 0..n {
            next.p[i] += (k1.p[i] + (k2.p[i] + k3.p[i]) * 2.0 + k4.p[i]) * h6;
            next.m[i] += (k1.m[i] + (k2.m[i] + k3.m[i]) * 2.0 + k4.m[i]) * h6;
        }
        let mut next = clear(next)?;
        if self.tracks_moments() {
            self.renormalise(&mut next, &c_b, centre);
        }
        Some(next)
    }

    /// Sets every moment along the field its agent feels (a settled start).
    pub fn align_moments(&self, s: &mut State, c: &CoilOutput, centre: Vec2) {
        let (b, _) = self.moment_fields(c, centre, s);
        for (m, bi) in s.m[..self.n].iter_mut().zip(&b) {
            if let Some(u) = bi.try_normalize(0.0) {
                *m = u;
            }
        }
    }

    /// Keeps each moment a unit vector. A moment exactly antiparallel to its field is an
    /// unstable equilibrium that any perturbation leaves; it is turned by 1 µrad about z.
    fn renormalise(&self, s: &mut State, c: &CoilOutput, centre: Vec2) {
        let (b, _) = self.moment_fields(c, centre, s);
        for (mi, bi) in s.m[..self.n].iter_mut().zip(&b) {
            let mut m = mi.try_normalize(0.0).unwrap_or(Vec3::x());
            if let Some(bh) = bi.try_normalize(0.0)
                && m.dot(&bh) < -1.0 + 1e-12
            {
                let (sn, cs) = 1e-6f64.sin_cos();
                m = Vec3::new(cs * m.x - sn * m.y, sn * m.x + cs * m.y, m.z);
            }
            *mi = m;
        }
    }
}

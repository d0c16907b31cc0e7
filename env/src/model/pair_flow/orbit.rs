//! The relative motion of a nominal pair under a constant planar field, in closed form.
//!
//! With `ψ = θ_B − φ` the field angle from the separation, `ṙ = κ(1 − 3cos²ψ)/r⁴` and
//! `ψ̇ = −κ sin 2ψ/r⁵`. Both are unchanged by `ψ → −ψ` and `ψ → π − ψ`, and `ψ̇ = 0` on
//! `ψ ∈ {0, π/2} mod π`, so `ψ` never leaves its quadrant: the motion is that of the folded angle
//! `ψ̂ = |ψ mod π| ∈ [0, π/2]`, which only decreases, with the pair turning by
//! `Δφ = σ (ψ̂₀ − ψ̂)` (`σ` the sign of `sin ψ cos ψ`). Along an orbit `r / (sin ψ̂ √cos ψ̂) = C`
//! and `2κ t / C⁵ = G(ψ̂₀) − G(ψ̂)` ([`super::special`]). Both are solved in ratios to the start,
//! so no `C⁵` is ever formed and orbits next to `ψ̂ = 0` (collapse: `r⁵ = r₀⁵ − 10κt`) and
//! `ψ̂ = π/2` (repulsion: `r⁵ = r₀⁵ + 5κt`) keep full accuracy; those two are the limits of the
//! general formulas, not special cases.

use super::quadrature::simpson;
use super::special::{
    G_TOTAL, g_mid, h, l, lower_guess, lower_inverse, upper_guess, upper_inverse,
};

/// An orbit of `(r, ψ̂)` from its start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// Relative-motion constant κ (BL⁵/s).
    kappa: f64,
    /// Starting separation (BL).
    r0: f64,
    /// `sin ψ̂₀`, `cos ψ̂₀`.
    s0: f64,
    c0: f64,
    /// Direction of turning: `φ` changes by `σ (ψ̂₀ − ψ̂)`.
    sign: f64,
    half: Half,
}

/// Which factored form the orbit starts in.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Half {
    /// `ψ̂₀ ≤ π/4`: `ρ⁵ H(ρ² x₀) = h₀ − rate·t`, with `sin ψ̂ = ρ sin ψ̂₀`.
    Lower { x0: f64, y0: f64, h0: f64, rate: f64 },
    /// `ψ̂₀ > π/4`: `μ^{5/2} L(μ² y₀) = l₀ + rate·t`, with `cos ψ̂ = μ cos ψ̂₀`, while
    /// `G(π/2) − G = y₀^{5/4}(l₀ + rate·t)` stays below `G(π/2) − G(π/4)`; then the lower form.
    Upper {
        x0: f64,
        y0: f64,
        l0: f64,
        rate: f64,
        scale: f64,
    },
}

/// Where an orbit is, in the variable of its time equation.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Place {
    /// `ρ = sin ψ̂ / sin ψ̂₀` on a lower orbit.
    Lower(f64),
    /// `μ = cos ψ̂ / cos ψ̂₀` on an upper orbit before `ψ̂ = π/4`.
    Upper(f64),
    /// `sin ψ̂` on an upper orbit past `ψ̂ = π/4`.
    Crossed(f64),
    /// The pair has collapsed (`r = 0` along `ψ̂ = 0`).
    Collapsed,
}

/// Where an orbit is at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitPoint {
    /// `r(t)/r₀`; 0 once the pair has collapsed (`r` reached 0 along `ψ̂ = 0`).
    pub ratio: f64,
    /// `sin ψ̂(t)`.
    pub sin: f64,
    /// `cos ψ̂(t)`.
    pub cos: f64,
}

impl Orbit {
    /// The orbit from separation `r0 > 0` at field angle `ψ₀`, given as `sin ψ₀` and `cos ψ₀`
    /// (any quadrant), under relative-motion constant `kappa > 0`.
    pub fn new(kappa: f64, r0: f64, sin_psi: f64, cos_psi: f64) -> Self {
        let sign = if sin_psi * cos_psi < 0.0 { -1.0 } else { 1.0 };
        let r5 = r0 * r0 * r0 * r0 * r0;
        let (s, c) = (sin_psi.abs(), cos_psi.abs());
        if s <= c {
            let x0 = s * s;
            let y0 = 1.0 - x0;
            let c0 = y0.sqrt();
            Orbit {
                kappa,
                r0,
                s0: s,
                c0,
                sign,
                half: Half::Lower {
                    x0,
                    y0,
                    h0: h(x0),
                    rate: 2.0 * kappa * y0 * c0.sqrt() / r5,
                },
            }
        } else {
            let y0 = c * c;
            let x0 = 1.0 - y0;
            let s0 = x0.sqrt();
            Orbit {
                kappa,
                r0,
                s0,
                c0: c,
                sign,
                half: Half::Upper {
                    x0,
                    y0,
                    l0: l(y0),
                    rate: 2.0 * kappa * x0 * x0 * s0 / r5,
                    scale: y0 * c.sqrt(),
                },
            }
        }
    }

    /// The starting separation (BL).
    pub fn r0(&self) -> f64 {
        self.r0
    }

    /// The orbit at time `t ≥ 0` (s). Depends on `t` and the start only, never on earlier calls.
    #[inline]
    pub fn at(&self, t: f64) -> OrbitPoint {
        self.point(self.solve(t))
    }

    /// Where the orbit is at time `t`, in its own variable: the time equation solved.
    #[inline]
    fn solve(&self, t: f64) -> Place {
        match self.half {
            Half::Lower { x0, h0, rate, .. } => {
                let target = h0 - rate * t;
                if target <= 0.0 {
                    return Place::Collapsed;
                }
                Place::Lower(lower_inverse(x0, target, lower_guess(x0, target)))
            }
            Half::Upper {
                y0,
                l0,
                rate,
                scale,
                ..
            } => {
                let target = l0 + rate * t;
                if scale * target <= G_TOTAL - g_mid() {
                    if y0 == 0.0 {
                        // on ψ̂ = π/2: μ^{5/2} L(0) = target, r⁵ = r₀⁵ + 5κt
                        return Place::Upper((target / l0).powf(0.4));
                    }
                    return Place::Upper(upper_inverse(y0, target, upper_guess(y0, target)));
                }
                // past ψ̂ = π/4: G = G(π/2) − k in the lower form, sin ψ̂ = s
                let g = G_TOTAL - scale * target;
                if g <= 0.0 {
                    return Place::Collapsed;
                }
                Place::Crossed(lower_inverse(1.0, g, lower_guess(1.0, g)))
            }
        }
    }

    /// The orbit point at a place.
    #[inline]
    fn point(&self, place: Place) -> OrbitPoint {
        match (place, self.half) {
            (Place::Lower(rho), Half::Lower { x0, y0, .. }) => {
                let y = 1.0 - rho * rho * x0;
                OrbitPoint {
                    ratio: rho * (y / y0).sqrt().sqrt(),
                    sin: rho * self.s0,
                    cos: y.sqrt(),
                }
            }
            (Place::Upper(mu), Half::Upper { x0, y0, .. }) => {
                let x = 1.0 - mu * mu * y0;
                OrbitPoint {
                    ratio: (mu * x / x0).sqrt(),
                    sin: x.sqrt(),
                    cos: mu * self.c0,
                }
            }
            (Place::Crossed(s), Half::Upper { x0, y0, .. }) => {
                let y = 1.0 - s * s;
                OrbitPoint {
                    ratio: (s * s / x0).sqrt() * (y / y0).sqrt().sqrt(),
                    sin: s,
                    cos: y.sqrt(),
                }
            }
            _ => OrbitPoint {
                ratio: 0.0,
                sin: 0.0,
                cos: 1.0,
            },
        }
    }

    /// `|dt/dv|` at a place, `v` its variable: from the time equation's closed-form derivative.
    #[inline]
    fn time_per_step(&self, place: Place) -> f64 {
        match (place, self.half) {
            (Place::Lower(rho), Half::Lower { x0, rate, .. }) => {
                let r2 = rho * rho;
                r2 * r2 * (1.0 - r2 * x0).sqrt().sqrt() / rate
            }
            (Place::Upper(mu), Half::Upper { y0, rate, .. }) => {
                let x = 1.0 - mu * mu * y0;
                mu * mu.sqrt() * x * x.sqrt() / rate
            }
            (Place::Crossed(s), Half::Upper { rate, scale, .. }) => {
                let s2 = s * s;
                s2 * s2 * (1.0 - s2).sqrt().sqrt() / (scale * rate)
            }
            _ => 0.0,
        }
    }

    /// `∫ f(p) dt` along the orbit from its start to time `t`: the same integral over the orbit's
    /// own variable (`ρ`, then or else `μ` and `sin ψ̂`), where every point is in closed form, by
    /// adaptive Simpson to a relative tolerance `tol`. Infinite if the pair collapses by `t`.
    pub fn integrate(&self, t: f64, tol: f64, f: impl Fn(&OrbitPoint) -> f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let g = |place: Place| f(&self.point(place)) * self.time_per_step(place);
        match (self.solve(t), self.half) {
            (Place::Collapsed, _) => f64::INFINITY,
            (Place::Lower(rho), _) => simpson(|v| g(Place::Lower(v)), rho, 1.0, tol),
            (Place::Upper(mu), _) => simpson(|v| g(Place::Upper(v)), 1.0, mu, tol),
            (Place::Crossed(s), Half::Upper { y0, .. }) => {
                let mid = (0.5 / y0).sqrt();
                simpson(|v| g(Place::Upper(v)), 1.0, mid, tol)
                    + simpson(
                        |v| g(Place::Crossed(v)),
                        s,
                        std::f64::consts::FRAC_1_SQRT_2,
                        tol,
                    )
            }
            (Place::Crossed(_), Half::Lower { .. }) => unreachable!("a lower orbit never crosses"),
        }
    }

    /// The separation at `p` (BL).
    pub fn separation(&self, p: &OrbitPoint) -> f64 {
        self.r0 * p.ratio
    }

    /// `(cos Δφ, sin Δφ)`: how far the separation has turned at `p`.
    pub fn turn(&self, p: &OrbitPoint) -> (f64, f64) {
        (
            self.c0 * p.cos + self.s0 * p.sin,
            self.sign * (self.s0 * p.cos - self.c0 * p.sin),
        )
    }

    /// The relative velocity at `p` along `r̂` and `ê_φ` (BL/s): `κ(1 − 3cos²ψ)/r⁴` and
    /// `κ sin 2ψ / r⁴`. Infinite once collapsed.
    pub fn rates(&self, p: &OrbitPoint) -> (f64, f64) {
        let r = self.separation(p);
        let k = self.kappa / (r * r * r * r);
        (
            k * (1.0 - 3.0 * p.cos * p.cos),
            k * 2.0 * self.sign * p.sin * p.cos,
        )
    }

    /// `cos²ψ̂` at the start.
    pub fn cos2_start(&self) -> f64 {
        self.c0 * self.c0
    }

    /// The largest separation of the whole orbit (at `cos²ψ̂ = ⅓`) if the orbit has not yet
    /// passed it, with the `cos²ψ̂` there; `None` when the separation only decreases from here.
    pub fn peak(&self) -> Option<f64> {
        match self.half {
            Half::Upper { x0, y0, .. } if 3.0 * y0 < 1.0 => {
                if y0 == 0.0 {
                    return Some(f64::INFINITY);
                }
                Some(self.r0 * (2.0 / (3.0 * x0)).sqrt() * (1.0 / (3.0 * y0)).sqrt().sqrt())
            }
            _ => None,
        }
    }

    /// The time (s) at which the orbit reaches its peak separation (`cos²ψ̂ = ⅓`), if it lies
    /// ahead: `μ = (3y₀)^{−1/2}` in the upper form.
    pub fn peak_time(&self) -> Option<f64> {
        match self.half {
            Half::Upper { y0, .. } if y0 == 0.0 => Some(f64::INFINITY),
            Half::Upper { y0, l0, rate, .. } if 3.0 * y0 < 1.0 => {
                let mu = (1.0 / (3.0 * y0)).sqrt();
                Some((mu * mu * mu.sqrt() * l(1.0 / 3.0) - l0) / rate)
            }
            _ => None,
        }
    }

    /// `κ`, the relative-motion constant (BL⁵/s).
    pub fn kappa(&self) -> f64 {
        self.kappa
    }
}

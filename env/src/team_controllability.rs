//! Controllability of a team of N identical agents under one field: the basis fields of the
//! shape motion, their Lie-bracket rank and whether the drift can be cancelled.
//!
//! The shape of a team is `s = (P_i − P_0)_{i ≥ 1}` (2(N−1) numbers); the pull moves every agent
//! alike, so only the field direction moves the shape. The in-plane pair force of aligned moments
//! depends on the field only through its in-plane components `b = (cos α cos θ, cos α sin θ)`,
//! and quadratically (docs/physics.md, "Teams of three and more"):
//!
//! ```text
//! ṡ = f(s; b) = F₀(s) + b₁² F₁₁(s) + b₁b₂ F₁₂(s) + b₂² F₂₂(s)
//! ```
//!
//! [`BasisFields::at`] gets the four fields exactly from the physics ([`Kinematics`]) by
//! evaluating `f` at `b ∈ {(0,0), (1,0), (0,1), (1/√2,1/√2)}`. In the plane (`|b| = 1`) the
//! velocity set is the ellipse `M + cos2θ A + sin2θ B` with `M = F₀ + (F₁₁+F₂₂)/2`,
//! `A = (F₁₁−F₂₂)/2`, `B = F₁₂/2`; with the elevation free `cos²α` scales the b-part:
//! `F₀ + cos²α (M' + cos2θ A + sin2θ B)`, `M' = (F₁₁+F₂₂)/2`. Per pair `M' = −(3/2) F₀` exactly
//! (the isotropic average of the dipole interaction), so the elevation adds no new direction;
//! it moves the radial part `(1 − (3/2)cos²α) F₀` through zero at cos²α = 2/3, the cone on which
//! a field sweeping θ cancels every pair force on average. [`team_report`] computes
//! the accessibility rank from these fields, their brackets and brackets of brackets (Jacobians
//! by central differences of the physics), the first-order span, and whether the origin lies in
//! the relative interior of the convex hull of the velocity set — whether some mix of fields
//! holds the formation (in full, or up to a rotation of the whole team).

use nalgebra::{DMatrix, DVector};

use crate::coil::Actuation;
use crate::math::{MAX_AGENTS, Vec2, Vec3};
use crate::model::Kinematics;

/// A point of shape space: `(P_i − P_0)_{i ≥ 1}`, x then y of each.
pub type Shape = DVector<f64>;

/// The shape of `positions` (agent 0 is the origin of the others).
pub fn shape_of(positions: &[Vec2]) -> Shape {
    let p0 = positions[0];
    DVector::from_iterator(
        2 * (positions.len() - 1),
        positions[1..].iter().flat_map(|p| [p.x - p0.x, p.y - p0.y]),
    )
}

/// The positions of shape `s` with agent 0 at the origin.
pub fn positions_of(s: &Shape) -> Vec<Vec2> {
    let mut p = vec![Vec2::zeros()];
    p.extend((0..s.len() / 2).map(|i| Vec2::new(s[2 * i], s[2 * i + 1])));
    p
}

/// The shape velocity `f(s; b)` under in-plane field components `b` (|b| ≤ 1; the field's
/// out-of-plane component makes it a unit vector), no pull.
pub fn shape_velocity(kin: &Kinematics, s: &Shape, b: [f64; 2]) -> Shape {
    let p = positions_of(s);
    let bz = (1.0 - b[0] * b[0] - b[1] * b[1]).max(0.0).sqrt();
    let act = Actuation {
        b_hat: Vec3::new(b[0], b[1], bz),
        pull: Vec3::zeros(),
    };
    let mut v = [Vec2::zeros(); MAX_AGENTS];
    kin.velocities(&p, &act, &mut v[..p.len()]);
    let v0 = v[0];
    DVector::from_iterator(
        s.len(),
        v[1..p.len()].iter().flat_map(|q| [q.x - v0.x, q.y - v0.y]),
    )
}

/// The four basis fields of the shape motion at one shape.
#[derive(Debug, Clone)]
pub struct BasisFields {
    /// The field straight up (α = 90°): every pair repels.
    pub f0: Shape,
    /// The b₁² part.
    pub f11: Shape,
    /// The b₁b₂ part.
    pub f12: Shape,
    /// The b₂² part.
    pub f22: Shape,
}

impl BasisFields {
    /// The basis fields at `s`, from four evaluations of the physics.
    pub fn at(kin: &Kinematics, s: &Shape) -> Self {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let f0 = shape_velocity(kin, s, [0.0, 0.0]);
        let f11 = shape_velocity(kin, s, [1.0, 0.0]) - &f0;
        let f22 = shape_velocity(kin, s, [0.0, 1.0]) - &f0;
        let f12 = (shape_velocity(kin, s, [h, h]) - &f0) * 2.0 - &f11 - &f22;
        BasisFields { f0, f11, f12, f22 }
    }

    /// `f(s; b)` from the basis.
    pub fn velocity(&self, b: [f64; 2]) -> Shape {
        &self.f0 + &self.f11 * (b[0] * b[0]) + &self.f12 * (b[0] * b[1]) + &self.f22 * (b[1] * b[1])
    }

    /// The fields a control set spans at first order: `{M, A, B}` in the plane, `{F₀, M', A, B}`
    /// with the elevation free.
    pub fn control_fields(&self, elevated: bool) -> Vec<Shape> {
        let m_prime = (&self.f11 + &self.f22) * 0.5;
        let a = (&self.f11 - &self.f22) * 0.5;
        let b = &self.f12 * 0.5;
        if elevated {
            vec![self.f0.clone(), m_prime, a, b]
        } else {
            vec![&self.f0 + m_prime, a, b]
        }
    }
}

/// Which field directions a plan may use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldSet {
    /// In the plane (α = 0).
    Planar,
    /// Elevated up to `alpha_max` (rad).
    Elevated {
        /// The largest elevation (rad).
        alpha_max: f64,
    },
}

/// The controllability report of one formation under one field set.
#[derive(Debug, Clone)]
pub struct TeamReport {
    /// Dimension of shape space, 2(N−1).
    pub dim: usize,
    /// Rank of the control fields alone (the first-order velocity span).
    pub first_order: usize,
    /// Rank with their brackets.
    pub depth1: usize,
    /// Rank with brackets of brackets too: the accessibility rank.
    pub depth2: usize,
    /// The origin lies in the relative interior of the velocity set's convex hull: some mix of
    /// field directions holds every relative position.
    pub holds: bool,
    /// The same up to a rotation of the whole team (the side lengths held).
    pub holds_shape: bool,
    /// Distance (shape velocity units) from the origin to the affine hull of the velocity set.
    pub offset: f64,
}

/// Numerical rank of the columns `v` (scaled to unit length; columns much shorter than the
/// longest are dropped as zero), with singular values relative to the largest above `tol`.
pub fn rank(v: &[Shape], tol: f64) -> usize {
    let longest = v.iter().map(|c| c.norm()).fold(0.0, f64::max);
    let cols: Vec<Shape> = v
        .iter()
        .filter(|c| c.norm() > 1e-7 * longest)
        .map(|c| c / c.norm())
        .collect();
    if cols.is_empty() {
        return 0;
    }
    let m = DMatrix::from_columns(&cols);
    let sv = m.singular_values();
    let max = sv.max();
    sv.iter().filter(|x| **x > tol * max).count()
}

/// Lie bracket `[X, Y](s) = DY·X − DX·Y` with Jacobians by central differences of step `h`.
fn bracket(x: &dyn Fn(&Shape) -> Shape, y: &dyn Fn(&Shape) -> Shape, s: &Shape, h: f64) -> Shape {
    jacobian(y, s, h) * x(s) - jacobian(x, s, h) * y(s)
}

fn jacobian(f: &dyn Fn(&Shape) -> Shape, s: &Shape, h: f64) -> DMatrix<f64> {
    let n = s.len();
    let mut j = DMatrix::zeros(n, n);
    for k in 0..n {
        let mut e = DVector::zeros(n);
        e[k] = h;
        j.set_column(k, &((f(&(s + &e)) - f(&(s - &e))) / (2.0 * h)));
    }
    j
}

/// Relative singular-value threshold of the rank tests (the brackets of brackets come from
/// nested central differences, good to about 1e-7).
pub const RANK_TOL: f64 = 1e-5;

/// The accessibility ranks of a team at one formation under one field set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ranks {
    /// Dimension of shape space, 2(N−1).
    pub dim: usize,
    /// Rank of the control fields alone (the first-order velocity span).
    pub first_order: usize,
    /// Rank with their brackets.
    pub depth1: usize,
    /// Rank with brackets of brackets too: the accessibility rank.
    pub depth2: usize,
}

/// The rank of the control fields at `positions` (BL) under `fields`, with their brackets and
/// brackets of brackets (Jacobians by central differences of the physics); brackets of
/// brackets are computed only when the brackets leave the rank short of `dim`.
pub fn accessibility(kin: &Kinematics, positions: &[Vec2], fields: FieldSet) -> Ranks {
    let s = shape_of(positions);
    let dim = s.len();
    let elevated = matches!(fields, FieldSet::Elevated { .. });
    let basis =
        |k: usize| move |x: &Shape| BasisFields::at(kin, x).control_fields(elevated)[k].clone();
    let count = BasisFields::at(kin, &s).control_fields(elevated).len();
    let scale = positions_scale(positions);
    let (h1, h2) = (1e-5 * scale, 1e-4 * scale);
    let mut cols: Vec<Shape> = (0..count).map(|k| basis(k)(&s)).collect();
    let first_order = rank(&cols, RANK_TOL);
    let mut firsts: Vec<(usize, usize)> = vec![];
    for i in 0..count {
        for j in (i + 1)..count {
            cols.push(bracket(&basis(i), &basis(j), &s, h1));
            firsts.push((i, j));
        }
    }
    let depth1 = rank(&cols, RANK_TOL);
    let mut depth2 = depth1;
    if depth1 < dim {
        for k in 0..count {
            for &(i, j) in &firsts {
                let inner = move |x: &Shape| bracket(&basis(i), &basis(j), x, h1);
                cols.push(bracket(&basis(k), &inner, &s, h2));
            }
        }
        depth2 = rank(&cols, RANK_TOL);
    }
    Ranks {
        dim,
        first_order,
        depth1,
        depth2,
    }
}

/// Controllability of the team at `positions` (BL) under `fields`.
pub fn team_report(kin: &Kinematics, positions: &[Vec2], fields: FieldSet) -> TeamReport {
    let Ranks {
        dim,
        first_order,
        depth1,
        depth2,
    } = accessibility(kin, positions, fields);
    let s = shape_of(positions);
    let set = velocity_set(kin, &s, fields);
    let (holds, offset) = origin_inside(&set, None);
    let rotation = rotation_direction(&s);
    let (holds_shape, _) = origin_inside(&set, Some(&rotation));
    TeamReport {
        dim,
        first_order,
        depth1,
        depth2,
        holds,
        holds_shape,
        offset,
    }
}

/// The largest distance of an agent from agent 0 (BL): the scale of finite-difference steps.
fn positions_scale(p: &[Vec2]) -> f64 {
    p.iter().map(|q| (q - p[0]).norm()).fold(1.0, f64::max)
}

/// The shape velocity of a rotation of the whole team about agent 0: `J s`.
fn rotation_direction(s: &Shape) -> Shape {
    DVector::from_iterator(
        s.len(),
        (0..s.len() / 2).flat_map(|i| [-s[2 * i + 1], s[2 * i]]),
    )
}

/// Field angles (over [0, π)) and elevation levels sampled for the velocity set.
const SET_ANGLES: usize = 180;
const SET_LEVELS: usize = 24;

/// Samples of the achievable shape velocities at `s`: every field angle, and with the elevation
/// free, elevations from 0 to `alpha_max`.
pub fn velocity_set(kin: &Kinematics, s: &Shape, fields: FieldSet) -> Vec<Shape> {
    let basis = BasisFields::at(kin, s);
    let alphas: Vec<f64> = match fields {
        FieldSet::Planar => vec![0.0],
        FieldSet::Elevated { alpha_max } => (0..=SET_LEVELS)
            .map(|l| alpha_max * l as f64 / SET_LEVELS as f64)
            .collect(),
    };
    let mut set = vec![];
    for a in alphas {
        let levels = if a >= std::f64::consts::FRAC_PI_2 - 1e-12 {
            1
        } else {
            SET_ANGLES
        };
        for k in 0..levels {
            let t = std::f64::consts::PI * k as f64 / SET_ANGLES as f64;
            set.push(basis.velocity([a.cos() * t.cos(), a.cos() * t.sin()]));
        }
    }
    set
}

/// Whether the origin lies in the relative interior of the convex hull of `set` (after removing
/// the component along `quotient`, if given), and the distance from the origin to the set's
/// affine hull. The affine hull is found by an SVD of the centred points; within it the origin
/// is tested by Gilbert's minimum-norm-point algorithm, together with small steps from it along
/// every axis of the hull (a point on the boundary fails).
pub fn origin_inside(set: &[Shape], quotient: Option<&Shape>) -> (bool, f64) {
    let project = |v: &Shape| match quotient {
        Some(q) if q.norm() > 0.0 => {
            let u = q / q.norm();
            v - &u * u.dot(v)
        }
        _ => v.clone(),
    };
    let pts: Vec<Shape> = set.iter().map(project).collect();
    let n = pts.len() as f64;
    let centre = pts.iter().fold(DVector::zeros(pts[0].len()), |a, p| a + p) / n;
    let scale = pts.iter().map(|p| p.norm()).fold(0.0, f64::max).max(1e-300);
    let centred = DMatrix::from_columns(&pts.iter().map(|p| p - &centre).collect::<Vec<_>>());
    let svd = centred.svd(true, false);
    let u = svd.u.expect("U");
    let top = svd.singular_values.max();
    let axes: Vec<Shape> = (0..svd.singular_values.len())
        .filter(|&k| svd.singular_values[k] > 1e-9 * top.max(1e-300))
        .map(|k| u.column(k).into_owned())
        .collect();
    // the origin's offset from the affine hull
    let mut rest = -&centre;
    for a in &axes {
        rest -= a * a.dot(&rest);
    }
    let offset = rest.norm();
    if offset > 1e-9 * scale || axes.is_empty() {
        return (false, offset);
    }
    let local: Vec<DVector<f64>> = pts
        .iter()
        .map(|p| DVector::from_iterator(axes.len(), axes.iter().map(|a| a.dot(p))))
        .collect();
    let eps = 1e-3 * scale;
    let mut probes = vec![DVector::zeros(axes.len())];
    for k in 0..axes.len() {
        for sign in [-1.0, 1.0] {
            let mut e = DVector::zeros(axes.len());
            e[k] = sign * eps;
            probes.push(e);
        }
    }
    let inside = probes.iter().all(|p| in_hull(&local, p, 1e-3 * eps));
    (inside, offset)
}

/// Gilbert's algorithm: whether `p` lies within `tol` of the convex hull of `pts` (a separating
/// direction proves it does not).
fn in_hull(pts: &[DVector<f64>], p: &DVector<f64>, tol: f64) -> bool {
    let mut x = &pts[0] - p;
    for _ in 0..20_000 {
        if x.norm() < tol {
            return true;
        }
        let (mut best, mut arg) = (f64::INFINITY, 0);
        for (i, q) in pts.iter().enumerate() {
            let d = (q - p).dot(&x);
            if d < best {
                best = d;
                arg = i;
            }
        }
        if best > 0.0 {
            return false;
        }
        let d = &pts[arg] - p - &x;
        let dd = d.norm_squared();
        if dd == 0.0 {
            return false;
        }
        let t = (-x.dot(&d) / dd).clamp(0.0, 1.0);
        if t == 0.0 {
            return false;
        }
        x += d * t;
    }
    x.norm() < tol
}

/// A named sample formation.
#[derive(Debug, Clone)]
pub struct Formation {
    /// Its name.
    pub name: &'static str,
    /// Agent positions (BL).
    pub positions: Vec<Vec2>,
}

/// The sample formations of three agents with side `d` (BL): an equilateral triangle, a row, an
/// isosceles triangle (apex 40°) and an L (a right angle).
pub fn three_agent_formations(d: f64) -> Vec<Formation> {
    let apex = 40f64.to_radians();
    vec![
        Formation {
            name: "equilateral",
            positions: vec![
                Vec2::zeros(),
                Vec2::new(d, 0.0),
                Vec2::new(0.5 * d, 0.75f64.sqrt() * d),
            ],
        },
        Formation {
            name: "row",
            positions: vec![Vec2::zeros(), Vec2::new(d, 0.0), Vec2::new(2.0 * d, 0.0)],
        },
        Formation {
            name: "isosceles-40",
            positions: vec![
                Vec2::zeros(),
                Vec2::new(d, 0.0),
                Vec2::new(d * apex.cos(), d * apex.sin()),
            ],
        },
        Formation {
            name: "L",
            positions: vec![Vec2::new(0.0, d), Vec2::zeros(), Vec2::new(d, 0.0)],
        },
    ]
}

/// The sample formations of four agents with side `d` (BL): a square, a row, a rhombus (60°,
/// two equilateral triangles), a centred triangle (one agent at the centre of an equilateral
/// triangle of the others, `d` from each) and a kite (an equilateral triangle with the fourth
/// agent beyond one side).
pub fn four_agent_formations(d: f64) -> Vec<Formation> {
    let h = 0.75f64.sqrt() * d;
    let c = d / 3f64.sqrt();
    vec![
        Formation {
            name: "square",
            positions: vec![
                Vec2::zeros(),
                Vec2::new(d, 0.0),
                Vec2::new(d, d),
                Vec2::new(0.0, d),
            ],
        },
        Formation {
            name: "row",
            positions: (0..4).map(|i| Vec2::new(i as f64 * d, 0.0)).collect(),
        },
        Formation {
            name: "rhombus-60",
            positions: vec![
                Vec2::zeros(),
                Vec2::new(d, 0.0),
                Vec2::new(1.5 * d, h),
                Vec2::new(0.5 * d, h),
            ],
        },
        Formation {
            name: "centred",
            positions: (0..3)
                .map(|k| {
                    let a =
                        std::f64::consts::FRAC_PI_2 + k as f64 * 2.0 * std::f64::consts::PI / 3.0;
                    Vec2::new(c * a.cos(), c * a.sin())
                })
                .chain([Vec2::zeros()])
                .collect(),
        },
        Formation {
            name: "kite",
            positions: vec![
                Vec2::zeros(),
                Vec2::new(d, 0.0),
                Vec2::new(0.5 * d, h),
                Vec2::new(0.5 * d, -1.5 * d),
            ],
        },
    ]
}

/// The sample formations of `n` agents: [`three_agent_formations`] or
/// [`four_agent_formations`] (none for other team sizes).
pub fn formations(n: usize, d: f64) -> Vec<Formation> {
    match n {
        3 => three_agent_formations(d),
        4 => four_agent_formations(d),
        _ => vec![],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controllability::tests::kin;
    use crate::controllability::velocity_ellipse;

    /// Four agents: a square drifts (it contracts) in the plane and is held with the elevation;
    /// a kite has the full accessibility rank 6 either way.
    #[test]
    fn four_agents_are_held_only_with_elevation() {
        let (kin, _) = kin();
        let f = four_agent_formations(2.0);
        let elevated = FieldSet::Elevated {
            alpha_max: std::f64::consts::FRAC_PI_2,
        };
        let square = &f[0].positions;
        let flat = team_report(&kin, square, FieldSet::Planar);
        let up = team_report(&kin, square, elevated);
        assert_eq!(flat.dim, 6);
        assert!(!flat.holds && flat.offset > 0.1);
        assert!(up.holds && up.holds_shape);
        let kite = &f.iter().find(|f| f.name == "kite").unwrap().positions;
        assert_eq!(team_report(&kin, kite, FieldSet::Planar).depth2, 6);
        assert_eq!(formations(4, 2.0).len(), f.len());
        assert!(formations(3, 2.0).iter().all(|f| f.positions.len() == 3));
    }

    /// The basis reproduces the physics at any in-plane field and elevation.
    #[test]
    fn the_quadratic_form_is_exact() {
        let (k, _) = kin();
        let s = shape_of(&three_agent_formations(2.5)[2].positions);
        let basis = BasisFields::at(&k, &s);
        for (t, a) in [(0.3, 0.0), (1.9, 0.6), (-2.2, 1.2), (0.0, 1.5)] {
            let b = [f64::cos(a) * f64::cos(t), f64::cos(a) * f64::sin(t)];
            let err = (basis.velocity(b) - shape_velocity(&k, &s, b)).norm();
            assert!(err < 1e-12 * basis.f0.norm(), "θ={t} α={a}: {err}");
        }
    }

    /// Two agents: the velocity set is the seed's ellipse and the origin lies inside it; the
    /// in-plane fields already span the plane.
    #[test]
    fn two_agents_reproduce_the_closed_form() {
        let (k, kappa) = kin();
        let (r, phi) = (2.0f64, 0.4f64);
        let p = [Vec2::zeros(), Vec2::new(r * phi.cos(), r * phi.sin())];
        let s = shape_of(&p);
        let basis = BasisFields::at(&k, &s);
        let (rh, eph) = (
            Vec2::new(phi.cos(), phi.sin()),
            Vec2::new(-phi.sin(), phi.cos()),
        );
        for d in [0.0, 20.0, 54.7356, 90.0, 133.0f64] {
            let psi = d.to_radians();
            let t = phi + psi;
            let v = basis.velocity([t.cos(), t.sin()]);
            let v = Vec2::new(v[0], v[1]) * r.powi(4) / kappa;
            let (er, et) = velocity_ellipse(psi);
            assert!((v.dot(&rh) - er).abs() < 1e-9 && (v.dot(&eph) - et).abs() < 1e-9);
        }
        let rep = team_report(&k, &p, FieldSet::Planar);
        assert_eq!((rep.dim, rep.first_order, rep.depth2), (2, 2, 2));
        assert!(rep.holds, "the origin lies inside the ellipse");
    }

    /// The equilateral triangle in the plane always contracts: its pair forces' radial parts sum
    /// to −3/2 Ω/r⁴ at every field angle, and its side lengths shrink at a summed rate of
    /// −9/4 κ/r⁴ (each side also feels the third agent); at cos²α = 2/3 both sums vanish. So it
    /// cannot be held in the plane; with the elevation free it can.
    #[test]
    fn the_equilateral_triangle_is_held_only_with_elevation() {
        let (k, kappa) = kin();
        let d = 2.5;
        let f = &three_agent_formations(d)[0];
        let s = shape_of(&f.positions);
        let basis = BasisFields::at(&k, &s);
        let side_rate_sum = |b: [f64; 2]| {
            let v = basis.velocity(b);
            let h = 1e-7;
            let p = positions_of(&(&s + &v * h));
            let sum: f64 = [(0, 1), (1, 2), (2, 0)]
                .iter()
                .map(|&(i, j)| ((p[j] - p[i]).norm() - d) / h)
                .sum();
            sum * d.powi(4) / kappa
        };
        let magic = (2.0f64 / 3.0).sqrt();
        for deg in [0.0, 17.0, 60.0, 125.0f64] {
            let t = deg.to_radians();
            let planar = side_rate_sum([t.cos(), t.sin()]);
            assert!((planar + 2.25).abs() < 1e-5, "θ={deg}: {planar}");
            let tilted = side_rate_sum([magic * t.cos(), magic * t.sin()]);
            assert!(tilted.abs() < 1e-5, "θ={deg}, cos²α = 2/3: {tilted}");
        }
        let planar = team_report(&k, &f.positions, FieldSet::Planar);
        assert!(!planar.holds && !planar.holds_shape);
        let free = team_report(
            &k,
            &f.positions,
            FieldSet::Elevated {
                alpha_max: std::f64::consts::FRAC_PI_2,
            },
        );
        assert!(free.holds && free.holds_shape, "{free:?}");
        assert_eq!((planar.first_order, planar.depth1), (3, 4));
    }

    /// The field's average over the plane's directions is −3/2 times the field straight up (the
    /// isotropic average of the dipole interaction), so the elevation adds no new direction: it
    /// rescales the radial part against the rest, through zero at cos²α = 2/3.
    #[test]
    fn the_in_plane_mean_is_minus_three_halves_of_the_vertical_field() {
        let (k, _) = kin();
        for f in three_agent_formations(2.2) {
            let b = BasisFields::at(&k, &shape_of(&f.positions));
            let m_prime = (&b.f11 + &b.f22) * 0.5;
            assert!(
                (m_prime + &b.f0 * 1.5).norm() < 1e-12 * b.f0.norm(),
                "{}",
                f.name
            );
        }
    }

    /// An evenly spaced row stays an evenly spaced row (the middle agent is held at the midpoint
    /// by symmetry): its rank drops to 2, spacing and heading.
    #[test]
    fn an_even_row_has_rank_two() {
        let (k, _) = kin();
        let row = &three_agent_formations(2.5)[1];
        for set in [
            FieldSet::Planar,
            FieldSet::Elevated {
                alpha_max: std::f64::consts::FRAC_PI_2,
            },
        ] {
            let r = team_report(&k, &row.positions, set);
            assert_eq!((r.first_order, r.depth2), (2, 2));
        }
    }

    /// A bracket of two constant fields is zero, so the rank test can fail.
    #[test]
    fn rank_counts_independent_columns() {
        let e = |v: [f64; 4]| DVector::from_row_slice(&v);
        assert_eq!(
            rank(&[e([1.0, 0.0, 0.0, 0.0]), e([2.0, 0.0, 0.0, 0.0])], 1e-9),
            1
        );
        assert_eq!(
            rank(&[e([1.0, 0.0, 0.0, 0.0]), e([0.0, 1.0, 1e-3, 0.0])], 1e-9),
            2
        );
        assert_eq!(rank(&[e([0.0; 4])], 1e-9), 0);
    }
}

#[cfg(test)]
mod ring_tests {
    use super::*;
    use crate::controllability::tests::kin;

    /// A regular ring of `n` at neighbour spacing 1.6 BL.
    fn ring(n: usize) -> Vec<Vec2> {
        let r = 1.6 / (2.0 * (std::f64::consts::PI / n as f64).sin());
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                Vec2::new(a.cos(), a.sin()) * r
            })
            .collect()
    }

    /// A ring of five has the full rank 8 by depth two; a ring of six is symmetric about its
    /// centroid and stays in the 6-dimensional set of such formations (three opposite pairs:
    /// three free vectors), and moved off it reaches the full rank 10.
    #[test]
    fn rings_reach_full_rank_except_in_their_invariant_set() {
        let (kin, _) = kin();
        let el = FieldSet::Elevated { alpha_max: 0.8 };
        let five = accessibility(&kin, &ring(5), el);
        assert_eq!((five.dim, five.first_order, five.depth2), (8, 3, 8));
        let mut six = ring(6);
        assert_eq!(accessibility(&kin, &six, el).depth2, 6);
        six[0].x += 0.137;
        six[1].y -= 0.071;
        assert_eq!(accessibility(&kin, &six, el).depth2, 10);
    }
}

//! `magbench stlc`: the Lie-algebra rank condition over ψ (two agents), or the accessibility
//! rank and drift cancellation of a team of three or four at sample formations, with and
//! without the elevation (`--agents 3`, `--agents 4`).

use clap::Args;
use magbench_env::PhysicalParams;
use magbench_env::Vec2;
use magbench_env::controllability::{closed_form, larc, velocity_ellipse};
use magbench_env::input::Bound;
use magbench_env::model::Kinematics;
use magbench_env::team_controllability::{FieldSet, TeamReport, formations, team_report};

use super::number::{checked, count};
use crate::Error;
use crate::output::outln;

/// Largest separation of the rank test (BL): at 50 BL the finite differences already miss the
/// rank drop at ψ = ±90°.
pub const MAX_R_BL: f64 = 30.0;

/// The largest team of the rank tables: beyond four the velocity-set hull test (thousands of
/// points in 2(N−1) dimensions) takes minutes.
pub const MAX_TEAM: usize = 4;

/// `--r`: a separation between touching (1 BL) and [`MAX_R_BL`].
const R: Bound = Bound::above(
    1.0,
    MAX_R_BL,
    " BL",
    "a separation: the agents touch at 1 BL; beyond 30 BL the pair forces, ∝ r⁻⁴, are too weak for the finite-difference rank test",
);

/// `--step`: the ψ sweep's step.
const STEP: Bound = Bound::closed(
    0.001,
    90.0,
    " degrees",
    "a step under 0.001° lists more than 90000 directions, finer than the rank test resolves",
);

/// `--agents`: the pair's local model (2) or a team of the rank tables (3 to [`MAX_TEAM`]).
const AGENTS: Bound = Bound::closed(
    2.0,
    MAX_TEAM as f64,
    " agents",
    "beyond four the velocity-set hull test (thousands of points in 2(N−1) dimensions) takes minutes",
);

/// `--alpha-max`: a field elevation out of the plane.
const ALPHA_MAX: Bound = Bound::above(
    0.0,
    90.0,
    " degrees",
    "an elevation out of the plane; 90° points the field straight up",
);

/// Arguments of `magbench stlc`.
#[derive(Debug, Args)]
pub struct StlcArgs {
    /// Separation r (BL).
    #[arg(long, default_value_t = 2.0)]
    pub r: f64,
    /// Step of the ψ sweep (degrees).
    #[arg(long, default_value_t = 7.5)]
    pub step: f64,
    /// Team size: 2 (the pair's local model), 3 or 4 (sample formations of side --r).
    #[arg(long, default_value_t = 2)]
    pub agents: usize,
    /// Largest elevation of the elevated field set (degrees, --agents 3 or 4).
    #[arg(long, default_value_t = 90.0)]
    pub alpha_max: f64,
}

/// Prints the rank table.
pub fn run(a: StlcArgs) -> Result<(), Error> {
    checked("--r", &R, a.r)?;
    checked("--step", &STEP, a.step)?;
    count("--agents", &AGENTS, a.agents as u64)?;
    checked("--alpha-max", &ALPHA_MAX, a.alpha_max)?;
    if a.agents > 2 {
        return team(&a);
    }
    let p = PhysicalParams::default();
    let kin = Kinematics::nominal(&p);
    let kappa = p.kappa();
    outln!(
        "LARC of the local model (r, φ, ψ), g = ∂/∂ψ, at r = {} BL, κ = {:.4} BL⁵/s",
        a.r,
        kappa
    );
    outln!(
        "Δ = [g, [f,g], [f,[f,g]]] by finite differences of the vector physics; margin = σ_min of Δ with unit columns"
    );
    outln!(
        "{:>9} {:>5} {:>10} {:>12} {:>10} {:>9} {:>9}",
        "ψ (deg)",
        "rank",
        "margin",
        "det Δ",
        "|Δ−closed|",
        "ṙ r⁴/κ",
        "rφ̇ r⁴/κ"
    );
    let mut angles: Vec<f64> = Vec::new();
    let mut d = -90.0;
    while d <= 90.0 + 1e-9 {
        angles.push(d);
        d += a.step;
    }
    for m in [-54.7356, 54.7356] {
        if !angles.iter().any(|x| (x - m).abs() < 1e-6) {
            angles.push(m);
        }
    }
    angles.sort_by(f64::total_cmp);
    for d in angles {
        let psi = d.to_radians();
        let rep = larc(&kin, a.r, psi);
        let cf = closed_form(kappa, a.r, psi);
        let rel = (0..3)
            .map(|c| (rep.delta.column(c) - cf.column(c)).norm() / cf.column(c).norm().max(1e-300))
            .fold(0.0, f64::max);
        let (er, et) = velocity_ellipse(psi);
        outln!(
            "{d:>9.3} {:>5} {:>10.4} {:>12.4e} {:>10.1e} {er:>9.4} {et:>9.4}",
            rep.rank,
            rep.margin,
            rep.det,
            rel
        );
    }
    outln!(
        "rank 3 except at ψ ∈ {{0°, ±90°}} (sin 2ψ = 0). As ψ sweeps, (ṙ, rφ̇)·r⁴/κ = (1 − 3cos²ψ, sin 2ψ)"
    );
    outln!(
        "traces an ellipse centred at (−½, 0) with semi-axes 3/2 and 1: zero lies strictly inside it."
    );
    Ok(())
}

/// The team tables: sample formations, then (three agents) a sweep of the isosceles apex angle.
fn team(a: &StlcArgs) -> Result<(), Error> {
    let kin = Kinematics::nominal(&PhysicalParams::default());
    let elevated = FieldSet::Elevated {
        alpha_max: a.alpha_max.to_radians(),
    };
    let n = a.agents;
    let dim = 2 * (n - 1);
    let shape: Vec<String> = (1..n).map(|i| format!("P{}−P₀", subscript(i))).collect();
    outln!(
        "{} agents, side {} BL: shape s = ({}) (dimension {dim}). Controls: the field in the plane",
        if n == 3 { "Three" } else { "Four" },
        a.r,
        shape.join(", ")
    );
    outln!(
        "(fields M, A, B) or elevated up to {}° (F₀, M', A, B). rank1 = the fields, rank2 = with their brackets,",
        a.alpha_max
    );
    outln!(
        "rank3 = with brackets of brackets (the accessibility rank, full = {dim}). hold = 0 inside the velocity set's"
    );
    outln!(
        "convex hull (every relative position held); hold-shape = the same up to a rotation (side lengths held)."
    );
    header("formation")?;
    for f in formations(n, a.r) {
        for (label, set) in [("planar", FieldSet::Planar), ("elevated", elevated)] {
            row(f.name, label, &team_report(&kin, &f.positions, set))?;
        }
    }
    if n != 3 {
        return footer();
    }
    outln!();
    outln!(
        "Isosceles triangles (two sides {} BL about agent 0) by apex angle: where the rank drops",
        a.r
    );
    header("apex (deg)")?;
    for k in 3..=18 {
        let apex = (10 * k) as f64;
        let g = apex.to_radians();
        let p = [
            Vec2::zeros(),
            Vec2::new(a.r, 0.0),
            Vec2::new(a.r * g.cos(), a.r * g.sin()),
        ];
        for (label, set) in [("planar", FieldSet::Planar), ("elevated", elevated)] {
            row(&format!("{apex}"), label, &team_report(&kin, &p, set))?;
        }
    }
    footer()
}

/// The subscript digit of `k` (< 10).
fn subscript(k: usize) -> char {
    char::from_u32(0x2080 + k as u32).unwrap_or('?')
}

/// What the offset column means.
fn footer() -> Result<(), Error> {
    outln!(
        "offset: distance of the origin from the velocity set's affine hull (BL/s); > 0 means no mix of field"
    );
    outln!("directions cancels the drift in every shape coordinate.");
    Ok(())
}

/// The team table's header, its first column titled `first`.
fn header(first: &str) -> Result<(), Error> {
    outln!(
        "{first:<14} {:<9} {:>5} {:>5} {:>5} {:>5} {:>12} {:>10}",
        "field",
        "rank1",
        "rank2",
        "rank3",
        "hold",
        "hold-shape",
        "offset"
    );
    Ok(())
}

/// One row of the team table.
fn row(name: &str, field: &str, r: &TeamReport) -> Result<(), Error> {
    let yes = |b: bool| if b { "yes" } else { "no" };
    outln!(
        "{name:<14} {field:<9} {:>5} {:>5} {:>5} {:>5} {:>12} {:>10.2e}",
        r.first_order,
        r.depth1,
        r.depth2,
        yes(r.holds),
        yes(r.holds_shape),
        r.offset
    );
    Ok(())
}

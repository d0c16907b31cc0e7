//! The achievable inter-agent velocity set of three agents, field in the plane against field
//! elevated: the side-length rates (ṙ₀₁, ṙ₁₂, ṙ₂₀) projected on the formation's size rate (their
//! mean) and one shape rate, for an equilateral triangle and an L. In the plane the set is an
//! ellipse that misses the origin (the triangle always contracts: the seed's "impossible motion
//! directions" of more than two agents); with the elevation free it fills a region around it.

use magbench_env::model::Kinematics;
use magbench_env::team_controllability::{BasisFields, Shape, shape_of, three_agent_formations};
use magbench_env::{PhysicalParams, Vec2};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::plot::legend::{self, Entry, Symbol};
use crate::plot::{Figure, PlotError, title_font, xy_mesh};

/// The velocity-set figure of three agents with side `side` (BL).
pub struct TeamVelocityFigure {
    /// Side of the sample formations (BL).
    pub side: f64,
}

const PLANAR: RGBColor = RGBColor(200, 30, 30);
const ELEVATED: RGBColor = RGBColor(70, 130, 200);
const MAGIC: RGBColor = RGBColor(20, 120, 60);

fn entries() -> Vec<Entry> {
    vec![
        Entry::new(
            Symbol::Line(PLANAR, 3),
            "field in the plane (α = 0): θ sweeps",
        ),
        Entry::new(
            Symbol::Disk(ELEVATED),
            "field elevated, α in [0°, 90°] (every θ)",
        ),
        Entry::new(
            Symbol::Line(MAGIC, 2),
            "cos²α = 2/3 (α = 35.26°): the radial parts cancel",
        ),
        Entry::new(
            Symbol::Circle(RGBColor(0, 0, 0)),
            "the origin: the formation held",
        ),
    ]
}

/// (size rate, shape rate) of shape velocity `v` at positions `p`, in units of κ/side⁴.
fn projection(p: &[Vec2], v: &Shape, unit: f64) -> (f64, f64) {
    let vel = [Vec2::zeros(), Vec2::new(v[0], v[1]), Vec2::new(v[2], v[3])];
    let rate = |i: usize, j: usize| {
        let d = p[j] - p[i];
        d.dot(&(vel[j] - vel[i])) / d.norm()
    };
    let (a, b, c) = (rate(0, 1), rate(1, 2), rate(2, 0));
    (
        (a + b + c) / 3.0 / unit,
        (2.0 * a - b - c) / 6f64.sqrt() / unit,
    )
}

/// The planar curve, the elevated cloud and the magic-cone curve of one formation.
type Sets = (Vec<(f64, f64)>, Vec<(f64, f64)>, Vec<(f64, f64)>);

fn sets(kin: &Kinematics, p: &[Vec2], unit: f64) -> Sets {
    let basis = BasisFields::at(kin, &shape_of(p));
    let at = |alpha: f64, theta: f64| {
        let c = alpha.cos();
        projection(p, &basis.velocity([c * theta.cos(), c * theta.sin()]), unit)
    };
    let angles = |n: usize| (0..=n).map(move |k| std::f64::consts::PI * k as f64 / n as f64);
    let planar = angles(180).map(|t| at(0.0, t)).collect();
    let magic = (2.0f64 / 3.0).sqrt().acos();
    let cone = angles(180).map(|t| at(magic, t)).collect();
    let mut cloud = vec![];
    for l in 0..=30 {
        let alpha = std::f64::consts::FRAC_PI_2 * l as f64 / 30.0;
        cloud.extend(angles(90).map(|t| at(alpha, t)));
    }
    (planar, cloud, cone)
}

impl Figure for TeamVelocityFigure {
    fn size(&self) -> (u32, u32) {
        (1200, 560 + legend::height(&entries(), 1200))
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let e = entries();
        let (_, h) = root.dim_in_pixel();
        let (top, bottom) = root.split_vertically(h - legend::height(&e, 1200));
        let panels = top.split_evenly((1, 2));
        let p = PhysicalParams::default();
        let kin = Kinematics::nominal(&p);
        let unit = p.kappa() / self.side.powi(4);
        let formations = three_agent_formations(self.side);
        let shown = [&formations[0], &formations[3]];
        for (area, f) in panels.iter().zip(shown) {
            let (planar, cloud, cone) = sets(&kin, &f.positions, unit);
            let all = || planar.iter().chain(&cloud).chain(&cone);
            let (x0, x1) = all().fold((0.0f64, 0.0f64), |(a, b), q| (a.min(q.0), b.max(q.0)));
            let (y0, y1) = all().fold((0.0f64, 0.0f64), |(a, b), q| (a.min(q.1), b.max(q.1)));
            let (mx, my) = (0.08 * (x1 - x0), 0.08 * (y1 - y0));
            let mut c = ChartBuilder::on(area)
                .caption(format!("{} (side {} BL)", f.name, self.side), title_font())
                .margin(12)
                .x_label_area_size(50)
                .y_label_area_size(70)
                .build_cartesian_2d((x0 - mx)..(x1 + mx), (y0 - my)..(y1 + my))?;
            xy_mesh(
                &mut c,
                "size rate (ṙ₀₁+ṙ₁₂+ṙ₂₀)/3 (κ/r⁴)",
                "shape rate (2ṙ₀₁−ṙ₁₂−ṙ₂₀)/√6 (κ/r⁴)",
            )?;
            c.draw_series(
                cloud
                    .iter()
                    .map(|q| Circle::new(*q, 2, ELEVATED.mix(0.35).filled())),
            )?;
            c.draw_series(std::iter::once(PathElement::new(
                cone,
                MAGIC.stroke_width(2),
            )))?;
            c.draw_series(std::iter::once(PathElement::new(
                planar,
                PLANAR.stroke_width(3),
            )))?;
            c.draw_series(std::iter::once(Circle::new(
                (0.0, 0.0),
                7,
                BLACK.stroke_width(2),
            )))?;
        }
        legend::draw(&bottom, &e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In the plane the equilateral triangle's size rate is −3/4 κ/r⁴ at every θ (the set misses
    /// the origin); elevated, the set reaches both sides of it.
    #[test]
    fn the_planar_triangle_always_shrinks_and_the_elevated_set_spans_the_origin() {
        let p = PhysicalParams::default();
        let kin = Kinematics::nominal(&p);
        let d = 2.5;
        let f = &three_agent_formations(d)[0];
        let (planar, cloud, cone) = sets(&kin, &f.positions, p.kappa() / d.powi(4));
        assert!(
            planar.iter().all(|q| (q.0 + 0.75).abs() < 1e-9),
            "{:?}",
            planar[0]
        );
        assert!(cone.iter().all(|q| q.0.abs() < 1e-9));
        let xs = || cloud.iter().map(|q| q.0);
        assert!(xs().fold(f64::INFINITY, f64::min) < -0.7 && xs().fold(0.0, f64::max) > 0.9);
    }
}

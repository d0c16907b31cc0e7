//! Force figures: the achievable pair force along a planned path (the seed's Fig. 1), and the
//! force ellipse in (f_r, f_φ) as the field angle ψ sweeps.
//!
//! The shape comes from env (`controllability::velocity_ellipse`): in the plane the pair force
//! is `(f_r, f_φ) = Ω/r⁴ (1 − 3cos²ψ, sin 2ψ)`, and the relative velocity `(ṙ, rφ̇)` is the same
//! ellipse times `κ/r⁴`.

use magbench_env::controllability::velocity_ellipse;
use magbench_env::{LocalView, Vec2, World};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::plot::legend::{self, Entry, Symbol};
use crate::plot::world::{chart, draw_goals, draw_path, draw_starts, draw_world, map_size};
use crate::plot::{Figure, PlotError, label_font, palette, tick_font, title_font, xy_mesh};

/// ψ where the radial force vanishes: cos²ψ = 1/3.
pub fn zero_radial_psi() -> f64 {
    (1.0f64 / 3.0).sqrt().acos()
}

const ATTRACT: RGBColor = RGBColor(40, 110, 220);
const REPEL: RGBColor = RGBColor(220, 60, 40);

/// The seed's Fig. 1: at waypoints of a planned two-agent path, the achievable relative
/// velocity (∝ pair force) as ψ sweeps, drawn in the world frame at the pair's centre; the
/// attractive (f_r < 0) and repulsive (f_r > 0) parts shaded, ±ê_φ (transverse) marked.
pub struct ForceAlongPath<'a> {
    /// The world.
    pub world: &'a World,
    /// Planned path per agent.
    pub planned: Vec<Vec<Vec2>>,
    /// Waypoints (pairs of positions) to draw the ellipse at.
    pub waypoints: Vec<[Vec2; 2]>,
    /// Relative-motion constant κ (BL⁵/s).
    pub kappa: f64,
    /// Drawing scale (BL of drawing per BL/s of relative velocity).
    pub scale: f64,
    /// Start positions and goals.
    pub starts: Vec<Vec2>,
    /// Goals.
    pub goals: Vec<magbench_env::Goal>,
    /// Title.
    pub title: String,
}

fn entries(scale: f64) -> Vec<Entry> {
    vec![
        Entry::new(Symbol::Line(palette::agent(0), 3), "agent 1 planned"),
        Entry::new(Symbol::Line(palette::agent(1), 3), "agent 2 planned"),
        Entry::new(Symbol::Band(ATTRACT), "attractive (f_r < 0)"),
        Entry::new(Symbol::Band(REPEL), "repulsive (f_r > 0)"),
        Entry::new(Symbol::Line(BLACK, 2), "transverse ±ê_φ"),
        Entry::new(
            Symbol::Line(RGBColor(90, 90, 90), 1),
            format!("scale: 1 BL = {:.2} BL/s of ṙ, rφ̇", 1.0 / scale),
        ),
    ]
}

impl Figure for ForceAlongPath<'_> {
    fn size(&self) -> (u32, u32) {
        map_size(
            self.world,
            1000,
            true,
            legend::height(&entries(self.scale), 1000),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let e = entries(self.scale);
        let (_, h) = root.dim_in_pixel();
        let lh = legend::height(&e, 1000);
        let (top, bottom) = root.split_vertically(h - lh);
        let mut c = chart(&top, self.world, Some(&self.title))?;
        draw_world(&mut c, self.world)?;
        for (i, p) in self.planned.iter().enumerate() {
            draw_path(&mut c, p, palette::agent(i), 3)?;
        }
        draw_goals(&mut c, &self.goals)?;
        draw_starts(&mut c, &self.starts)?;
        for wp in &self.waypoints {
            let v = LocalView::from_pair(wp[0], wp[1]);
            let centre = Vec2::new(v.xc, v.yc);
            let er = Vec2::new(v.phi.cos(), v.phi.sin());
            let ephi = Vec2::new(-v.phi.sin(), v.phi.cos());
            let k = self.kappa / v.r.powi(4) * self.scale;
            let n = 180;
            let pts: Vec<(f64, Vec2)> = (0..=n)
                .map(|j| {
                    let psi =
                        std::f64::consts::PI * j as f64 / n as f64 - std::f64::consts::FRAC_PI_2;
                    let (a, b) = velocity_ellipse(psi);
                    (a, centre + (er * a + ephi * b) * k)
                })
                .collect();
            // Fans from the centre over the attractive and repulsive arcs.
            for w in pts.windows(2) {
                let col = if w[0].0 + w[1].0 < 0.0 {
                    ATTRACT
                } else {
                    REPEL
                };
                let tri = vec![
                    (centre.x, centre.y),
                    (w[0].1.x, w[0].1.y),
                    (w[1].1.x, w[1].1.y),
                ];
                c.draw_series(std::iter::once(Polygon::new(tri, col.mix(0.35).filled())))?;
            }
            let outline: Vec<(f64, f64)> = pts.iter().map(|(_, p)| (p.x, p.y)).collect();
            c.draw_series(std::iter::once(PathElement::new(
                outline,
                RGBColor(60, 60, 60).stroke_width(1),
            )))?;
            for s in [1.0, -1.0] {
                let tip = centre + ephi * (k * s);
                c.draw_series(std::iter::once(PathElement::new(
                    vec![(centre.x, centre.y), (tip.x, tip.y)],
                    BLACK.stroke_width(2),
                )))?;
                c.draw_series(std::iter::once(Circle::new(
                    (tip.x, tip.y),
                    3,
                    BLACK.filled(),
                )))?;
            }
            for (i, p) in wp.iter().enumerate() {
                c.draw_series(std::iter::once(PathElement::new(
                    crate::plot::world::circle_points(*p, 0.5, 32),
                    palette::agent(i).stroke_width(1),
                )))?;
            }
        }
        legend::draw(&bottom, &e)
    }
}

/// The force ellipse `(f_r, f_φ)·r⁴/Ω` as ψ sweeps, with ψ = ±54.74° (no radial force),
/// 0° (strongest attraction), ±45° (strongest transverse force) and ±90° (repulsion) marked.
pub struct ForceEllipse;

impl Figure for ForceEllipse {
    fn size(&self) -> (u32, u32) {
        (900, 700)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let mut c = ChartBuilder::on(root)
            .caption(
                "Pair force as the field angle ψ sweeps (in plane, α = 0)",
                title_font(),
            )
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(-2.4..1.6, -1.4..1.4)?;
        xy_mesh(
            &mut c,
            "radial force f_r · r⁴/Ω   (< 0: attraction)",
            "transverse force f_φ · r⁴/Ω",
        )?;
        c.draw_series(std::iter::once(Rectangle::new(
            [(-2.4, -1.4), (0.0, 1.4)],
            ATTRACT.mix(0.08).filled(),
        )))?;
        c.draw_series(std::iter::once(Rectangle::new(
            [(0.0, -1.4), (1.6, 1.4)],
            REPEL.mix(0.08).filled(),
        )))?;
        c.draw_series(std::iter::once(PathElement::new(
            vec![(0.0, -1.4), (0.0, 1.4)],
            RGBColor(120, 120, 120).stroke_width(1),
        )))?;
        c.draw_series(std::iter::once(PathElement::new(
            vec![(-2.4, 0.0), (1.6, 0.0)],
            RGBColor(120, 120, 120).stroke_width(1),
        )))?;
        let pts: Vec<(f64, f64)> = (0..=360)
            .map(|j| velocity_ellipse((j as f64 * 0.5 - 90.0).to_radians()))
            .collect();
        c.draw_series(std::iter::once(PathElement::new(
            pts,
            palette::series(0).stroke_width(3),
        )))?;
        let z = zero_radial_psi().to_degrees();
        let (plus, minus) = (
            format!("ψ = +{z:.2}°: f_r = 0"),
            format!("ψ = −{z:.2}°: f_r = 0"),
        );
        let marks: [(f64, &str, RGBColor); 7] = [
            (z, &plus, BLACK),
            (-z, &minus, BLACK),
            (0.0, "ψ = 0°: strongest attraction (−2)", ATTRACT),
            (90.0, "ψ = ±90°: repulsion (+1)", REPEL),
            (45.0, "ψ = +45°", palette::series(1)),
            (-45.0, "ψ = −45°", palette::series(1)),
            (-90.0, "", REPEL),
        ];
        for (deg, text, col) in marks {
            let (x, y) = velocity_ellipse(deg.to_radians());
            c.draw_series(std::iter::once(Circle::new((x, y), 6, col.filled())))?;
            if !text.is_empty() {
                let (h, dx) = if x < -1.0 {
                    (HPos::Left, 0.08)
                } else if x > 0.5 {
                    (HPos::Right, -0.08)
                } else {
                    (HPos::Left, 0.08)
                };
                let v = if y >= 0.0 { VPos::Bottom } else { VPos::Top };
                let dy = if y >= 0.0 { 0.05 } else { -0.05 };
                c.draw_series(std::iter::once(Text::new(
                    text.to_string(),
                    (x + dx, y + dy),
                    label_font().pos(Pos::new(h, v)),
                )))?;
            }
        }
        let note = "centre (−½, 0), semi-axes 3/2 and 1: zero lies inside, so switching ψ can produce any small relative motion";
        c.draw_series(std::iter::once(Text::new(
            note,
            (-2.35, -1.32),
            tick_font().pos(Pos::new(HPos::Left, VPos::Bottom)),
        )))?;
        Ok(())
    }
}

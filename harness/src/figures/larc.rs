//! The LARC margin (smallest singular value of Δ = [g, [f,g], [f,[f,g]]] with unit columns,
//! from env's numerical Lie brackets) against the field angle ψ.

use magbench_env::PhysicalParams;
use magbench_env::controllability::larc;
use magbench_env::model::Kinematics;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::forces::zero_radial_psi;
use crate::plot::legend::{self, Entry, Symbol};
use crate::plot::{Figure, PlotError, palette, title_font, xy_mesh};

/// The LARC margin against ψ at several separations.
pub struct LarcFigure {
    /// Separations r (BL).
    pub separations: Vec<f64>,
}

fn entries(rs: &[f64]) -> Vec<Entry> {
    let mut e: Vec<Entry> = rs
        .iter()
        .enumerate()
        .map(|(i, r)| Entry::new(Symbol::Line(palette::series(i), 2), format!("r = {r} BL")))
        .collect();
    e.push(Entry::new(
        Symbol::Line(RGBColor(200, 30, 30), 1),
        "rank 2 (ψ = 0°, ±90°)",
    ));
    e.push(Entry::new(
        Symbol::Line(RGBColor(120, 120, 120), 1),
        "f_r = 0 (ψ = ±54.74°)",
    ));
    e
}

impl Figure for LarcFigure {
    fn size(&self) -> (u32, u32) {
        (900, 560 + legend::height(&entries(&self.separations), 900))
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let e = entries(&self.separations);
        let (_, h) = root.dim_in_pixel();
        let lh = legend::height(&e, 900);
        let (top, bottom) = root.split_vertically(h - lh);
        let kin = Kinematics::nominal(&PhysicalParams::default());
        let curves: Vec<Vec<(f64, f64)>> = self
            .separations
            .iter()
            .map(|&r| {
                (0..=360)
                    .map(|j| j as f64 * 0.5 - 90.0)
                    .map(|d| (d, larc(&kin, r, d.to_radians()).margin))
                    .collect()
            })
            .collect();
        let top_y = curves.iter().flatten().map(|p| p.1).fold(0.0, f64::max) * 1.1;
        let mut c = ChartBuilder::on(&top)
            .caption(
                "Lie-algebra rank condition: margin against the field angle",
                title_font(),
            )
            .margin(12)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(-90.0..90.0, 0.0..top_y.max(1e-3))?;
        xy_mesh(
            &mut c,
            "ψ = θ_B − φ (deg)",
            "LARC margin σ_min(Δ) (unit columns)",
        )?;
        for d in [-90.0, 0.0, 90.0] {
            c.draw_series(std::iter::once(PathElement::new(
                vec![(d, 0.0), (d, top_y)],
                RGBColor(200, 30, 30).stroke_width(1),
            )))?;
        }
        let z = zero_radial_psi().to_degrees();
        for d in [-z, z] {
            c.draw_series(std::iter::once(PathElement::new(
                vec![(d, 0.0), (d, top_y)],
                RGBColor(120, 120, 120).stroke_width(1),
            )))?;
        }
        for (i, pts) in curves.into_iter().enumerate() {
            c.draw_series(std::iter::once(PathElement::new(
                pts,
                palette::series(i).stroke_width(2),
            )))?;
        }
        legend::draw(&bottom, &e)
    }
}

//! Fig. 4A: the C-space path (x_c, r, φ) of a two-agent plan, planned and tracked: r and φ
//! against the centre of mass x_c, so that a tracker running late still overlays its plan.

use magbench_env::{LocalView, Vec2};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::plot::legend::{self, Entry, Symbol};
use crate::plot::{Figure, PlotError, palette, title_font, xy_mesh};

/// Local coordinates along a path: (t, x_c, y_c, r, φ unwrapped in degrees).
pub fn local_path(samples: &[(f64, Vec<Vec2>)]) -> Vec<[f64; 5]> {
    let mut out: Vec<[f64; 5]> = vec![];
    for (t, s) in samples {
        let v = LocalView::from_pair(s[0], s[1]);
        let mut phi = v.phi.to_degrees();
        if let Some(prev) = out.last() {
            while phi - prev[4] > 180.0 {
                phi -= 360.0;
            }
            while phi - prev[4] < -180.0 {
                phi += 360.0;
            }
        }
        out.push([*t, v.xc, v.yc, v.r, phi]);
    }
    out
}

/// Two stacked panels: r and φ against x_c.
pub struct CSpaceFigure {
    /// Title.
    pub title: String,
    /// Legend note (the run).
    pub note: String,
    /// Planned samples.
    pub planned: Vec<[f64; 5]>,
    /// Tracked samples.
    pub tracked: Vec<[f64; 5]>,
}

fn entries(note: &str) -> Vec<Entry> {
    vec![
        Entry::new(Symbol::Line(palette::agent(0), 3), "planned"),
        Entry::new(
            Symbol::Line(palette::TRACKED, 1),
            format!("tracked ({note})"),
        ),
    ]
}

impl Figure for CSpaceFigure {
    fn size(&self) -> (u32, u32) {
        (900, 720 + legend::height(&entries(&self.note), 900))
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (_, h) = root.dim_in_pixel();
        let lh = legend::height(&entries(&self.note), 900);
        let (top, bottom) = root.split_vertically(h - lh);
        let top = top.titled(&self.title, title_font())?;
        let panels = top.split_evenly((2, 1));
        let xs = self.planned.iter().chain(&self.tracked).map(|p| p[1]);
        let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let xpad = ((x1 - x0) * 0.02).max(0.05);
        let specs: [(usize, &str); 2] = [(3, "separation r (BL)"), (4, "heading φ (deg)")];
        for (panel, (col, label)) in panels.iter().zip(specs) {
            let vals = self.planned.iter().chain(&self.tracked).map(|p| p[col]);
            let (lo, hi) = vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
            let pad = ((hi - lo) * 0.08).max(0.05);
            let mut c = ChartBuilder::on(panel)
                .margin(8)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(x0 - xpad..x1 + xpad, lo - pad..hi + pad)?;
            xy_mesh(&mut c, "centre of mass x_c (BL)", label)?;
            c.draw_series(std::iter::once(PathElement::new(
                self.planned
                    .iter()
                    .map(|p| (p[1], p[col]))
                    .collect::<Vec<_>>(),
                palette::agent(0).stroke_width(3),
            )))?;
            c.draw_series(std::iter::once(PathElement::new(
                self.tracked
                    .iter()
                    .map(|p| (p[1], p[col]))
                    .collect::<Vec<_>>(),
                palette::TRACKED.stroke_width(1),
            )))?;
        }
        legend::draw(&bottom, &entries(&self.note))
    }
}

//! The figure of `magbench calibrate bench`: one panel per parameter, each rig's error against
//! the parameter's true value (under the fit's scale convention). Filled dots are fitted
//! values, hollow ones the base value a parameter kept when the data did not identify it; the
//! dashed lines are the tolerance. Failed rigs have no point.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::calibrate_bench::report::RigResult;
use super::calibrate_bench::score::{Param, Verdict};
use crate::plot::{Figure, PlotError, palette, title_font, xy_mesh};

/// Panels per row.
const COLUMNS: usize = 4;

/// Error against true value, one panel per parameter.
pub struct BenchFigure<'a> {
    results: &'a [RigResult],
    params: &'a [Param],
}

impl<'a> BenchFigure<'a> {
    /// The figure of `results`, whose scores follow `params`.
    pub fn new(results: &'a [RigResult], params: &'a [Param]) -> Self {
        Self { results, params }
    }

    /// (true value, error, written: fitted or imprecise) of parameter `k` on every rig that ran.
    fn points(&self, k: usize) -> Vec<(f64, f64, bool)> {
        self.results
            .iter()
            .filter_map(|r| {
                let s = &r.scores[k];
                let e = s.error.filter(|e| e.is_finite())?;
                let e = if s.param.relative() { 100.0 * e } else { e };
                let written = matches!(s.verdict, Verdict::Fitted | Verdict::Imprecise(_));
                Some((s.compared, e, written))
            })
            .collect()
    }
}

/// `(lo, hi)` padded by 5%, or around `v` when empty or flat.
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (-1.0, 1.0);
    }
    let pad = if hi - lo > 1e-9 {
        (hi - lo) * 0.05
    } else {
        0.1 * lo.abs().max(1.0)
    };
    (lo - pad, hi + pad)
}

impl Figure for BenchFigure<'_> {
    fn size(&self) -> (u32, u32) {
        let rows = self.params.len().div_ceil(COLUMNS).max(1) as u32;
        (1600, 60 + 330 * rows)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (title, body) = root.split_vertically(60);
        title.titled(
            "Error against true value per parameter (dots: written by the fit, fitted or imprecise; rings: not identified, base value kept; dashes: tolerance)",
            title_font(),
        )?;
        let rows = self.params.len().div_ceil(COLUMNS).max(1);
        let cells = body.split_evenly((rows, COLUMNS));
        for (k, (cell, p)) in cells.iter().zip(self.params).enumerate() {
            let pts = self.points(k);
            let tol = if p.relative() {
                100.0 * p.tolerance()
            } else {
                p.tolerance()
            };
            let (xlo, xhi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, q| {
                (a.0.min(q.0), a.1.max(q.0))
            });
            let (elo, ehi) = pts
                .iter()
                .fold((-tol, tol), |a, q| (a.0.min(q.1), a.1.max(q.1)));
            let (x, y) = (padded(xlo, xhi), padded(elo, ehi));
            let unit = if p.relative() {
                "%".into()
            } else {
                p.unit().to_string()
            };
            let mut chart = ChartBuilder::on(cell)
                .caption(p.name(), title_font())
                .margin(10)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
            xy_mesh(&mut chart, "true value", &format!("error ({unit})"))?;
            for t in [-tol, tol] {
                chart.draw_series(DashedLineSeries::new(
                    [(x.0, t), (x.1, t)],
                    6,
                    4,
                    BLACK.stroke_width(1),
                ))?;
            }
            let colour = palette::series(0);
            chart.draw_series(pts.iter().map(|&(t, e, fitted)| {
                let style = if fitted {
                    colour.filled()
                } else {
                    colour.stroke_width(2)
                };
                Circle::new((t, e), 4, style)
            }))?;
        }
        Ok(())
    }
}

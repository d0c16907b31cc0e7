//! The report of `magbench calibrate`: predicted against observed motion per agent, one row per
//! agent with its x and y over time. Dots are the camera's observations; each line is one
//! segment's prediction by the fitted preset from the segment's first observation.

use plotters::coord::Shift;
use plotters::prelude::*;

use magbench_drivers::fit::SegmentTrace;

use crate::plot::{Figure, PlotError, palette, title_font, xy_mesh};

/// Predicted against observed motion of every agent.
pub struct MotionFigure<'a> {
    traces: &'a [SegmentTrace],
    agents: usize,
}

impl<'a> MotionFigure<'a> {
    /// The figure of `traces` (segments of one run, in order).
    pub fn new(traces: &'a [SegmentTrace]) -> Self {
        let agents = traces
            .first()
            .and_then(|t| t.predicted.first())
            .map_or(0, Vec::len);
        Self { traces, agents }
    }

    /// Time range and the range of coordinate `c` of agent `i` over every trace.
    fn ranges(&self, i: usize, c: usize) -> ((f64, f64), (f64, f64)) {
        let mut t = (f64::INFINITY, f64::NEG_INFINITY);
        let mut v = (f64::INFINITY, f64::NEG_INFINITY);
        for tr in self.traces {
            for (k, &tk) in tr.t.iter().enumerate() {
                t = (t.0.min(tk), t.1.max(tk));
                let p = tr.predicted[k][i];
                let mut vals = vec![p[c]];
                if let Some(o) = tr.observed[k][i] {
                    vals.push(o[c]);
                }
                for x in vals {
                    v = (v.0.min(x), v.1.max(x));
                }
            }
        }
        if t.0.partial_cmp(&t.1) != Some(std::cmp::Ordering::Less) {
            t = (0.0, 1.0);
        }
        let pad = ((v.1 - v.0) * 0.05).max(0.05);
        if !v.0.is_finite() {
            v = (0.0, 1.0);
        }
        (t, (v.0 - pad, v.1 + pad))
    }
}

impl Figure for MotionFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1400, 60 + 320 * self.agents.max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (title, body) = root.split_vertically(60);
        title.titled(
            "Predicted (lines, from each segment's first observation) against observed (dots)",
            title_font(),
        )?;
        if self.agents == 0 {
            return Ok(());
        }
        let cells = body.split_evenly((self.agents, 2));
        for (cell, idx) in cells.iter().zip(0..) {
            let (i, c) = (idx / 2, idx % 2);
            let (t, v) = self.ranges(i, c);
            let axis = ["x", "y"][c];
            let mut chart = ChartBuilder::on(cell)
                .caption(format!("agent {i}: {axis}"), title_font())
                .margin(10)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(t.0..t.1, v.0..v.1)?;
            xy_mesh(&mut chart, "t (s)", &format!("{axis} (BL)"))?;
            let colour = palette::agent(i);
            for tr in self.traces {
                chart.draw_series(
                    tr.t.iter()
                        .zip(&tr.observed)
                        .filter_map(|(&tk, o)| o[i].map(|p| (tk, p[c])))
                        .map(|pt| Circle::new(pt, 2, colour.filled())),
                )?;
                chart.draw_series(LineSeries::new(
                    tr.t.iter().zip(&tr.predicted).map(|(&tk, p)| (tk, p[i][c])),
                    BLACK.stroke_width(2),
                ))?;
            }
        }
        Ok(())
    }
}

//! Grouped horizontal bar charts: one row per category, one bar per series in each row (e.g.
//! each plant term's contribution to the tracking error, measured two ways).

use plotters::coord::Shift;
use plotters::prelude::*;

use super::charts::{Series, rows_chart};
use super::legend::{self, Entry, Symbol};
use super::{Figure, PlotError, palette};

const W: u32 = 900;

/// Grouped horizontal bars; values may be negative (bars grow from zero either way).
#[derive(Debug, Clone, PartialEq)]
pub struct BarChart {
    /// Title.
    pub title: String,
    /// Value axis label with unit.
    pub value_label: String,
    /// Row labels, top to bottom.
    pub categories: Vec<String>,
    /// One series per bar of a row: its legend text and one value per category (NaN: no bar).
    pub series: Vec<Series<Vec<f64>>>,
}

impl BarChart {
    fn entries(&self) -> Vec<Entry> {
        self.series
            .iter()
            .enumerate()
            .map(|(i, s)| Entry::new(Symbol::Band(palette::series(i)), s.label.clone()))
            .collect()
    }

    fn label_width(&self) -> u32 {
        let longest = self
            .categories
            .iter()
            .map(|c| c.chars().count())
            .max()
            .unwrap_or(8);
        ((longest as f64 * 8.4) as u32 + 30).clamp(90, 360)
    }
}

impl Figure for BarChart {
    fn size(&self) -> (u32, u32) {
        let rows = self.categories.len().max(1) as u32;
        let per_row = 14 * self.series.len().max(1) as u32 + 16;
        (W, 110 + rows * per_row + legend::height(&self.entries(), W))
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let entries = self.entries();
        let lh = legend::height(&entries, W);
        let (_, h) = root.dim_in_pixel();
        let (top, bottom) = root.split_vertically(h - lh);
        let n = self.categories.len().max(1);
        let values = self.series.iter().flat_map(|s| s.data.iter().copied());
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let pad = 0.05 * (hi - lo).max(1e-9);
        let (v0, v1) = (lo - if lo < 0.0 { pad } else { 0.0 }, hi + pad);
        let mut c = rows_chart(
            &top,
            &self.title,
            &self.value_label,
            self.categories.clone(),
            self.label_width(),
            plotters::coord::types::RangedCoordf64::from(v0..v1),
        )?;
        let k = self.series.len().max(1) as f64;
        let band = 0.8 / k;
        for (si, s) in self.series.iter().enumerate() {
            let col = palette::series(si);
            c.draw_series(
                s.data
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| v.is_finite())
                    .map(|(ci, &v)| {
                        let y = (n - 1 - ci) as f64 + 0.4 - band * (si as f64 + 0.5);
                        Rectangle::new([(0.0, y - 0.45 * band), (v, y + 0.45 * band)], col.filled())
                    }),
            )?;
        }
        c.draw_series(std::iter::once(PathElement::new(
            vec![(0.0, -0.5), (0.0, n as f64 - 0.5)],
            BLACK.stroke_width(1),
        )))?;
        legend::draw(&bottom, &entries)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_negative_and_missing_bars() {
        let dir = tempfile::tempdir().unwrap();
        let fig = BarChart {
            title: "t".into(),
            value_label: "Δ RMS (BL)".into(),
            categories: vec!["a".into(), "b".into(), "c".into()],
            series: vec![
                Series {
                    label: "off in turn".into(),
                    data: vec![0.1, -0.02, f64::NAN],
                },
                Series {
                    label: "alone".into(),
                    data: vec![0.05, 0.0, 0.2],
                },
            ],
        };
        let files = super::super::save(&fig, &dir.path().join("bars")).unwrap();
        assert!(files.iter().all(|f| f.exists()));
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(
            svg.contains("off in turn") && svg.contains("alone"),
            "legend"
        );
    }
}

//! Statistical charts: lines with confidence bands, horizontal box plots and empirical CDFs.
//! Each is a [`Figure`], written as SVG and PNG by [`super::save`].

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::legend::{self, Entry, Symbol};
use super::{Figure, PlotError, label_font, palette, tick_font, tick_label, title_font};
use crate::stats::quantile::{quantile_sorted, sorted_finite};

/// One point of a line with an optional band `[lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandPoint {
    /// x.
    pub x: f64,
    /// The line's value (NaN: no line here).
    pub y: f64,
    /// Lower edge of the band (NaN: no band here).
    pub lo: f64,
    /// Upper edge of the band.
    pub hi: f64,
}

/// A labelled series.
#[derive(Debug, Clone, PartialEq)]
pub struct Series<T> {
    /// Legend text.
    pub label: String,
    /// Data.
    pub data: T,
}

/// Lines with shaded bands (e.g. success rate with its 95% interval, or a median with its IQR).
#[derive(Debug, Clone, PartialEq)]
pub struct LineBandChart {
    /// Title.
    pub title: String,
    /// x axis label with unit.
    pub x_label: String,
    /// y axis label with unit.
    pub y_label: String,
    /// Series, one colour each.
    pub series: Vec<Series<Vec<BandPoint>>>,
    /// Fixed y range, or `None` to fit the data.
    pub y_range: Option<(f64, f64)>,
    /// Draw lines as steps (value holds until the next x).
    pub steps: bool,
    /// Band legend text (e.g. "95% Wilson interval").
    pub band_label: String,
    /// Text shown in the chart when no series has a line to draw.
    pub empty_note: String,
}

const W: u32 = 900;
const H: u32 = 560;

fn finite_range(vals: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo <= hi).then_some((lo, hi))
}

fn padded((lo, hi): (f64, f64), frac: f64) -> (f64, f64) {
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    (lo - frac * span, hi + frac * span)
}

/// Contiguous runs of points where the band is defined.
fn band_segments(d: &[BandPoint]) -> Vec<Vec<BandPoint>> {
    let mut out: Vec<Vec<BandPoint>> = vec![];
    let mut cur = vec![];
    for p in d {
        if p.lo.is_finite() && p.hi.is_finite() {
            cur.push(*p);
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

fn step_points(d: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = vec![];
    for (i, &(x, y)) in d.iter().enumerate() {
        if i > 0 {
            out.push((x, d[i - 1].1));
        }
        out.push((x, y));
    }
    out
}

/// A tick label on an axis spanning `span`: [`tick_label`], with as many decimals as ticks about
/// a tenth of the span apart need to differ (a narrow range, e.g. 0.124 to 0.130, would
/// otherwise repeat labels).
fn span_tick_label(v: f64, span: f64) -> String {
    let decimals = if span.is_finite() && span > 0.0 {
        (-(span / 10.0).log10()).ceil().clamp(0.0, 9.0) as usize
    } else {
        0
    };
    if decimals <= 3 {
        return tick_label(v);
    }
    let s = format!("{v:.decimals$}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A horizontal chart with one row per label (top to bottom) over the values `v0..v1`: the
/// frame, the value axis and the row labels that box plots and bar charts share.
pub(super) fn rows_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    title: &str,
    value_label: &str,
    labels: Vec<String>,
    label_width: u32,
    (v0, v1): (f64, f64),
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, PlotError> {
    let n = labels.len().max(1);
    let mut c = ChartBuilder::on(area)
        .caption(title, title_font())
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(label_width)
        .build_cartesian_2d(v0..v1, -0.5..n as f64 - 0.5)?;
    c.configure_mesh()
        .disable_y_mesh()
        .x_desc(value_label)
        .axis_desc_style(label_font())
        .label_style(tick_font())
        .x_label_formatter(&|v| span_tick_label(*v, v1 - v0))
        .y_labels(n * 2 + 1)
        .y_label_formatter(&move |v| {
            let i = v.round();
            if (v - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < labels.len() {
                labels[n - 1 - i as usize].clone()
            } else {
                String::new()
            }
        })
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    Ok(c)
}

fn legend_entries<T>(series: &[Series<T>], line_w: u32, band: bool) -> Vec<Entry> {
    series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            Entry::new(
                if band {
                    Symbol::Band(palette::series(i))
                } else {
                    Symbol::Line(palette::series(i), line_w)
                },
                s.label.clone(),
            )
        })
        .collect()
}

impl Figure for LineBandChart {
    fn size(&self) -> (u32, u32) {
        (
            W,
            H + legend::height(&legend_entries(&self.series, 2, true), W),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let mut entries = legend_entries(&self.series, 2, true);
        if !self.band_label.is_empty() {
            entries.push(Entry::new(
                Symbol::Band(RGBColor(120, 120, 120)),
                self.band_label.clone(),
            ));
        }
        let lh = legend::height(&entries, W);
        let (_, h) = root.dim_in_pixel();
        let (top, bottom) = root.split_vertically(h - lh);
        let all = self.series.iter().flat_map(|s| s.data.iter());
        let (x0, x1) = finite_range(all.clone().map(|p| p.x)).unwrap_or((0.0, 1.0));
        let (x0, x1) = if x1 > x0 {
            (x0, x1)
        } else {
            (x0 - 0.5, x0 + 0.5)
        };
        let (y0, y1) = self.y_range.unwrap_or_else(|| {
            padded(
                finite_range(all.flat_map(|p| [p.y, p.lo, p.hi])).unwrap_or((0.0, 1.0)),
                0.05,
            )
        });
        let mut c = ChartBuilder::on(&top)
            .caption(&self.title, title_font())
            .margin(12)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        c.configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .axis_desc_style(label_font())
            .label_style(tick_font())
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .light_line_style(TRANSPARENT)
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;
        let clamp = |v: f64| v.clamp(y0, y1);
        for (i, s) in self.series.iter().enumerate() {
            let col = palette::series(i);
            for seg in band_segments(&s.data) {
                let upper: Vec<(f64, f64)> = seg.iter().map(|p| (p.x, clamp(p.hi))).collect();
                let lower: Vec<(f64, f64)> = seg.iter().map(|p| (p.x, clamp(p.lo))).collect();
                let (mut upper, mut lower) = if self.steps {
                    (step_points(&upper), step_points(&lower))
                } else {
                    (upper, lower)
                };
                lower.reverse();
                upper.extend(lower);
                c.draw_series(std::iter::once(Polygon::new(upper, col.mix(0.18).filled())))?;
            }
        }
        for (i, s) in self.series.iter().enumerate() {
            let col = palette::series(i);
            // Lines break where y is undefined.
            let mut seg: Vec<(f64, f64)> = vec![];
            let mut segs = vec![];
            for p in &s.data {
                if p.y.is_finite() {
                    seg.push((p.x, clamp(p.y)));
                } else if !seg.is_empty() {
                    segs.push(std::mem::take(&mut seg));
                }
            }
            segs.push(seg);
            for seg in segs.into_iter().filter(|s| !s.is_empty()) {
                let pts = if self.steps { step_points(&seg) } else { seg };
                c.draw_series(std::iter::once(PathElement::new(pts, col.stroke_width(2))))?;
            }
        }
        if !self.empty_note.is_empty()
            && self
                .series
                .iter()
                .all(|s| s.data.iter().all(|p| !p.y.is_finite()))
        {
            let style = label_font().pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ));
            c.draw_series(std::iter::once(Text::new(
                self.empty_note.clone(),
                ((x0 + x1) / 2.0, (y0 + y1) / 2.0),
                style,
            )))?;
        }
        legend::draw(&bottom, &entries)
    }
}

/// Horizontal box plots, one per group: box = quartiles, line = median, whiskers to the most
/// extreme values within 1.5 IQR, dots = the values beyond.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxChart {
    /// Title.
    pub title: String,
    /// Value axis label with unit.
    pub value_label: String,
    /// Groups (top to bottom) and their values (non-finite values are left out and counted).
    pub groups: Vec<Series<Vec<f64>>>,
    /// The colour of each group (e.g. one per agent); empty: the series palette in order.
    pub colors: Vec<RGBColor>,
}

impl BoxChart {
    fn label_width(&self) -> u32 {
        let longest = self
            .groups
            .iter()
            .map(|g| g.label.chars().count() + 8)
            .max()
            .unwrap_or(8);
        ((longest as f64 * 8.4) as u32 + 20).clamp(90, 420)
    }
}

impl Figure for BoxChart {
    fn size(&self) -> (u32, u32) {
        (W, 140 + 48 * self.groups.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let n = self.groups.len().max(1);
        let sorted: Vec<Vec<f64>> = self.groups.iter().map(|g| sorted_finite(&g.data)).collect();
        let (v0, v1) = padded(
            finite_range(sorted.iter().flatten().copied()).unwrap_or((0.0, 1.0)),
            0.05,
        );
        let labels: Vec<String> = self
            .groups
            .iter()
            .zip(&sorted)
            .map(|(g, s)| {
                let missing = g.data.len() - s.len();
                if missing > 0 {
                    format!("{} (n={}, {missing} none)", g.label, s.len())
                } else {
                    format!("{} (n={})", g.label, s.len())
                }
            })
            .collect();
        let mut c = rows_chart(
            root,
            &self.title,
            &self.value_label,
            labels,
            self.label_width(),
            (v0, v1),
        )?;
        for (gi, s) in sorted.iter().enumerate() {
            if s.is_empty() {
                continue;
            }
            let y = (n - 1 - gi) as f64;
            let col = self
                .colors
                .get(gi)
                .copied()
                .unwrap_or_else(|| palette::series(gi));
            let (q1, med, q3) = (
                quantile_sorted(s, 0.25),
                quantile_sorted(s, 0.5),
                quantile_sorted(s, 0.75),
            );
            let iqr = q3 - q1;
            let lo = s
                .iter()
                .copied()
                .find(|v| *v >= q1 - 1.5 * iqr)
                .unwrap_or(s[0]);
            let hi = s
                .iter()
                .rev()
                .copied()
                .find(|v| *v <= q3 + 1.5 * iqr)
                .unwrap_or(s[s.len() - 1]);
            let hh = 0.3;
            c.draw_series(std::iter::once(Rectangle::new(
                [(q1, y - hh), (q3, y + hh)],
                col.mix(0.3).filled(),
            )))?;
            c.draw_series(std::iter::once(Rectangle::new(
                [(q1, y - hh), (q3, y + hh)],
                col.stroke_width(2),
            )))?;
            c.draw_series(std::iter::once(PathElement::new(
                vec![(med, y - hh), (med, y + hh)],
                BLACK.stroke_width(3),
            )))?;
            for (a, b) in [(lo, q1), (q3, hi)] {
                c.draw_series(std::iter::once(PathElement::new(
                    vec![(a, y), (b, y)],
                    col.stroke_width(2),
                )))?;
            }
            for w in [lo, hi] {
                c.draw_series(std::iter::once(PathElement::new(
                    vec![(w, y - hh / 2.0), (w, y + hh / 2.0)],
                    col.stroke_width(2),
                )))?;
            }
            c.draw_series(
                s.iter()
                    .filter(|v| **v < lo || **v > hi)
                    .map(|v| Circle::new((*v, y), 3, col.stroke_width(1))),
            )?;
        }
        Ok(())
    }
}

/// Empirical cumulative distribution functions, one step line per series.
#[derive(Debug, Clone, PartialEq)]
pub struct CdfChart {
    /// Title.
    pub title: String,
    /// x axis label with unit.
    pub x_label: String,
    /// Series and their samples.
    pub series: Vec<Series<Vec<f64>>>,
}

impl Figure for CdfChart {
    fn size(&self) -> (u32, u32) {
        (
            W,
            H + legend::height(&legend_entries(&self.series, 2, false), W),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let entries = legend_entries(&self.series, 2, false);
        let lh = legend::height(&entries, W);
        let (_, h) = root.dim_in_pixel();
        let (top, bottom) = root.split_vertically(h - lh);
        let (x0, x1) = padded(
            finite_range(self.series.iter().flat_map(|s| s.data.iter().copied()))
                .unwrap_or((0.0, 1.0)),
            0.03,
        );
        let mut c = ChartBuilder::on(&top)
            .caption(&self.title, title_font())
            .margin(12)
            .x_label_area_size(50)
            .y_label_area_size(75)
            .build_cartesian_2d(x0..x1, 0.0..1.0)?;
        c.configure_mesh()
            .x_desc(&self.x_label)
            .y_desc("fraction of runs ≤ x")
            .axis_desc_style(label_font())
            .label_style(tick_font())
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .light_line_style(TRANSPARENT)
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;
        for (i, s) in self.series.iter().enumerate() {
            let v = sorted_finite(&s.data);
            let n = s.data.len().max(1) as f64;
            let mut pts = vec![(x0, 0.0)];
            for (k, x) in v.iter().enumerate() {
                pts.push((*x, k as f64 / n));
                pts.push((*x, (k + 1) as f64 / n));
            }
            pts.push((x1, v.len() as f64 / n));
            c.draw_series(std::iter::once(PathElement::new(
                pts,
                palette::series(i).stroke_width(2),
            )))?;
        }
        legend::draw(&bottom, &entries)
    }
}

#[cfg(test)]
mod tests {
    use super::span_tick_label;

    #[test]
    fn ticks_of_a_narrow_range_differ() {
        let (v0, v1) = (0.1243, 0.1301);
        let labels: Vec<String> = (0..=10)
            .map(|k| span_tick_label(v0 + (v1 - v0) * k as f64 / 10.0, v1 - v0))
            .collect();
        for w in labels.windows(2) {
            assert_ne!(w[0], w[1], "{labels:?}");
        }
        // a wide range keeps the short labels
        assert_eq!(span_tick_label(0.25, 2.0), "0.25");
        assert_eq!(span_tick_label(3.0, 10.0), "3");
    }
}

//! Statistical charts: lines with confidence bands, horizontal box plots and empirical CDFs.
//! Each is a [`Figure`], written as SVG and PNG by [`super::save`].

use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::legend::{self, Entry, Symbol};
use super::style::{self, Family, Look};
use super::{Figure, PlotError, label_font, tick_font, tick_label, title_font};
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
    /// Each series' look; missing entries take the planners' family in order.
    pub looks: Vec<Look>,
    /// A logarithmic x axis (points with x ≤ 0 are left out).
    pub x_log: bool,
    /// Width (px); the plot area keeps the height of a 900-px figure scaled to this width.
    pub width: u32,
}

/// The width of a screen figure (px).
pub const W: u32 = 900;
const H: u32 = 560;

/// The plot height of a figure `width` px wide: 560 at 900 px, never below 340.
fn plot_height(width: u32) -> u32 {
    (H * width / W).max(340)
}

/// Room right of the plot so the last x tick label (e.g. "20000") is never clipped.
const RIGHT_MARGIN: u32 = 40;

fn look_of(looks: &[Look], i: usize) -> Look {
    looks
        .get(i)
        .copied()
        .unwrap_or_else(|| style::look(Family::Planner, i))
}

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

/// A horizontal chart with one row per label (top to bottom) over the value axis `x` (a
/// linear or logarithmic range): the frame, the value axis and the row labels that box plots
/// and bar charts share.
pub(super) fn rows_chart<'a, DB: DrawingBackend, X>(
    area: &'a DrawingArea<DB, Shift>,
    title: &str,
    value_label: &str,
    labels: Vec<String>,
    label_width: u32,
    x: X,
) -> Result<ChartContext<'a, DB, Cartesian2d<X, RangedCoordf64>>, PlotError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let n = labels.len().max(1);
    let r = x.range();
    let span = r.end - r.start;
    let mut c = ChartBuilder::on(area)
        .caption(title, title_font())
        .margin(12)
        .margin_right(RIGHT_MARGIN)
        .x_label_area_size(50)
        .y_label_area_size(label_width)
        .build_cartesian_2d(x, -0.5..n as f64 - 0.5)?;
    c.configure_mesh()
        .disable_y_mesh()
        .x_desc(value_label)
        .x_labels(8)
        .axis_desc_style(label_font())
        .label_style(tick_font())
        .x_label_formatter(&|v| span_tick_label(*v, span))
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

fn legend_entries<T>(series: &[Series<T>], looks: &[Look], band: bool) -> Vec<Entry> {
    series
        .iter()
        .enumerate()
        .map(|(i, s)| Entry::new(Symbol::Styled(look_of(looks, i), band), s.label.clone()))
        .collect()
}

/// A linear x range, or a logarithmic one over its positive part.
fn x_axis(log: bool, (x0, x1): (f64, f64)) -> XAxis {
    if log {
        let hi = x1.max(1e-300);
        let lo = if x0 > 0.0 { x0 } else { hi / 1e3 };
        XAxis::Log((lo.min(hi / 1.0001)..hi).log_scale().into())
    } else {
        XAxis::Linear((x0..x1).into())
    }
}

enum XAxis {
    Linear(RangedCoordf64),
    Log(LogCoord<f64>),
}

/// Lines with bands and markers on a chart whose x axis is `X`.
fn draw_lines<DB: DrawingBackend, X>(
    chart: &LineBandChart,
    top: &DrawingArea<DB, Shift>,
    x: X,
    (y0, y1): (f64, f64),
) -> Result<(), PlotError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let xr = x.range();
    let mut c = ChartBuilder::on(top)
        .caption(&chart.title, title_font())
        .margin(12)
        .margin_right(RIGHT_MARGIN)
        .x_label_area_size(50)
        .y_label_area_size(75)
        .build_cartesian_2d(x, y0..y1)?;
    c.configure_mesh()
        .x_desc(&chart.x_label)
        .x_labels(8)
        .y_desc(&chart.y_label)
        .axis_desc_style(label_font())
        .label_style(tick_font())
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    let inside = |x: f64| x >= xr.start.min(xr.end) && x <= xr.end.max(xr.start);
    let clamp = |v: f64| v.clamp(y0, y1);
    for (i, s) in chart.series.iter().enumerate() {
        let col = look_of(&chart.looks, i).color;
        for seg in band_segments(&s.data) {
            let seg: Vec<BandPoint> = seg.into_iter().filter(|p| inside(p.x)).collect();
            let upper: Vec<(f64, f64)> = seg.iter().map(|p| (p.x, clamp(p.hi))).collect();
            let lower: Vec<(f64, f64)> = seg.iter().map(|p| (p.x, clamp(p.lo))).collect();
            let (upper, lower) = if chart.steps {
                (step_points(&upper), step_points(&lower))
            } else {
                (upper, lower)
            };
            // A light fill to read the other series through, and thin edges to tell the
            // bands apart where they overlap.
            let mut poly = upper.clone();
            poly.extend(lower.iter().rev());
            c.draw_series(std::iter::once(Polygon::new(poly, col.mix(0.08).filled())))?;
            for edge in [upper, lower] {
                c.draw_series(std::iter::once(PathElement::new(
                    edge,
                    col.mix(0.45).stroke_width(1),
                )))?;
            }
        }
    }
    let n = chart.series.len().max(1);
    for (i, s) in chart.series.iter().enumerate() {
        let look = look_of(&chart.looks, i);
        // Lines break where y is undefined.
        let mut seg: Vec<(f64, f64)> = vec![];
        let mut segs = vec![];
        for p in s.data.iter().filter(|p| inside(p.x)) {
            if p.y.is_finite() {
                seg.push((p.x, clamp(p.y)));
            } else if !seg.is_empty() {
                segs.push(std::mem::take(&mut seg));
            }
        }
        segs.push(seg);
        let mut points = vec![];
        for seg in segs.into_iter().filter(|s| !s.is_empty()) {
            points.extend(seg.iter().copied());
            let pts = if chart.steps { step_points(&seg) } else { seg };
            let px: Vec<(i32, i32)> = pts.iter().map(|p| c.backend_coord(p)).collect();
            style::draw_line(top, px, &look, 2)?;
        }
        // Markers every `every` points, staggered by series so coinciding lines show all.
        let every = (points.len() / 8).max(1);
        let offset = i * every / n;
        for p in points.iter().skip(offset).step_by(every) {
            style::draw_marker(top, c.backend_coord(p), &look, 4)?;
        }
    }
    if !chart.empty_note.is_empty()
        && chart
            .series
            .iter()
            .all(|s| s.data.iter().all(|p| !p.y.is_finite()))
    {
        let style = label_font().pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
        let (w, h) = top.dim_in_pixel();
        top.draw(&Text::new(
            chart.empty_note.clone(),
            (w as i32 / 2, h as i32 / 2),
            style,
        ))?;
    }
    Ok(())
}

impl LineBandChart {
    fn entries(&self) -> Vec<Entry> {
        let mut entries = legend_entries(&self.series, &self.looks, false);
        if !self.band_label.is_empty() {
            entries.push(Entry::new(
                Symbol::Band(RGBColor(120, 120, 120)),
                self.band_label.clone(),
            ));
        }
        entries
    }
}

impl Figure for LineBandChart {
    fn size(&self) -> (u32, u32) {
        let w = self.width;
        (w, plot_height(w) + legend::height(&self.entries(), w))
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let entries = self.entries();
        let (w, h) = root.dim_in_pixel();
        let lh = legend::height(&entries, w);
        let (top, bottom) = root.split_vertically(h - lh);
        let all = self.series.iter().flat_map(|s| s.data.iter());
        let xs = all.clone().map(|p| p.x).filter(|x| !self.x_log || *x > 0.0);
        let (x0, x1) = finite_range(xs).unwrap_or((0.0, 1.0));
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
        match x_axis(self.x_log, (x0, x1)) {
            XAxis::Linear(x) => draw_lines(self, &top, x, (y0, y1))?,
            XAxis::Log(x) => draw_lines(self, &top, x, (y0, y1))?,
        }
        legend::draw(&bottom, &entries)
    }
}

/// Horizontal box plots, one per group: box = quartiles, line = median, whiskers to the most
/// extreme values within 1.5 IQR, and every value as a dot (jittered across the row); a group
/// of more than [`BOX_DOTS`] values draws that many of them, at evenly spread ranks.
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
    /// A logarithmic value axis (values ≤ 0 are left out and counted).
    pub log: bool,
    /// Width (px).
    pub width: u32,
}

impl BoxChart {
    fn label_width(&self) -> u32 {
        let longest = self
            .groups
            .iter()
            .map(|g| g.label.chars().count() + 8)
            .max()
            .unwrap_or(8);
        ((longest as f64 * 8.4) as u32 + 20).clamp(90, (self.width / 2).max(90))
    }

    /// The values drawn in each group, sorted (finite, and positive on a log axis).
    fn drawn(&self) -> Vec<Vec<f64>> {
        self.groups
            .iter()
            .map(|g| {
                let mut v = sorted_finite(&g.data);
                if self.log {
                    v.retain(|x| *x > 0.0);
                }
                v
            })
            .collect()
    }
}

/// A box plot's group of more values than this draws this many as dots, at ranks spread evenly
/// from the smallest to the largest, so that a figure's size does not grow with its runs.
pub const BOX_DOTS: usize = 2_000;

/// The ranks of the values of a sorted group of `n` drawn as dots: all of them, or
/// [`BOX_DOTS`] spread evenly from the first to the last.
fn dot_ranks(n: usize) -> impl Iterator<Item = usize> {
    let drawn = n.min(BOX_DOTS);
    (0..drawn).map(move |i| {
        if drawn == n {
            i
        } else {
            i * (n - 1) / (drawn - 1)
        }
    })
}

/// A deterministic jitter in [-1, 1] for the `k`-th dot of a row (a golden-ratio sequence).
fn jitter(k: usize) -> f64 {
    let f = (k as f64 * 0.618_033_988_749_895).fract();
    2.0 * f - 1.0
}

fn draw_boxes<DB: DrawingBackend, X>(
    chart: &BoxChart,
    root: &DrawingArea<DB, Shift>,
    x: X,
    sorted: &[Vec<f64>],
    labels: Vec<String>,
) -> Result<(), PlotError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let n = chart.groups.len().max(1);
    let mut c = rows_chart(
        root,
        &chart.title,
        &chart.value_label,
        labels,
        chart.label_width(),
        x,
    )?;
    for (gi, s) in sorted.iter().enumerate() {
        if s.is_empty() {
            continue;
        }
        let y = (n - 1 - gi) as f64;
        let col = chart
            .colors
            .get(gi)
            .copied()
            .unwrap_or_else(|| style::look(Family::Planner, gi).color);
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
            col.mix(0.15).filled(),
        )))?;
        c.draw_series(std::iter::once(Rectangle::new(
            [(q1, y - hh), (q3, y + hh)],
            col.stroke_width(2),
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
        // Every run as a dot (or BOX_DOTS of them): filled inside the whiskers, hollow beyond.
        c.draw_series(dot_ranks(s.len()).enumerate().map(|(k, rank)| {
            let v = &s[rank];
            let style = if *v < lo || *v > hi {
                col.stroke_width(1)
            } else {
                col.mix(0.55).filled()
            };
            Circle::new((*v, y + 0.22 * jitter(k)), 3, style)
        }))?;
        c.draw_series(std::iter::once(PathElement::new(
            vec![(med, y - hh), (med, y + hh)],
            BLACK.stroke_width(3),
        )))?;
    }
    Ok(())
}

impl Figure for BoxChart {
    fn size(&self) -> (u32, u32) {
        (self.width, 140 + 48 * self.groups.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let sorted = self.drawn();
        let labels: Vec<String> = self
            .groups
            .iter()
            .zip(&sorted)
            .map(|(g, s)| {
                let missing = g.data.len() - s.len();
                let drawn = if s.len() > BOX_DOTS {
                    format!(", {BOX_DOTS} dots")
                } else {
                    String::new()
                };
                if missing > 0 {
                    format!("{} (n={}, {missing} none{drawn})", g.label, s.len())
                } else {
                    format!("{} (n={}{drawn})", g.label, s.len())
                }
            })
            .collect();
        let range = finite_range(sorted.iter().flatten().copied()).unwrap_or((0.0, 1.0));
        if self.log {
            let (lo, hi) = (range.0.max(1e-300), range.1.max(1e-300));
            let (lo, hi) = if hi > lo {
                (lo, hi)
            } else {
                (lo / 2.0, lo * 2.0)
            };
            let x: LogCoord<f64> = ((lo / 1.25)..(hi * 1.25)).log_scale().into();
            draw_boxes(self, root, x, &sorted, labels)
        } else {
            let (v0, v1) = padded(range, 0.05);
            let x: RangedCoordf64 = (v0..v1).into();
            draw_boxes(self, root, x, &sorted, labels)
        }
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
    /// Each series' look; missing entries take the planners' family in order.
    pub looks: Vec<Look>,
    /// Width (px).
    pub width: u32,
}

impl Figure for CdfChart {
    fn size(&self) -> (u32, u32) {
        let w = self.width;
        (
            w,
            plot_height(w) + legend::height(&legend_entries(&self.series, &self.looks, false), w),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let entries = legend_entries(&self.series, &self.looks, false);
        let (w, h) = root.dim_in_pixel();
        let lh = legend::height(&entries, w);
        let (top, bottom) = root.split_vertically(h - lh);
        let (x0, x1) = padded(
            finite_range(self.series.iter().flat_map(|s| s.data.iter().copied()))
                .unwrap_or((0.0, 1.0)),
            0.03,
        );
        let mut c = ChartBuilder::on(&top)
            .caption(&self.title, title_font())
            .margin(12)
            .margin_right(RIGHT_MARGIN)
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
        let n_series = self.series.len().max(1);
        for (i, s) in self.series.iter().enumerate() {
            let look = look_of(&self.looks, i);
            let v = sorted_finite(&s.data);
            let n = s.data.len().max(1) as f64;
            let mut pts = vec![(x0, 0.0)];
            for (k, x) in v.iter().enumerate() {
                pts.push((*x, k as f64 / n));
                pts.push((*x, (k + 1) as f64 / n));
            }
            pts.push((x1, v.len() as f64 / n));
            let px: Vec<(i32, i32)> = pts.iter().map(|p| c.backend_coord(p)).collect();
            style::draw_line(&top, px, &look, 2)?;
            let every = (v.len() / 6).max(1);
            let offset = i * every / n_series;
            for (k, x) in v.iter().enumerate().skip(offset).step_by(every) {
                let p = (*x, (k + 1) as f64 / n);
                style::draw_marker(&top, c.backend_coord(&p), &look, 4)?;
            }
        }
        legend::draw(&bottom, &entries)
    }
}

#[cfg(test)]
mod tests {
    use super::{BOX_DOTS, dot_ranks, span_tick_label};

    #[test]
    fn a_large_box_draws_its_extremes_and_evenly_spread_ranks() {
        assert_eq!(dot_ranks(5).collect::<Vec<_>>(), [0, 1, 2, 3, 4]);
        let r: Vec<usize> = dot_ranks(1_000_000).collect();
        assert_eq!(r.len(), BOX_DOTS);
        assert_eq!((r[0], r[BOX_DOTS - 1]), (0, 999_999));
        assert!(r.windows(2).all(|w| w[1] > w[0]));
        let gaps: Vec<usize> = r.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().max().unwrap() - gaps.iter().min().unwrap() <= 1);
    }

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

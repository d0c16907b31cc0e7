//! Figure output options: the size preset (screen, one or two journal columns), the PNG's
//! resolution, the axis scale and whether a PDF is written; and the conversions from the SVG
//! every figure is drawn into: PNG at any DPI (resvg) and PDF (svg2pdf), both with the
//! embedded font, so the three files show the same figure. The conversions need the `print`
//! feature; without it, [`FigureOptions::needs_print`] names the option that asks for one.

use crate::units::Units;
use magbench_env::input::Bound;
use std::path::Path;
#[cfg(feature = "print")]
use std::sync::Arc;

use super::PlotError;

/// A figure size preset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum SizePreset {
    /// 900 px wide, for the report and a screen.
    #[default]
    Screen,
    /// 3.5 in (89 mm) wide, a journal's single column; text about 9 pt.
    OneColumn,
    /// 7.16 in (182 mm) wide, a journal's full page width; text about 9 pt.
    TwoColumn,
}

impl SizePreset {
    /// The width the figure is laid out in (px, the SVG's user units): the fonts keep their
    /// size in these units, so a narrower layout makes larger text on paper.
    pub fn layout_width(self) -> u32 {
        match self {
            SizePreset::Screen => 900,
            SizePreset::OneColumn => 560,
            SizePreset::TwoColumn => 1100,
        }
    }

    /// The printed width (in), or `None` for the screen preset.
    pub fn inches(self) -> Option<f64> {
        match self {
            SizePreset::Screen => None,
            SizePreset::OneColumn => Some(3.5),
            SizePreset::TwoColumn => Some(7.16),
        }
    }
}

/// Linear or logarithmic axes for quantities such as iterations and times.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum AxisScale {
    /// Logarithmic when the positive values span more than a decade, linear otherwise.
    #[default]
    Auto,
    /// Always linear.
    Linear,
    /// Always logarithmic (values ≤ 0 are left out).
    Log,
}

impl AxisScale {
    /// Whether an axis holding `values` is drawn logarithmic.
    pub fn is_log(self, values: impl IntoIterator<Item = f64>) -> bool {
        match self {
            AxisScale::Linear => false,
            AxisScale::Log => true,
            AxisScale::Auto => {
                let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
                for v in values.into_iter().filter(|v| v.is_finite() && *v > 0.0) {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
                lo.is_finite() && hi > 10.0 * lo
            }
        }
    }
}

/// `--dpi`: the column presets' PNG resolution.
pub const DPI: Bound = Bound::closed(
    50.0,
    1200.0,
    " dpi",
    "below 50 dpi a column figure's text is unreadable; at 1200 dpi a two-column figure is already 8592 px wide",
);

/// How figures are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::Args)]
pub struct FigureOptions {
    /// Figure size: screen (900 px), one-column (3.5 in) or two-column (7.16 in).
    #[arg(long = "figure-size", value_enum, default_value_t = SizePreset::Screen)]
    pub size: SizePreset,
    /// Resolution of the PNGs of the one- and two-column presets (dots per inch).
    #[arg(long, default_value_t = 300)]
    pub dpi: u32,
    /// Axes of iterations and times: log when they span more than a decade (auto), linear or
    /// log.
    #[arg(long, value_enum, default_value_t = AxisScale::Auto)]
    pub axes: AxisScale,
    /// Also write each figure as PDF.
    #[arg(long)]
    pub pdf: bool,
    /// Lengths in body lengths (bl) or in µm and mm/s from each scenario's agent diameter
    /// (physical), in the report and the plots.
    #[arg(long, value_enum, default_value_t = Units::Bl)]
    pub units: Units,
}

impl Default for FigureOptions {
    fn default() -> Self {
        FigureOptions {
            size: SizePreset::Screen,
            dpi: 300,
            axes: AxisScale::Auto,
            pdf: false,
            units: Units::Bl,
        }
    }
}

impl FigureOptions {
    /// The option that asks for a conversion of the `print` feature (a column size preset or
    /// `--pdf`), if any.
    pub fn needs_print(&self) -> Option<&'static str> {
        if self.size.inches().is_some() {
            Some("--figure-size")
        } else if self.pdf {
            Some("--pdf")
        } else {
            None
        }
    }

    /// Refuses, naming the option, what this build cannot write: a column preset or a PDF
    /// without the `print` feature.
    pub fn check_build(&self) -> Result<(), (&'static str, String)> {
        match self.needs_print() {
            Some(option) if !cfg!(feature = "print") => Err((option, print_refusal())),
            _ => Ok(()),
        }
    }
}

/// Why a print figure cannot be written by a build without the `print` feature, and how to
/// get one that can.
pub fn print_refusal() -> String {
    "print figures (the column presets and PDF) need magbench built with the `print` feature: \
     `cargo run --release -p magbench --features print -- …` or \
     `cargo install --path cli --features print`"
        .to_string()
}

#[cfg(feature = "print")]
fn usvg_options() -> usvg::Options<'static> {
    let mut db = usvg::fontdb::Database::new();
    db.load_font_data(super::font::DEJAVU_SANS.to_vec());
    db.set_sans_serif_family("DejaVu Sans");
    db.set_serif_family("DejaVu Sans");
    db.set_monospace_family("DejaVu Sans");
    usvg::Options {
        fontdb: Arc::new(db),
        ..usvg::Options::default()
    }
}

#[cfg(feature = "print")]
fn parse(svg: &str) -> Result<usvg::Tree, PlotError> {
    usvg::Tree::from_str(svg, &usvg_options()).map_err(|e| PlotError(format!("SVG: {e}")))
}

/// Gives the SVG text a printed size of `inches` wide (its user units unchanged).
pub fn with_print_size(svg: &str, inches: f64) -> String {
    let Some(start) = svg.find("<svg") else {
        return svg.to_string();
    };
    let end = start + svg[start..].find('>').unwrap_or(0);
    let head = &svg[start..end];
    let attr = |name: &str| -> Option<f64> {
        let at = head.find(&format!(" {name}=\""))? + name.len() + 3;
        head[at..].split('"').next()?.parse().ok()
    };
    let (Some(w), Some(h)) = (attr("width"), attr("height")) else {
        return svg.to_string();
    };
    let new_head = head
        .replacen(
            &format!(" width=\"{w}\""),
            &format!(" width=\"{inches:.3}in\""),
            1,
        )
        .replacen(
            &format!(" height=\"{h}\""),
            &format!(" height=\"{:.3}in\"", inches * h / w),
            1,
        );
    format!("{}{new_head}{}", &svg[..start], &svg[end..])
}

/// Renders the SVG text into a PNG `width_px` wide.
#[cfg(feature = "print")]
pub fn svg_to_png(svg: &str, width_px: u32, out: &Path) -> Result<(), PlotError> {
    let tree = parse(svg)?;
    let size = tree.size();
    let scale = width_px as f32 / size.width();
    let h = (size.height() * scale).ceil() as u32;
    let mut pixmap = resvg::tiny_skia::Pixmap::new(width_px, h.max(1))
        .ok_or_else(|| PlotError(format!("PNG of {width_px}×{h} px")))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .save_png(out)
        .map_err(|e| PlotError(format!("{}: {e}", out.display())))
}

/// Converts the SVG text into a PDF page `inches` wide (the SVG's own size at 72 user units
/// per inch when `None`).
#[cfg(feature = "print")]
pub fn svg_to_pdf(svg: &str, inches: Option<f64>, out: &Path) -> Result<(), PlotError> {
    let tree = parse(svg)?;
    let dpi = match inches {
        Some(i) => (tree.size().width() as f64 / i) as f32,
        None => 72.0,
    };
    let pdf = svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi },
    )
    .map_err(|e| PlotError(format!("PDF: {e}")))?;
    std::fs::write(out, pdf).map_err(|e| PlotError(format!("{}: {e}", out.display())))
}

/// Without the `print` feature: refuses with [`print_refusal`].
#[cfg(not(feature = "print"))]
pub fn svg_to_png(_svg: &str, _width_px: u32, _out: &Path) -> Result<(), PlotError> {
    Err(PlotError(print_refusal()))
}

/// Without the `print` feature: refuses with [`print_refusal`].
#[cfg(not(feature = "print"))]
pub fn svg_to_pdf(_svg: &str, _inches: Option<f64>, _out: &Path) -> Result<(), PlotError> {
    Err(PlotError(print_refusal()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_is_log_only_beyond_a_decade() {
        assert!(AxisScale::Auto.is_log([0.0, 50.0, 20000.0]));
        assert!(!AxisScale::Auto.is_log([2.0, 19.0]));
        assert!(!AxisScale::Auto.is_log([0.0, f64::NAN]));
        assert!(AxisScale::Log.is_log([2.0, 3.0]));
        assert!(!AxisScale::Linear.is_log([1.0, 1e6]));
    }

    #[test]
    fn the_options_that_need_print_are_named() {
        let mut o = FigureOptions::default();
        assert_eq!(o.needs_print(), None);
        assert_eq!(o.check_build(), Ok(()));
        o.pdf = true;
        assert_eq!(o.needs_print(), Some("--pdf"));
        o.size = SizePreset::OneColumn;
        assert_eq!(o.needs_print(), Some("--figure-size"));
        let refused = o.check_build().err();
        assert_eq!(refused.is_none(), cfg!(feature = "print"));
        if let Some((option, why)) = refused {
            assert_eq!(option, "--figure-size");
            assert!(why.contains("--features print"), "{why}");
        }
    }

    #[test]
    fn print_size_keeps_the_view_box() {
        let s = "<?xml?>\n<svg width=\"900\" height=\"450\" viewBox=\"0 0 900 450\" xmlns=\"x\">";
        let t = with_print_size(s, 3.5);
        assert!(
            t.contains("width=\"3.500in\" height=\"1.750in\" viewBox=\"0 0 900 450\""),
            "{t}"
        );
    }
}

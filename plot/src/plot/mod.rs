//! Plots: every figure is written as `STEM.svg` (vector) and `STEM.png` (bitmap), and with
//! [`export::FigureOptions::pdf`] as `STEM.pdf`.
//!
//! Text is rendered with an embedded DejaVu Sans ([`font`]), so PNGs carry their labels on a
//! machine without system fonts. A figure implements [`Figure`] once, generically over the
//! plotters backend, and [`save`] draws it into the files ([`save_with`] at a size preset).
//!
//! - [`world`]: the world map (walls, obstacles, tree, planned and tracked paths, starts, goals);
//! - [`anim`]: an animated GIF of agents moving over a world map;
//! - [`bars`]: grouped horizontal bar charts (the ablation's contributions);
//! - [`grid`]: panels of shaded cell tables (the formation study);
//! - [`legend`]: a legend strip drawn under a chart;
//! - [`palette`]: one colour per agent, and the planners' and trackers' colour families;
//! - [`style`]: a series' colour, dash and marker;
//! - [`export`]: size presets, axis scales, PNG at any DPI and PDF from the SVG;
//! - [`png`]: a figure at its own size as a PNG.

pub mod anim;
pub mod bars;
pub mod charts;
pub mod export;
pub mod font;
pub mod grid;
pub mod legend;
pub mod palette;
pub mod png;
pub mod style;
pub mod world;

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Why a figure could not be drawn or written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError(e.to_string())
    }
}

impl From<std::io::Error> for PlotError {
    fn from(e: std::io::Error) -> Self {
        PlotError(e.to_string())
    }
}

/// A figure that can be drawn on any plotters backend.
pub trait Figure {
    /// Size in pixels (the SVG uses the same numbers as its user units).
    fn size(&self) -> (u32, u32);
    /// Draws the figure on `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// Draws `fig` into `STEM.svg` and `STEM.png` (creating the folder) and returns both paths.
pub fn save<F: Figure + ?Sized>(fig: &F, out_stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    save_with(fig, out_stem, &export::FigureOptions::default())
}

/// Draws `fig` into `STEM.svg`, `STEM.png` and, if asked, `STEM.pdf` (creating the folder)
/// and returns the paths. The screen preset draws the PNG directly at the figure's size; the
/// column presets give the SVG and PDF their printed width and render the PNG from the SVG at
/// `opts.dpi`.
pub fn save_with<F: Figure + ?Sized>(
    fig: &F,
    out_stem: &Path,
    opts: &export::FigureOptions,
) -> Result<Vec<PathBuf>, PlotError> {
    font::ensure_registered();
    if let Some(dir) = out_stem.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let svg_path = with_ext(out_stem, "svg");
    let png_path = with_ext(out_stem, "png");
    let size = fig.size();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE)?;
        fig.draw(&root)?;
        root.present()?;
    }
    let inches = opts.size.inches();
    if let Some(i) = inches {
        svg = export::with_print_size(&svg, i);
    }
    std::fs::write(&svg_path, &svg)?;
    match inches {
        Some(i) => export::svg_to_png(&svg, (i * opts.dpi as f64).round() as u32, &png_path)?,
        None => png::save_png(fig, &png_path)?,
    }
    let mut files = vec![svg_path, png_path];
    if opts.pdf {
        let pdf = with_ext(out_stem, "pdf");
        export::svg_to_pdf(&svg, inches, &pdf)?;
        files.push(pdf);
    }
    Ok(files)
}

/// `stem` with `.ext` appended (keeps dots already in the stem, e.g. `goal-zoom-rrt{k=5}`).
pub fn with_ext(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// The text style of axis labels and legends.
pub fn label_font() -> TextStyle<'static> {
    ("sans-serif", 18).into_font().color(&BLACK)
}

/// The text style of tick labels.
pub fn tick_font() -> TextStyle<'static> {
    ("sans-serif", 15).into_font().color(&BLACK)
}

/// The text style of titles.
pub fn title_font() -> TextStyle<'static> {
    ("sans-serif", 22).into_font().color(&BLACK)
}

/// The axes of an x–y figure: both axis titles, tick labels and a light grid.
pub fn xy_mesh<DB: DrawingBackend>(
    c: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x_desc: &str,
    y_desc: &str,
) -> Result<(), PlotError> {
    c.configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style(label_font())
        .label_style(tick_font())
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    Ok(())
}

/// A tick label: integers without decimals, other values with up to 3 significant decimals.
pub fn tick_label(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) {
        format!("{}", v.round() as i64)
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

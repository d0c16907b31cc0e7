//! The scenario preview of `magbench scenario show --out`: every leg's map side by side with
//! its start (agents drawn to scale), its goal regions and the pair's proximity range.

use std::path::Path;

use magbench_env::{Scenario, Vec2};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::Error;
use crate::plot::legend::{self, Entry, Symbol};
use crate::plot::world::{chart, circle_points, draw_goals, draw_world, map_size};
use crate::plot::{Figure, PlotError, font, palette};

/// Width of one leg's panel (px).
const PANEL_PX: u32 = 560;
/// Most panels in one row.
const PER_ROW: usize = 3;
/// The colour of the proximity range.
const RANGE: RGBColor = RGBColor(120, 120, 120);

/// The preview of a scenario.
pub struct ScenarioPreview<'a> {
    /// The scenario.
    pub scenario: &'a Scenario,
}

impl ScenarioPreview<'_> {
    fn grid(&self) -> (usize, usize) {
        let legs = self.scenario.legs.len();
        let cols = legs.min(PER_ROW);
        (cols, legs.div_ceil(cols))
    }

    fn panel(&self) -> (u32, u32) {
        let s = self.scenario;
        // every panel as tall as the tallest leg's map
        (0..s.legs.len())
            .map(|k| map_size(&s.world_for_leg(k), PANEL_PX, true, 0))
            .fold((PANEL_PX, 0), |(w, h), (_, ph)| (w, h.max(ph)))
    }

    fn entries(&self) -> Vec<Entry> {
        let s = self.scenario;
        let mut e: Vec<Entry> = (0..s.agents())
            .map(|i| Entry::new(Symbol::Disk(palette::agent(i)), format!("agent {}", i + 1)))
            .collect();
        e.push(Entry::new(
            Symbol::Circle(RGBColor(60, 60, 60)),
            "goal ± tolerance",
        ));
        if s.agents() > 1 {
            e.push(Entry::new(
                Symbol::Line(RANGE, 1),
                format!(
                    "pair range {}–{} BL around agent 1",
                    s.physics.r_min, s.physics.r_max
                ),
            ));
        }
        e
    }

    fn width(&self) -> u32 {
        self.grid().0 as u32 * PANEL_PX
    }
}

/// The team's position at the start of leg `k`: the scenario's start, then each earlier
/// leg's goal centres.
fn leg_start(s: &Scenario, k: usize) -> Vec<Vec2> {
    if k == 0 {
        s.start.clone()
    } else {
        s.legs[k - 1].goal.agents.clone()
    }
}

impl Figure for ScenarioPreview<'_> {
    fn size(&self) -> (u32, u32) {
        let (_, rows) = self.grid();
        let (_, ph) = self.panel();
        let lh = legend::height(&self.entries(), self.width());
        (self.width(), rows as u32 * ph + lh)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let s = self.scenario;
        let entries = self.entries();
        let (_, h) = root.dim_in_pixel();
        let lh = legend::height(&entries, self.width());
        let (top, bottom) = root.split_vertically(h - lh);
        let (cols, rows) = self.grid();
        let panels = top.split_evenly((rows, cols));
        for (k, area) in panels.iter().enumerate().take(s.legs.len()) {
            let world = s.world_for_leg(k);
            let title = if s.legs.len() > 1 {
                format!("{} · leg {}", s.name, k + 1)
            } else {
                s.name.clone()
            };
            let mut c = chart(area, &world, Some(&title))?;
            draw_world(&mut c, &world)?;
            draw_goals(&mut c, std::slice::from_ref(&s.legs[k].goal))?;
            let start = leg_start(s, k);
            if start.len() > 1 {
                for r in [s.physics.r_min, s.physics.r_max] {
                    c.draw_series(std::iter::once(PathElement::new(
                        circle_points(start[0], r, 96),
                        RANGE.stroke_width(1),
                    )))?;
                }
            }
            for (i, p) in start.iter().enumerate() {
                c.draw_series(std::iter::once(Polygon::new(
                    circle_points(*p, 0.5, 32),
                    palette::agent(i).filled(),
                )))?;
            }
        }
        legend::draw(&bottom, &entries)
    }
}

/// Writes the preview of `s` to `path`: SVG or PNG by its extension (`option` names the
/// command-line option in errors).
pub fn write(s: &Scenario, path: &Path, option: &str) -> Result<(), Error> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let fig = ScenarioPreview { scenario: s };
    font::ensure_registered();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::Failed(format!("{}: {e}", dir.display())))?;
    }
    let size = fig.size();
    let drawn: Result<(), PlotError> = match ext.as_deref() {
        Some("svg") => (|| {
            let root = SVGBackend::new(path, size).into_drawing_area();
            root.fill(&WHITE)?;
            fig.draw(&root)?;
            root.present()?;
            Ok(())
        })(),
        Some("png") => crate::plot::png::save_png(&fig, path),
        _ => {
            return Err(Error::arg(
                option,
                format!("{}: the file must end in .svg or .png", path.display()),
            ));
        }
    };
    drawn.map_err(|e| Error::Failed(format!("{}: {e}", path.display())))
}

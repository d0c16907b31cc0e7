//! The world map: walls, obstacles, an optional tree, planned and tracked paths, starts and
//! goals, in BL with equal axis scales.
//!
//! [`render`] writes a [`WorldPlot`] as SVG and PNG. The building blocks ([`chart`],
//! [`draw_world`], [`draw_starts`], [`draw_goals`], [`draw_path`]) are public so that other
//! figures can put a world map in one of their panels.

use std::path::{Path, PathBuf};

use magbench_env::{Goal, Obstacle, Scenario, Vec2, World};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor;

use super::legend::{self, Entry, Symbol};
use super::{Figure, PlotError, label_font, palette, tick_font, title_font};

/// A chart whose data coordinates are world coordinates (BL).
pub type WorldChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Everything drawn on a world map. Paths are polylines in BL, one per agent.
#[derive(Debug, Clone)]
pub struct WorldPlot<'a> {
    /// The world: its rectangle's edges are drawn as walls, its obstacles filled grey.
    pub world: &'a World,
    /// Tree edges (thin grey), e.g. a planner's search tree projected on one agent.
    pub tree: Vec<(Vec2, Vec2)>,
    /// Planned path of each agent (one colour per agent).
    pub planned: Vec<Vec<Vec2>>,
    /// Tracked (executed) path of each agent (black).
    pub tracked: Vec<Vec<Vec2>>,
    /// Start position of each agent (squares of side 1 BL).
    pub starts: Vec<Vec2>,
    /// Goal regions, one per leg (centres with tolerance circles).
    pub goals: Vec<Goal>,
    /// Title above the map.
    pub title: Option<String>,
    /// Width of the figure in pixels (the height follows the world's aspect).
    pub width_px: u32,
}

impl<'a> WorldPlot<'a> {
    /// An empty map of `world`.
    pub fn new(world: &'a World) -> Self {
        WorldPlot {
            world,
            tree: vec![],
            planned: vec![],
            tracked: vec![],
            starts: vec![],
            goals: vec![],
            title: None,
            width_px: 1000,
        }
    }

    /// The map of a scenario's first world with its start and every leg's goal.
    pub fn scenario(s: &'a Scenario) -> Self {
        let mut p = WorldPlot::new(&s.world);
        p.starts = s.start.clone();
        p.goals = s.legs.iter().map(|l| l.goal.clone()).collect();
        p.title = Some(s.name.clone());
        p
    }

    /// The number of agents shown (the most of starts, goals and paths).
    pub fn agents(&self) -> usize {
        let g = self.goals.iter().map(|g| g.agents.len()).max().unwrap_or(0);
        self.starts
            .len()
            .max(g)
            .max(self.planned.len())
            .max(self.tracked.len())
    }

    fn legend_entries(&self) -> Vec<Entry> {
        let mut e = vec![];
        for i in 0..self.agents() {
            let c = palette::agent(i);
            let what = if self.planned.get(i).is_some_and(|p| p.len() > 1) {
                " planned"
            } else {
                ""
            };
            e.push(Entry::new(
                Symbol::Line(c, 3),
                format!("agent {}{what}", i + 1),
            ));
        }
        if self.tracked.iter().any(|p| p.len() > 1) {
            e.push(Entry::new(Symbol::Line(palette::TRACKED, 1), "tracked"));
        }
        if !self.tree.is_empty() {
            e.push(Entry::new(Symbol::Line(palette::TREE, 1), "tree"));
        }
        if !self.starts.is_empty() {
            e.push(Entry::new(Symbol::Square(RGBColor(60, 60, 60)), "start"));
        }
        if !self.goals.is_empty() {
            e.push(Entry::new(
                Symbol::Circle(RGBColor(60, 60, 60)),
                "goal ± tolerance",
            ));
        }
        e
    }
}

/// Margin around the world rectangle (BL).
const MARGIN_BL: f64 = 0.8;
const LEFT_PX: u32 = 75;
const RIGHT_PX: u32 = 25;
const BOTTOM_PX: u32 = 55;

/// The pixel size of a map of `world` `width_px` wide, with a title and `legend_px` of legend.
pub fn map_size(world: &World, width_px: u32, title: bool, legend_px: u32) -> (u32, u32) {
    let top = if title { 45 } else { 15 };
    let plot_w = width_px.saturating_sub(LEFT_PX + RIGHT_PX + 8).max(100) as f64;
    let aspect = (world.height + 2.0 * MARGIN_BL) / (world.width + 2.0 * MARGIN_BL);
    let plot_h = (plot_w * aspect).round() as u32;
    (width_px, plot_h + top + BOTTOM_PX + legend_px)
}

/// A chart over `world` (plus a small margin) with axes in BL; equal scales if `area` was sized
/// by [`map_size`].
pub fn chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    world: &World,
    title: Option<&str>,
) -> Result<WorldChart<'a, DB>, PlotError> {
    let mut b = ChartBuilder::on(area);
    b.margin_left(8)
        .margin_right(RIGHT_PX)
        .margin_top(if title.is_some() { 8 } else { 15 });
    b.x_label_area_size(BOTTOM_PX).y_label_area_size(LEFT_PX);
    if let Some(t) = title {
        b.caption(t, title_font());
    }
    // Expand the shorter data range so that one BL spans as many pixels along x as along y.
    let (aw, ah) = area.dim_in_pixel();
    let top = if title.is_some() { 45 } else { 15 };
    let px_w = aw.saturating_sub(LEFT_PX + RIGHT_PX + 8).max(1) as f64;
    let px_h = ah.saturating_sub(top + BOTTOM_PX).max(1) as f64;
    let (mut xr, mut yr) = (
        (-MARGIN_BL, world.width + MARGIN_BL),
        (-MARGIN_BL, world.height + MARGIN_BL),
    );
    let (dx, dy) = (xr.1 - xr.0, yr.1 - yr.0);
    if dx / px_w > dy / px_h {
        let extra = dx / px_w * px_h - dy;
        yr = (yr.0 - extra / 2.0, yr.1 + extra / 2.0);
    } else {
        let extra = dy / px_h * px_w - dx;
        xr = (xr.0 - extra / 2.0, xr.1 + extra / 2.0);
    }
    let mut c = b.build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    c.configure_mesh()
        .disable_mesh()
        .x_desc("x (BL)")
        .y_desc("y (BL)")
        .axis_desc_style(label_font())
        .label_style(tick_font())
        .x_label_formatter(&|v| super::tick_label(*v))
        .y_label_formatter(&|v| super::tick_label(*v))
        .draw()?;
    Ok(c)
}

/// Points of a circle (closed polyline) of radius `r` around `c`.
pub fn circle_points(c: Vec2, r: f64, n: usize) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            (c.x + r * a.cos(), c.y + r * a.sin())
        })
        .collect()
}

/// Draws the walls (the rectangle's edges) and the obstacles.
pub fn draw_world<DB: DrawingBackend>(
    c: &mut WorldChart<'_, DB>,
    world: &World,
) -> Result<(), PlotError> {
    for o in &world.obstacles {
        let pts: Vec<(f64, f64)> = match o {
            Obstacle::Polygon(v) => v.iter().map(|p| (p.x, p.y)).collect(),
            Obstacle::Circle { center, radius } => circle_points(*center, *radius, 96),
        };
        c.draw_series(std::iter::once(Polygon::new(
            pts.clone(),
            palette::OBSTACLE.filled(),
        )))?;
        let mut outline = pts;
        outline.push(outline[0]);
        c.draw_series(std::iter::once(PathElement::new(
            outline,
            RGBColor(90, 90, 90).stroke_width(1),
        )))?;
    }
    let (w, h) = (world.width, world.height);
    let walls = vec![(0.0, 0.0), (w, 0.0), (w, h), (0.0, h), (0.0, 0.0)];
    c.draw_series(std::iter::once(PathElement::new(
        walls,
        BLACK.stroke_width(3),
    )))?;
    Ok(())
}

/// Draws tree edges as thin grey segments.
pub fn draw_tree<DB: DrawingBackend>(
    c: &mut WorldChart<'_, DB>,
    edges: &[(Vec2, Vec2)],
) -> Result<(), PlotError> {
    let style = palette::TREE.stroke_width(1);
    c.draw_series(
        edges
            .iter()
            .map(|(a, b)| PathElement::new(vec![(a.x, a.y), (b.x, b.y)], style)),
    )?;
    Ok(())
}

/// Draws a polyline path.
pub fn draw_path<DB: DrawingBackend>(
    c: &mut WorldChart<'_, DB>,
    path: &[Vec2],
    color: RGBColor,
    width: u32,
) -> Result<(), PlotError> {
    if path.len() > 1 {
        let pts: Vec<(f64, f64)> = path.iter().map(|p| (p.x, p.y)).collect();
        c.draw_series(std::iter::once(PathElement::new(
            pts,
            color.stroke_width(width),
        )))?;
    }
    Ok(())
}

/// Draws start squares of side 1 BL (one agent diameter), one colour per agent.
pub fn draw_starts<DB: DrawingBackend>(
    c: &mut WorldChart<'_, DB>,
    starts: &[Vec2],
) -> Result<(), PlotError> {
    for (i, s) in starts.iter().enumerate() {
        let sq = vec![
            (s.x - 0.5, s.y - 0.5),
            (s.x + 0.5, s.y - 0.5),
            (s.x + 0.5, s.y + 0.5),
            (s.x - 0.5, s.y + 0.5),
            (s.x - 0.5, s.y - 0.5),
        ];
        c.draw_series(std::iter::once(PathElement::new(
            sq,
            palette::agent(i).stroke_width(2),
        )))?;
    }
    Ok(())
}

/// Draws each goal's centres (crosses) and tolerance circles; goals of several legs are numbered.
pub fn draw_goals<DB: DrawingBackend>(
    c: &mut WorldChart<'_, DB>,
    goals: &[Goal],
) -> Result<(), PlotError> {
    for (leg, g) in goals.iter().enumerate() {
        for (i, p) in g.agents.iter().enumerate() {
            let col = palette::agent(i);
            c.draw_series(std::iter::once(PathElement::new(
                circle_points(*p, g.tolerance, 48),
                col.stroke_width(2),
            )))?;
            c.draw_series(std::iter::once(Cross::new(
                (p.x, p.y),
                4,
                col.stroke_width(2),
            )))?;
            if goals.len() > 1 && i == 0 {
                let style = tick_font().pos(text_anchor::Pos::new(
                    text_anchor::HPos::Left,
                    text_anchor::VPos::Bottom,
                ));
                c.draw_series(std::iter::once(Text::new(
                    format!("G{}", leg + 1),
                    (p.x + g.tolerance, p.y + g.tolerance),
                    style,
                )))?;
            }
        }
    }
    Ok(())
}

impl Figure for WorldPlot<'_> {
    fn size(&self) -> (u32, u32) {
        let lh = legend::height(&self.legend_entries(), self.width_px);
        map_size(self.world, self.width_px, self.title.is_some(), lh)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let entries = self.legend_entries();
        let (_, h) = root.dim_in_pixel();
        let lh = legend::height(&entries, self.width_px);
        let (top, bottom) = root.split_vertically(h - lh);
        let mut c = chart(&top, self.world, self.title.as_deref())?;
        draw_tree(&mut c, &self.tree)?;
        draw_world(&mut c, self.world)?;
        for (i, p) in self.planned.iter().enumerate() {
            draw_path(&mut c, p, palette::agent(i), 3)?;
        }
        for p in &self.tracked {
            draw_path(&mut c, p, palette::TRACKED, 1)?;
        }
        draw_goals(&mut c, &self.goals)?;
        draw_starts(&mut c, &self.starts)?;
        legend::draw(&bottom, &entries)
    }
}

/// Writes `plot` to `OUT_STEM.svg` and `OUT_STEM.png`; returns the two paths.
pub fn render(plot: &WorldPlot, out_stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    super::save(plot, out_stem)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_size_keeps_equal_scales() {
        let w = World {
            width: 60.0,
            height: 40.0,
            obstacles: vec![],
        };
        let (pw, ph) = map_size(&w, 1000, false, 0);
        assert_eq!(pw, 1000);
        let plot_h = ph - 15 - BOTTOM_PX;
        let ratio = plot_h as f64 / (1000 - LEFT_PX - RIGHT_PX - 8) as f64;
        assert!((ratio - 41.6 / 61.6).abs() < 0.01, "{ratio}");
    }
}

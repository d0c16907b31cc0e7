//! Animated GIFs of agents (disks of diameter 1 BL) moving over a world map, e.g. for
//! `magbench track --out`. Each agent is drawn in its own colour (as its planned path, start
//! and goal), numbered from 1 beside its disk, with a legend below the map.

use std::path::{Path, PathBuf};

use magbench_env::Vec2;
use plotters::prelude::*;

use plotters::coord::Shift;
use plotters::style::text_anchor;

use super::legend::{self, Entry, Symbol};
use super::world::{
    WorldPlot, chart, circle_points, draw_goals, draw_path, draw_starts, draw_tree, draw_world,
    map_size,
};
use super::{PlotError, font, palette, tick_font};

/// One frame: the agents' positions at a time.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Time (s) shown in the title.
    pub time_s: f64,
    /// Position of each agent (BL).
    pub agents: Vec<Vec2>,
}

/// How a GIF is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GifOptions {
    /// Delay between frames (ms).
    pub frame_delay_ms: u32,
    /// At most this many frames; longer sequences are subsampled evenly (first and last kept).
    pub max_frames: usize,
    /// Width in pixels.
    pub width_px: u32,
    /// Draw each agent's trail (the frames so far) in black.
    pub trails: bool,
}

impl Default for GifOptions {
    fn default() -> Self {
        GifOptions {
            frame_delay_ms: 50,
            max_frames: 300,
            width_px: 640,
            trails: true,
        }
    }
}

/// Indices of at most `max` frames out of `n`, evenly spread, first and last included.
pub fn subsample(n: usize, max: usize) -> Vec<usize> {
    if n <= max {
        return (0..n).collect();
    }
    if max <= 1 {
        return vec![n - 1];
    }
    (0..max)
        .map(|k| ((k as f64) * (n - 1) as f64 / (max - 1) as f64).round() as usize)
        .collect()
}

/// Writes `frames` over the static map `base` (world, tree, planned paths, starts, goals; its
/// `tracked` paths are not drawn) to the GIF file `path`.
pub fn render_gif(
    base: &WorldPlot,
    frames: &[Frame],
    path: &Path,
    opts: &GifOptions,
) -> Result<PathBuf, PlotError> {
    font::ensure_registered();
    if frames.is_empty() {
        return Err(PlotError("no frames to animate".into()));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let agents = frames.iter().map(|f| f.agents.len()).max().unwrap_or(0);
    let entries = legend_entries(agents);
    let lh = legend::height(&entries, opts.width_px);
    let (w, h) = map_size(base.world, opts.width_px, true, lh);
    let gif_err = |e: gif::EncodingError| PlotError(format!("{}: {e}", path.display()));
    let (gw, gh) = (gif_side(w)?, gif_side(h)?);
    let mut gif = gif::Encoder::new(std::fs::File::create(path)?, gw, gh, &[]).map_err(gif_err)?;
    gif.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
    // GIF delays are in hundredths of a second: the nearest one
    let delay_cs = u16::try_from(opts.frame_delay_ms.saturating_add(5) / 10).unwrap_or(u16::MAX);
    let mut rgb = vec![0u8; w as usize * h as usize * 3];
    for k in subsample(frames.len(), opts.max_frames) {
        {
            let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
            draw_frame(&root, base, frames, k, opts, &entries)?;
            root.present()?;
        }
        // a 256-colour palette by NeuQuant at speed 10 (1 is the best palette, 30 the fastest)
        let mut frame = gif::Frame::from_rgb_speed(gw, gh, &rgb, 10);
        frame.delay = delay_cs;
        gif.write_frame(&frame).map_err(gif_err)?;
    }
    Ok(path.to_path_buf())
}

/// A GIF's width or height: at most 65,535 px.
fn gif_side(px: u32) -> Result<u16, PlotError> {
    u16::try_from(px).map_err(|_| PlotError(format!("a GIF is at most 65535 px wide, not {px}")))
}

/// The legend of a GIF of `agents` agents: one filled disk per agent in its colour.
fn legend_entries(agents: usize) -> Vec<Entry> {
    (0..agents)
        .map(|i| Entry::new(Symbol::Disk(palette::agent(i)), format!("agent {}", i + 1)))
        .collect()
}

/// Draws frame `k` of `frames` over `base` on `root`, the legend `entries` below the map.
fn draw_frame<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    base: &WorldPlot,
    frames: &[Frame],
    k: usize,
    opts: &GifOptions,
    entries: &[Entry],
) -> Result<(), PlotError> {
    let f = &frames[k];
    root.fill(&WHITE)?;
    let (_, h) = root.dim_in_pixel();
    let lh = legend::height(entries, opts.width_px);
    let (top, bottom) = root.split_vertically(h - lh);
    let title = match &base.title {
        Some(t) => format!("{t}   t = {:.2} s", f.time_s),
        None => format!("t = {:.2} s", f.time_s),
    };
    let mut c = chart(&top, base.world, Some(&title))?;
    draw_tree(&mut c, &base.tree)?;
    draw_world(&mut c, base.world)?;
    for (i, p) in base.planned.iter().enumerate() {
        draw_path(&mut c, p, palette::agent(i), 2)?;
    }
    draw_goals(&mut c, &base.goals)?;
    draw_starts(&mut c, &base.starts)?;
    if opts.trails {
        for i in 0..f.agents.len() {
            let trail: Vec<Vec2> = frames[..=k]
                .iter()
                .filter_map(|g| g.agents.get(i).copied())
                .collect();
            draw_path(&mut c, &trail, palette::TRACKED, 1)?;
        }
    }
    let number = tick_font().pos(text_anchor::Pos::new(
        text_anchor::HPos::Left,
        text_anchor::VPos::Bottom,
    ));
    for (i, a) in f.agents.iter().enumerate() {
        let col = palette::agent(i);
        c.draw_series(std::iter::once(Polygon::new(
            circle_points(*a, 0.5, 32),
            col.filled(),
        )))?;
        c.draw_series(std::iter::once(PathElement::new(
            circle_points(*a, 0.5, 32),
            BLACK.stroke_width(1),
        )))?;
        c.draw_series(std::iter::once(Text::new(
            format!("{}", i + 1),
            (a.x + 0.45, a.y + 0.45),
            number.clone(),
        )))?;
    }
    legend::draw(&bottom, entries)
}

#[cfg(test)]
mod tests {
    use magbench_env::Scenario;

    use super::*;

    #[test]
    fn subsample_keeps_ends_and_count() {
        assert_eq!(subsample(5, 10), vec![0, 1, 2, 3, 4]);
        let s = subsample(1000, 7);
        assert_eq!(s.len(), 7);
        assert_eq!((s[0], s[6]), (0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(subsample(10, 1), vec![9]);
    }

    /// Pixels of `buf` (RGB) of exactly colour `c`.
    fn count(buf: &[u8], c: RGBColor) -> usize {
        buf.chunks(3).filter(|p| *p == [c.0, c.1, c.2]).count()
    }

    #[test]
    fn each_agent_is_drawn_in_its_colour_with_a_legend() {
        font::ensure_registered();
        let s = Scenario::load("quad-square").unwrap();
        let mut base = WorldPlot::new(&s.world);
        base.title = Some("quad".into());
        let frames = vec![Frame {
            time_s: 0.0,
            agents: s.start.clone(),
        }];
        let opts = GifOptions::default();
        let entries = legend_entries(4);
        let lh = legend::height(&entries, opts.width_px);
        let (w, h) = map_size(&s.world, opts.width_px, true, lh);
        let mut buf = vec![0u8; (w * h * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            draw_frame(&root, &base, &frames, 0, &opts, &entries).unwrap();
            root.present().unwrap();
        }
        // a disk of 1 BL is a few hundred pixels; the legend's disk adds some more
        for i in 0..4 {
            let n = count(&buf, palette::agent(i));
            assert!(n > 100, "agent {} has {n} pixels of its colour", i + 1);
        }
        // the legend alone: no agent on the map, still every agent's colour below it
        let empty = vec![Frame {
            time_s: 0.0,
            agents: vec![],
        }];
        let mut buf2 = vec![0u8; (w * h * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buf2, (w, h)).into_drawing_area();
            draw_frame(&root, &base, &empty, 0, &opts, &entries).unwrap();
            root.present().unwrap();
        }
        for i in 0..4 {
            let (legend, all) = (
                count(&buf2, palette::agent(i)),
                count(&buf, palette::agent(i)),
            );
            assert!(
                legend > 20 && legend < all,
                "agent {}: {legend} vs {all}",
                i + 1
            );
        }
    }
}

//! Animated GIFs of agents (disks of diameter 1 BL) moving over a world map, e.g. for
//! `magbench track --out`.

use std::path::{Path, PathBuf};

use magbench_env::Vec2;
use plotters::prelude::*;

use super::world::{
    WorldPlot, chart, circle_points, draw_goals, draw_path, draw_starts, draw_tree, draw_world,
    map_size,
};
use super::{PlotError, font, palette};

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
    let size = map_size(base.world, opts.width_px, true, 0);
    let root = BitMapBackend::gif(path, size, opts.frame_delay_ms)
        .map_err(|e| PlotError(format!("{}: {e}", path.display())))?
        .into_drawing_area();
    let keep = subsample(frames.len(), opts.max_frames);
    for &k in &keep {
        let f = &frames[k];
        root.fill(&WHITE)?;
        let title = match &base.title {
            Some(t) => format!("{t}   t = {:.2} s", f.time_s),
            None => format!("t = {:.2} s", f.time_s),
        };
        let mut c = chart(&root, base.world, Some(&title))?;
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
        }
        root.present()?;
    }
    Ok(path.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::subsample;

    #[test]
    fn subsample_keeps_ends_and_count() {
        assert_eq!(subsample(5, 10), vec![0, 1, 2, 3, 4]);
        let s = subsample(1000, 7);
        assert_eq!(s.len(), 7);
        assert_eq!((s[0], s[6]), (0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(subsample(10, 1), vec![9]);
    }
}

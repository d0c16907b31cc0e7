//! The picture next to a tree file: each leg's map with the tree projected on the team's
//! centroid, the plan's agent paths, the start and the goal (SVG).

use std::path::{Path, PathBuf};

use magbench_env::{Goal, Vec2, World};
use plotters::prelude::*;

use super::tree::LegTree;
use crate::Error;
use crate::plot::world::WorldPlot;
use crate::plot::{Figure, font};

/// Most tree edges drawn.
const MAX_EDGES: usize = 20_000;

/// One leg's picture.
pub struct TreePicture<'a> {
    /// The leg's map.
    pub world: &'a World,
    /// The leg's tree.
    pub tree: &'a LegTree,
    /// The plan's path of each agent.
    pub planned: Vec<Vec<Vec2>>,
    /// The leg's goal.
    pub goal: Goal,
    /// The title.
    pub title: String,
}

/// The SVG files next to tree file `file` for `legs` legs: `STEM.svg`, or `STEM-legK.svg`
/// for each leg K of several (STEM is `file` without a `.json` extension).
pub fn svg_paths(file: &Path, legs: usize) -> Vec<PathBuf> {
    let stem = match file.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("json") => file.with_extension(""),
        _ => file.to_path_buf(),
    };
    (0..legs)
        .map(|k| {
            if legs > 1 {
                crate::plot::with_ext(&stem, &format!("leg{}.svg", k + 1))
                    .to_string_lossy()
                    .replacen(".leg", "-leg", 1)
                    .into()
            } else {
                crate::plot::with_ext(&stem, "svg")
            }
        })
        .collect()
}

/// Writes `pic` as SVG to `path`.
pub fn write(pic: &TreePicture, path: &Path) -> Result<(), Error> {
    font::ensure_registered();
    let mut plot = WorldPlot::new(pic.world);
    plot.tree = pic
        .tree
        .centroid_edges(MAX_EDGES)
        .into_iter()
        .map(|(a, b)| (Vec2::new(a[0], a[1]), Vec2::new(b[0], b[1])))
        .collect();
    plot.planned = pic.planned.clone();
    plot.starts = pic.tree.states[0]
        .iter()
        .map(|p| Vec2::new(p[0], p[1]))
        .collect();
    plot.goals = vec![pic.goal.clone()];
    plot.title = Some(pic.title.clone());
    let fail = |e: String| Error::Failed(format!("{}: {e}", path.display()));
    let root = SVGBackend::new(path, plot.size()).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
    plot.draw(&root).map_err(|e| fail(e.to_string()))?;
    root.present().map_err(|e| fail(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_names() {
        assert_eq!(
            svg_paths(Path::new("out/tree.json"), 1),
            [PathBuf::from("out/tree.svg")]
        );
        assert_eq!(
            svg_paths(Path::new("t.json"), 2),
            [PathBuf::from("t-leg1.svg"), PathBuf::from("t-leg2.svg")]
        );
        assert_eq!(svg_paths(Path::new("t"), 1), [PathBuf::from("t.svg")]);
    }
}

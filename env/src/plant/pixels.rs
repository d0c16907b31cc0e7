//! The camera at the pixel level (`[camera.pixels]`): what a thresholding or Hough detector
//! makes of agents imaged at a finite resolution.
//!
//! Each agent's image is a disc one body length across, `px_per_bl` pixels wide, on a pixel
//! grid fixed in the map (pixel `k` spans `[k, k + 1)` px, `x_px = x_bl · px_per_bl`). A
//! thresholding detector sees the pixels whose centres fall inside the disc and reports their
//! centroid: the quantisation error of a digitised circle (Matsuoka et al., "Measurement
//! accuracy of center location of a circle by centroid method", PIA11, LNCS 6952, 2011: the
//! error's variance oscillates with a one-pixel period in the diameter and falls with it). A
//! Hough detector reports the centre of an accumulator cell instead: with `centre_step_px`
//! = `dp` (OpenCV `HoughCircles`: "if dp = 1, the accumulator has the same resolution as the
//! input image") the centroid is rounded to that grid. Two agents whose images come closer
//! than `merge_gap_px` (edge to edge) form one blob: both are reported at the merged blob's
//! centroid (the count-weighted mean of the two discs' pixels), so a close pair's detections
//! are pulled toward each other by half their separation, exactly when the pair is closest.
//! Agents chain into one blob through their close neighbours.

use serde::{Deserialize, Serialize};

use crate::input::{Bound, Rejection};
use crate::math::Vec2;

/// The image scales a preset accepts (px per BL).
const PX_PER_BL: Bound = Bound::closed(
    2.0,
    1000.0,
    " px per BL",
    "an agent narrower than 2 px may cover no pixel centre; 1000 px per BL puts a 16-BL field on a 16384-px sensor",
);

/// The centre grids a preset accepts (px; 0 = the blob's own centroid).
const CENTRE_STEP_PX: Bound = Bound::closed(
    0.0,
    16.0,
    " px",
    "a Hough accumulator coarser than 16 image pixels (dp > 16) no longer finds discs",
);

/// The merge gaps a preset accepts (px, edge to edge).
const MERGE_GAP_PX: Bound = Bound::closed(
    0.0,
    100.0,
    " px",
    "a blur or meniscus halo wider than 100 px hides the agents altogether",
);

/// The `[camera.pixels]` table: resolution, the detector's quantisation and blob merging.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pixels {
    /// Whether the term acts (off: the detector sees the true centres).
    pub enabled: bool,
    /// Image scale: pixels across one body length (one agent's diameter).
    pub px_per_bl: f64,
    /// Grid the detector reports centres on (px): `dp` of a Hough accumulator; 0 = the
    /// thresholded blob's centroid, unrounded.
    pub centre_step_px: f64,
    /// Edge-to-edge gap (px) below which two agents' blobs merge into one.
    pub merge_gap_px: f64,
}

impl Default for Pixels {
    /// Off; when switched on: 13 px per BL, blob centroids, blobs merging when their edges
    /// are less than one pixel apart (their pixels touch).
    fn default() -> Self {
        Self {
            enabled: false,
            px_per_bl: 13.0,
            centre_step_px: 0.0,
            merge_gap_px: 1.0,
        }
    }
}

/// A blob's pixel count and the sum of its pixel centres (px).
#[derive(Debug, Clone, Copy, Default)]
struct Blob {
    count: f64,
    sum: Vec2,
}

impl Pixels {
    /// Checks every value; fields within the table (`px_per_bl`).
    pub fn check(&self) -> Result<(), Rejection> {
        PX_PER_BL.check("px_per_bl", self.px_per_bl)?;
        CENTRE_STEP_PX.check("centre_step_px", self.centre_step_px)?;
        MERGE_GAP_PX.check("merge_gap_px", self.merge_gap_px)?;
        Ok(())
    }

    /// The detected centre (BL) of every agent at the true centres `truth` (BL).
    pub fn detect(&self, truth: &[Vec2]) -> Vec<Vec2> {
        let s = self.px_per_bl;
        let blobs: Vec<Blob> = truth.iter().map(|p| disc(p * s, 0.5 * s)).collect();
        let merge_r = 1.0 + self.merge_gap_px / s;
        let mut group: Vec<usize> = (0..truth.len()).collect();
        for i in 0..truth.len() {
            for j in (i + 1)..truth.len() {
                if (truth[j] - truth[i]).norm() < merge_r {
                    let (a, b) = (root(&group, i), root(&group, j));
                    group[a.max(b)] = a.min(b);
                }
            }
        }
        let mut merged = vec![Blob::default(); truth.len()];
        for (i, b) in blobs.iter().enumerate() {
            let m = &mut merged[root(&group, i)];
            m.count += b.count;
            m.sum += b.sum;
        }
        (0..truth.len())
            .map(|i| {
                let m = merged[root(&group, i)];
                let c = m.sum / m.count;
                self.round(c) / s
            })
            .collect()
    }

    /// `c` (px) on the detector's centre grid.
    fn round(&self, c: Vec2) -> Vec2 {
        let h = self.centre_step_px;
        if h > 0.0 {
            Vec2::new((c.x / h).round() * h, (c.y / h).round() * h)
        } else {
            c
        }
    }
}

/// The root of `i`'s group (groups point to a smaller index).
fn root(group: &[usize], mut i: usize) -> usize {
    while group[i] != i {
        i = group[i];
    }
    i
}

/// The pixels whose centres `(k + ½, l + ½)` lie inside the disc of centre `c` and radius `r`
/// (px), row by row in closed form. Never empty for `r ≥ 1` (a pixel centre lies within √½
/// of every point).
fn disc(c: Vec2, r: f64) -> Blob {
    let mut blob = Blob::default();
    let (lo_row, hi_row) = ((c.y - r - 0.5).ceil(), (c.y + r - 0.5).floor());
    let mut l = lo_row;
    while l <= hi_row {
        let dy = l + 0.5 - c.y;
        let half = (r * r - dy * dy).max(0.0).sqrt();
        let (lo, hi) = ((c.x - half - 0.5).ceil(), (c.x + half - 0.5).floor());
        if hi >= lo {
            let n = hi - lo + 1.0;
            blob.count += n;
            blob.sum += Vec2::new(n * (0.5 * (lo + hi) + 0.5), n * (l + 0.5));
        }
        l += 1.0;
    }
    if blob.count == 0.0 {
        // r < 1 is refused by the bounds; the centre's own pixel keeps the blob non-empty
        let k = Vec2::new(c.x.floor() + 0.5, c.y.floor() + 0.5);
        return Blob { count: 1.0, sum: k };
    }
    blob
}

/// RMS error per coordinate (px) of the thresholded blob's centroid of a disc `d` px across,
/// over centres spread uniformly within a pixel (an `n` × `n` sub-pixel lattice): the
/// quantisation a detector adds to a perfectly segmented image.
pub fn centroid_rms_px(d: f64, n: usize) -> f64 {
    let mut sq = 0.0;
    for a in 0..n {
        for b in 0..n {
            let c = Vec2::new(
                100.0 + (a as f64 + 0.5) / n as f64,
                100.0 + (b as f64 + 0.5) / n as f64,
            );
            let blob = disc(c, 0.5 * d);
            let e = blob.sum / blob.count - c;
            sq += e.x * e.x + e.y * e.y;
        }
    }
    (sq / (2 * n * n) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on(px: f64, step: f64, gap: f64) -> Pixels {
        Pixels {
            enabled: true,
            px_per_bl: px,
            centre_step_px: step,
            merge_gap_px: gap,
        }
    }

    #[test]
    fn a_disc_covers_its_area_and_centres_on_a_pixel_centre() {
        let b = disc(Vec2::new(10.5, 20.5), 6.5);
        assert!((b.count - std::f64::consts::PI * 6.5 * 6.5).abs() < 6.5 * 4.0);
        let c = b.sum / b.count;
        assert!(
            (c - Vec2::new(10.5, 20.5)).norm() < 1e-12,
            "symmetric: {c:?}"
        );
    }

    #[test]
    fn the_centroid_error_is_sub_pixel_and_shrinks_with_resolution() {
        let (e5, e13, e40) = (
            centroid_rms_px(5.0, 32),
            centroid_rms_px(13.0, 32),
            centroid_rms_px(40.0, 32),
        );
        assert!(e5 > e40 && e13 > e40, "{e5} {e13} {e40}");
        assert!(e13 < 0.2 && e13 > 0.005, "13 px: {e13} px");
        // a 1-px accumulator adds the grid's own 1/√12 px
        let p = on(13.0, 1.0, 0.0);
        let mut sq = 0.0;
        for k in 0..400 {
            let t = Vec2::new(3.0 + k as f64 * 0.0137, 4.0 + k as f64 * 0.0071);
            let e = (p.detect(&[t])[0] - t) * 13.0;
            sq += e.norm_squared() / 2.0;
        }
        let rms = (sq / 400.0).sqrt();
        assert!((rms - 12f64.powf(-0.5)).abs() < 0.06, "{rms} px");
    }

    #[test]
    fn close_agents_merge_and_are_pulled_together() {
        let p = on(13.0, 0.0, 2.0);
        let a = Vec2::new(5.0, 5.0);
        // 1.1 BL apart: 1.3 px between the edges, under the 2 px gap
        let close = p.detect(&[a, a + Vec2::new(1.1, 0.0), Vec2::new(9.0, 5.0)]);
        assert!((close[0] - close[1]).norm() < 1e-12, "one blob: {close:?}");
        assert!((close[0].x - (a.x + 0.55)).abs() < 0.05, "{close:?}");
        assert!(
            (close[2] - Vec2::new(9.0, 5.0)).norm() < 0.05,
            "the far one alone"
        );
        // 1.2 BL apart: 2.6 px, two blobs
        let apart = p.detect(&[a, a + Vec2::new(1.2, 0.0)]);
        assert!((apart[1] - apart[0]).norm() > 1.1, "{apart:?}");
    }

    #[test]
    fn each_field_is_bounded() {
        for (field, p) in [
            ("px_per_bl", on(1.0, 0.0, 1.0)),
            ("px_per_bl", on(f64::NAN, 0.0, 1.0)),
            ("centre_step_px", on(13.0, -1.0, 1.0)),
            ("merge_gap_px", on(13.0, 0.0, 1e9)),
        ] {
            assert_eq!(p.check().unwrap_err().field, field);
        }
        assert!(Pixels::default().check().is_ok());
    }
}

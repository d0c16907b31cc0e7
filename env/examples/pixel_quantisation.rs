//! Prints the detection error that `[camera.pixels]` adds at several image scales: the RMS
//! error per coordinate of a thresholded blob's centroid, and of a Hough detector reporting
//! centres on a 1-px grid (`centre_step_px = 1`), over agent centres spread across a pixel;
//! then the merge distance and the bias of a merged pair at a 1-px merge gap.
//!
//! `cargo run -p magbench-env --example pixel_quantisation`

use magbench_env::math::Vec2;
use magbench_env::plant::{Pixels, centroid_rms_px};

fn main() {
    println!(
        "px_per_bl  blob_rms_px  blob_rms_bl  hough1px_rms_px  hough1px_rms_bl  merge_below_bl"
    );
    for s in [5.0, 8.0, 10.0, 13.0, 16.0, 21.0, 32.0, 64.0] {
        let blob = centroid_rms_px(s, 64);
        let hough = Pixels {
            enabled: true,
            px_per_bl: s,
            centre_step_px: 1.0,
            merge_gap_px: 1.0,
        };
        let n = 64;
        let mut sq = 0.0;
        for a in 0..n {
            for b in 0..n {
                let t = Vec2::new(
                    (100.0 + (a as f64 + 0.5) / n as f64) / s,
                    (100.0 + (b as f64 + 0.5) / n as f64) / s,
                );
                let e = (hough.detect(&[t])[0] - t) * s;
                sq += e.norm_squared() / 2.0;
            }
        }
        let hough_rms = (sq / (n * n) as f64).sqrt();
        println!(
            "{s:9.0}  {blob:11.3}  {:11.4}  {hough_rms:15.3}  {:15.4}  {:14.3}",
            blob / s,
            hough_rms / s,
            1.0 + 1.0 / s
        );
    }
}

//! Prints, as a Markdown table, the detection error that `[camera.pixels]` adds at several
//! image scales: the RMS error per coordinate of a thresholded blob's centroid, and of a Hough
//! detector reporting centres on a 1-px grid (`centre_step_px = 1`), over agent centres spread
//! across a pixel; then the distance below which a pair merges into one blob at a 1-px merge
//! gap. `cargo xtask measure --only pixel-quantisation` keeps the table in
//! `docs/measured/pixel-quantisation.md`.
//!
//! `cargo run -p magbench-env --example pixel_quantisation`

use magbench_env::math::Vec2;
use magbench_env::plant::{Pixels, centroid_rms_px};

/// Image scales tabled, px per BL.
const SCALES: [f64; 5] = [5.0, 8.0, 13.0, 21.0, 32.0];

/// Agent centres per axis, spread evenly across one pixel.
const SPREAD: usize = 64;

/// RMS error per coordinate (px) of a Hough detector whose centres lie on a grid of
/// `centre_step_px` at `px_per_bl`, over centres spread across one pixel.
fn hough_rms_px(px_per_bl: f64, centre_step_px: f64) -> f64 {
    let hough = Pixels {
        enabled: true,
        px_per_bl,
        centre_step_px,
        merge_gap_px: 1.0,
    };
    let n = SPREAD;
    let mut sq = 0.0;
    for a in 0..n {
        for b in 0..n {
            let t = Vec2::new(
                (100.0 + (a as f64 + 0.5) / n as f64) / px_per_bl,
                (100.0 + (b as f64 + 0.5) / n as f64) / px_per_bl,
            );
            let e = (hough.detect(&[t])[0] - t) * px_per_bl;
            sq += e.norm_squared() / 2.0;
        }
    }
    (sq / (n * n) as f64).sqrt()
}

fn main() {
    println!("| px per BL | thresholded centroid | Hough, dp = 1 px | merge below (gap 1 px) |");
    println!("| --- | --- | --- | --- |");
    for s in SCALES {
        let blob = centroid_rms_px(s, SPREAD);
        let hough = hough_rms_px(s, 1.0);
        // two discs one BL across merge when their edges are closer than the gap: r < 1 + gap/s
        println!(
            "| {s:.0} | {blob:.3} px = {:.3} BL | {hough:.3} px = {:.3} BL | r < {:.3} BL |",
            blob / s,
            hough / s,
            1.0 + 1.0 / s
        );
    }
}

//! Thresholded connected components (imageproc) with their moments.

use image::{GrayImage, Luma};
use imageproc::region_labelling::{Connectivity, connected_components};
use magbench_env::Vec2;

use crate::rigfile::Polarity;

/// An axis-aligned pixel rectangle `[x0, x1) × [y0, y1)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Rect {
    /// The rectangle around `c` with half-size `half`, clipped to a `w × h` image.
    pub fn around(c: Vec2, half: f64, w: u32, h: u32) -> Rect {
        let clip = |v: f64, m: u32| v.clamp(0.0, m as f64) as u32;
        Rect {
            x0: clip((c.x - half).floor(), w),
            y0: clip((c.y - half).floor(), h),
            x1: clip((c.x + half).ceil() + 1.0, w),
            y1: clip((c.y + half).ceil() + 1.0, h),
        }
    }

    /// This rectangle grown by `m` pixels on each side, clipped to a `w × h` image.
    pub fn grown(&self, m: u32, w: u32, h: u32) -> Rect {
        Rect {
            x0: self.x0.saturating_sub(m),
            y0: self.y0.saturating_sub(m),
            x1: (self.x1 + m).min(w),
            y1: (self.y1 + m).min(h),
        }
    }

    /// True when the rectangles share a pixel.
    pub fn intersects(&self, o: &Rect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    /// The smallest rectangle holding both.
    pub fn union(&self, o: &Rect) -> Rect {
        Rect {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }

    /// Pixel count.
    pub fn area(&self) -> u64 {
        (self.x1.saturating_sub(self.x0)) as u64 * (self.y1.saturating_sub(self.y0)) as u64
    }
}

/// A connected set of foreground pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct Blob {
    /// Pixel count.
    pub area: usize,
    /// Centroid (pixels).
    pub mean: Vec2,
    /// Second central moments `(xx, xy, yy)` (pixels²).
    pub cov: [f64; 3],
    /// Bounding box.
    pub bbox: Rect,
}

impl Blob {
    /// Unit vector along the blob's longest axis and the variance along it.
    pub fn major_axis(&self) -> (Vec2, f64) {
        let [a, b, c] = self.cov;
        let tr = a + c;
        let det = a * c - b * b;
        let l1 = tr / 2.0 + ((tr * tr / 4.0 - det).max(0.0)).sqrt();
        let v = if b.abs() > 1e-12 {
            Vec2::new(l1 - c, b)
        } else if a >= c {
            Vec2::new(1.0, 0.0)
        } else {
            Vec2::new(0.0, 1.0)
        };
        (v.normalize(), l1)
    }
}

/// The foreground blobs of `img` inside `roi`: pixels darker (or brighter) than `threshold`,
/// 8-connected.
pub fn find_blobs(img: &GrayImage, roi: Rect, polarity: Polarity, threshold: u8) -> Vec<Blob> {
    let (w, h) = (roi.x1 - roi.x0, roi.y1 - roi.y0);
    if w == 0 || h == 0 {
        return vec![];
    }
    let fg = |v: u8| match polarity {
        Polarity::Dark => v < threshold,
        Polarity::Bright => v > threshold,
    };
    let mask = GrayImage::from_fn(w, h, |x, y| {
        Luma([if fg(img.get_pixel(roi.x0 + x, roi.y0 + y).0[0]) {
            255
        } else {
            0
        }])
    });
    let labels = connected_components(&mask, Connectivity::Eight, Luma([0u8]));
    #[derive(Default, Clone)]
    struct Acc {
        n: usize,
        sx: f64,
        sy: f64,
        sxx: f64,
        sxy: f64,
        syy: f64,
        x0: u32,
        y0: u32,
        x1: u32,
        y1: u32,
    }
    let mut acc: Vec<Acc> = Vec::new();
    for (x, y, l) in labels.enumerate_pixels() {
        let l = l.0[0] as usize;
        if l == 0 {
            continue;
        }
        if acc.len() < l {
            acc.resize(
                l,
                Acc {
                    x0: u32::MAX,
                    y0: u32::MAX,
                    ..Default::default()
                },
            );
        }
        let a = &mut acc[l - 1];
        let (gx, gy) = (roi.x0 + x, roi.y0 + y);
        let (fx, fy) = (gx as f64, gy as f64);
        a.n += 1;
        a.sx += fx;
        a.sy += fy;
        a.sxx += fx * fx;
        a.sxy += fx * fy;
        a.syy += fy * fy;
        a.x0 = a.x0.min(gx);
        a.y0 = a.y0.min(gy);
        a.x1 = a.x1.max(gx + 1);
        a.y1 = a.y1.max(gy + 1);
    }
    acc.into_iter()
        .filter(|a| a.n > 0)
        .map(|a| {
            let n = a.n as f64;
            let (mx, my) = (a.sx / n, a.sy / n);
            Blob {
                area: a.n,
                mean: Vec2::new(mx, my),
                cov: [
                    a.sxx / n - mx * mx,
                    a.sxy / n - mx * my,
                    a.syy / n - my * my,
                ],
                bbox: Rect {
                    x0: a.x0,
                    y0: a.y0,
                    x1: a.x1,
                    y1: a.y1,
                },
            }
        })
        .collect()
}

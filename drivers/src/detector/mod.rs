//! The detector: finds dark or bright disks of known radius in a grey-level frame.
//!
//! 1. Threshold and 8-connected components ([`blobs`]), inside windows around the agents' last
//!    positions while every agent is tracked, over the whole frame otherwise.
//! 2. A blob's area says how many agents it holds (touching agents make one blob); its principal
//!    axis places their first guesses.
//! 3. Blobs whose windows overlap are fitted together with blurred disks ([`fit`]): sub-pixel
//!    centres, exact for touching agents.
//! 4. A fit with the wrong contrast sign, a poor residual or a centre that ran off is dropped.
//! 5. Identities carry over by nearest assignment ([`identity`]) gated by `max_jump_bl` (the gate
//!    widens while an agent is missing). An agent without a candidate is reported missing.

pub mod blobs;
pub mod fit;
pub mod identity;

use image::GrayImage;
use magbench_env::Vec2;

use self::blobs::{Blob, Rect, find_blobs};
use self::fit::fit_disks;
use crate::pixel_map::PixelMap;
use crate::rigfile::{DetectorConfig, Polarity};

/// What the detector found in one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Detection {
    /// Each agent's position (BL); `None` when it was not found.
    pub agents: Vec<Option<Vec2>>,
    /// Each agent's position in pixels.
    pub px: Vec<Option<Vec2>>,
    /// Candidate disks found (before identity assignment).
    pub candidates: usize,
    /// True when only windows around the last positions were searched.
    pub windowed: bool,
}

/// Missed-frame count of an agent never seen: found anywhere.
const UNSEEN: u32 = u32::MAX;

/// A detector with its identity memory.
#[derive(Debug, Clone)]
pub struct Detector {
    cfg: DetectorConfig,
    map: PixelMap,
    last: Vec<Vec2>,
    missed: Vec<u32>,
}

impl Detector {
    /// A detector for agents expected near `prior` (BL): the first frame assigns identities by
    /// nearest distance to these positions (e.g. the scenario's start).
    pub fn new(cfg: DetectorConfig, map: PixelMap, prior: &[Vec2]) -> Self {
        let last = prior.iter().map(|p| map.to_px(*p)).collect();
        Self {
            cfg,
            map,
            last,
            missed: vec![UNSEEN; prior.len()],
        }
    }

    /// Number of agents tracked.
    pub fn agents(&self) -> usize {
        self.last.len()
    }

    /// The pixel map.
    pub fn map(&self) -> &PixelMap {
        &self.map
    }

    /// Finds the agents in `img`.
    pub fn detect(&mut self, img: &GrayImage) -> Detection {
        let (w, h) = img.dimensions();
        let n = self.last.len();
        let r = self.cfg.radius_px;
        let jump_px = self.cfg.max_jump_bl * self.map.px_per_bl;
        let margin = (3.0 * self.cfg.blur_px + 2.0).ceil() as u32;
        let tracking = self.missed.iter().all(|m| *m == 0);
        let rois: Vec<Rect> = if tracking {
            merge(
                self.last
                    .iter()
                    .map(|c| Rect::around(*c, r + jump_px + margin as f64, w, h))
                    .collect(),
            )
        } else {
            vec![Rect {
                x0: 0,
                y0: 0,
                x1: w,
                y1: h,
            }]
        };
        let disk_area = std::f64::consts::PI * r * r;
        let blobs: Vec<Blob> = rois
            .iter()
            .flat_map(|roi| find_blobs(img, *roi, self.cfg.polarity, self.cfg.threshold))
            .filter(|b| b.area as f64 >= 0.3 * disk_area)
            .collect();
        // group blobs whose fit windows overlap
        let windows: Vec<Rect> = blobs.iter().map(|b| b.bbox.grown(margin, w, h)).collect();
        let mut group: Vec<usize> = (0..blobs.len()).collect();
        for i in 0..blobs.len() {
            for j in (i + 1)..blobs.len() {
                if windows[i].intersects(&windows[j]) {
                    let (gi, gj) = (group[i], group[j]);
                    group.iter_mut().filter(|g| **g == gj).for_each(|g| *g = gi);
                }
            }
        }
        let mut candidates: Vec<Vec2> = Vec::new();
        let mut gids: Vec<usize> = group.clone();
        gids.sort_unstable();
        gids.dedup();
        for g in gids {
            let members: Vec<usize> = (0..blobs.len()).filter(|i| group[*i] == g).collect();
            let window = members
                .iter()
                .map(|i| windows[*i])
                .reduce(|a, b| a.union(&b))
                .expect("a group has a member");
            if window.area() > 250_000 {
                continue; // a huge dark region is not agents
            }
            let mut init = Vec::new();
            for &i in &members {
                init.extend(initial_centres(&blobs[i], r, n));
            }
            if init.is_empty() || init.len() > n {
                continue;
            }
            let fit = fit_disks(img, window, &init, r, self.cfg.blur_px);
            let sign_ok = match self.cfg.polarity {
                Polarity::Dark => fit.contrast < 0.0,
                Polarity::Bright => fit.contrast > 0.0,
            };
            let level_gap = (fit.background - self.cfg.threshold as f64).abs();
            if !sign_ok || fit.contrast.abs() < level_gap || fit.rms > 0.25 * fit.contrast.abs() {
                continue;
            }
            for (c, c0) in fit.centres.iter().zip(&init) {
                let inside = c.x >= window.x0 as f64
                    && c.y >= window.y0 as f64
                    && c.x < window.x1 as f64
                    && c.y < window.y1 as f64;
                if inside && (c - c0).norm() <= r {
                    candidates.push(*c);
                }
            }
        }
        let gates: Vec<f64> = self
            .missed
            .iter()
            .map(|m| {
                if *m == UNSEEN {
                    f64::INFINITY
                } else {
                    jump_px * (1.0 + *m as f64)
                }
            })
            .collect();
        let which = identity::assign(&self.last, &gates, &candidates);
        let mut px = vec![None; n];
        for (i, j) in which.iter().enumerate() {
            match j {
                Some(j) => {
                    self.last[i] = candidates[*j];
                    self.missed[i] = 0;
                    px[i] = Some(candidates[*j]);
                }
                None => {
                    if self.missed[i] != UNSEEN {
                        self.missed[i] += 1;
                    }
                }
            }
        }
        let agents = px.iter().map(|p| p.map(|p| self.map.to_world(p))).collect();
        Detection {
            agents,
            px,
            candidates: candidates.len(),
            windowed: tracking,
        }
    }
}

/// Merges overlapping rectangles until none overlap.
fn merge(mut rs: Vec<Rect>) -> Vec<Rect> {
    loop {
        let mut merged = false;
        'outer: for i in 0..rs.len() {
            for j in (i + 1)..rs.len() {
                if rs[i].intersects(&rs[j]) {
                    rs[i] = rs[i].union(&rs[j]);
                    rs.remove(j);
                    merged = true;
                    break 'outer;
                }
            }
        }
        if !merged {
            return rs;
        }
    }
}

/// First guesses of the centres in a blob: as many disks as its area holds, spread along its
/// longest axis (two touching disks of radius R at ±s have variance R²/4 + s² along it).
fn initial_centres(b: &Blob, r: f64, max_agents: usize) -> Vec<Vec2> {
    let k = ((b.area as f64 / (std::f64::consts::PI * r * r)).round() as usize)
        .clamp(1, max_agents.max(1));
    if k == 1 {
        return vec![b.mean];
    }
    let (axis, var) = b.major_axis();
    if k == 2 {
        let s = (var - r * r / 4.0).max(r * r).sqrt();
        return vec![b.mean - axis * s, b.mean + axis * s];
    }
    (0..k)
        .map(|i| b.mean + axis * ((i as f64 - (k - 1) as f64 / 2.0) * 2.0 * r))
        .collect()
}

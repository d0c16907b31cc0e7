//! Renders grey-level camera frames of the agents: walls and obstacles, blurred disks, noise.
//!
//! Each frame: the static background (walls and obstacles at their grey level, blurred once),
//! then each agent's exact disk coverage (edge pixels supersampled 16 × 16) blurred by a
//! Gaussian of σ = `blur_px` and composited at the agent grey level, then Gaussian sensor
//! noise, then 8-bit quantisation. Disks are disjoint, so blurring each one apart and adding
//! the coverages equals blurring the whole scene.

use image::{GrayImage, ImageBuffer, Luma};
use magbench_env::collision::CollisionWorld;
use magbench_env::{Vec2, World};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use crate::pixel_map::PixelMap;

/// How frames look.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderParams {
    /// Background grey level.
    pub background: f64,
    /// Agent grey level.
    pub agent: f64,
    /// Wall and obstacle grey level.
    pub obstacle: f64,
    /// Optical blur, Gaussian σ (pixels).
    pub blur_px: f64,
    /// Sensor noise standard deviation (grey levels).
    pub noise: f64,
}

impl Default for RenderParams {
    /// Dark agents (50) on a bright background (200), obstacles at 170, σ = 1 px blur, noise 3.
    fn default() -> Self {
        Self {
            background: 200.0,
            agent: 50.0,
            obstacle: 170.0,
            blur_px: 1.0,
            noise: 3.0,
        }
    }
}

/// SplitMix64: a well-mixed 64-bit hash of `x`.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A frame renderer for one rig's camera and one world.
pub struct Renderer {
    map: PixelMap,
    size: (u32, u32),
    radius_px: f64,
    params: RenderParams,
    static_bg: Vec<f32>,
    noise_bank: Vec<f32>,
    rng: ChaCha8Rng,
    seed: u64,
}

impl Renderer {
    /// A renderer: agents of diameter 1 BL seen through `map` on a `size` sensor.
    pub fn new(
        map: PixelMap,
        size: [u32; 2],
        world: Option<&World>,
        params: RenderParams,
        seed: u64,
    ) -> Self {
        let (w, h) = (size[0], size[1]);
        let radius_px = 0.5 * map.px_per_bl;
        let bg = params.background as f32;
        let mut img: ImageBuffer<Luma<f32>, Vec<f32>> = ImageBuffer::from_pixel(w, h, Luma([bg]));
        if let Some(world) = world {
            let cw = CollisionWorld::new(world, 0.0);
            let ob = params.obstacle as f32;
            for (x, y, p) in img.enumerate_pixels_mut() {
                let mut inside = 0;
                for (dx, dy) in [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)] {
                    let wp = map.to_world(Vec2::new(x as f64 + dx, y as f64 + dy));
                    if cw.clearance(wp) <= 0.0 {
                        inside += 1;
                    }
                }
                let f = inside as f32 / 4.0;
                p.0[0] = bg * (1.0 - f) + ob * f;
            }
            if params.blur_px > 0.0 {
                img = imageproc::filter::gaussian_blur_f32(&img, params.blur_px as f32);
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5E_4502_0000_0007);
        let n = (w * h) as usize;
        let normal = Normal::new(0.0, params.noise.max(0.0)).expect("finite noise");
        let noise_bank = (0..n * 2 + 4096)
            .map(|_| normal.sample(&mut rng) as f32)
            .collect();
        Self {
            map,
            size: (w, h),
            radius_px,
            params,
            static_bg: img.into_raw(),
            noise_bank,
            rng,
            seed,
        }
    }

    /// The pixel map.
    pub fn map(&self) -> &PixelMap {
        &self.map
    }

    /// A frame of agents at `agents` (BL), with sensor noise.
    pub fn render(&mut self, agents: &[Vec2]) -> GrayImage {
        let index = self.rng.random::<u64>();
        self.render_frame(agents, index)
    }

    /// Frame number `index` of agents at `agents` (BL): its sensor noise depends only on the
    /// seed and the index, so a frame can be rendered again identically.
    pub fn render_frame(&self, agents: &[Vec2], index: u64) -> GrayImage {
        let mut f = self.render_clean(agents);
        if self.params.noise > 0.0 {
            let range = (self.noise_bank.len() - f.len()) as u64;
            let off = (splitmix64(self.seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15)) % range)
                as usize;
            for (p, n) in f.iter_mut().zip(&self.noise_bank[off..]) {
                *p += n;
            }
        }
        let px = f
            .iter()
            .map(|v| v.round().clamp(0.0, 255.0) as u8)
            .collect();
        GrayImage::from_raw(self.size.0, self.size.1, px).expect("size")
    }

    /// The noise-free frame as floating-point grey levels (row-major).
    pub fn render_clean(&self, agents: &[Vec2]) -> Vec<f32> {
        let mut f = self.static_bg.clone();
        let (w, h) = (self.size.0 as i64, self.size.1 as i64);
        let level = self.params.agent as f32;
        // coverages add (the disks are disjoint), then composite once
        let mut cov = vec![0.0f32; f.len()];
        let mut touched = Vec::new();
        for a in agents {
            let c = self.map.to_px(*a);
            let (patch, x0, y0, side) = self.blurred_disk(c);
            for j in 0..side {
                for i in 0..side {
                    let (x, y) = (x0 + i as i64, y0 + j as i64);
                    if x < 0 || y < 0 || x >= w || y >= h {
                        continue;
                    }
                    let (k, v) = ((y * w + x) as usize, patch[j * side + i]);
                    if v <= 0.0 {
                        continue;
                    }
                    if cov[k] == 0.0 {
                        touched.push(k);
                    }
                    cov[k] += v;
                }
            }
        }
        for k in touched {
            let c = cov[k].min(1.0);
            f[k] += (level - f[k]) * c;
        }
        f
    }

    /// A square patch of the blurred disk coverage at pixel centre `c`: (values, x0, y0, side).
    fn blurred_disk(&self, c: Vec2) -> (Vec<f32>, i64, i64, usize) {
        let r = self.radius_px;
        let sigma = self.params.blur_px;
        let half = (r + 4.0 * sigma + 2.0).ceil() as i64;
        let (cx, cy) = (c.x.round() as i64, c.y.round() as i64);
        let (x0, y0) = (cx - half, cy - half);
        let side = (2 * half + 1) as usize;
        let mut cov: ImageBuffer<Luma<f32>, Vec<f32>> = ImageBuffer::new(side as u32, side as u32);
        const SS: usize = 16;
        for (i, j, p) in cov.enumerate_pixels_mut() {
            let (px, py) = ((x0 + i as i64) as f64, (y0 + j as i64) as f64);
            let d = ((px - c.x).powi(2) + (py - c.y).powi(2)).sqrt();
            p.0[0] = if d <= r - 0.75 {
                1.0
            } else if d >= r + 0.75 {
                0.0
            } else {
                let mut n = 0;
                for sj in 0..SS {
                    for si in 0..SS {
                        let sx = px - 0.5 + (si as f64 + 0.5) / SS as f64;
                        let sy = py - 0.5 + (sj as f64 + 0.5) / SS as f64;
                        if (sx - c.x).powi(2) + (sy - c.y).powi(2) <= r * r {
                            n += 1;
                        }
                    }
                }
                n as f32 / (SS * SS) as f32
            };
        }
        if sigma > 0.0 {
            cov = imageproc::filter::gaussian_blur_f32(&cov, sigma as f32);
        }
        (cov.into_raw(), x0, y0, side)
    }
}

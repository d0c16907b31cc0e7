//! The camera model: frame rate, latency that jitters, detection noise with a slow bias, and
//! missed and swapped detections that become likelier when agents are close.
//!
//! At every frame `t_k` the camera delivers one observation. It shows the agents where they
//! were at `t_k − L_k`, with the true latency `L_k = L + J·N(0, 1)` (never negative; the true
//! positions are interpolated linearly between frames), but it is stamped `t_k − L` with the
//! nominal latency `L`: the estimator is told only the nominal value. Each detection is the
//! true position plus a per-agent bias that wanders slowly (an Ornstein–Uhlenbeck process with
//! the set standard deviation and correlation time) plus white noise. An agent is missed with
//! probability `p + p_c·exp(−(r − 1)/ℓ)`, `r` its distance to its nearest neighbour (BL); two
//! agents' detections swap identities with probability `p_s·exp(−(r − 1)/ℓ_s)`. With
//! `[camera.pixels]` on, the detections start from what a detector makes of the pixels (the
//! quantised centroid, close agents merged into one blob: [`Pixels`]) instead of the true
//! centres. Every part draws from its own random stream.

use std::collections::VecDeque;

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::pixels::Pixels;
use super::streams::{Stream, normal, stream};
use crate::input::Rejection;
use crate::input::bounds::{non_negative, positive, probability, within};
use crate::math::Vec2;

/// The camera of a disturbance preset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraParams {
    /// Frames per second (the control rate).
    pub fps: f64,
    /// Capture-to-delivery latency.
    #[serde(default)]
    pub latency: Latency,
    /// Detection noise and its slow bias.
    #[serde(default)]
    pub noise: DetectionNoise,
    /// Missed detections.
    #[serde(default)]
    pub misses: Misses,
    /// Swapped detections.
    #[serde(default)]
    pub swaps: Swaps,
    /// The image's resolution, the detector's quantisation and blob merging.
    #[serde(default)]
    pub pixels: Pixels,
}

/// Latency: nominal (what the estimator is told) and its jitter.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Latency {
    /// Whether the term acts (off: every frame is delivered at once).
    pub enabled: bool,
    /// Nominal latency (frames; 1 frame at 60 fps = 16.7 ms).
    pub frames: f64,
    /// Standard deviation of the true latency around the nominal (frames).
    pub jitter_frames: f64,
}

/// Detection noise.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DetectionNoise {
    /// Whether the term acts.
    pub enabled: bool,
    /// Standard deviation of the white noise per coordinate (BL).
    pub sigma_bl: f64,
    /// Standard deviation of the slow per-agent bias per coordinate (BL).
    pub bias_bl: f64,
    /// Correlation time of the bias (s).
    pub bias_time_s: f64,
}

/// Missed detections.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Misses {
    /// Whether the term acts.
    pub enabled: bool,
    /// Probability that an agent far from the others is not detected in a frame.
    pub prob: f64,
    /// Extra miss probability for an agent touching another (r = 1 BL).
    pub close_prob: f64,
    /// Distance (BL beyond contact) over which the extra probability falls by 1/e.
    pub close_range_bl: f64,
}

/// Swapped detections (two agents' detections exchange identities).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Swaps {
    /// Whether the term acts.
    pub enabled: bool,
    /// Swap probability per frame for two agents in contact (r = 1 BL).
    pub close_prob: f64,
    /// Distance (BL beyond contact) over which the probability falls by 1/e.
    pub close_range_bl: f64,
}

impl Default for CameraParams {
    /// A perfect 60 fps camera: no latency, no noise, no misses or swaps.
    fn default() -> Self {
        Self {
            fps: 60.0,
            latency: Latency::default(),
            noise: DetectionNoise::default(),
            misses: Misses::default(),
            swaps: Swaps::default(),
            pixels: Pixels::default(),
        }
    }
}

impl CameraParams {
    /// Checks every value; returns (field, reason).
    pub fn check(&self) -> Result<(), Rejection> {
        within("camera.fps", self.fps, 1.0, 10_000.0, "")?;
        non_negative("camera.latency.frames", self.latency.frames)?;
        if self.latency.frames > 100.0 {
            return Err(Rejection::new(
                "camera.latency.frames",
                format!("must be ≤ 100 frames, got {}", self.latency.frames),
            ));
        }
        non_negative("camera.latency.jitter_frames", self.latency.jitter_frames)?;
        if self.latency.jitter_frames > 10.0 {
            return Err(Rejection::new(
                "camera.latency.jitter_frames",
                format!("must be ≤ 10 frames, got {}", self.latency.jitter_frames),
            ));
        }
        non_negative("camera.noise.sigma_bl", self.noise.sigma_bl)?;
        non_negative("camera.noise.bias_bl", self.noise.bias_bl)?;
        if self.noise.enabled && self.noise.bias_bl > 0.0 {
            positive("camera.noise.bias_time_s", self.noise.bias_time_s)?;
        } else {
            non_negative("camera.noise.bias_time_s", self.noise.bias_time_s)?;
        }
        probability("camera.misses.prob", self.misses.prob)?;
        probability("camera.misses.close_prob", self.misses.close_prob)?;
        non_negative("camera.misses.close_range_bl", self.misses.close_range_bl)?;
        probability("camera.swaps.close_prob", self.swaps.close_prob)?;
        non_negative("camera.swaps.close_range_bl", self.swaps.close_range_bl)?;
        self.pixels.check().map_err(|r| r.under("camera.pixels"))
    }

    /// The nominal latency in frames (0 when the term is off).
    pub fn nominal_latency_frames(&self) -> f64 {
        if self.latency.enabled {
            self.latency.frames
        } else {
            0.0
        }
    }
}

/// What the tracker sees: a capture timestamp and each agent's measured position.
#[derive(Debug, Clone, PartialEq)]
pub struct Observation {
    /// When the frame was captured (s), as the camera reports it.
    pub t: f64,
    /// Measured position per agent; `None` is a missed detection.
    pub agents: Vec<Option<Vec2>>,
}

/// A simulated camera (see the module documentation).
#[derive(Debug, Clone)]
pub struct Camera {
    params: CameraParams,
    latency_rng: ChaCha8Rng,
    noise_rng: ChaCha8Rng,
    miss_rng: ChaCha8Rng,
    swap_rng: ChaCha8Rng,
    /// True positions at each frame, oldest first.
    history: VecDeque<(f64, Vec<Vec2>)>,
    bias: Vec<Vec2>,
}

/// `a·exp(−(r − 1)/ℓ)`, 0 when ℓ = 0.
fn near(a: f64, r: f64, range: f64) -> f64 {
    if a > 0.0 && range > 0.0 {
        a * (-(r - 1.0).max(0.0) / range).exp()
    } else {
        0.0
    }
}

impl Camera {
    /// A camera with its own random streams.
    pub fn new(params: CameraParams, seed: u64) -> Self {
        Self {
            params,
            latency_rng: stream(seed, Stream::CameraLatency),
            noise_rng: stream(seed, Stream::CameraNoise),
            miss_rng: stream(seed, Stream::CameraMisses),
            swap_rng: stream(seed, Stream::CameraSwaps),
            history: VecDeque::new(),
            bias: vec![],
        }
    }

    /// Seconds between frames.
    pub fn frame_period(&self) -> f64 {
        1.0 / self.params.fps
    }

    /// The parameters.
    pub fn params(&self) -> &CameraParams {
        &self.params
    }

    /// The nominal latency (s): what the estimator is told.
    pub fn nominal_latency(&self) -> f64 {
        self.params.nominal_latency_frames() * self.frame_period()
    }

    /// Records the true positions `truth` at frame time `t` and returns the observation
    /// delivered now. Before the first frame the agents are taken to have rested where the
    /// first frame shows them. Frames must come in time order.
    pub fn capture(&mut self, t: f64, truth: &[Vec2]) -> Option<Observation> {
        let period = self.frame_period();
        self.history.push_back((t, truth.to_vec()));
        let lat = &self.params.latency;
        let nominal = self.params.nominal_latency_frames();
        let actual = if lat.enabled && lat.jitter_frames > 0.0 {
            (nominal + lat.jitter_frames * normal(&mut self.latency_rng)).max(0.0)
        } else {
            nominal
        };
        let keep = (nominal + 8.0 * lat.jitter_frames).ceil() as usize + 3;
        while self.history.len() > keep {
            self.history.pop_front();
        }
        let seen = self.truth_at(t - actual * period);
        let mut agents: Vec<Option<Vec2>> = if self.params.pixels.enabled {
            self.params
                .pixels
                .detect(&seen)
                .into_iter()
                .map(Some)
                .collect()
        } else {
            seen.iter().map(|p| Some(*p)).collect()
        };
        self.add_noise(&mut agents, period);
        self.drop_misses(&seen, &mut agents);
        self.swap(&seen, &mut agents);
        Some(Observation {
            t: t - nominal * period,
            agents,
        })
    }

    /// The true positions at time `tc`, interpolated linearly between recorded frames.
    fn truth_at(&self, tc: f64) -> Vec<Vec2> {
        let (first, last) = (
            self.history.front().expect("a frame was just recorded"),
            self.history.back().expect("a frame was just recorded"),
        );
        let eps = 1e-9 * self.frame_period();
        if tc <= first.0 + eps {
            return first.1.clone();
        }
        if tc >= last.0 - eps {
            return last.1.clone();
        }
        for w in self.history.iter().zip(self.history.iter().skip(1)) {
            let ((t0, p0), (t1, p1)) = w;
            if (tc - t1).abs() <= eps {
                return p1.clone();
            }
            if tc < *t1 {
                let s = (tc - t0) / (t1 - t0);
                return p0.iter().zip(p1).map(|(a, b)| a + (b - a) * s).collect();
            }
        }
        last.1.clone()
    }

    fn add_noise(&mut self, agents: &mut [Option<Vec2>], period: f64) {
        let n = &self.params.noise;
        if !n.enabled {
            return;
        }
        let rng = &mut self.noise_rng;
        if n.bias_bl > 0.0 {
            if self.bias.len() != agents.len() {
                self.bias = (0..agents.len())
                    .map(|_| Vec2::new(normal(rng), normal(rng)) * n.bias_bl)
                    .collect();
            } else {
                let a = (-period / n.bias_time_s).exp();
                let s = n.bias_bl * (1.0 - a * a).sqrt();
                for b in &mut self.bias {
                    *b = *b * a + Vec2::new(normal(rng), normal(rng)) * s;
                }
            }
        }
        for (i, p) in agents.iter_mut().enumerate() {
            let Some(p) = p else { continue };
            if n.sigma_bl > 0.0 {
                *p += Vec2::new(normal(rng), normal(rng)) * n.sigma_bl;
            }
            if let Some(b) = self.bias.get(i) {
                *p += b;
            }
        }
    }

    fn drop_misses(&mut self, seen: &[Vec2], agents: &mut [Option<Vec2>]) {
        let m = &self.params.misses;
        if !m.enabled {
            return;
        }
        for (i, a) in agents.iter_mut().enumerate() {
            let r = nearest(seen, i);
            let p = (m.prob + near(m.close_prob, r, m.close_range_bl)).min(1.0);
            if p > 0.0 && self.miss_rng.random::<f64>() < p {
                *a = None;
            }
        }
    }

    fn swap(&mut self, seen: &[Vec2], agents: &mut [Option<Vec2>]) {
        let s = &self.params.swaps;
        if !s.enabled || s.close_prob == 0.0 {
            return;
        }
        let n = seen.len();
        let mut done = vec![false; n];
        for i in 0..n {
            for j in (i + 1)..n {
                if done[i] || done[j] {
                    continue;
                }
                let p = near(s.close_prob, (seen[j] - seen[i]).norm(), s.close_range_bl);
                if p > 0.0 && self.swap_rng.random::<f64>() < p {
                    agents.swap(i, j);
                    done[i] = true;
                    done[j] = true;
                }
            }
        }
    }
}

/// Distance from agent `i` to its nearest neighbour (∞ when alone).
fn nearest(p: &[Vec2], i: usize) -> f64 {
    p.iter()
        .enumerate()
        .filter(|(j, _)| *j != i)
        .map(|(_, q)| (q - p[i]).norm())
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn latency(frames: f64, jitter: f64) -> CameraParams {
        CameraParams {
            latency: Latency {
                enabled: true,
                frames,
                jitter_frames: jitter,
            },
            ..Default::default()
        }
    }

    #[test]
    fn latency_delays_by_whole_frames() {
        let mut c = Camera::new(latency(1.0, 0.0), 1);
        let p = [Vec2::new(1.0, 2.0)];
        let o = c.capture(0.0, &p).unwrap();
        assert_eq!(
            o.agents[0],
            Some(p[0]),
            "the agents rested before the first frame"
        );
        let o = c.capture(1.0 / 60.0, &[Vec2::new(5.0, 5.0)]).unwrap();
        assert_eq!(o.t, 0.0);
        assert_eq!(o.agents[0], Some(Vec2::new(1.0, 2.0)));
    }

    #[test]
    fn jittered_latency_is_stamped_nominal_but_shows_other_times() {
        let mut c = Camera::new(latency(1.0, 0.3), 2);
        let period = 1.0 / 60.0;
        let mut off_nominal = 0;
        for k in 0..200 {
            let t = k as f64 * period;
            // an agent moving at 1 BL/s along x: its detected x is the time it was seen
            let o = c.capture(t, &[Vec2::new(t, 0.0)]).unwrap();
            assert!(
                (o.t - (t - period)).abs() < 1e-12,
                "stamped with the nominal latency"
            );
            let seen = o.agents[0].unwrap().x;
            if k > 20 && (seen - o.t).abs() > 1e-9 {
                off_nominal += 1;
            }
            assert!(seen <= t + 1e-12);
        }
        assert!(
            off_nominal > 150,
            "{off_nominal} frames off the nominal latency"
        );
    }

    fn misses(prob: f64, close: f64) -> CameraParams {
        CameraParams {
            misses: Misses {
                enabled: true,
                prob,
                close_prob: close,
                close_range_bl: 0.3,
            },
            ..Default::default()
        }
    }

    fn count_misses(c: &mut Camera, p: &[Vec2], frames: usize) -> usize {
        (0..frames)
            .map(|k| {
                c.capture(k as f64 / 60.0, p)
                    .unwrap()
                    .agents
                    .iter()
                    .filter(|a| a.is_none())
                    .count()
            })
            .sum()
    }

    #[test]
    fn misses_happen_at_about_the_set_rate() {
        let mut c = Camera::new(misses(0.1, 0.0), 7);
        let p = [Vec2::zeros(), Vec2::new(3.0, 0.0)];
        let m = count_misses(&mut c, &p, 5000);
        assert!((800..1200).contains(&m), "{m} misses of 10000");
    }

    #[test]
    fn misses_rise_as_agents_get_close() {
        let mut c = Camera::new(misses(0.01, 0.3), 8);
        let far = count_misses(&mut c, &[Vec2::zeros(), Vec2::new(3.0, 0.0)], 3000);
        let close = count_misses(&mut c, &[Vec2::zeros(), Vec2::new(1.1, 0.0)], 3000);
        let touching = count_misses(&mut c, &[Vec2::zeros(), Vec2::new(1.0, 0.0)], 3000);
        assert!(far < close && close < touching, "{far} {close} {touching}");
        // at contact the rate is p + p_c = 31%
        assert!((1650..2070).contains(&touching), "{touching} of 6000");
    }

    #[test]
    fn swaps_happen_only_close() {
        let params = CameraParams {
            swaps: Swaps {
                enabled: true,
                close_prob: 0.2,
                close_range_bl: 0.2,
            },
            ..Default::default()
        };
        let mut c = Camera::new(params, 9);
        let count = |c: &mut Camera, r: f64| {
            let p = [Vec2::zeros(), Vec2::new(r, 0.0)];
            (0..2000)
                .filter(|k| c.capture(*k as f64 / 60.0, &p).unwrap().agents[0] != Some(p[0]))
                .count()
        };
        let (touching, far) = (count(&mut c, 1.0), count(&mut c, 4.0));
        assert!(
            (320..480).contains(&touching),
            "{touching} swaps of 2000 at contact"
        );
        assert_eq!(far, 0);
    }

    #[test]
    fn bias_wanders_slowly_and_noise_does_not() {
        let params = CameraParams {
            noise: DetectionNoise {
                enabled: true,
                sigma_bl: 0.0,
                bias_bl: 0.05,
                bias_time_s: 10.0,
            },
            ..Default::default()
        };
        let mut c = Camera::new(params, 10);
        let p = [Vec2::zeros()];
        let e: Vec<Vec2> = (0..6000)
            .map(|k| c.capture(k as f64 / 60.0, &p).unwrap().agents[0].unwrap())
            .collect();
        let step = e
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .fold(0.0, f64::max);
        assert!(
            step < 0.02,
            "the bias changes by at most {step} BL per frame"
        );
        let spread = e.iter().map(|v| v.norm()).fold(0.0, f64::max);
        assert!(spread > 0.02, "the bias is there: {spread}");
    }

    #[test]
    fn check_names_the_field() {
        let mut p = misses(1.5, 0.0);
        assert_eq!(p.check().unwrap_err().field, "camera.misses.prob");
        p.misses.prob = f64::NAN;
        assert_eq!(p.check().unwrap_err().field, "camera.misses.prob");
        let l = latency(-1.0, 0.0);
        assert_eq!(l.check().unwrap_err().field, "camera.latency.frames");
    }
}

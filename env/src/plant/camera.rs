//! The camera model: frame rate, latency, detection noise and missed detections.

use std::collections::VecDeque;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

use crate::math::Vec2;

/// Camera parameters of a disturbance preset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraParams {
    /// Frames per second (the control rate).
    pub fps: f64,
    /// Frames between capture and delivery of an observation.
    pub latency_frames: u32,
    /// Standard deviation of the detection noise per coordinate (BL).
    pub noise_bl: f64,
    /// Probability that an agent is not detected in a frame.
    pub miss_prob: f64,
}

impl Default for CameraParams {
    /// 60 fps, one frame of latency, 0.02 BL noise, 1% missed detections.
    fn default() -> Self {
        Self {
            fps: 60.0,
            latency_frames: 1,
            noise_bl: 0.02,
            miss_prob: 0.01,
        }
    }
}

/// What the tracker sees: a capture timestamp and each agent's measured position.
#[derive(Debug, Clone, PartialEq)]
pub struct Observation {
    /// When the frame was captured (s).
    pub t: f64,
    /// Measured position per agent; `None` is a missed detection.
    pub agents: Vec<Option<Vec2>>,
}

/// A simulated camera: noisy, sometimes blind, and late by `latency_frames`.
#[derive(Debug, Clone)]
pub struct Camera {
    params: CameraParams,
    rng: ChaCha8Rng,
    pipeline: VecDeque<Observation>,
}

impl Camera {
    /// A camera with its own random stream.
    pub fn new(params: CameraParams, seed: u64) -> Self {
        Self {
            params,
            rng: ChaCha8Rng::seed_from_u64(seed ^ 0xCA3E_7A00_D1A6_0001),
            pipeline: VecDeque::new(),
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

    /// Captures a frame of `truth` at time `t` and returns the observation delivered now
    /// (the one captured `latency_frames` frames ago), if there is one yet.
    pub fn capture(&mut self, t: f64, truth: &[Vec2]) -> Option<Observation> {
        let noise = self.params.noise_bl;
        let miss = self.params.miss_prob;
        let rng = &mut self.rng;
        let agents = truth
            .iter()
            .map(|p| {
                if miss > 0.0 && rng.random::<f64>() < miss {
                    return None;
                }
                if noise > 0.0 {
                    let nx: f64 = StandardNormal.sample(rng);
                    let ny: f64 = StandardNormal.sample(rng);
                    Some(p + Vec2::new(nx, ny) * noise)
                } else {
                    Some(*p)
                }
            })
            .collect();
        self.pipeline.push_back(Observation { t, agents });
        if self.pipeline.len() > self.params.latency_frames as usize {
            self.pipeline.pop_front()
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latency_delays_by_whole_frames() {
        let mut c = Camera::new(
            CameraParams {
                fps: 60.0,
                latency_frames: 1,
                noise_bl: 0.0,
                miss_prob: 0.0,
            },
            1,
        );
        let p = [Vec2::new(1.0, 2.0)];
        assert!(c.capture(0.0, &p).is_none());
        let o = c.capture(1.0 / 60.0, &[Vec2::new(5.0, 5.0)]).unwrap();
        assert_eq!(o.t, 0.0);
        assert_eq!(o.agents[0], Some(Vec2::new(1.0, 2.0)));
    }

    #[test]
    fn misses_happen_at_about_the_set_rate() {
        let mut c = Camera::new(
            CameraParams {
                fps: 60.0,
                latency_frames: 0,
                noise_bl: 0.02,
                miss_prob: 0.1,
            },
            7,
        );
        let p = [Vec2::zeros(); 2];
        let misses: usize = (0..5000)
            .map(|k| {
                c.capture(k as f64, &p)
                    .unwrap()
                    .agents
                    .iter()
                    .filter(|a| a.is_none())
                    .count()
            })
            .sum();
        assert!((800..1200).contains(&misses), "{misses} misses of 10000");
    }
}

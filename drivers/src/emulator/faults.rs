//! Fault injection for the emulator: `--faults drop=0.05,delay=0.1:30,corrupt=0.02,...`.

use image::GrayImage;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::log::EventLog;
use magbench_env::Vec2;
use magbench_env::input::Rejection;

/// Which link a disconnect cuts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// The coil link.
    Coil,
    /// The camera's frame stream.
    Camera,
}

/// The faults an emulator run injects.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FaultPlan {
    /// Each frame is dropped (never sent) with this probability.
    pub drop: f64,
    /// Each frame is sent late, by `.1` ms, with probability `.0`.
    pub delay: Option<(f64, f64)>,
    /// This long (s) after the host's HELLO, a link is cut.
    pub disconnect: Option<(f64, Cut)>,
    /// Each coil-link chunk the device receives, and each reply it sends, has one byte flipped
    /// with this probability.
    pub corrupt: f64,
    /// From `.0` s after the host's HELLO, for `.1` s, the camera repeats one frame.
    pub stuck: Option<(f64, f64)>,
}

/// The syntax, for help texts.
pub const FAULT_SYNTAX: &str = "drop=P | delay=P:MS | disconnect=T[:coil|:camera] | corrupt=P | stuck=T:D (comma-separated; P probability, MS milliseconds, T and D seconds of device time after the host's HELLO)";

impl FaultPlan {
    /// Parses a comma-separated fault list; a rejection names the fault (`drop`, `delay`, ...)
    /// and why.
    pub fn parse(spec: &str) -> Result<FaultPlan, Rejection> {
        let mut plan = FaultPlan::default();
        for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (kind, args) = item.split_once('=').ok_or_else(|| {
                Rejection::new(item, format!("expected KIND=VALUE ({FAULT_SYNTAX})"))
            })?;
            let bad = |reason: String| Rejection::new(kind, format!("{item:?}: {reason}"));
            let nums = |n: usize| -> Result<Vec<f64>, Rejection> {
                let parts: Vec<&str> = args.split(':').collect();
                let v: Result<Vec<f64>, _> =
                    parts.iter().take(n).map(|p| p.parse::<f64>()).collect();
                let v = v.map_err(|_| bad("not a number".into()))?;
                if v.len() != n || v.iter().any(|x| !x.is_finite() || *x < 0.0) {
                    return Err(bad(format!(
                        "needs {n} non-negative number(s) ({FAULT_SYNTAX})"
                    )));
                }
                Ok(v)
            };
            let prob = |p: f64| {
                if p <= 1.0 {
                    Ok(p)
                } else {
                    Err(bad("a probability is at most 1".into()))
                }
            };
            match kind {
                "drop" => plan.drop = prob(nums(1)?[0])?,
                "corrupt" => plan.corrupt = prob(nums(1)?[0])?,
                "delay" => {
                    let v = nums(2)?;
                    plan.delay = Some((prob(v[0])?, v[1]));
                }
                "stuck" => {
                    let v = nums(2)?;
                    plan.stuck = Some((v[0], v[1]));
                }
                "disconnect" => {
                    let (t, which) = match args.split_once(':') {
                        Some((t, "coil")) => (t, Cut::Coil),
                        Some((t, "camera")) => (t, Cut::Camera),
                        Some(_) => return Err(bad("the link is `coil` or `camera`".into())),
                        None => (args, Cut::Coil),
                    };
                    let t: f64 = t.parse().map_err(|_| bad("not a number".into()))?;
                    if !t.is_finite() || t < 0.0 {
                        return Err(bad("the time must be ≥ 0".into()));
                    }
                    plan.disconnect = Some((t, which));
                }
                other => {
                    return Err(Rejection::new(
                        other,
                        format!("unknown fault ({FAULT_SYNTAX})"),
                    ));
                }
            }
        }
        Ok(plan)
    }

    /// True when a frame at time `t` is repeated from the stuck frame.
    pub fn stuck_at(&self, t: f64) -> bool {
        self.stuck.is_some_and(|(t0, d)| t >= t0 && t < t0 + d)
    }
}

/// What becomes of one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Delivery {
    /// Send it.
    Send,
    /// Send it this many milliseconds late.
    Delay(f64),
    /// Never send it (dropped, or the stream is cut).
    Withhold,
}

/// The frame faults of a run, drawn from their own seeded stream: a stuck camera, dropped and
/// delayed frames, a cut stream. Link faults (corruption, a coil disconnect) are the coil
/// server's.
pub struct FaultInjector {
    plan: FaultPlan,
    rng: ChaCha8Rng,
    stuck_frame: Option<GrayImage>,
    was_stuck: bool,
    camera_cut: bool,
}

impl FaultInjector {
    /// The injector of `plan`, drawing with `seed`.
    pub fn new(plan: FaultPlan, seed: u64) -> Self {
        Self {
            plan,
            rng: ChaCha8Rng::seed_from_u64(seed ^ 0xF4A3E5),
            stuck_frame: None,
            was_stuck: false,
            camera_cut: false,
        }
    }

    /// The image of the frame at device time `t` (`since_hello` after the host's HELLO): the
    /// repeated frame while the camera is stuck, else `render()`. Logs when sticking starts
    /// and ends.
    pub fn image(
        &mut self,
        t: f64,
        since_hello: Option<f64>,
        render: impl FnOnce() -> GrayImage,
        (log, in_force, truth): (&EventLog, &[f64], &[Vec2]),
    ) -> GrayImage {
        let stuck = since_hello.is_some_and(|s| self.plan.stuck_at(s));
        let image = match (&self.stuck_frame, stuck) {
            (Some(img), true) => img.clone(),
            _ => render(),
        };
        if stuck && !self.was_stuck {
            self.stuck_frame = Some(image.clone());
            log.event(
                t,
                "fault_stuck_start",
                None,
                in_force,
                truth,
                "the camera repeats this frame",
            );
        }
        if !stuck && self.was_stuck {
            self.stuck_frame = None;
            log.event(t, "fault_stuck_end", None, in_force, truth, "");
        }
        self.was_stuck = stuck;
        image
    }

    /// Whether frame `k` at device time `t` goes out, and when. `cut_camera` is called once,
    /// when the camera stream is cut.
    pub fn delivery(
        &mut self,
        k: u64,
        t: f64,
        since_hello: Option<f64>,
        cut_camera: impl FnOnce(),
        (log, in_force): (&EventLog, &[f64]),
    ) -> Delivery {
        if let Some((tc, Cut::Camera)) = self.plan.disconnect
            && since_hello.is_some_and(|s| s >= tc)
            && !self.camera_cut
        {
            self.camera_cut = true;
            // logged before the cut, so that the host's reaction is logged after it
            log.event(
                t,
                "fault_disconnect",
                None,
                in_force,
                &[],
                "camera stream cut",
            );
            cut_camera();
        }
        if self.camera_cut {
            return Delivery::Withhold;
        }
        if self.plan.drop > 0.0 && self.rng.random::<f64>() < self.plan.drop {
            log.event(
                t,
                "fault_drop",
                None,
                in_force,
                &[],
                &format!("frame {k} dropped"),
            );
            return Delivery::Withhold;
        }
        if let Some((p, ms)) = self.plan.delay
            && self.rng.random::<f64>() < p
        {
            log.event(
                t,
                "fault_delay",
                None,
                in_force,
                &[],
                &format!("frame {k} delayed {ms} ms"),
            );
            return Delivery::Delay(ms);
        }
        Delivery::Send
    }
}

/// Flips one random byte of `bytes` with probability `p`; returns whether it did.
pub fn maybe_corrupt(bytes: &mut [u8], p: f64, rng: &mut ChaCha8Rng) -> bool {
    if p <= 0.0 || bytes.is_empty() || rng.random::<f64>() >= p {
        return false;
    }
    let i = rng.random_range(0..bytes.len());
    bytes[i] ^= 1 << rng.random_range(0..8);
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_fault_and_rejects_nonsense() {
        let p = FaultPlan::parse(
            "drop=0.05, delay=0.1:30,disconnect=4:camera,corrupt=0.02,stuck=2:0.5",
        )
        .unwrap();
        assert_eq!(p.drop, 0.05);
        assert_eq!(p.delay, Some((0.1, 30.0)));
        assert_eq!(p.disconnect, Some((4.0, Cut::Camera)));
        assert!(p.stuck_at(2.2) && !p.stuck_at(2.6));
        assert!(FaultPlan::parse("drop=2").is_err());
        assert_eq!(FaultPlan::parse("fire=1").unwrap_err().field, "fire");
        assert!(FaultPlan::parse("delay=0.5").is_err());
        assert_eq!(
            FaultPlan::parse("disconnect=3").unwrap().disconnect,
            Some((3.0, Cut::Coil))
        );
    }
}

//! Stretches of a log in which the team is stuck in contact, found from the observed positions
//! alone (what a real rig's log holds: detections, with their noise).
//!
//! Two agents that touch stick (env's plant freezes the pair) and then move as one, which says
//! nothing of the parameters. A pair is taken as stuck over a stretch of consecutive frames in
//! which its observed separation stays within contact (`2 ×` [`AGENT_RADIUS_BL`]) plus a noise
//! margin for at least [`STUCK_FRAMES`] frames and does not rise across the stretch (the pair
//! is not moving apart). The margin is [`CONTACT_NOISE_SIGMAS`] standard deviations of the
//! observed separation, whose noise is that of two independent detections (`√2 σ`), with σ
//! estimated from the log itself ([`detection_sigma`]), and never below
//! [`CONTACT_MARGIN_MIN_BL`]. The fit leaves such frames out of the fit and of the held-out
//! check.

use magbench_env::plant::AGENT_RADIUS_BL;

use super::log::LoggedRun;
use super::model::frame_period;

/// Standard deviations of the observed separation's noise the contact band allows: a pair
/// whose true separation lies outside the band enters it by noise in at most 0.13% of frames.
pub const CONTACT_NOISE_SIGMAS: f64 = 3.0;

/// Smallest noise margin (BL) above contact: a noise-free log still shows a stuck pair at
/// contact to within the plant's collision resolution, well under a hundredth of a body length.
pub const CONTACT_MARGIN_MIN_BL: f64 = 0.01;

/// Fewest consecutive frames within the band that make a stuck stretch: a pair outside the
/// band enters it by noise with a probability of at most 0.13% per frame, so 10 frames in a
/// row (1/6 s at 60 fps) do not happen by chance; a shorter visit is a pair passing by.
pub const STUCK_FRAMES: usize = 10;

/// The frames of one run found stuck in contact.
#[derive(Debug, Clone, PartialEq)]
pub struct StuckFrames {
    /// The run's file.
    pub source: String,
    /// Per frame of the run: whether it lies in a stuck stretch.
    pub stuck: Vec<bool>,
    /// Stretches found.
    pub stretches: usize,
    /// The band's noise margin above contact (BL).
    pub margin_bl: f64,
    /// Seconds of the run in stuck stretches (frames × the run's frame period).
    pub seconds: f64,
    /// Seconds of the run (frames × its frame period).
    pub run_seconds: f64,
}

impl StuckFrames {
    /// Frames in stuck stretches.
    pub fn frames(&self) -> usize {
        self.stuck.iter().filter(|s| **s).count()
    }
}

/// Detection noise σ (BL per coordinate) of `run`, from the second differences of every
/// agent's observed coordinates over three consecutive frames: white detection noise gives
/// them a variance of `6σ²`, the motion between frames little at camera rates. The median
/// absolute value (÷ 0.6745 for a normal's σ) keeps command steps and swaps from inflating it;
/// 0 when no agent was seen in three consecutive frames.
pub fn detection_sigma(run: &LoggedRun) -> f64 {
    let f = &run.frames;
    let mut d = vec![];
    for k in 1..f.len().saturating_sub(1) {
        if f[k].frame != f[k - 1].frame + 1 || f[k + 1].frame != f[k].frame + 1 {
            continue;
        }
        for i in 0..f[k].agents.len() {
            if let (Some(a), Some(b), Some(c)) =
                (f[k - 1].agents[i], f[k].agents[i], f[k + 1].agents[i])
            {
                let dd = a - 2.0 * b + c;
                d.extend([dd.x.abs(), dd.y.abs()]);
            }
        }
    }
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2] / 0.6745 / 6f64.sqrt()
}

/// The frames of `run` in which some pair of agents is stuck in contact (see the module).
pub fn stuck_frames(run: &LoggedRun) -> StuckFrames {
    let f = &run.frames;
    let margin =
        (CONTACT_NOISE_SIGMAS * 2f64.sqrt() * detection_sigma(run)).max(CONTACT_MARGIN_MIN_BL);
    let band = 2.0 * AGENT_RADIUS_BL + margin;
    let n = f.first().map_or(0, |fr| fr.agents.len());
    let mut stuck = vec![false; f.len()];
    let mut stretches = 0;
    for i in 0..n {
        for j in i + 1..n {
            // (frame position, separation) of the open stretch; a missed detection neither
            // breaks nor extends it, a gap in the frame index or a separation out of the band
            // closes it
            let mut open: Vec<(usize, f64)> = vec![];
            let mut first = 0;
            let mut close = |open: &mut Vec<(usize, f64)>, first: usize, end: usize| {
                if is_stuck(open, margin) {
                    stretches += 1;
                    for s in &mut stuck[first..end] {
                        *s = true;
                    }
                }
                open.clear();
            };
            for k in 0..f.len() {
                if k > 0 && f[k].frame != f[k - 1].frame + 1 && !open.is_empty() {
                    close(&mut open, first, k);
                }
                let Some(r) = f[k].agents[i]
                    .zip(f[k].agents[j])
                    .map(|(a, b)| (a - b).norm())
                else {
                    continue;
                };
                if r <= band {
                    if open.is_empty() {
                        first = k;
                    }
                    open.push((k, r));
                } else if !open.is_empty() {
                    close(&mut open, first, k);
                }
            }
            if !open.is_empty() {
                close(&mut open, first, f.len());
            }
        }
    }
    let period = frame_period(f);
    let frames = stuck.iter().filter(|s| **s).count();
    StuckFrames {
        source: run.source.clone(),
        stuck,
        stretches,
        margin_bl: margin,
        seconds: frames as f64 * period,
        run_seconds: f.len() as f64 * period,
    }
}

/// Whether the separations of a stretch within the band make a stuck pair: at least
/// [`STUCK_FRAMES`] of them, the mean of the last third no more than `margin` above that of the
/// first third (a pair moving apart rises across the band; a stuck one stays at contact).
fn is_stuck(open: &[(usize, f64)], margin: f64) -> bool {
    if open.len() < STUCK_FRAMES {
        return false;
    }
    let third = open.len() / 3;
    let mean = |s: &[(usize, f64)]| s.iter().map(|p| p.1).sum::<f64>() / s.len() as f64;
    mean(&open[open.len() - third..]) - mean(&open[..third]) <= margin
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::log::LoggedFrame;
    use magbench_env::Vec2;

    /// A run of `len` frames at 60 fps, agent 1 at `sep(k)` from agent 0 along x, both with a
    /// deterministic pseudo-noise of about `sigma`.
    fn run(len: usize, sigma: f64, sep: impl Fn(usize) -> f64) -> LoggedRun {
        let jitter = |k: usize, c: usize| sigma * (((k * 7 + c * 13) % 11) as f64 / 5.0 - 1.0);
        LoggedRun {
            source: "log.csv".into(),
            frames: (0..len)
                .map(|k| LoggedFrame {
                    frame: k as u64,
                    t: k as f64 / 60.0,
                    agents: vec![
                        Some(Vec2::new(10.0 + jitter(k, 0), 10.0 + jitter(k, 1))),
                        Some(Vec2::new(10.0 + sep(k) + jitter(k, 2), 10.0 + jitter(k, 3))),
                    ],
                    command: None,
                })
                .collect(),
        }
    }

    #[test]
    fn a_pair_at_contact_for_the_second_half_is_stuck_there_only() {
        let r = run(600, 0.02, |k| {
            if k < 300 { 3.0 - k as f64 / 150.0 } else { 1.0 }
        });
        let s = stuck_frames(&r);
        assert!(s.margin_bl > CONTACT_MARGIN_MIN_BL, "{s:?}");
        assert_eq!(s.stretches, 1);
        assert!(s.stuck[300..].iter().all(|v| *v));
        assert!(s.stuck[..250].iter().all(|v| !*v));
        assert!((s.seconds - 5.0).abs() < 0.5, "{}", s.seconds);
    }

    #[test]
    fn a_pair_kept_apart_or_passing_by_is_not_stuck() {
        assert_eq!(stuck_frames(&run(600, 0.02, |_| 1.8)).frames(), 0);
        // down to contact and straight back up: within the band for a few frames only
        let v = |k: usize| 1.0 + (k as f64 - 300.0).abs() / 15.0;
        assert_eq!(stuck_frames(&run(600, 0.02, v)).frames(), 0);
    }
}

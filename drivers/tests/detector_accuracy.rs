//! The detector finds both agents in emulated frames to within 0.25 px RMS of the true
//! centres, apart, nearly touching and touching — primed with the true positions, and from a
//! cold start: primed with positions up to 0.45 BL off (a hand-placed pair), or with positions
//! that have nothing to do with the frame. Run with `--nocapture` to see the figures.

use magbench_drivers::emulator::render::{RenderParams, Renderer};
use magbench_drivers::{Detector, RigConfig};
use magbench_env::Vec2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn rig() -> RigConfig {
    RigConfig::parse(
        include_str!("../../rigs/emulator.toml"),
        "rigs/emulator.toml",
    )
    .unwrap()
}

/// Frames of the emulator's renderer for `rig`, without a world, noise drawn with `seed`.
fn renderer(rig: &RigConfig, seed: u64) -> Renderer {
    Renderer::new(
        rig.pixels.clone(),
        rig.camera.size_px,
        None,
        RenderParams::default(),
        seed,
    )
}

/// What a fresh detector is primed with.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Prior {
    /// The true positions.
    Truth,
    /// The true positions moved by up to this far (BL) in random directions: identities must
    /// still come out right (each prior is nearer its own agent while the offset is < r/2).
    Offset(f64),
    /// Two corners of the field, unrelated to the frame: only the centres are scored (the
    /// identities are arbitrary).
    Unrelated,
}

/// RMS pixel error over `frames` pairs at separation drawn from `sep` (BL), random heading and
/// sub-pixel position, each frame detected by a fresh detector (no memory) primed by `prior`.
fn rms_px(sep: (f64, f64), frames: usize, seed: u64, prior: Prior) -> (f64, usize) {
    let rig = rig();
    let mut renderer = renderer(&rig, seed);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut sum, mut n, mut missed) = (0.0, 0usize, 0usize);
    for _ in 0..frames {
        let c = Vec2::new(rng.random_range(8.0..22.0), rng.random_range(6.0..14.0));
        let phi = rng.random_range(0.0..std::f64::consts::TAU);
        let r = rng.random_range(sep.0..=sep.1);
        let d = Vec2::new(phi.cos(), phi.sin()) * (r / 2.0);
        let truth = [c - d, c + d];
        let img = renderer.render(&truth);
        let primed: Vec<Vec2> = match prior {
            Prior::Truth => truth.to_vec(),
            Prior::Offset(max) => truth
                .iter()
                .map(|t| {
                    let a = rng.random_range(0.0..std::f64::consts::TAU);
                    t + Vec2::new(a.cos(), a.sin()) * rng.random_range(0.0..=max)
                })
                .collect(),
            Prior::Unrelated => vec![Vec2::new(0.5, 0.5), Vec2::new(29.5, 19.5)],
        };
        let mut det = Detector::new(rig.detector.clone(), rig.pixels.clone(), &primed);
        let out = det.detect(&img);
        let px: Vec<Vec2> = truth.iter().map(|t| rig.pixels.to_px(*t)).collect();
        let found: Vec<Vec2> = out.px.iter().flatten().copied().collect();
        missed += 2 - found.len();
        let err = |order: [usize; 2]| -> f64 {
            found
                .iter()
                .zip(order)
                .map(|(p, i)| (p - px[i]).norm_squared())
                .sum()
        };
        sum += match (prior, found.len()) {
            // both found: either identity may be right when the prior says nothing
            (Prior::Unrelated, 2) => err([0, 1]).min(err([1, 0])),
            _ => out
                .px
                .iter()
                .zip(&px)
                .filter_map(|(p, t)| p.map(|p| (p - t).norm_squared()))
                .sum(),
        };
        n += found.len();
    }
    ((sum / n.max(1) as f64).sqrt(), missed)
}

#[test]
fn apart_nearly_touching_and_touching_within_a_quarter_pixel() {
    let cases = [
        ("apart (r 2-5 BL)", (2.0, 5.0)),
        ("nearly touching (gap 0.01-0.1 BL)", (1.01, 1.1)),
        ("touching (r = 1 BL)", (1.0, 1.0)),
    ];
    println!("| prior | case | RMS (px) | centres | missed |");
    println!("| --- | --- | --- | --- | --- |");
    for prior in [Prior::Truth, Prior::Offset(0.45), Prior::Unrelated] {
        for (k, (name, sep)) in cases.iter().enumerate() {
            let (rms, missed) = rms_px(*sep, 150, 11 + k as u64, prior);
            println!("| {prior:?} | {name} | {rms:.4} | 300 | {missed} |");
            assert_eq!(missed, 0, "{name}, {prior:?} prior: missed detections");
            assert!(rms <= 0.25, "{name}, {prior:?} prior: RMS {rms} px");
        }
    }
}

#[test]
fn tracking_keeps_identity_and_reports_a_missing_agent() {
    let rig = rig();
    let mut renderer = renderer(&rig, 5);
    let mut a = [Vec2::new(10.0, 10.0), Vec2::new(12.0, 10.0)];
    let mut det = Detector::new(rig.detector.clone(), rig.pixels.clone(), &a);
    // the pair rotates by 180° in 90 frames: identities must follow
    for k in 0..=90 {
        let phi = std::f64::consts::PI * k as f64 / 90.0;
        let d = Vec2::new(phi.cos(), phi.sin());
        a = [Vec2::new(11.0, 10.0) - d, Vec2::new(11.0, 10.0) + d];
        let out = det.detect(&renderer.render(&a));
        for (i, truth) in a.iter().enumerate() {
            let p = out.agents[i].expect("found");
            assert!(
                (p - truth).norm() < 0.05,
                "frame {k} agent {i}: {p:?} vs {truth:?}"
            );
        }
    }
    // one agent leaves the picture: it is reported missing, the other is still found
    let out = det.detect(&renderer.render(&[a[0]]));
    assert!(out.agents[0].is_some() && out.agents[1].is_none());
    // it comes back: found again
    let out = det.detect(&renderer.render(&a));
    assert!(out.agents[1].is_some_and(|p| (p - a[1]).norm() < 0.05));
}

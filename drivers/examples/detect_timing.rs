//! Times the detector on emulated frames of a pair turning in place (tracking windows on).
//! `cargo run --release -p magbench-drivers --example detect_timing` (`cargo xtask measure
//! --only detect-timing` runs it), printing a Markdown table.

use std::time::Instant;

use magbench_drivers::emulator::render::{RenderParams, Renderer};
use magbench_drivers::stats::percentile;
use magbench_drivers::{Detector, RigConfig};
use magbench_env::Vec2;

fn main() {
    let rig = RigConfig::parse(
        include_str!("../../rigs/emulator.toml"),
        "rigs/emulator.toml",
    )
    .unwrap();
    let mut renderer = Renderer::new(
        rig.pixels.clone(),
        rig.camera.size_px,
        None,
        RenderParams::default(),
        1,
    );
    let pair = |k: usize| {
        let phi = k as f64 * 0.01;
        let d = Vec2::new(phi.cos(), phi.sin());
        [Vec2::new(15.0, 10.0) - d, Vec2::new(15.0, 10.0) + d]
    };
    let frames: Vec<_> = (0..600).map(|k| renderer.render(&pair(k))).collect();
    let mut det = Detector::new(rig.detector.clone(), rig.pixels.clone(), &pair(0));
    let mut ms = Vec::new();
    for f in &frames {
        let t = Instant::now();
        let d = det.detect(f);
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        assert!(d.agents.iter().all(|a| a.is_some()));
    }
    let full: Vec<f64> = frames[..50]
        .iter()
        .map(|f| {
            let mut d = Detector::new(rig.detector.clone(), rig.pixels.clone(), &pair(0));
            let t = Instant::now();
            d.detect(f);
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    println!("| detection | frames | median (ms) | p99 (ms) |");
    println!("| --- | --- | --- | --- |");
    println!(
        "| tracking (windows about the last positions) | {} | {:.3} | {:.3} |",
        ms.len(),
        percentile(&ms, 0.5).unwrap(),
        percentile(&ms, 0.99).unwrap()
    );
    println!(
        "| full-frame search (a fresh detector) | {} | {:.3} | {:.3} |",
        full.len(),
        percentile(&full, 0.5).unwrap(),
        percentile(&full, 0.99).unwrap()
    );
}

//! A fake executor: synthetic, deterministic results without planners or trackers, for
//! testing the sweep machinery (resume, shards, merge, plots, regression checks) quickly.
//!
//! Planner `fake{p=0.7, cost=10, spin=0, sleep_ms=0, panic=false}`: solves with probability
//! `p`; the first solution arrives at a random iteration and its cost falls towards `cost`.
//! `spin` burns that many rounds of CPU work (for speed-up measurements), `sleep_ms` sleeps.
//! Tracker `fake{gain=1}`: RMS error ≈ 0.1/gain BL, reaching the goal while the error is small.
//! Everything is drawn from a ChaCha8 stream seeded by a hash of the run id. The environment
//! variable `MAGBENCH_FAKE_TRACKER_GAIN_SCALE` scales every fake tracker's gain, to inject a
//! "code change" without changing the configuration's label (regression-check tests). With
//! `MAGBENCH_FAKE_STALL_AFTER=N`, once N runs of the process have finished every later run
//! blocks until the process is killed: a sweep that is certainly unfinished when a test kills
//! it, whatever the machine's load.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use magbench_env::input::Rejection;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sha2::{Digest, Sha256};

use super::executor::base_record;
use super::record::AgentErrors;
use super::{Executor, ProgressRow, RunError, RunOutput, RunSpec, Status, Variant};
use crate::metrics::Metric;

/// Runs of this process the fake executor has finished.
static FINISHED: AtomicUsize = AtomicUsize::new(0);

/// Blocks for good once `MAGBENCH_FAKE_STALL_AFTER` runs have finished (see the module docs).
fn stall_if_asked() {
    let after = std::env::var("MAGBENCH_FAKE_STALL_AFTER")
        .ok()
        .and_then(|v| v.parse::<usize>().ok());
    if after.is_some_and(|n| FINISHED.load(Ordering::SeqCst) >= n) {
        loop {
            std::thread::park();
        }
    }
}

/// The fake executor.
#[derive(Debug, Clone, Copy, Default)]
pub struct FakeExecutor;

/// A 64-bit seed from a string (the first 8 bytes of its SHA-256).
pub fn seed_of(s: &str) -> u64 {
    let d = Sha256::digest(s.as_bytes());
    u64::from_le_bytes(d[..8].try_into().expect("8 bytes"))
}

fn num(v: &Variant, k: &str, default: f64) -> f64 {
    v.params.get(k).and_then(|p| p.as_f64()).unwrap_or(default)
}

fn check(v: &Variant, what: &str, known: &[&str]) -> Result<(), Rejection> {
    let refuse = |reason: String| Rejection::new("", reason);
    if v.name != "fake" {
        return Err(refuse(format!(
            "unknown {what} {:?} (the fake executor knows only \"fake\")",
            v.name
        )));
    }
    for (k, p) in &v.params {
        if !known.contains(&k.as_str()) {
            return Err(refuse(format!(
                "{}: unknown parameter {k:?} (known: {})",
                v.label(),
                known.join(", ")
            )));
        }
        if k != "panic" && p.as_f64().is_none() {
            return Err(refuse(format!("{}: {k} must be a number", v.label())));
        }
    }
    Ok(())
}

/// Burns `rounds` rounds of deterministic CPU work.
fn spin(rounds: u64) -> u64 {
    let mut h = Sha256::new();
    let mut acc = 0u64;
    for i in 0..rounds {
        h.update(i.to_le_bytes());
        if i % 64 == 63 {
            acc ^= u64::from_le_bytes(h.finalize_reset()[..8].try_into().expect("8 bytes"));
        }
    }
    acc
}

impl Executor for FakeExecutor {
    fn name(&self) -> &str {
        "fake"
    }

    fn check_planner(&self, v: &Variant) -> Result<(), Rejection> {
        check(v, "planner", &["p", "cost", "spin", "sleep_ms", "panic"])
    }

    fn check_tracker(&self, v: &Variant) -> Result<(), Rejection> {
        check(v, "tracker", &["gain"])
    }

    fn execute(&self, spec: &RunSpec) -> Result<RunOutput, RunError> {
        stall_if_asked();
        let t0 = Instant::now();
        let pv = &spec.planner;
        if matches!(pv.params.get("panic"), Some(super::ParamValue::Bool(true))) {
            panic!("fake planner asked to panic");
        }
        std::hint::black_box(spin(num(pv, "spin", 0.0) as u64));
        let sleep = num(pv, "sleep_ms", 0.0);
        if sleep > 0.0 {
            std::thread::sleep(Duration::from_secs_f64(sleep / 1000.0));
        }
        // The planner's stream depends on everything but the tracker and preset, like a real
        // planner seeded by the run's seed.
        let planner_key = format!("{}|{}|{}", spec.scenario_label, pv.label(), spec.seed);
        let mut rng = ChaCha8Rng::seed_from_u64(seed_of(&planner_key));
        let budget = spec.limits.iterations.unwrap_or(1000).max(10);
        let mut r = base_record(spec);
        let solved = rng.random::<f64>() < num(pv, "p", 0.7);
        let first = (budget as f64 * (0.05 + 0.8 * rng.random::<f64>())) as u64;
        let base_cost = num(pv, "cost", 10.0) * (1.0 + 0.3 * rng.random::<f64>());
        let secs_per_iter = 2e-5;
        let mut progress = vec![];
        let mut best = None;
        let step = (budget / 50).max(1);
        let mut it = 0;
        while it <= budget {
            if solved && it >= first {
                let c = base_cost * (1.0 + (first as f64 / (it as f64 + 1.0)).min(1.0));
                best = Some(best.map_or(c, |b: f64| b.min(c)));
            }
            progress.push(ProgressRow {
                run: spec.index,
                run_id: r.run_id.clone(),
                iteration: it,
                time_s: it as f64 * secs_per_iter,
                best_cost: best,
            });
            it += step;
        }
        r.set(Metric::Iterations, Some((budget) as f64));
        r.set(Metric::Nodes, Some((budget / 3) as f64));
        r.solved = solved;
        r.approximate = !solved;
        r.status = if solved {
            Status::Exact
        } else {
            Status::Approximate
        };
        r.set(Metric::Cost, if solved { best } else { None });
        r.set(
            Metric::GoalDistance,
            Some(if solved {
                0.2 * rng.random::<f64>()
            } else {
                1.0 + 5.0 * rng.random::<f64>()
            }),
        );
        r.set(
            Metric::FirstSolutionIteration,
            (solved.then_some(first)).map(|v| v as f64),
        );
        r.set(
            Metric::FirstSolutionTime,
            solved.then_some(first as f64 * secs_per_iter),
        );
        r.set(
            Metric::PlanEdges,
            Some((5 + (rng.random::<f64>() * 20.0) as u64) as f64),
        );
        r.set(
            Metric::PlanDuration,
            Some(10.0 + 30.0 * rng.random::<f64>()),
        );
        if let Some(tv) = &spec.tracker {
            let mut trng = ChaCha8Rng::seed_from_u64(seed_of(&spec.id()));
            let scale = std::env::var("MAGBENCH_FAKE_TRACKER_GAIN_SCALE")
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or(1.0);
            let gain = (num(tv, "gain", 1.0) * scale).max(1e-6);
            let noise = if spec.preset.as_deref() == Some("realistic") {
                1.5
            } else {
                1.0
            };
            let rms = 0.1 / gain * noise * (0.7 + 0.6 * trng.random::<f64>());
            r.set(Metric::RmsError, Some(rms));
            r.set(Metric::RmsErrorTrue, Some(rms * 0.8));
            r.set(Metric::RmsErrorSync, Some(rms * 1.2));
            r.set(Metric::RmsErrorTime, Some(rms * 2.0));
            r.set(Metric::RmsErrorNode, Some(rms * 1.5));
            r.set(Metric::MaxError, Some(rms * (2.0 + trng.random::<f64>())));
            // each agent's share, drawn from nothing (the random stream above stays as it was)
            let agents = spec.scenario.agents();
            r.per_agent = (0..agents)
                .map(|i| {
                    let e = rms * (0.8 + 0.4 * i as f64 / agents.max(2) as f64);
                    AgentErrors {
                        rms_bl: Some(e),
                        max_bl: Some(2.0 * e),
                        rms_true_bl: Some(0.8 * e),
                        max_true_bl: Some(1.6 * e),
                    }
                })
                .collect();
            let worst = |of: fn(&AgentErrors) -> Option<f64>| {
                r.per_agent.iter().filter_map(of).reduce(f64::max)
            };
            let (rms_worst, rms_true_worst, max_true) = (
                worst(|a| a.rms_bl),
                worst(|a| a.rms_true_bl),
                worst(|a| a.max_true_bl),
            );
            r.set(Metric::RmsErrorWorstAgent, rms_worst);
            r.worst_agent = Some(agents.saturating_sub(1) as u64);
            r.set(Metric::RmsErrorTrueWorstAgent, rms_true_worst);
            r.set(Metric::MaxErrorTrue, max_true);
            let reached = solved && rms < 0.3 && trng.random::<f64>() < 0.97;
            r.reached_goal = Some(reached);
            r.track_status = if reached { "reached-goal" } else { "timeout" }.into();
            r.set(
                Metric::TimeToGoal,
                reached.then(|| {
                    r.get(Metric::PlanDuration).unwrap_or(0.0) * (1.0 + 0.1 * trng.random::<f64>())
                }),
            );
            r.set(
                Metric::FinalDistance,
                Some(if reached {
                    0.3 * trng.random::<f64>()
                } else {
                    1.0 + trng.random::<f64>()
                }),
            );
            r.agent_contact = Some(false);
            r.set(
                Metric::WallContacts,
                Some(((trng.random::<f64>() * 3.0) as u64) as f64),
            );
            r.set(
                Metric::MissedFrames,
                Some(((trng.random::<f64>() * 10.0) as u64) as f64),
            );
            r.set(Metric::Replans, Some(0.0));
            r.set(
                Metric::TrackDuration,
                Some(r.get(Metric::PlanDuration).unwrap_or(0.0) * 1.1),
            );
            r.set(Metric::TrackTime, Some(0.0));
        }
        r.set(Metric::PlanTime, Some(t0.elapsed().as_secs_f64()));
        FINISHED.fetch_add(1, Ordering::SeqCst);
        Ok(RunOutput {
            record: r,
            progress,
            replay: None,
            replans: vec![],
        })
    }
}

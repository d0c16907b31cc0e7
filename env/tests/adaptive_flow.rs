//! The adaptive flow (Dormand–Prince 5(4)) against a fine reference integration (RK4 at a step
//! 100× smaller than `dt`), its determinism and its sampling rule, for teams of three to six.

use magbench_env::model::{
    Dp5Grid, ErrorBudget, Flow, TOLERANCE_BL, dp5_solve, rk4_step, step_schedule,
};
use magbench_env::{Control, MAX_AGENTS, PhysicalParams, PlanningModel, Vec2};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Reference refinement: RK4 steps per `dt`.
const FINE: usize = 100;

fn model() -> PlanningModel {
    PlanningModel::new(&PhysicalParams::default()).with_flow(Flow::PairAdaptive)
}

/// A random team of `n` agents in a 4.5 BL square, every pair between `r_min + 0.75` and
/// `r_max` apart.
fn team(rng: &mut ChaCha8Rng, n: usize, p: &PhysicalParams) -> Vec<Vec2> {
    loop {
        let s: Vec<Vec2> = (0..n)
            .map(|_| Vec2::new(rng.random_range(0.0..4.5), rng.random_range(0.0..4.5)))
            .collect();
        let ok = (0..n).all(|i| {
            ((i + 1)..n).all(|j| {
                let d = (s[i] - s[j]).norm();
                d > p.r_min + 0.75 && d < p.r_max
            })
        });
        if ok {
            return s;
        }
    }
}

/// A random command: any field angle, elevation up to 30° on every third, any gradient.
fn command(rng: &mut ChaCha8Rng, g: f64, k: usize) -> Control {
    Control {
        theta: rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
        alpha: if k.is_multiple_of(3) {
            rng.random_range(0.0..0.5)
        } else {
            0.0
        },
        grad: [rng.random_range(-g..=g), rng.random_range(-g..=g)],
    }
}

/// The fine reference's samples at every whole `dt` and at the end, up to and including the
/// first where two agents are closer than `r_min` (after it no planner keeps the motion).
fn reference(
    m: &PlanningModel,
    start: &[Vec2],
    u: &Control,
    duration: f64,
    r_min: f64,
) -> Vec<Vec<Vec2>> {
    let act = m.coil.actuation(u);
    let f = |p: &[Vec2], v: &mut [Vec2]| m.kinematics.velocities(p, &act, v);
    let (steps, rest) = step_schedule(duration, m.dt);
    let mut y = start.to_vec();
    let mut samples = Vec::new();
    for k in 0..steps + usize::from(rest > 0.0) {
        let h = if k < steps { m.dt } else { rest };
        for _ in 0..FINE {
            rk4_step(&f, &mut y, h / FINE as f64);
        }
        samples.push(y.clone());
        if closest(&y) < r_min {
            break;
        }
    }
    samples
}

/// The smallest separation of a team (BL).
fn closest(y: &[Vec2]) -> f64 {
    (0..y.len())
        .flat_map(|i| ((i + 1)..y.len()).map(move |j| (y[i] - y[j]).norm()))
        .fold(f64::INFINITY, f64::min)
}

fn deviation(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// Every visited sample of a valid team (all separations at least `r_min`), the end included,
/// within the tolerance of the fine reference, over many random motions of teams of three to
/// six (planar and elevated commands), and for each team size the largest deviation no larger
/// than fixed-step RK4's at `dt` on the same samples. A motion is followed up to its first
/// invalid sample, where the proximity check stops it.
#[test]
fn adaptive_samples_match_a_fine_reference_within_the_tolerance() {
    let p = PhysicalParams::default();
    let m = model();
    let rk4 = m.with_flow(Flow::Rk4);
    let g = m.coil.gradient_limit();
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut rows = Vec::new();
    for n in 3..=6 {
        let mut w = Work::default();
        for k in 0..60 {
            let start = team(&mut rng, n, &p);
            let u = command(&mut rng, g, k);
            let duration = rng.random_range(15..=120) as f64 / 60.0;
            let reference = reference(&m, &start, &u, duration, p.r_min);
            let mut seen = Vec::new();
            let mut out = vec![Vec2::zeros(); n];
            m.propagate_with(&start, &u, duration, &mut out, |s| {
                seen.push(s.to_vec());
                seen.len() < reference.len()
            });
            assert_eq!(seen.len(), reference.len(), "n = {n}, motion {k}");
            for (i, (a, b)) in seen.iter().zip(&reference).enumerate() {
                if closest(b) < p.r_min {
                    continue;
                }
                let d = deviation(a, b);
                w.worst = w.worst.max(d);
                w.compared += 1;
                assert!(
                    d <= TOLERANCE_BL,
                    "n = {n}, motion {k}, sample {i}: {d:e} BL from the reference"
                );
            }
            assert_eq!(out, *seen.last().unwrap());
            let mut i = 0;
            rk4.propagate_with(&start, &u, duration, &mut out, |s| {
                if closest(&reference[i]) >= p.r_min {
                    w.worst_rk4 = w.worst_rk4.max(deviation(s, &reference[i]));
                }
                i += 1;
                i < reference.len()
            });
            w.whole += usize::from(closest(reference.last().unwrap()) >= p.r_min);
            w.count(&m, &start, &u, duration, reference.len());
        }
        assert!(
            w.worst <= w.worst_rk4,
            "n = {n}: the adaptive flow's largest deviation {:e} BL exceeds fixed-step RK4's {:e} BL",
            w.worst,
            w.worst_rk4
        );
        rows.push((n, w));
    }
    let compared: usize = rows.iter().map(|(_, w)| w.compared).sum();
    assert!(compared >= 10_000, "only {compared} samples were compared");
    print_table(&rows);
}

/// What one team size's motions of the accuracy test gave: the largest deviations from the
/// fine reference, and the work of the adaptive solver against fixed-step RK4.
#[derive(Default)]
struct Work {
    /// Motions followed.
    motions: usize,
    /// Motions that end with every separation at least `r_min`.
    whole: usize,
    /// Samples of valid teams compared with the reference.
    compared: usize,
    /// Largest deviation of an adaptive sample (BL).
    worst: f64,
    /// Largest deviation of a fixed-step RK4 sample (BL).
    worst_rk4: f64,
    /// Attempted adaptive steps (accepted and rejected), over all motions.
    steps: usize,
    /// Fixed-step RK4 steps over the same samples, over all motions.
    steps_rk4: usize,
}

impl Work {
    /// Counts the steps of one motion followed over its first `samples` samples, solved again
    /// by [`dp5_solve`] with the model's velocities and error budget.
    fn count(&mut self, m: &PlanningModel, start: &[Vec2], u: &Control, d: f64, samples: usize) {
        let act = m.coil.actuation(u);
        let f = |p: &[Vec2], v: &mut [Vec2]| m.kinematics.velocities(p, &act, v);
        let grid = Dp5Grid {
            dt: m.dt,
            budget: m.error_budget(start.len()),
        };
        let mut out = vec![Vec2::zeros(); start.len()];
        let mut seen = 0;
        let (_, stats) = dp5_solve(&f, start, d, grid, &mut out, true, |_| {
            seen += 1;
            seen < samples
        });
        assert_eq!(seen, samples, "the solver visits the model's samples");
        self.motions += 1;
        self.steps += stats.accepted + stats.rejected;
        self.steps_rk4 += samples;
    }
}

/// The accuracy test's figures as a Markdown table on stdout, one row per team size.
fn print_table(rows: &[(usize, Work)]) {
    println!(
        "| N | motions | whole motions | valid samples compared | adaptive: largest deviation \
         (BL) | fixed-step RK4: largest deviation (BL) | adaptive steps per motion (accepted + \
         rejected), mean | force evaluations per motion, mean: adaptive (1 + 6 per step) / \
         RK4 at `dt` (4 per step) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for (n, w) in rows {
        let per = |x: usize| x as f64 / w.motions as f64;
        println!(
            "| {n} | {} | {} | {} | {:.2e} | {:.2e} | {:.1} | {:.0} / {:.0} |",
            w.motions,
            w.whole,
            w.compared,
            w.worst,
            w.worst_rk4,
            per(w.steps),
            1.0 + 6.0 * per(w.steps),
            4.0 * per(w.steps_rk4),
        );
    }
}

/// The same start, command and duration give the same bits; the end without visits is the last
/// visit; a motion stopped at a sample time ends on the sample a longer motion visited there;
/// `propagate_many` agrees with one at a time.
#[test]
fn adaptive_flow_is_deterministic_and_consistent() {
    let p = PhysicalParams::default();
    let m = model();
    let g = m.coil.gradient_limit();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for n in 3..=6 {
        let start = team(&mut rng, n, &p);
        let controls: Vec<_> = (0..6).map(|k| command(&mut rng, g, k)).collect();
        let durations: Vec<_> = (0..6).map(|k| (10 + 17 * k) as f64 / 60.0).collect();
        let mut ends = vec![[Vec2::zeros(); MAX_AGENTS]; 6];
        m.propagate_many(&start, &controls, &durations, &mut ends);
        for (k, (u, &d)) in controls.iter().zip(&durations).enumerate() {
            let (mut a, mut b) = (vec![Vec2::zeros(); n], vec![Vec2::zeros(); n]);
            m.propagate(&start, u, d, &mut a);
            m.propagate(&start, u, d, &mut b);
            assert_eq!(a, b, "n = {n}, motion {k}");
            assert_eq!(&ends[k][..n], &a[..], "propagate_many, n = {n}, motion {k}");
            let mut seen = Vec::new();
            m.propagate_with(&start, u, 2.0, &mut b, |s| {
                seen.push(s.to_vec());
                true
            });
            let steps = (d / m.dt).round() as usize;
            assert_eq!(seen[steps - 1], a, "n = {n}, motion {k}: stop at {d} s");
        }
    }
}

/// `solve_many` starts the motions in the order given, hands each end over as one-at-a-time
/// propagation gives it, and drops the motions `wanted` refuses, before or during their steps.
#[test]
fn solve_many_follows_order_and_drops_unwanted_motions() {
    let p = PhysicalParams::default();
    let m = model();
    let g = m.coil.gradient_limit();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for n in 3..=6 {
        let start = team(&mut rng, n, &p);
        let k = 9;
        let controls: Vec<_> = (0..k).map(|i| command(&mut rng, g, i)).collect();
        let mut durations: Vec<_> = (0..k).map(|i| (12 + 13 * i) as f64 / 60.0).collect();
        durations[0] = 0.0;
        durations[8] = 2.0;
        let order = [8, 0, 5, 2, 7, 1, 4, 6, 3];
        // motion 4 is refused from the start; motion 8, started first, once motion 0 (no
        // duration: its end, the start, is handed over as a second lane is filled) has ended,
        // which is after 8's first step (6 `dt`) and long before its end
        let finished = std::cell::Cell::new(0);
        let mut reported = Vec::new();
        m.solve_many(
            &start,
            &controls,
            &durations,
            order,
            |i| i != 4 && (i != 8 || finished.get() < 1),
            |i, end| {
                finished.set(finished.get() + 1);
                let mut a = vec![Vec2::zeros(); n];
                m.propagate(&start, &controls[i], durations[i], &mut a);
                assert_eq!(end, &a[..], "n = {n}, motion {i}");
                reported.push(i);
            },
        );
        reported.sort();
        assert_eq!(reported, [0, 1, 2, 3, 5, 6, 7], "n = {n}");
    }
}

/// With identical agents the pair forces cancel, so the centre of mass moves at the pull and
/// background velocity; the adaptive steps and their dense output keep it on that line.
#[test]
fn adaptive_centre_of_mass_is_exact() {
    let p = PhysicalParams::default();
    let m = model();
    let g = m.coil.gradient_limit();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for n in 3..=6 {
        let start = team(&mut rng, n, &p);
        let u = Control::planar(0.7, 0.8 * g, -0.3 * g);
        let act = m.coil.actuation(&u);
        let v = Vec2::new(act.pull.x, act.pull.y) * m.kinematics.pull_coeff;
        assert_eq!(m.kinematics.centroid_velocity(&act, n), Some(v), "n = {n}");
        let c0 = start.iter().sum::<Vec2>() / n as f64;
        let mut t = 0.0;
        let mut out = vec![Vec2::zeros(); n];
        m.propagate_with(&start, &u, 1.5, &mut out, |s| {
            t += m.dt;
            let c = s.iter().sum::<Vec2>() / n as f64;
            let d = (c - (c0 + v * t)).norm();
            assert!(d < 1e-12, "n = {n}, t = {t}: {d:e} BL off the line");
            closest(s) >= p.r_min
        });
    }
}

/// The solver alone: `ẏ = −y` sampled every `dt` within the tolerance of `e^{−t}`, and far fewer
/// steps than the fixed-step count.
#[test]
fn dp5_solves_decay_within_tolerance_in_few_steps() {
    let f = |p: &[Vec2], v: &mut [Vec2]| v[0] = -p[0];
    let dt = 1.0 / 120.0;
    let start = [Vec2::new(1.0, -2.0)];
    let mut out = [Vec2::zeros()];
    let mut k = 0;
    let grid = Dp5Grid {
        dt,
        budget: ErrorBudget::new(2.0, 1.0, 0.0),
    };
    let (ok, stats) = dp5_solve(&f, &start, 2.0, grid, &mut out, true, |s| {
        k += 1;
        let exact = start[0] * (-(k as f64) * dt).exp();
        assert!((s[0] - exact).norm() < TOLERANCE_BL, "sample {k}");
        true
    });
    assert!(ok && k == 240);
    assert!(stats.accepted < 30, "{stats:?}");
    let (ok, _) = dp5_solve(&f, &start, 2.0, grid, &mut out, true, |_| {
        k += 1;
        k < 250
    });
    assert!(!ok, "a false visit stops the motion");
}

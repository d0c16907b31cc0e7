//! EXTEND, the seed's Algorithm 3: brute-force optimisation over random controls.
//!
//! From `q_near`, try `k` random (control, duration) pairs, propagate each through the planning
//! model and keep the one whose end is closest to the target under the problem's metric (the
//! seed's DISTANCE ρ = ‖P̃‖², P̃ = P_new − P_sample). Collision is checked by the caller on the
//! winner only, as in Algorithm 2. RRT* reuses it as its shooting connection.
//!
//! The seed's EXTEND keeps "the physical kinematic constraints satisfied", the first of which is
//! the proximity range. For a motion the exact flow solves, the separation's whole range over the
//! try is known at no extra cost, so a try that leaves the range (a pair collapsing into contact,
//! or flying apart) is no candidate. Without this, a collapsing try would win: the exact flow
//! ends it at contact, next to many targets, where RK4 would blow up and land far away. RK4
//! tries (three or more agents, an elevated field) are compared by their ends only.
//!
//! With `alpha_max` set, each try also draws the field elevation α (for teams of three or more,
//! where the in-plane field alone cannot hold a formation); such tries are RK4 motions.
//!
//! [`Timing`] picks each try's duration: a random one (the seed's Algorithm 3, the default),
//! or the whole control period at which the try's motion passes closest to the target
//! ([`Timing::Closest`]: the exact flow makes a look along the whole motion cheap).

use std::cell::Cell;

use magbench_env::math::centroid;
use magbench_env::params::{BadValue, ParamType, Value, choose};
use magbench_env::{Control, MAX_AGENTS, Vec2};
use rand::RngExt;

use crate::distance::floor_exceeds;
use crate::motion::{aimed, random_control, random_elevated_control};
use crate::{Problem, Rng};

/// How EXTEND picks the duration of each try.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Timing {
    /// A random whole number of control periods in the range (the seed's Algorithm 3).
    #[default]
    Random,
    /// The whole number of periods in the range at which the try comes closest to the target.
    Closest,
}

impl Timing {
    /// The parameter value naming it.
    pub fn name(self) -> &'static str {
        match self {
            Timing::Random => "random",
            Timing::Closest => "closest",
        }
    }

    /// The timing of a parameter value.
    pub fn from_name(name: &str) -> Option<Self> {
        Timing::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Every timing.
    pub const ALL: [Timing; 2] = [Timing::Random, Timing::Closest];
}

impl ParamType for Timing {
    type Domain = ();

    fn parse(text: &str, _: &()) -> Result<Self, BadValue> {
        let options = Timing::ALL.map(|t| (t.name(), t));
        choose(text, &options)
    }

    fn value(&self) -> Value {
        Value::Name(self.name())
    }

    fn describe(_: &()) -> String {
        Timing::ALL.map(Timing::name).join("|")
    }
}

/// The EXTEND optimiser's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extend {
    /// Random (control, duration) tries per call (the seed's k).
    pub tries: usize,
    /// Shortest duration, in control periods (≥ 1).
    pub min_periods: u32,
    /// Longest duration, in control periods.
    pub max_periods: u32,
    /// How each try's duration is picked.
    pub timing: Timing,
    /// The largest elevation drawn (rad), or `None` for planar controls only.
    pub alpha_max: Option<f64>,
    /// Whether each try's gradients are aimed ([`aimed`]): the field and duration stay
    /// random, the gradients carry the centroid as close to the target's as the coil allows.
    /// With [`Timing::Closest`] the duration is picked after the control, so nothing is aimed
    /// (the search settings refuse the pair).
    pub aim: bool,
}

/// The best try of one EXTEND call.
#[derive(Debug, Clone, Copy)]
pub struct Extension {
    /// The control of the best try.
    pub control: Control,
    /// Its duration in control periods.
    pub periods: u32,
    /// Its end state (first N entries).
    pub end: [Vec2; MAX_AGENTS],
    /// Its distance to the target under the problem's metric.
    pub distance: f64,
}

impl Extension {
    /// The end state of an N-agent team.
    pub fn end(&self, agents: usize) -> &[Vec2] {
        &self.end[..agents]
    }
}

impl Extend {
    /// `u` with its gradients [`aimed`] from centroid `from` at centroid `to` over `duration`
    /// when `aim` is set (the random gradients were drawn all the same, so the random stream
    /// does not depend on it); `u` itself otherwise.
    #[inline]
    pub(crate) fn aim_at(
        &self,
        problem: &Problem,
        u: Control,
        agents: usize,
        from: Vec2,
        to: Vec2,
        duration: f64,
    ) -> Control {
        if self.aim {
            aimed(problem, u, agents, from, to, duration)
        } else {
            u
        }
    }

    /// A random duration in control periods, uniform in `[min_periods, max_periods]`.
    #[inline]
    pub fn random_periods(&self, rng: &mut Rng) -> u32 {
        rng.random_range(self.min_periods..=self.max_periods)
    }

    /// EXTEND(q_near, q_sample): the try whose end is closest to `target` (the first on ties).
    /// A pair's planar tries of random duration go through the batch
    /// ([`crate::extend_batch`]); every other setting through [`Extend::run_scalar`]. Both
    /// choose the same try bit for bit.
    pub fn run(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        near: &[Vec2],
        target: &[Vec2],
    ) -> Extension {
        if self.batches(near.len()) {
            return self.run_batch(problem, rng, near, target);
        }
        self.run_scalar(problem, rng, near, target)
    }

    /// EXTEND(q_near, q_sample) one try at a time, for any setting. The tries are integrated
    /// together by `PlanningModel::propagate_many`, whose ends equal one-at-a-time propagation
    /// bit for bit.
    pub fn run_scalar(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        near: &[Vec2],
        target: &[Vec2],
    ) -> Extension {
        let g = problem.model.coil.gradient_limit();
        let k = self.tries.max(1);
        let mut controls = Vec::with_capacity(k);
        let mut periods = Vec::with_capacity(k);
        let mut durations = Vec::with_capacity(k);
        let (from, to) = (centroid(near), centroid(target));
        for _ in 0..k {
            let u = match self.alpha_max {
                None => random_control(rng, g),
                Some(a) => random_elevated_control(rng, g, a),
            };
            if self.timing == Timing::Random {
                let p = self.random_periods(rng);
                let d = problem.periods(p);
                controls.push(self.aim_at(problem, u, near.len(), from, to, d));
                periods.push(p);
                durations.push(d);
            } else {
                controls.push(u);
            }
        }
        let mut ends = vec![[Vec2::zeros(); MAX_AGENTS]; k];
        if self.timing == Timing::Closest {
            for i in 0..k {
                let p = self.closest_period(problem, near, &controls[i], target, &mut ends[i]);
                periods.push(p);
                durations.push(problem.periods(p));
            }
        }
        let integrate = self.timing == Timing::Random;
        self.choose(
            problem, near, target, &controls, &periods, &durations, ends, integrate,
        )
    }

    /// The closest candidate among tries already drawn, each solved from `near` (the
    /// scalar evaluation of a batch).
    pub(crate) fn evaluate(
        &self,
        problem: &Problem,
        near: &[Vec2],
        target: &[Vec2],
        controls: &[Control],
        periods: &[u32],
        durations: &[f64],
    ) -> Extension {
        let ends = vec![[Vec2::zeros(); MAX_AGENTS]; controls.len()];
        self.choose(
            problem, near, target, controls, periods, durations, ends, true,
        )
    }

    /// The closest candidate: exact tries end and are ranged by their edge, the others are
    /// integrated when `integrate` holds (else `ends` already holds them), nearest centroid
    /// floor first and without those the floor rules out ([`solve_nearest_first`]).
    #[allow(clippy::too_many_arguments)]
    fn choose(
        &self,
        problem: &Problem,
        near: &[Vec2],
        target: &[Vec2],
        controls: &[Control],
        periods: &[u32],
        durations: &[f64],
        mut ends: Vec<[Vec2; MAX_AGENTS]>,
        integrate: bool,
    ) -> Extension {
        let n = near.len();
        let k = controls.len();
        let mut candidate = vec![true; k];
        let (r_min, r_max) = (problem.checker.r_min, problem.checker.r_max);
        let mut integrated = Vec::with_capacity(k);
        let mut closest = f64::INFINITY;
        for i in 0..k {
            match problem.model.pair_edge(near, &controls[i]) {
                Some(edge) => {
                    let (lo, hi) = edge.end_and_range(durations[i], &mut ends[i][..n]);
                    candidate[i] = lo > r_min && hi < r_max;
                    if candidate[i] {
                        let d2 = problem.metric.distance_squared(&ends[i][..n], target);
                        closest = closest.min(d2);
                    }
                }
                None => integrated.push(i),
            }
        }
        if !integrated.is_empty() && integrate {
            for &i in &integrated {
                candidate[i] = false;
            }
            solve_nearest_first(
                problem,
                near,
                target,
                controls,
                durations,
                integrated,
                closest,
                &mut ends,
                &mut candidate,
            );
        }
        let mut best = Extension {
            control: Control::default(),
            periods: 0,
            end: [Vec2::zeros(); MAX_AGENTS],
            distance: f64::INFINITY,
        };
        for i in (0..k).filter(|&i| candidate[i]) {
            let d2 = problem.metric.distance_squared(&ends[i][..n], target);
            if d2 < best.distance {
                best = Extension {
                    control: controls[i],
                    periods: periods[i],
                    end: ends[i],
                    distance: d2,
                };
            }
        }
        best.distance = best.distance.sqrt();
        best
    }

    /// The whole number of periods in `[min_periods, max_periods]` at which the motion from
    /// `near` under `u` comes closest to `target`; its end goes to `end`. An exact motion is
    /// looked at on a coarse grid of periods, then by ternary search about the best of them; an
    /// integrated one at every period.
    fn closest_period(
        &self,
        problem: &Problem,
        near: &[Vec2],
        u: &Control,
        target: &[Vec2],
        end: &mut [Vec2; MAX_AGENTS],
    ) -> u32 {
        let n = near.len();
        let (lo, hi) = (self.min_periods, self.max_periods.max(self.min_periods));
        let Some(edge) = problem.model.pair_edge(near, u) else {
            let mut best = (lo, f64::INFINITY);
            let mut step = 0u64;
            let per = (problem.control_period / problem.model.dt).round().max(1.0) as u64;
            let mut out = [Vec2::zeros(); MAX_AGENTS];
            problem
                .model
                .propagate_with(near, u, problem.periods(hi), &mut out[..n], |s| {
                    step += 1;
                    let p = (step / per) as u32;
                    if step.is_multiple_of(per) && p >= lo {
                        let d2 = problem.metric.distance_squared(s, target);
                        if d2 < best.1 {
                            best = (p, d2);
                            end[..n].copy_from_slice(s);
                        }
                    }
                    true
                });
            return best.0;
        };
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let mut dist = |p: u32| {
            edge.at(problem.periods(p), &mut out[..n]);
            problem.metric.distance_squared(&out[..n], target)
        };
        let step = ((hi - lo) / CLOSEST_GRID).max(1);
        let mut best = (lo, dist(lo));
        let mut p = lo;
        while p < hi {
            p = (p + step).min(hi);
            let d = dist(p);
            if d < best.1 {
                best = (p, d);
            }
        }
        let (mut a, mut b) = (
            best.0.saturating_sub(step - 1).max(lo),
            (best.0 + step - 1).min(hi),
        );
        while b - a >= 3 {
            let (m1, m2) = (a + (b - a) / 3, b - (b - a) / 3);
            if dist(m1) <= dist(m2) {
                b = m2 - 1;
            } else {
                a = m1 + 1;
            }
        }
        for p in a..=b {
            let d = dist(p);
            if d < best.1 {
                best = (p, d);
            }
        }
        best.0
    }
}

/// Solves the tries `integrated` (those without a closed form) from `near` into `ends`, in
/// order of their centroid floors ([`crate::distance::Distance::centroid_floor`]; the centroid of a
/// team of equally mobile agents moves in a straight line,
/// [`magbench_env::model::Kinematics::centroid_velocity`]), and drops a try, before or while it
/// is solved, once its floor exceeds the smallest squared distance to `target` so far (starting
/// from `closest`): such a try cannot be the closest. A solved try is marked in `solved`.
/// Without floors (agents of unequal mobility) every try is solved, in the order given.
#[allow(clippy::too_many_arguments)]
fn solve_nearest_first(
    problem: &Problem,
    near: &[Vec2],
    target: &[Vec2],
    controls: &[Control],
    durations: &[f64],
    mut integrated: Vec<usize>,
    closest: f64,
    ends: &mut [[Vec2; MAX_AGENTS]],
    solved: &mut [bool],
) {
    let n = near.len();
    let model = &problem.model;
    let (from, to) = (centroid(near), centroid(target));
    let mut floor = vec![0.0; controls.len()];
    for &i in &integrated {
        let act = model.coil.actuation(&controls[i]);
        if let Some(v) = model.kinematics.centroid_velocity(&act, n) {
            floor[i] = problem
                .metric
                .centroid_floor(n, from + v * durations[i], to);
        }
    }
    integrated.sort_by(|&a, &b| floor[a].total_cmp(&floor[b]));
    let closest = Cell::new(closest);
    model.solve_many(
        near,
        controls,
        durations,
        integrated,
        |i| !floor_exceeds(floor[i], closest.get()),
        |i, end| {
            ends[i][..n].copy_from_slice(end);
            solved[i] = true;
            closest.set(
                closest
                    .get()
                    .min(problem.metric.distance_squared(end, target)),
            );
        },
    );
}

/// Coarse grid intervals of [`Timing::Closest`]'s search over the duration range.
const CLOSEST_GRID: u32 = 12;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::Distance;
    use crate::sampler::{StateSampler, valid_sample};
    use crate::search_settings::SearchSettings;
    use magbench_env::model::Flow;
    use rand::SeedableRng;

    /// For teams of three and four, with equal and unequal agents, under both metrics and both
    /// integrators, EXTEND's choice (tries solved nearest floor first, the hopeless ones
    /// dropped) is the try a plain scan of every try's one-at-a-time end chooses, bit for bit.
    #[test]
    fn team_extend_chooses_the_closest_try_of_all() {
        let weighted = Distance::CentroidShape {
            centroid: 2.0,
            shape: 0.5,
        };
        let mut dropped_some = false;
        for (name, agents) in [("trio-triangle", 3), ("quad-square", 4), ("trio-maze", 3)] {
            let s = magbench_env::Scenario::load(name).unwrap();
            let base = Problem::from_scenario(&s, 0, None, 0);
            assert_eq!(base.start.len(), agents);
            for (metric, unequal, flow) in [
                (Distance::Positions, false, Flow::PairAdaptive),
                (weighted, false, Flow::PairAdaptive),
                (Distance::Positions, true, Flow::PairAdaptive),
                (Distance::Positions, false, Flow::PairExact),
            ] {
                let mut p = base.clone();
                p.metric = metric;
                p.model = p.model.with_flow(flow);
                if unequal {
                    p.model.kinematics.mobility[1] *= 1.1;
                }
                let extend = SearchSettings::default().extend(&p);
                let sampler = StateSampler::new(&p);
                let mut rng = Rng::seed_from_u64(5);
                let n = agents;
                let (mut near, mut target) = (vec![Vec2::zeros(); n], vec![Vec2::zeros(); n]);
                for _ in 0..40 {
                    assert!(valid_sample(&p, 1000, &mut near, |x| sampler.uniform(&mut rng, x)));
                    assert!(valid_sample(&p, 1000, &mut target, |x| sampler.uniform(&mut rng, x)));
                    let g = p.model.coil.gradient_limit();
                    let controls: Vec<_> = (0..extend.tries)
                        .map(|_| random_control(&mut rng, g))
                        .collect();
                    let periods: Vec<_> = (0..extend.tries)
                        .map(|_| extend.random_periods(&mut rng))
                        .collect();
                    let durations: Vec<_> = periods.iter().map(|&q| p.periods(q)).collect();
                    let chosen =
                        extend.evaluate(&p, &near, &target, &controls, &periods, &durations);
                    let mut best = (f64::INFINITY, usize::MAX);
                    let mut out = vec![Vec2::zeros(); n];
                    let mut dists = Vec::new();
                    for i in 0..controls.len() {
                        p.model
                            .propagate(&near, &controls[i], durations[i], &mut out);
                        let d2 = p.metric.distance_squared(&out, &target);
                        dists.push(d2);
                        if d2 < best.0 {
                            best = (d2, i);
                        }
                    }
                    assert_eq!(chosen.distance, best.0.sqrt(), "{name}");
                    assert_eq!(chosen.control, controls[best.1], "{name}");
                    assert_eq!(chosen.periods, periods[best.1], "{name}");
                    p.model
                        .propagate(&near, &controls[best.1], durations[best.1], &mut out);
                    assert_eq!(chosen.end(n), &out[..], "{name}");
                    // some try's floor alone rules it out
                    dropped_some |= !unequal
                        && controls.iter().zip(&durations).any(|(u, &d)| {
                            let act = p.model.coil.actuation(u);
                            let v = p.model.kinematics.centroid_velocity(&act, n).unwrap();
                            let f = p.metric.centroid_floor(
                                n,
                                centroid(&near) + v * d,
                                centroid(&target),
                            );
                            floor_exceeds(f, best.0)
                        });
                }
            }
        }
        assert!(dropped_some, "no try was ever ruled out by its floor");
    }
}

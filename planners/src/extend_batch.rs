//! EXTEND's tries for a pair under the exact flow, evaluated as one batch.
//!
//! The k (control, duration) draws go into fixed-size stack arrays (structure of arrays: the
//! controls, the periods and the durations apart), and one loop evaluates every try's exact
//! end and separation range from one shared [`PairStart`], keeping only the running best: no
//! heap buffer, no per-try copy of the end states and no repeated start preparation. The
//! arithmetic of each try is that of [`Extend::run_scalar`], in the same order, so the chosen
//! try equals the scalar path's bit for bit and the random stream is consumed identically.
//! The continuous validity check stays with the caller, on the chosen try only.
//!
//! The centre of mass moves in a straight line, so the centroid part of the distance
//! (`w_c² N ‖Δc‖²`, a lower bound of the whole squared distance under either metric) is known
//! before the orbit is solved; a try whose bound already exceeds the best distance so far (by
//! a margin far above rounding) cannot win: its orbit is neither built nor solved. The tries are
//! solved in order of their bounds, so the first bound above the best distance ends the batch.

use arrayvec::ArrayVec;
use magbench_env::math::centroid;
use magbench_env::model::pair_flow::PairStart;
use magbench_env::{Actuation, Control, MAX_AGENTS, Vec2};

use crate::distance::floor_exceeds;
use crate::extend::{Extend, Extension, Timing};
use crate::motion::random_control;
use crate::{Problem, Rng};

/// The most tries one batch holds; more go through the scalar path.
pub const BATCH_MAX: usize = 64;

/// The k tries of one EXTEND call, as arrays (on the stack, unused slots never written).
#[derive(Default)]
struct Tries {
    controls: ArrayVec<Control, BATCH_MAX>,
    periods: ArrayVec<u32, BATCH_MAX>,
    durations: ArrayVec<f64, BATCH_MAX>,
}

impl Tries {
    /// Draws `k ≤ BATCH_MAX` planar tries with random durations, in the scalar path's order,
    /// their gradients aimed from `near`'s centroid at `target`'s when the settings say so.
    fn draw(
        &mut self,
        extend: &Extend,
        problem: &Problem,
        rng: &mut Rng,
        k: usize,
        near: &[Vec2],
        target: &[Vec2],
    ) {
        let g = problem.model.coil.gradient_limit();
        let (from, to) = (centroid(near), centroid(target));
        for _ in 0..k {
            let u = random_control(rng, g);
            let p = extend.random_periods(rng);
            let d = problem.periods(p);
            self.controls
                .push(extend.aim_at(problem, u, 2, from, to, d));
            self.periods.push(p);
            self.durations.push(d);
        }
    }

    /// The closest candidate's try under the exact flow, or `None` when some try has no
    /// closed form (then the scalar evaluation decides).
    fn best_exact(&self, problem: &Problem, near: &[Vec2], target: &[Vec2]) -> Option<Extension> {
        let model = &problem.model;
        if !model.flow.pair_exact() || near.len() != 2 {
            return None;
        }
        let start = PairStart::new(near)?;
        let (r_min, r_max) = (problem.checker.r_min, problem.checker.r_max);
        let mut best = Extension {
            control: Control::default(),
            periods: 0,
            end: [Vec2::zeros(); MAX_AGENTS],
            distance: f64::INFINITY,
        };
        let goal_centre = (target[0] + target[1]) * 0.5;
        // every try's actuation and centroid floor first, then the tries in order of their
        // floors: once a floor exceeds the best distance, so do all later ones
        let mut acts = ArrayVec::<Actuation, BATCH_MAX>::new();
        let mut floors = ArrayVec::<f64, BATCH_MAX>::new();
        let mut order = ArrayVec::<u8, BATCH_MAX>::new();
        for (i, u) in self.controls.iter().enumerate() {
            let act = model.coil.actuation(u);
            let velocity = model.kinematics.pair_velocity(&act)?;
            let centre = start.centre() + velocity * self.durations[i];
            let floor = problem.metric.centroid_floor(2, centre, goal_centre);
            if floor.is_nan() {
                return None;
            }
            acts.push(act);
            floors.push(floor);
            order.push(i as u8);
        }
        order.sort_unstable_by(|&a, &b| floors[a as usize].total_cmp(&floors[b as usize]));
        let mut chosen = usize::MAX;
        let mut end = [Vec2::zeros(); 2];
        for &i in order.iter() {
            let i = i as usize;
            if floor_exceeds(floors[i], best.distance) {
                break;
            }
            let edge = model.kinematics.pair_edge_from(&start, &acts[i])?;
            let (lo, hi) = edge.end_and_range(self.durations[i], &mut end);
            if !(lo > r_min && hi < r_max) {
                continue;
            }
            let d2 = problem.metric.distance_squared(&end, target);
            // the first try on ties, as the scalar path's scan in index order
            if d2 < best.distance || (d2 == best.distance && chosen < usize::MAX && i < chosen) {
                chosen = i;
                best.control = self.controls[i];
                best.periods = self.periods[i];
                best.end[..2].copy_from_slice(&end);
                best.distance = d2;
            }
        }
        best.distance = best.distance.sqrt();
        Some(best)
    }
}

impl Extend {
    /// Whether [`Extend::run`] takes the batch: planar tries of random duration, at most
    /// [`BATCH_MAX`] of them, from a pair.
    pub fn batches(&self, agents: usize) -> bool {
        agents == 2
            && self.timing == Timing::Random
            && self.alpha_max.is_none()
            && self.tries.max(1) <= BATCH_MAX
    }

    /// EXTEND(q_near, q_sample) by the batch; equal to [`Extend::run_scalar`] bit for bit.
    /// Only for settings where [`Extend::batches`] holds.
    pub(crate) fn run_batch(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        near: &[Vec2],
        target: &[Vec2],
    ) -> Extension {
        let k = self.tries.max(1);
        let mut tries = Tries::default();
        tries.draw(self, problem, rng, k, near, target);
        if let Some(best) = tries.best_exact(problem, near, target) {
            return best;
        }
        self.evaluate(
            problem,
            near,
            target,
            &tries.controls,
            &tries.periods,
            &tries.durations,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::Distance;
    use crate::sampler::{StateSampler, valid_sample};
    use crate::search_settings::SearchSettings;
    use rand::{RngExt, SeedableRng};

    /// The batch and the scalar path choose the same try, bit for bit, and leave the random
    /// stream in the same place.
    #[test]
    fn batch_equals_scalar_bit_for_bit() {
        let weighted = Distance::CentroidShape {
            centroid: 2.0,
            shape: 0.5,
        };
        for (name, metric) in [
            ("micro-factory", Distance::Positions),
            ("narrow-passage", Distance::Positions),
            ("micro-factory", weighted),
        ] {
            let s = magbench_env::Scenario::load(name).unwrap();
            let mut p = Problem::from_scenario(&s, 0, None, 0);
            p.metric = metric;
            let sampler = StateSampler::new(&p);
            let mut rng = Rng::seed_from_u64(11);
            let (mut near, mut target) = (vec![Vec2::zeros(); 2], vec![Vec2::zeros(); 2]);
            let mut found = 0;
            for (k, aim) in [1, 5, 12, 40, BATCH_MAX]
                .into_iter()
                .flat_map(|k| [(k, false), (k, true)])
            {
                let extend = SearchSettings {
                    tries: k,
                    aim,
                    ..SearchSettings::default()
                }
                .extend(&p);
                assert!(extend.batches(2));
                for _ in 0..300 {
                    assert!(valid_sample(&p, 1000, &mut near, |x| sampler.uniform(&mut rng, x)));
                    assert!(valid_sample(&p, 1000, &mut target, |x| sampler.uniform(&mut rng, x)));
                    let seed: u64 = rng.random();
                    let (mut a, mut b) = (Rng::seed_from_u64(seed), Rng::seed_from_u64(seed));
                    let x = extend.run_batch(&p, &mut a, &near, &target);
                    let y = extend.run_scalar(&p, &mut b, &near, &target);
                    assert_eq!(x.control, y.control, "{name} k {k} aim {aim}");
                    assert_eq!(x.periods, y.periods);
                    assert_eq!(x.end, y.end);
                    assert_eq!(x.distance.to_bits(), y.distance.to_bits());
                    assert_eq!(a.random::<u64>(), b.random::<u64>());
                    found += usize::from(x.periods > 0);
                }
            }
            assert!(found > 2000, "{name}: only {found} tries with a candidate");
        }
    }
}

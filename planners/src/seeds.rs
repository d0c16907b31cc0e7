//! The seed rule: which random stream each plan of a run draws, from the run's seed.
//!
//! Leg `k` of a run is planned with [`leg_seed`]; the `k`-th plan the tracking loop makes
//! (a new leg or a replan) with [`replan_seed`]. Sweeps, `magbench plan`, `track`, `rig run`
//! and the Python package all plan through these two functions, so one seed gives one set of
//! plans wherever it is run.

/// Step between the seeds of successive legs of a run (a prime, so that the legs of nearby
/// seeds do not share streams).
pub const LEG_STEP: u64 = 1_000_003;

/// Step between the seeds of successive plans of the tracking loop: the 64-bit golden ratio,
/// so that every replan draws a fresh, reproducible random stream.
pub const REPLAN_STEP: u64 = 0x9E37_79B9_7F4A_7C15;

/// The planner seed of leg `leg` (0 for the first) of a run with seed `seed`.
pub fn leg_seed(seed: u64, leg: usize) -> u64 {
    seed.wrapping_add((leg as u64).wrapping_mul(LEG_STEP))
}

/// The planner seed of the `k`-th plan (0 for the first) the tracking loop makes in a run with
/// seed `seed`.
pub fn replan_seed(seed: u64, k: usize) -> u64 {
    seed.wrapping_add((k as u64).wrapping_mul(REPLAN_STEP))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_leg_and_the_first_plan_use_the_runs_seed() {
        assert_eq!(leg_seed(7, 0), 7);
        assert_eq!(replan_seed(7, 0), 7);
        assert_eq!(leg_seed(7, 2), 7 + 2 * 1_000_003);
        assert_eq!(leg_seed(u64::MAX, 1), LEG_STEP - 1, "wraps");
    }
}

//! Plans of teams of three and four made under the adaptive flow (the default) pass the
//! validator, also after a round trip through the plan file format; the same controls claimed
//! under the fixed-step flow do not replay.

use crate::common;

use common::*;
use magbench_env::Scenario;
use magbench_env::model::Flow;
use magbench_planners::{Plan, PlanError, Planners, validate_plan};

#[test]
fn adaptive_plans_pass_the_validator_after_a_file_round_trip() {
    let mut plans = 0;
    for s in [
        scenario(TRIO),
        Scenario::load("trio-triangle").unwrap(),
        Scenario::load("quad-square").unwrap(),
    ] {
        for seed in 0..3 {
            let p = problem(&s, seed, 200_000);
            assert_eq!(p.model.flow, Flow::PairAdaptive);
            let r = Planners::builtin()
                .create("goal-zoom-rrt", &[])
                .unwrap()
                .solve(&p);
            assert!(r.solved, "{}, seed {seed}: not solved", s.name);
            assert_eq!(r.plan.flow, Flow::PairAdaptive);
            let text = serde_json::to_string(&r.plan).unwrap();
            let stored: Plan = serde_json::from_str(&text).unwrap();
            validate_plan(&p, &stored).unwrap_or_else(|e| panic!("{}, seed {seed}: {e}", s.name));
            assert_solution(&p, &r);

            // the same controls claimed under RK4 at the fixed step end elsewhere
            let mut other = stored.clone();
            other.flow = Flow::PairExact;
            if stored.edges() > 0 {
                assert!(
                    matches!(
                        validate_plan(&p, &other),
                        Err(PlanError::ReplayMismatch { .. } | PlanError::InvalidMotion { .. })
                    ),
                    "{}, seed {seed}: a plan replayed under the other flow",
                    s.name
                );
            }
            plans += 1;
        }
    }
    assert_eq!(plans, 9);
}

#[test]
fn adaptive_replay_is_bit_exact_every_time() {
    let s = scenario(TRIO);
    let p = problem(&s, 4, 200_000);
    let r = Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .unwrap()
        .solve(&p);
    assert!(r.solved);
    let first = replay(&p, &r.plan);
    for _ in 0..3 {
        assert_eq!(replay(&p, &r.plan), first);
    }
    assert_eq!(first, r.plan.states);
}

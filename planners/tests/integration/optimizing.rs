//! RRT*, informed RRT* and SST: informed samples, bounded SST trees, improvement.

use crate::common;

use common::*;
use magbench_planners::Planner;
use magbench_planners::informed::InformedSet;
use magbench_planners::planners::{RrtStar, Sst};

/// Ellipse sampling gives way to drawing from the whole space (then rejecting) once an agent's
/// ellipse is larger than the world: on micro-factory a first solution costs ≈ 270 BL against
/// a straight-line bound of ≈ 72 BL, and the ellipses would put nearly every draw off the map.
#[test]
fn ellipses_larger_than_the_world_are_not_sampled() {
    let s = magbench_env::Scenario::load("micro-factory").unwrap();
    let p = problem(&s, 0, 10);
    let set = InformedSet::new(&p);
    let area = s.world.width * s.world.height;
    assert!(set.ellipses_exceed(270.0, area));
    assert!(!set.ellipses_exceed(80.0, area));
}

/// Every sample informed RRT* draws after its first solution lies in the informed set of the
/// best cost at that moment; plain RRT* (same seed) draws samples outside it, so the test can
/// tell the two apart.
#[test]
fn informed_samples_after_the_first_solution_lie_in_the_informed_set() {
    let s = scenario(ROOMY);
    let p = problem(&s, 2, 10000);
    let set = InformedSet::new(&p);
    let mut informed = RrtStar::informed();
    informed.sample_log = Some(Vec::new());
    let r = informed.solve(&p);
    assert_solution(&p, &r);
    let log = informed.sample_log.unwrap();
    let after: Vec<_> = log.iter().filter(|x| x.c_best.is_some()).collect();
    assert!(
        after.len() > 500,
        "only {} samples after the first solution",
        after.len()
    );
    for x in &after {
        let c = x.c_best.unwrap();
        assert!(
            set.contains(&p, &x.state, c),
            "iteration {}: heuristic {} ≥ c_best {c}",
            x.iteration,
            set.heuristic(&p, &x.state)
        );
    }

    let mut plain = RrtStar::default();
    plain.sample_log = Some(Vec::new());
    plain.solve(&p);
    let outside = plain
        .sample_log
        .unwrap()
        .iter()
        .filter(|x| x.c_best.is_some_and(|c| !set.contains(&p, &x.state, c)))
        .count();
    assert!(
        outside > 50,
        "plain RRT* drew only {outside} samples outside the informed set"
    );
}

/// SST really prunes: dominated nodes leave the tree, the tree stays within a small multiple of
/// the witness count (at most one active node per witness), and the witness set — a δ_s-packing
/// of the reachable space, hence bounded — grows ever more slowly. A tree that kept every
/// locally-best node would hold every added node.
#[test]
fn sst_tree_size_stays_bounded() {
    let s = scenario(BOX);
    let mut runs = Vec::new();
    for iterations in [10_000, 40_000] {
        let p = problem(&s, 3, iterations);
        let mut sst = Sst {
            pruning_radius: 1.0,
            selection_radius: 2.0,
            ..Sst::default()
        };
        let (r, stats) = sst.solve_with_stats(&p);
        eprintln!("{iterations} iterations: {stats:?}");
        assert_eq!(r.nodes, stats.nodes);
        if r.solved {
            assert_solution(&p, &r);
        } else {
            magbench_planners::validate_path(&p, &r.plan).unwrap();
        }
        assert!(stats.active <= stats.witnesses);
        assert!(stats.nodes <= 2 * stats.witnesses, "{stats:?}");
        assert_eq!(stats.nodes as u64, stats.added + 1 - stats.pruned);
        runs.push(stats);
    }
    let (a, b) = (runs[0], runs[1]);
    assert!(
        2 * b.nodes < b.added as usize,
        "pruned only {} of {} added nodes",
        b.pruned,
        b.added
    );
    assert!(
        (b.witnesses as f64) < 2.5 * a.witnesses as f64,
        "witnesses grew from {} to {}",
        a.witnesses,
        b.witnesses
    );
}

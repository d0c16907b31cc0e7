"""mb.plan plans a scenario's legs as `magbench plan` and sweeps do: one seed rule."""

import numpy as np

import magbench as mb


def test_plan_gives_the_plans_of_magbench_plan_for_the_same_seed_on_every_leg(tmp_path):
    seed = 3
    out = tmp_path / "plan"
    mb.main(
        [
            "plan",
            "cargo-delivery",
            "--planner",
            "goal-zoom-rrt",
            "--seed",
            str(seed),
            "--max-iters",
            "5000",
            "--out",
            str(out),
        ]
    )
    start = None
    for leg in range(2):
        sc = mb.Scenario.load("cargo-delivery", leg=leg)
        p = mb.plan(sc, "goal-zoom-rrt", seed=seed, max_iterations=5000, start=start)
        assert p.solved
        cli = mb.Plan.load(out / f"plan-leg{leg + 1}.json", sc)
        np.testing.assert_array_equal(p.states, cli.states)
        np.testing.assert_array_equal(p.controls, cli.controls)
        np.testing.assert_array_equal(p.durations, cli.durations)
        start = p.states[-1]

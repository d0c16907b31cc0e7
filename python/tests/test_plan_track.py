"""plan, Plan, save/load and track."""

import json

import numpy as np
import pytest

import magbench as mb


def test_plan_arrays_replay(sc, plan):
    k = len(plan)
    assert plan.states.shape == (k + 1, 4)
    assert plan.controls.shape == (k, 4) and plan.durations.shape == (k,)
    np.testing.assert_array_equal(plan.states[0], sc.start)
    assert sc.in_goal(plan.states[-1])
    # the plan's states are what propagate gives, bit for bit
    for i in range(k):
        np.testing.assert_array_equal(
            sc.propagate(plan.states[i], plan.controls[i], plan.durations[i]), plan.states[i + 1]
        )
        assert sc.motion_valid(plan.states[i], plan.controls[i], plan.durations[i])
    assert plan.planner == "goal-zoom-rrt" and plan.scenario == "open-field"
    info = plan.info
    assert info["solved"] and info["iterations"] <= 3000 and info["cost"] > 0
    prog = plan.progress
    assert prog["iteration"].shape == prog["best_cost"].shape and len(prog["time_s"]) > 0


def test_plan_is_seeded(sc, plan):
    again = mb.plan(sc, "goal-zoom-rrt", seed=0, max_iterations=3000)
    np.testing.assert_array_equal(again.states, plan.states)
    other = mb.plan(sc, "goal-zoom-rrt", seed=1, max_iterations=3000)
    assert not np.array_equal(other.states, plan.states)


def test_plan_params_and_time_limit(sc):
    # an anytime planner runs to its iteration limit, and a parameter changes what it draws
    p = mb.plan(sc, "rrt-star", seed=2, max_iterations=3000, params={"k": 10})
    assert p.solved is True and p.info["iterations"] == 3000
    q = mb.plan(sc, "rrt-star", seed=2, max_iterations=3000, params={"k": 2})
    assert not np.array_equal(p.states, q.states)
    # with a time limit only, it stops at the limit, not at the default iteration cap
    t = mb.plan(sc, "rrt-star", seed=2, time_limit_s=0.2)
    assert t.info["time_s"] >= 0.2 and t.info["iterations"] < 200_000


def test_trajopt_plans_and_refines(sc, plan):
    # the optimiser as a planner, from its straight line, and as the pass after another's plan
    t = mb.plan(sc, "trajopt", seed=0, params={"max_subproblems": 20})
    assert t.solved is True and t.info["iterations"] <= 20
    assert t.info["stop_reason"] is None
    r = mb.plan(sc, "goal-zoom-rrt", seed=0, max_iterations=3000, params={"trajopt": 5})
    assert r.solved is True and r.info["cost"] < plan.info["cost"]


def test_unsolved_plan(sc):
    p = mb.plan(sc, "goal-zoom-rrt", seed=0, max_iterations=1)
    assert p.solved is False and p.info["stop_reason"] is None


def test_unsolved_trajopt_says_why():
    # its straight line crosses micro-factory's walls: the optimiser stops and says why
    p = mb.plan(mb.Scenario.load("micro-factory"), "trajopt", seed=0, params={"max_subproblems": 5})
    assert p.solved is False
    assert p.info["stop_reason"].startswith("trajopt: no feasible plan; ")


def test_save_and_load(sc, plan, tmp_path):
    plan.save(tmp_path / "plan.json")
    plan.save(tmp_path / "plan.csv")
    back = mb.Plan.load(tmp_path / "plan.json", sc)
    np.testing.assert_array_equal(back.states, plan.states)
    np.testing.assert_array_equal(back.controls, plan.controls)
    assert back.solved is None
    assert json.loads((tmp_path / "plan.json").read_text())["flow"] == "pair-adaptive"
    assert (tmp_path / "plan.csv").read_text().startswith("waypoint,t_s,x0,y0,x1,y1")
    with pytest.raises(mb.InputError):
        mb.Plan.load(tmp_path / "plan.csv", sc)
    with pytest.raises(OSError):
        plan.save(tmp_path / "no" / "such" / "dir" / "plan.json")


def test_python_plan_round_trip(sc, plan):
    p = mb.Plan(states=plan.states, controls=plan.controls, durations=plan.durations)
    assert p.solved is None and len(p) == len(plan)
    assert p.duration == pytest.approx(plan.durations.sum())
    # open loop on the ideal plant is the planning model: it ends where the plan ends
    t = mb.track(sc, p, tracker="open-loop", preset="ideal", seed=0)
    assert t["reached_goal"] is True


def test_track_metrics_and_traces(sc, plan):
    t = mb.track(sc, plan, tracker="obc", preset="realistic", seed=0)
    m = t.metrics
    for key in ("status", "reached_goal", "rms_error_bl", "max_error_bl", "replans", "per_agent"):
        assert key in m, key
    assert m["scenario"] == "open-field" and m["tracker"] == "obc"
    tr = t.traces
    n = len(tr["t"])
    assert n > 10
    assert tr["estimate"].shape == (n, 4) and tr["truth"].shape == (n, 4)
    assert tr["command"].shape == (n, 4) and tr["error"].shape == (n, 2)
    assert tr["in_goal"].dtype == bool and len(tr["mode"]) == n
    assert np.all(np.diff(tr["t"]) > 0)
    np.testing.assert_allclose(tr["truth"][0], sc.start, atol=0.2)
    assert t.plans[0]["reason"] == "initial" or t.plans[0]["leg"] == 0
    assert isinstance(t.plans[0]["plan"], mb.Plan)
    # seeded: the same run again gives the same metrics
    again = mb.track(sc, plan, tracker="obc", preset="realistic", seed=0)
    assert again["rms_error_bl"] == m["rms_error_bl"]


def test_a_plan_made_for_one_medium_is_refused_in_another(sc, plan):
    # `plan` is made for bulk liquid; `hardware` is an interface, where drag is half and every
    # motion of the plan goes twice as far
    with pytest.raises(mb.InputError, match="not a valid motion"):
        mb.track(sc, plan, tracker="obc", preset="hardware", seed=1)


def test_plan_for_a_preset_and_a_bad_preset(sc):
    with pytest.raises(mb.InputError, match="preset"):
        mb.plan(sc, "goal-zoom-rrt", max_iterations=10, preset="no-such-preset")


def test_track_replans_with_a_planner(sc):
    plan = mb.plan(sc, "goal-zoom-rrt", seed=0, max_iterations=3000, preset="hardware")
    assert plan.solved
    t = mb.track(sc, plan, tracker="obc", preset="hardware", seed=1,
                 planner="goal-zoom-rrt", planner_params={"k": 10})
    assert len(t.plans) == 1 + t["replans"]

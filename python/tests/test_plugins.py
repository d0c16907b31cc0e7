"""Python planners and trackers: registration, parameters, progress, failures, and bench."""

import json
import os
import sys

import numpy as np
import pytest

import magbench as mb

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "python", "examples"))
from py_pd import PyPd  # noqa: E402
from py_rrt import PyRrt  # noqa: E402


@pytest.fixture(autouse=True)
def clean_registry():
    yield
    for kind in mb.registered().values():
        for name in kind:
            mb.unregister(name)


class Seen:
    """Records what the problem offers, then gives up."""

    last = None

    def __init__(self, flag=True, count=3, scale=0.5, label="x"):
        Seen.last = {"params": (flag, count, scale, label)}

    def solve(self, problem):
        Seen.last.update(
            max_iterations=problem.max_iterations,
            time_limit_s=problem.time_limit_s,
            seed=problem.seed,
            stop_at_limit=problem.should_stop(problem.max_iterations),
            stop_before=problem.should_stop(0),
            start=problem.start,
            goal=problem.goal,
            period=problem.control_period,
            valid=problem.is_valid(problem.start),
        )
        problem.report_progress(1)
        problem.report_progress(2, None)
        return None


class Raises:
    def solve(self, problem):
        raise RuntimeError("planner exploded on purpose")


class WrongType:
    def solve(self, problem):
        return "a plan"


class Teleports:
    """Returns a plan that jumps straight to the goal: the validator must refuse it."""

    def solve(self, problem):
        return mb.Plan(states=np.stack([problem.start, problem.goal]),
                       controls=np.zeros((1, 4)), durations=[problem.control_period])


class Picky:
    def __init__(self, k=1):
        if k > 10:
            raise ValueError("k must be at most 10")

    def solve(self, problem):
        return None


def test_python_rrt_plans_like_a_builtin(sc):
    mb.register_planner("py-rrt", PyRrt)
    assert mb.registered()["planners"] == ["py-rrt"]
    p = mb.plan(sc, "py-rrt", seed=0, max_iterations=20000, params={"goal_bias": 0.3})
    assert p.solved and p.planner == "py-rrt"
    assert sc.in_goal(p.states[-1])
    for i in range(len(p)):
        assert sc.motion_valid(p.states[i], p.controls[i], p.durations[i])
    info = p.info
    assert 0 < info["iterations"] <= 20000 and info["cost"] > 0
    assert info["first_solution_iteration"] == info["iterations"]
    prog = p.progress
    assert len(prog["iteration"]) >= 2 and np.isfinite(prog["best_cost"][-1])
    again = mb.plan(sc, "py-rrt", seed=0, max_iterations=20000, params={"goal_bias": 0.3})
    np.testing.assert_array_equal(again.states, p.states)


class OwnShortcut(PyRrt):
    """A planner with its own ``shortcut`` parameter: magbench's pass leaves it alone."""

    def __init__(self, shortcut=0, goal_bias=0.1, max_periods=30):
        super().__init__(goal_bias, max_periods)
        self.own_shortcut = shortcut


def test_python_plans_go_through_the_shortcut_pass(sc):
    mb.register_planner("py-rrt", PyRrt)
    opts = dict(seed=0, max_iterations=20000)
    raw = mb.plan(sc, "py-rrt", **opts)
    short = mb.plan(sc, "py-rrt", params={"shortcut": 200}, **opts)
    assert raw.solved and short.solved
    assert short.info["cost"] < 0.95 * raw.info["cost"]
    assert sc.in_goal(short.states[-1])
    for i in range(len(short)):
        assert sc.motion_valid(short.states[i], short.controls[i], short.durations[i])
    # the search's first solution is reported as before, the pass's plan as the last point
    assert short.info["first_solution_iteration"] == raw.info["first_solution_iteration"]
    assert short.progress["best_cost"][-1] == pytest.approx(short.info["cost"])
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "py-rrt", params={"shortcut": -1})
    assert e.value.field == "param.shortcut"
    mb.register_planner("own-shortcut", OwnShortcut)
    own = mb.plan(sc, "own-shortcut", params={"shortcut": 200}, **opts)
    np.testing.assert_array_equal(own.states, raw.states)


class OwnStraighten(PyRrt):
    """A planner with its own ``straighten`` parameter: magbench's pass leaves it alone."""

    def __init__(self, straighten=False, goal_bias=0.1, max_periods=30):
        super().__init__(goal_bias, max_periods)
        self.own_straighten = straighten


def test_python_plans_go_through_straightening(sc):
    mb.register_planner("py-rrt", PyRrt)
    opts = dict(seed=0, max_iterations=20000)
    raw = mb.plan(sc, "py-rrt", **opts)
    straight = mb.plan(sc, "py-rrt", params={"straighten": True}, **opts)
    assert raw.solved and straight.solved
    # this RRT's plans have hundreds of short edges: the chaotic relative dynamics, replayed
    # over the rest of the plan, refuse most runs but the last ones
    assert straight.info["cost"] < raw.info["cost"]
    assert sc.in_goal(straight.states[-1])
    for i in range(len(straight)):
        assert sc.motion_valid(straight.states[i], straight.controls[i], straight.durations[i])
    # the fields and durations are the search's; only the gradients change
    np.testing.assert_array_equal(straight.durations, raw.durations)
    np.testing.assert_array_equal(straight.controls[:, :2], raw.controls[:, :2])
    assert straight.progress["best_cost"][-1] == pytest.approx(straight.info["cost"])
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "py-rrt", params={"straighten": "maybe"})
    assert e.value.field == "param.straighten"
    mb.register_planner("own-straighten", OwnStraighten)
    own = mb.plan(sc, "own-straighten", params={"straighten": True}, **opts)
    np.testing.assert_array_equal(own.states, raw.states)


def test_problem_limits_params_and_progress(sc):
    mb.register_planner("seen", Seen)
    p = mb.plan(sc, "seen", seed=7, max_iterations=123,
                params={"flag": False, "count": 9, "scale": 2.5, "label": "hello"})
    s = Seen.last
    assert s["params"] == (False, 9, 2.5, "hello")
    assert s["max_iterations"] == 123 and s["time_limit_s"] is None and s["seed"] == 7
    assert s["stop_at_limit"] and not s["stop_before"] and s["valid"]
    np.testing.assert_array_equal(s["start"], sc.start)
    assert s["period"] == pytest.approx(1 / 60)
    assert p.solved is False and len(p) == 0
    assert list(p.progress["iteration"]) == [1, 2]
    mb.plan(sc, "seen", time_limit_s=2.0)
    assert Seen.last["time_limit_s"] == pytest.approx(2.0)


def test_bad_plugin_params(sc):
    mb.register_planner("seen", Seen)
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "seen", params={"nope": 1})
    assert e.value.field == "param.nope"
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "seen", params={"count": "many"})
    assert e.value.field == "param.count"
    with pytest.raises(mb.InputError):
        mb.plan(sc, "seen", params={"flag": "maybe"})
    mb.register_planner("picky", Picky)
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "picky", params={"k": 11})
    assert "k must be at most 10" in str(e.value)


def test_registration_errors():
    with pytest.raises(mb.InputError):
        mb.register_planner("sst", Seen)  # a built-in's name
    assert mb.registered()["planners"] == []
    with pytest.raises(TypeError):
        mb.register_planner("not-a-class", Seen())
    with pytest.raises(TypeError):
        mb.register_tracker("no-control", Seen)

    class NoDefault:
        def __init__(self, k):
            pass

        def solve(self, problem):
            return None

    with pytest.raises(TypeError):
        mb.register_planner("no-default", NoDefault)
    mb.register_planner("seen", Seen)
    with pytest.raises(ValueError):
        mb.register_planner("seen", Seen)
    mb.register_planner("seen", Seen, replace=True)


def test_failing_planners_raise(sc):
    mb.register_planner("raises", Raises)
    with pytest.raises(mb.MagbenchError) as e:
        mb.plan(sc, "raises")
    assert "planner exploded on purpose" in str(e.value) and "RuntimeError" in str(e.value)
    mb.register_planner("wrong-type", WrongType)
    with pytest.raises(mb.MagbenchError) as e:
        mb.plan(sc, "wrong-type")
    assert "not a magbench.Plan" in str(e.value)
    mb.register_planner("teleports", Teleports)
    with pytest.raises(mb.MagbenchError) as e:
        mb.plan(sc, "teleports")
    assert "invalid plan" in str(e.value)


def test_python_tracker(sc, plan):
    mb.register_tracker("py-pd", PyPd)
    t = mb.track(sc, plan, tracker="py-pd", preset="realistic", seed=0)
    assert t["status"] == "reached-goal" and t["tracker"] == "py-pd"
    assert "python" in set(t.traces["mode"])
    with pytest.raises(mb.InputError):
        mb.track(sc, plan, tracker="py-pd", params={"kp": "strong"})
    # the loop's own parameters go with a Python tracker too
    t2 = mb.track(sc, plan, tracker="py-pd", preset="realistic", seed=0,
                  params={"kp": 0.2, "max_replans": 0})
    assert t2["replans"] == 0


class BadTracker:
    def reset(self, problem, plan):
        self.n = 0

    def control(self, observation):
        self.n += 1
        if self.n > 5:
            raise ValueError("tracker exploded on purpose")
        return np.zeros(4)


class NanTracker:
    def reset(self, problem, plan):
        pass

    def control(self, observation):
        return np.array([np.nan, 0, 0, 0])


class SeesWorld(PyPd):
    """A PD tracker that records what its problem says of the world."""

    seen = None

    def reset(self, problem, plan):
        w, _ = problem.bounds
        outside = np.array(problem.start, dtype=float)
        outside[0] = w + 5.0
        SeesWorld.seen = (problem.bounds, bool(problem.is_valid(problem.start)),
                          bool(problem.is_valid(outside)))
        super().reset(problem, plan)


def test_a_tracker_problem_has_the_world_bounds(sc, plan):
    mb.register_tracker("sees-world", SeesWorld)
    mb.track(sc, plan, tracker="sees-world", preset="ideal", seed=0)
    bounds, start_valid, outside_valid = SeesWorld.seen
    assert bounds == sc.bounds and all(np.isfinite(bounds)), bounds
    assert start_valid and not outside_valid


def test_failing_trackers_raise(sc, plan):
    mb.register_tracker("bad", BadTracker)
    with pytest.raises(mb.MagbenchError) as e:
        mb.track(sc, plan, tracker="bad")
    assert "tracker exploded on purpose" in str(e.value)
    mb.register_tracker("nan", NanTracker)
    with pytest.raises(mb.MagbenchError) as e:
        mb.track(sc, plan, tracker="nan")
    assert "not finite" in str(e.value)


def test_bench_with_python_plugins(tmp_path):
    mb.register_planner("py-rrt", PyRrt)
    mb.register_planner("raises", Raises)
    mb.register_tracker("py-pd", PyPd)
    f = tmp_path / "plugins.toml"
    f.write_text(
        'name = "plugins"\n'
        'scenarios = ["open-field"]\n'
        'planners = ["goal-zoom-rrt", "py-rrt{goal_bias=0.3}", "raises"]\n'
        'trackers = ["obc", "py-pd"]\n'
        'presets = ["realistic"]\n'
        "seeds = 1\n"
        "[limits]\niterations = 20000\n"
    )
    with pytest.warns(RuntimeWarning, match="crashed"):
        res = mb.bench(f, out=tmp_path / "out", threads=2)
    assert len(res) == 6
    by = {(r["planner_name"], r["tracker"]): r for r in res.rows}
    assert by[("py-rrt", "py-pd")]["solved"] is True
    assert by[("py-rrt", "py-pd")]["reached_goal"] is True
    assert by[("goal-zoom-rrt", "py-pd")]["reached_goal"] is True
    crashed = [r for r in res.rows if r["status"] == "crash"]
    assert len(crashed) == 2 and all("planner exploded on purpose" in r["error"] for r in crashed)
    py_runs = [r["run_id"] for r in res.rows if r["planner_name"] == "py-rrt"]
    assert all(len(res.progress[i]["iteration"]) >= 2 for i in py_runs)
    report = (tmp_path / "out" / "report.html").read_text()
    assert "py-rrt" in report and "py-pd" in report
    # the plugins hold the GIL: their runs went one at a time, and the report and manifest say so
    assert "went one at a time" in report and "GIL" in report
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert manifest["one_at_a_time"] == ["py-pd", "py-rrt", "raises"]


def test_main_lists_plugins(capfd):
    mb.register_planner("seen", Seen)
    mb.main(["plan", "--list"])
    out = capfd.readouterr().out
    assert "seen" in out and "count" in out and "goal-zoom-rrt" in out

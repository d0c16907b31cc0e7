"""Bad input raises clear exceptions (InputError, a ValueError, with file/field/reason)."""

import numpy as np
import pytest

import magbench as mb


def test_unknown_scenario():
    with pytest.raises(mb.InputError) as e:
        mb.Scenario.load("no-such-scenario")
    assert e.value.file == "no-such-scenario"
    assert "not a built-in scenario" in e.value.reason
    assert isinstance(e.value, ValueError)
    assert str(e.value).startswith("no-such-scenario: ")


def test_bad_scenario_file_names_field(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(
        'name = "bad"\n[world]\nwidth = -3\nheight = 10\n'
        "[start]\nagents = [[3.0, 5.0], [5.5, 5.0]]\n"
        "[goal]\nagents = [[15.0, 5.0], [17.5, 5.0]]\ntolerance = 1.0\n"
    )
    with pytest.raises(mb.InputError) as e:
        mb.Scenario.load(str(f))
    assert e.value.file == str(f) and e.value.field.startswith("world"), str(e.value)


@pytest.mark.parametrize(
    "x0,u,d,field",
    [
        ([1.0, 2.0, 3.0], [0, 0, 0, 0], 0.1, "x0"),
        (np.zeros((2, 2, 4)), [0, 0, 0, 0], 0.1, "x0"),
        ([4.0, 4.0, 6.5, np.nan], [0, 0, 0, 0], 0.1, "x0"),
        ([4.0, 4.0, 6.5, 4.0], [0, 0, 0], 0.1, "u"),
        ([4.0, 4.0, 6.5, 4.0], [0, 0, np.inf, 0], 0.1, "u"),
        ([4.0, 4.0, 6.5, 4.0], [0, 0, 0, 0], np.nan, "duration_s"),
        ([4.0, 4.0, 6.5, 4.0], [0, 0, 0, 0], -1.0, "duration_s"),
        ([4.0, 4.0, 6.5, 4.0], [0, 0, 0, 0], 1e12, "duration_s"),
        (np.zeros((3, 4)), np.zeros((2, 4)), 0.1, "u"),
    ],
)
def test_bad_arrays(sc, x0, u, d, field):
    for call in (sc.propagate, sc.motion_valid):
        with pytest.raises(mb.InputError) as e:
            call(x0, u, d)
        assert e.value.field == field, str(e.value)


def test_bad_states_for_checks(sc):
    for call in (sc.is_valid, sc.in_goal, sc.goal_distance):
        with pytest.raises(mb.InputError):
            call([1.0, 2.0])
        with pytest.raises(mb.InputError):
            call([np.nan, 0.0, 1.0, 1.0])
    with pytest.raises(ValueError):
        sc.is_valid("not an array")


def test_bad_planner_and_params(sc):
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "no-such-planner")
    assert e.value.field == "planner"
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "goal-zoom-rrt", params={"no_such_param": 1})
    assert e.value.field == "param.no_such_param"
    with pytest.raises(mb.InputError) as e:
        mb.plan(sc, "goal-zoom-rrt", time_limit_s=-1.0)
    assert e.value.field == "time_limit_s"
    with pytest.raises(mb.InputError):
        mb.plan(sc, "goal-zoom-rrt", max_iterations=0)


def test_plan_for_another_scenario(plan):
    other = mb.Scenario.load("micro-factory")
    with pytest.raises(mb.InputError) as e:
        mb.track(other, plan, tracker="obc")
    assert "open-field" in str(e.value)
    # a plan built in Python that starts elsewhere
    p = mb.Plan(states=plan.states, controls=plan.controls, durations=plan.durations)
    with pytest.raises(mb.InputError) as e:
        mb.track(other, p, tracker="obc")
    # within the goal tolerance of micro-factory's start (the one start rule), refused by its fit
    assert e.value.field.split("[")[0] in ("states", "controls")
    trio = mb.Scenario.load("trio-row")
    with pytest.raises(mb.InputError) as e:
        mb.track(trio, p, tracker="obc")
    assert "agent" in e.value.reason


def test_bad_tracker_preset(sc, plan):
    with pytest.raises(mb.InputError) as e:
        mb.track(sc, plan, tracker="no-such-tracker")
    assert e.value.field == "tracker"
    with pytest.raises(mb.InputError):
        mb.track(sc, plan, tracker="obc", params={"nope": 3})
    with pytest.raises(mb.InputError) as e:
        mb.track(sc, plan, tracker="obc", preset="no-such-preset")
    assert "no-such-preset" in str(e.value)


def test_bad_plan_arrays(plan):
    S, U, D = plan.states, plan.controls, plan.durations
    with pytest.raises(mb.InputError) as e:
        mb.Plan(states=S, controls=U[:-1], durations=D)
    assert e.value.field == "controls"
    with pytest.raises(mb.InputError) as e:
        mb.Plan(states=S, controls=U, durations=D[:-1])
    assert e.value.field == "durations"
    bad = S.copy()
    bad[3, 1] = np.nan
    with pytest.raises(mb.InputError) as e:
        mb.Plan(states=bad, controls=U, durations=D)
    assert e.value.field == "states[3]"
    with pytest.raises(mb.InputError):
        mb.Plan(states=S, controls=U, durations=D, flow="euler")


def test_invalid_plan_is_refused_by_track(sc, plan):
    # a plan whose stored states are not what its controls give
    S = plan.states.copy()
    S[5:, 0] += 0.5
    p = mb.Plan(states=S, controls=plan.controls, durations=plan.durations)
    with pytest.raises(mb.InputError):
        mb.track(sc, p, tracker="obc")


def test_command_line_errors():
    with pytest.raises(mb.InputError):
        mb.main(["no-such-command"])
    with pytest.raises(mb.InputError):
        mb.main(["plan", "no-such-scenario", "--planner", "sst"])

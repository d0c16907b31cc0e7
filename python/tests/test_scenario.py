"""Scenario loading and its operations, single and batched, against each other."""

import numpy as np
import pytest

import magbench as mb


def test_load_builtin_and_file(sc, tmp_path):
    assert sc.name == "open-field"
    assert sc.agents == 2 and sc.legs >= 1 and sc.leg == 0
    assert sc.start.shape == (4,) and sc.goal.shape == (4,)
    assert sc.state_names == ["x0", "y0", "x1", "y1"]
    assert sc.control_names == ["theta_rad", "alpha_rad", "grad_x_t_per_m", "grad_y_t_per_m"]
    assert sc.control_period == pytest.approx(1 / 60)
    w, h = sc.bounds
    assert w > 0 and h > 0
    f = tmp_path / "mine.toml"
    f.write_text(
        'name = "mine"\n[world]\nwidth = 20\nheight = 10\n'
        "[start]\nagents = [[3.0, 5.0], [5.5, 5.0]]\n"
        "[goal]\nagents = [[15.0, 5.0], [17.5, 5.0]]\ntolerance = 1.0\n"
    )
    mine = mb.Scenario.load(str(f))
    assert mine.name == "mine" and mine.bounds == (20.0, 10.0)
    np.testing.assert_array_equal(mine.start, [3.0, 5.0, 5.5, 5.0])


def test_propagate_moves_and_is_deterministic(sc):
    u = sc.sample_control(3)
    x1 = sc.propagate(sc.start, u, 0.5)
    assert x1.shape == (4,)
    assert not np.allclose(x1, sc.start)
    np.testing.assert_array_equal(x1, sc.propagate(sc.start, u, 0.5))
    np.testing.assert_array_equal(sc.propagate(sc.start, u, 0.0), sc.start)
    # a list is an array too
    np.testing.assert_array_equal(x1, sc.propagate(list(sc.start), list(u), 0.5))


def test_batched_forms_match_single_calls(sc):
    U = sc.sample_control(7, n=32)
    assert U.shape == (32, 4)
    X = sc.propagate(sc.start, U, 0.25)
    assert X.shape == (32, 4)
    for i in range(32):
        np.testing.assert_array_equal(X[i], sc.propagate(sc.start, U[i], 0.25))
    X0 = np.tile(sc.start, (32, 1))
    D = np.full(32, 0.25)
    np.testing.assert_array_equal(X, sc.propagate(X0, U, D))
    ok = sc.motion_valid(X0, U, D)
    assert ok.dtype == bool and ok.shape == (32,)
    assert list(ok) == [sc.motion_valid(sc.start, U[i], 0.25) for i in range(32)]
    valid = sc.is_valid(X)
    assert list(valid) == [sc.is_valid(x) for x in X]
    goal = sc.in_goal(np.stack([sc.goal, sc.start]))
    assert list(goal) == [True, False]


def test_validity_goal_and_motion(sc):
    assert sc.is_valid(sc.start) is True
    assert sc.in_goal(sc.goal) is True and sc.in_goal(sc.start) is False
    assert sc.goal_distance(sc.goal) == 0.0
    # agents on top of each other break the proximity range
    same = np.array([sc.start[0], sc.start[1], sc.start[0], sc.start[1]])
    assert sc.is_valid(same) is False
    # outside the world
    assert sc.is_valid(sc.start + [1e4, 0, 1e4, 0]) is False
    u = sc.sample_control(1)
    ok, end = sc.motion_valid(sc.start, u, 0.5, return_state=True)
    assert ok is sc.motion_valid(sc.start, u, 0.5) and end.shape == (4,)
    if ok:
        # a valid motion ends where the model's flow does, in a valid configuration
        np.testing.assert_array_equal(end, sc.propagate(sc.start, u, 0.5))
        assert sc.is_valid(end) is True


def test_sample_control_is_admissible_and_seeded(sc):
    U = sc.sample_control(11, n=1000)
    g = sc.gradient_limit
    assert np.all(np.abs(U[:, 2:]) <= g) and np.all(np.abs(U[:, 0]) <= np.pi)
    assert np.all(U[:, 1] == 0.0)  # two agents: the field stays in the plane
    np.testing.assert_array_equal(sc.sample_control(5), sc.sample_control(5))
    assert not np.array_equal(sc.sample_control(5), sc.sample_control(6))


def test_three_agents_at_an_interface_may_tilt():
    trio = mb.Scenario.load("trio-row")
    assert trio.agents == 3 and len(trio.state_names) == 6
    U = trio.sample_control(1, n=200)
    assert trio.elevation_free == bool(np.any(U[:, 1] > 0))
    assert np.all(U[:, 1] <= trio.alpha_max + 1e-12)

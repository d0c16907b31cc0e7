"""A kinodynamic RRT written in Python with three operations of the problem: ``propagate``
(not needed here: ``motion_valid(..., return_state=True)`` gives the end state of the motion it
checks), ``motion_valid`` and ``in_goal``. Nearest neighbours are a numpy scan.

Register it and plan with it like a built-in:

    import magbench as mb
    from py_rrt import PyRrt
    mb.register_planner("py-rrt", PyRrt)
    p = mb.plan(mb.Scenario.load("open-field"), "py-rrt", seed=0, max_iterations=3000)
"""

import numpy as np

import magbench as mb


class PyRrt:
    """RRT: sample a target (the goal with probability ``goal_bias``), extend the nearest node
    by a random control held for 1..``max_periods`` control periods, keep the motion if it is
    valid, stop at the first node in the goal region."""

    def __init__(self, goal_bias=0.1, max_periods=30):
        if not 0.0 <= goal_bias <= 1.0:
            raise ValueError(f"goal_bias must be in [0, 1], got {goal_bias}")
        if max_periods < 1:
            raise ValueError(f"max_periods must be at least 1, got {max_periods}")
        self.goal_bias = float(goal_bias)
        self.max_periods = int(max_periods)

    def solve(self, problem):
        rng = np.random.default_rng(problem.seed)
        d = len(problem.start)
        width, height = problem.bounds
        g = problem.gradient_limit
        cap = 1024
        nodes = np.empty((cap, d))
        parent = np.empty(cap, dtype=np.int64)
        controls = np.empty((cap, 4))
        durations = np.empty(cap)
        nodes[0] = problem.start
        parent[0] = -1
        n = 1
        budget = problem.max_iterations
        every = max(1, budget // 100) if budget < 2**62 else 1000
        lo, hi = np.zeros(d), np.tile([width, height], d // 2)
        it = 0
        while not problem.should_stop(it):
            it += 1
            if rng.random() < self.goal_bias:
                target = problem.goal
            else:
                target = rng.uniform(lo, hi)
            near = int(np.argmin(((nodes[:n] - target) ** 2).sum(axis=1)))
            u = np.array([rng.uniform(-np.pi, np.pi), 0.0, rng.uniform(-g, g), rng.uniform(-g, g)])
            dt = problem.control_period * int(rng.integers(1, self.max_periods + 1))
            ok, x = problem.motion_valid(nodes[near], u, dt, return_state=True)
            if it % every == 0:
                problem.report_progress(it, None)
            if not ok:
                continue
            if n == cap:
                cap *= 2
                nodes = np.resize(nodes, (cap, d))
                parent = np.resize(parent, cap)
                controls = np.resize(controls, (cap, 4))
                durations = np.resize(durations, cap)
            nodes[n], parent[n], controls[n], durations[n] = x, near, u, dt
            n += 1
            if problem.in_goal(x):
                path = [n - 1]
                while parent[path[-1]] >= 0:
                    path.append(int(parent[path[-1]]))
                path.reverse()
                plan = mb.Plan(
                    states=nodes[path],
                    controls=controls[path[1:]],
                    durations=durations[path[1:]],
                )
                problem.report_progress(it, problem.cost(plan))
                return plan
        return None

"""Python call overhead of the Scenario operations, and the example Python RRT's speed.

Measures, with time.perf_counter over many calls:

1. per call of ``propagate`` and ``motion_valid`` from Python, against the same call timed in
   Rust (``magbench._magbench.rust_call_cost``): the difference is the binding's overhead;
2. the batched form (an (n, d) array) per state, against the Rust cost per call;
3. the example Python RRT's iterations/s (python/examples/py_rrt.py) beside goal-zoom-rrt's,
   on the same scenario, seeds and iteration budget.

Usage: python python/bench/overhead.py [--quick]
"""

import os
import sys
import time

import numpy as np

import magbench as mb
from magbench import _magbench

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "examples"))


ROUNDS = 30


def per_call(f, calls):
    """Best of ROUNDS rounds of ``calls`` calls of f(), seconds per call. Short rounds and the
    best of many: on a shared machine most long rounds are preempted by other work."""
    best = float("inf")
    for _ in range(ROUNDS):
        t0 = time.perf_counter()
        for _ in range(calls):
            f()
        best = min(best, (time.perf_counter() - t0) / calls)
    return best


def rust_cost(sc, op, x0, u, d, calls):
    return min(_magbench.rust_call_cost(sc, op, x0, u, d, calls) for _ in range(ROUNDS))


def calls_table(quick):
    calls = 200 if quick else 2000
    rows = []
    for name in ["micro-factory", "trio-row"]:
        sc = mb.Scenario.load(name)
        x0 = sc.start.copy()
        u = sc.sample_control(3)
        d = sc.control_period
        for op in ["propagate", "motion_valid"]:
            f = getattr(sc, op)
            py = per_call(lambda: f(x0, u, d), calls)
            rs = rust_cost(sc, op, x0, u, d, calls)
            n = 1000 if quick else 10000
            X0 = np.tile(x0, (n, 1))
            U = np.tile(u, (n, 1))
            batch = per_call(lambda: f(X0, U, d), 1) / n
            rows.append((name, op, sc.agents, rs, py, py - rs, batch, batch / rs))
    print(f"one call = {1 / 60:.4f} s (one control period); best of {ROUNDS} rounds")
    print(f"{'scenario':<14} {'call':<13} {'agents':>6} {'rust µs':>9} {'python µs':>10} "
          f"{'overhead µs':>12} {'batched µs/state':>17} {'batched/rust':>13}")
    for name, op, n, rs, py, over, batch, ratio in rows:
        print(f"{name:<14} {op:<13} {n:>6} {rs * 1e6:>9.3f} {py * 1e6:>10.3f} "
              f"{over * 1e6:>12.3f} {batch * 1e6:>17.3f} {ratio:>13.2f}")


def rrt_table(quick):
    from py_rrt import PyRrt

    mb.register_planner("py-rrt", PyRrt, replace=True)
    seeds = range(3 if quick else 10)
    budget = 20000
    print(f"\nopen-field, {len(seeds)} seeds, max_iterations = {budget} (stops at the first solution)")
    print(f"{'planner':<16} {'solved':>7} {'iterations':>11} {'time s':>9} {'iterations/s':>13}")
    for planner in ["goal-zoom-rrt", "py-rrt"]:
        its = secs = solved = 0
        for s in seeds:
            sc = mb.Scenario.load("open-field")
            p = mb.plan(sc, planner, seed=s, max_iterations=budget)
            its += p.info["iterations"]
            secs += p.info["time_s"]
            solved += bool(p.solved)
        print(f"{planner:<16} {solved:>4}/{len(seeds):<2} {its:>11} {secs:>9.3f} {its / secs:>13.0f}")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    calls_table(quick)
    if "--no-rrt" not in sys.argv:
        rrt_table(quick)

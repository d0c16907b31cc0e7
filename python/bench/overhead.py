"""Python call overhead of the Scenario operations, and the example Python RRT's speed.

Measures, with time.perf_counter over many calls, and prints as Markdown tables:

1. ``calls``: per call of ``propagate`` and ``motion_valid`` from Python, against the same call
   timed in Rust (``magbench._magbench.rust_call_cost``): the difference is the binding's
   overhead; the batched form (an (n, d) array) per state against the Rust cost per call; and
   ``propagate`` given its control as a Python list (converted by numpy on each call);
2. ``rrt``: the example Python RRT's iterations/s (python/examples/py_rrt.py) beside
   goal-zoom-rrt's, on the same scenario, seeds and iteration budget, and their ratios.

Usage: python python/bench/overhead.py [--quick] [--only calls|rrt]

`cargo xtask measure --only python-overhead` and `--only python-rrt` keep these tables.
"""

import argparse
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
    """Best of ROUNDS rounds of the Rust loop's seconds per call of ``op``."""
    return min(_magbench.rust_call_cost(sc, op, x0, u, d, calls) for _ in range(ROUNDS))


def us(seconds):
    """Seconds as microseconds with three decimals."""
    return f"{seconds * 1e6:.3f} µs"


def calls_table(quick):
    """The Markdown table of the call costs."""
    calls = 200 if quick else 2000
    n = 1000 if quick else 10000
    lines = [
        "| scenario | call | agents | Rust | Python | overhead | batched, per state | batched / Rust |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name in ["micro-factory", "trio-row"]:
        sc = mb.Scenario.load(name)
        x0 = sc.start.copy()
        u = sc.sample_control(3)
        d = sc.control_period
        model = "exact pair flow" if name == "micro-factory" else "RK4"
        for op in ["propagate", "motion_valid"]:
            f = getattr(sc, op)
            py = per_call(lambda: f(x0, u, d), calls)
            rs = rust_cost(sc, op, x0, u, d, calls)
            X0 = np.tile(x0, (n, 1))
            U = np.tile(u, (n, 1))
            batch = per_call(lambda: f(X0, U, d), 1) / n
            agents = f"{sc.agents} ({model})" if op == "propagate" else f"{sc.agents}"
            lines.append(
                f"| {name} | `{op}` | {agents} | {us(rs)} | {us(py)} | **{us(py - rs)}** "
                f"| {us(batch)} | **{batch / rs:.2f}×** |"
            )
        if name == "micro-factory":
            ul = [float(v) for v in u]
            rs = rust_cost(sc, "propagate", x0, u, d, calls)
            py = per_call(lambda: sc.propagate(x0, ul, d), calls)
            lines.append(
                f"| {name} | `propagate`, the control a list of four floats | {sc.agents} "
                f"| {us(rs)} | {us(py)} | **{us(py - rs)}** | – | – |"
            )
    return "\n".join(lines)


def rrt_table(quick):
    """The Markdown table of the Python RRT beside goal-zoom-rrt."""
    from py_rrt import PyRrt

    mb.register_planner("py-rrt", PyRrt, replace=True)
    seeds = range(3 if quick else 10)
    budget = 20000
    lines = [
        "| planner | solved | iterations (sum) | time (sum) | iterations/s | time per iteration |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    sums = {}
    for planner in ["goal-zoom-rrt", "py-rrt"]:
        its = secs = solved = 0
        for s in seeds:
            sc = mb.Scenario.load("open-field")
            p = mb.plan(sc, planner, seed=s, max_iterations=budget)
            its += p.info["iterations"]
            secs += p.info["time_s"]
            solved += bool(p.solved)
        sums[planner] = (its, secs)
        lines.append(
            f"| {planner} | {solved}/{len(seeds)} | {its} | {secs:.3f} s | {its / secs:.0f} "
            f"| {secs / its * 1e6:.1f} µs |"
        )
    (gi, gs), (pi, ps) = sums["goal-zoom-rrt"], sums["py-rrt"]
    lines.append(
        f"| py-rrt / goal-zoom-rrt | – | {pi / gi:.1f}× | {ps / gs:.0f}× "
        f"| {(pi / ps) / (gi / gs):.3f}× | {(ps / pi) / (gs / gi):.0f}× |"
    )
    caption = (
        f"open-field, {len(seeds)} seeds, max_iterations = {budget}, each run stopping at its "
        "first solution"
    )
    return caption, "\n".join(lines)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer calls, rows and seeds")
    ap.add_argument("--only", choices=["calls", "rrt"], help="print only this table")
    a = ap.parse_args(argv)
    if a.only in (None, "calls"):
        print(f"One call = {1 / 60:.4f} s (one control period); best of {ROUNDS} rounds.\n")
        print(calls_table(a.quick))
    if a.only in (None, "rrt"):
        caption, table = rrt_table(a.quick)
        print(f"\n{caption}:\n")
        print(table)


if __name__ == "__main__":
    main(sys.argv[1:])

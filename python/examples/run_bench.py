"""Benchmarks the example Python planner and tracker beside the built-ins.

    python python/examples/run_bench.py [OUT]      (OUT: results/python-plugins)

Registers ``py-rrt`` (py_rrt.PyRrt) and ``py-pd`` (py_pd.PyPd), runs bench.toml with
``magbench.bench`` and prints, as a Markdown table, one row per planner and tracker from the
results (`cargo xtask measure --only python-plugins` keeps that table). The results folder
has the plugins' rows in runs.csv, their curves in progress.csv and their series in the plots,
like any built-in's. A crashed run is an error (exit code 1, its message on stderr).
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import magbench as mb  # noqa: E402
from py_pd import PyPd  # noqa: E402
from py_rrt import PyRrt  # noqa: E402

PLANNERS = ["goal-zoom-rrt", "py-rrt"]
TRACKERS = ["obc", "py-pd"]


def table(rows):
    """The Markdown table of the runs ``rows``: one line per planner and tracker."""
    lines = [
        "| planner | tracker | runs | solved | mean iterations | reached the goal | mean RMS error |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for planner in PLANNERS:
        for tracker in TRACKERS:
            mine = [r for r in rows if r["planner"] == planner and r["tracker"] == tracker]
            if not mine:
                continue
            rms = [r["rms_error_bl"] for r in mine if r["rms_error_bl"] is not None]
            rms_text = f"{np.mean(rms):.3f} BL" if rms else "–"
            lines.append(
                f"| {planner} | {tracker} | {len(mine)} "
                f"| {sum(bool(r['solved']) for r in mine)} "
                f"| {np.mean([r['iterations'] for r in mine]):.0f} "
                f"| {sum(bool(r['reached_goal']) for r in mine)} | {rms_text} |"
            )
    return "\n".join(lines)


def main(out):
    mb.register_planner("py-rrt", PyRrt, replace=True)
    mb.register_tracker("py-pd", PyPd, replace=True)
    res = mb.bench(os.path.join(HERE, "bench.toml"), out=out)
    print(f"{len(res)} runs in {out}\n")
    print(table(res.rows))
    crashed = [r for r in res.rows if r["status"] == "crash"]
    for r in crashed:
        print(f"run {r['run_id']} crashed: {r['error']}", file=sys.stderr)
    return res, len(crashed)


if __name__ == "__main__":
    _, crashed = main(sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "python-plugins"))
    sys.exit(1 if crashed else 0)

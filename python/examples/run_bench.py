"""Benchmarks the example Python planner and tracker beside the built-ins.

    python python/examples/run_bench.py [OUT]      (OUT: results/python-plugins)

Registers ``py-rrt`` (py_rrt.PyRrt) and ``py-pd`` (py_pd.PyPd), runs bench.toml with
``magbench.bench`` and prints one line per planner and tracker from the results. The results
folder has the plugins' rows in runs.csv, their curves in progress.csv and their series in the
plots, like any built-in's.
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import magbench as mb  # noqa: E402
from py_pd import PyPd  # noqa: E402
from py_rrt import PyRrt  # noqa: E402


def main(out):
    mb.register_planner("py-rrt", PyRrt, replace=True)
    mb.register_tracker("py-pd", PyPd, replace=True)
    res = mb.bench(os.path.join(HERE, "bench.toml"), out=out)
    print(f"{len(res)} runs in {out}")
    print(f"{'planner':<14} {'tracker':<8} {'runs':>4} {'solved':>6} {'iterations':>10} "
          f"{'reached':>7} {'rms error BL':>12} {'crashed':>7}")
    for planner in ["goal-zoom-rrt", "py-rrt"]:
        for tracker in ["obc", "py-pd"]:
            rows = [r for r in res.rows if r["planner"] == planner and r["tracker"] == tracker]
            if not rows:
                continue
            rms = [r["rms_error_bl"] for r in rows if r["rms_error_bl"] is not None]
            print(f"{planner:<14} {tracker:<8} {len(rows):>4} "
                  f"{sum(bool(r['solved']) for r in rows):>6} "
                  f"{np.mean([r['iterations'] for r in rows]):>10.0f} "
                  f"{sum(bool(r['reached_goal']) for r in rows):>7} "
                  f"{np.mean(rms) if rms else float('nan'):>12.3f} "
                  f"{sum(r['status'] == 'crash' for r in rows):>7}")
    return res


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "python-plugins"))

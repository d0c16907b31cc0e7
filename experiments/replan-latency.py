#!/usr/bin/env python3
"""Replan latency on micro-factory under the hardware preset: repair against restart.

Runs `magbench track --json` for every seed, once with `replan_mode=restart` and once with
`replan_mode=repair` (interleaved, so both see the same machine load), with a low replan
threshold (replan_error = 0.1 BL for 0.5 s) so that drift calls for many replans, and prints
per mode: the replan wall-time and CPU-time distributions (p50, p95, max; every replan for a
persistent error, from the run's replan_log), how the replans found their plans, the work per replan
(load-independent: rejoins, tree iterations, edges repair checked, planner
iterations) and the tracking error.

    python3 experiments/replan-latency.py [--bin target/release/magbench] [--seeds 40]
                                          [--json OUT.json]

The book's figures (docs/measured/replan-latency.md) come from the same loop settings run as
`experiments/replan.toml` by `cargo xtask measure --only replan-latency`; this script is for
a look at single runs (`--json` keeps each run's replan log) and at `magbench track`'s
defaults.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

LOOP = ["replan_error=0.1", "replan_after=0.5", "max_replans=100"]
MODES = ["restart", "repair"]


def percentile(xs, q):
    """The q-quantile of xs by linear interpolation (numpy's default)."""
    xs = sorted(xs)
    if not xs:
        return float("nan")
    pos = q * (len(xs) - 1)
    lo = int(pos)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def track(binary, seed, mode, extra):
    cmd = [binary, "track", "micro-factory", "--tracker", "lookahead", "--preset", "hardware",
           "--seed", str(seed), "--json"]
    for p in LOOP + [f"replan_mode={mode}"] + extra:
        cmd += ["--param", p]
    out = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if out.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {out.returncode}: {out.stderr.strip()}")
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="target/release/magbench")
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--param", action="append", default=[],
                    help="an extra loop parameter for the repair runs, key=value")
    ap.add_argument("--json", help="write every run's replan log and metrics here")
    a = ap.parse_args()
    if not os.path.exists(a.bin):
        sys.exit(f"--bin: {a.bin} does not exist (cargo build --release -p magbench)")
    if a.seeds < 1:
        sys.exit("--seeds: must be at least 1")
    runs = {m: [] for m in MODES}
    for seed in range(a.seeds):
        for m in MODES:
            runs[m].append(track(a.bin, seed, m, a.param if m == "repair" else []))
    print(f"micro-factory, lookahead, hardware preset, seeds 0-{a.seeds - 1}, "
          f"loop {' '.join(LOOP)}")
    for m in MODES:
        events = [r for run in runs[m] for r in run["replan_log"] if r["reason"] == "error"]
        ms = [1e3 * r["wall_s"] for r in events]
        cpu = [1e3 * r["cpu_s"] for r in events if r["cpu_s"] is not None]
        hows = {}
        for r in events:
            hows[r["how"]] = hows.get(r["how"], 0) + 1
        work = {k: [r[k] for r in events] for k in ("rejoins", "tree_iterations",
                                                   "repair_edges", "planner_iterations")}
        rms = [run["rms_error_bl"] for run in runs[m]]
        rms_true = [run["rms_error_true_bl"] for run in runs[m]]
        reached = sum(run["reached_goal"] for run in runs[m])
        within = sum(x <= 1000.0 / 60.0 for x in ms)
        print(f"\n{m}: {len(events)} drift replans; wall ms p50 {percentile(ms, 0.5):.2f}, "
              f"p95 {percentile(ms, 0.95):.2f}, max {max(ms, default=float('nan')):.2f}; "
              f"{within}/{len(events)} within one 60 Hz frame (16.7 ms)")
        print(f"  CPU ms (the loop thread's): p50 {percentile(cpu, 0.5):.2f}, "
              f"p95 {percentile(cpu, 0.95):.2f}, max {max(cpu, default=float('nan')):.2f}; "
              f"{sum(x <= 1000.0 / 60.0 for x in cpu)}/{len(cpu)} within one frame")
        print(f"  how: {dict(sorted(hows.items()))}")
        for k, xs in work.items():
            print(f"  {k} per replan: mean {statistics.fmean(xs) if xs else 0:.1f}, "
                  f"p95 {percentile(xs, 0.95):.0f}, max {max(xs, default=0)}")
        print(f"  tracking: RMS error (observed) mean {statistics.fmean(rms):.4f} BL, "
              f"(true) mean {statistics.fmean(rms_true):.4f} BL; reached goal {reached}/{len(rms)}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({m: [{k: run[k] for k in ("seed", "status", "rms_error_bl",
                                                 "rms_error_true_bl", "replans", "replan_log")}
                           for run in runs[m]] for m in MODES}, f, indent=1)


if __name__ == "__main__":
    main()

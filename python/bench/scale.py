"""What a results folder costs as it grows: wall time and peak memory of the harness's
commands against the number of runs.

For each size N (``N`` or ``N/S``: N runs in S shards, 10 unless given), with the harness's
fake executor (synthetic runs through the whole sweep machinery: five planners tracked by one
tracker, 51 progress points per run; no planning), or with ``--real`` real planning runs (the
seed's goal-zoom RRT, as it is and straightened, on the four built-in pair mazes; N a multiple
of 8), each command runs in its own process, started by this script, and is timed with its
peak resident memory read from ``os.wait4``:

- ``bench``: the N runs in one folder (``--replays none``, 2 threads), for N up to
  ``--whole-up-to``;
- ``bench --resume``: that folder again, its last ``runs.csv`` row cut in half as a kill
  leaves it (the run's row and trace are dropped, both run files rewritten, and the run runs
  again);
- ``bench (S shards)``: the same experiment as S shards, one after another (the largest);
- ``merge``: the S shards into one folder;
- ``results verify``: the merged folder;
- ``results plot``: the merged folder's derived files (plots, report, ompl.log, runs.parquet,
  progress.parquet);
- ``regress``: the merged folder against the unsharded one (against itself above
  ``--whole-up-to``: both folders are read all the same);
- the merged folder's run files on disk: in Parquet, and in CSV;
- the sharded path: the shards, merge, verify, plot and regress, their wall times summed and
  their largest peak.

Each process is the magbench binary that ``$MAGBENCH_BIN`` names (``cargo xtask measure`` sets
it to itself), else ``python -c "import magbench; magbench.main([...])"``, whose interpreter with
numpy (the row ``import magbench``) is then part of every figure.

Usage: python python/bench/scale.py [--runs N[/S] ...] [--whole-up-to N] [--real] [--work DIR]

`cargo xtask measure --only scale` keeps the table, and `--only scale-real` the real runs'.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

SHARDS = 10
WHOLE_UP_TO = 1_000_000


BIN = os.environ.get("MAGBENCH_BIN")


def run(args):
    """Runs magbench ``args`` in a process of its own; its wall time (s) and peak RSS (MB)."""
    if BIN:
        argv = [BIN, *args] if args else [BIN, "--version"]
    else:
        code = f"import magbench; magbench.main({args!r})" if args else "import magbench"
        argv = [sys.executable, "-c", code]
    t0 = time.perf_counter()
    p = subprocess.Popen(argv, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise SystemExit(f"magbench {' '.join(args)}: exit {p.returncode}")
    return wall, usage.ru_maxrss / 1024


def experiment(work, runs):
    """An experiment file of ``runs`` fake runs: five planners, each run planning alone and
    planned and tracked, so ten runs a seed (a million runs are 100,000 seeds, the most an
    experiment file takes)."""
    path = os.path.join(work, "scale.toml")
    with open(path, "w") as f:
        f.write(
            'name = "scale"\nscenarios = ["open-field"]\n'
            'planners = ["fake", "fake{p=0.5}", "fake{p=0.7}", "fake{p=0.9}", "fake{cost=20}"]\n'
            f"seeds = {max(1, runs // 10)}\n"
            '[limits]\niterations = 1000\n[tracking]\ntrackers = ["fake"]\npresets = ["realistic"]\n'
        )
    return path


def real_experiment(work, runs):
    """An experiment file of ``runs`` real planning runs: the seed's goal-zoom RRT, as it is and
    with its plans straightened, on the four built-in pair mazes, so eight runs a seed (the
    planner's first solution ends a run; 20,000 iterations or 1 s at most)."""
    path = os.path.join(work, "scale-real.toml")
    with open(path, "w") as f:
        f.write(
            'name = "scale-real"\n'
            'scenarios = ["open-field", "micro-factory", "narrow-passage", "cargo-delivery"]\n'
            'planners = ["goal-zoom-rrt", "goal-zoom-rrt{straighten=true}"]\n'
            f"seeds = {max(1, runs // 8)}\n"
            "[limits]\niterations = 20000\ntime = 1.0\n"
        )
    return path


def cut_last_row(path):
    """Cuts the last line of the file at ``path`` in half, as a kill while it was written."""
    with open(path, "rb+") as f:
        f.seek(0, os.SEEK_END)
        size = f.tell()
        f.seek(max(0, size - 65536))
        tail = f.read()
        start = tail.rstrip(b"\n").rfind(b"\n") + 1
        f.truncate(size - (len(tail) - start) // 2)


def measure(work, runs, shard_count, whole_up_to, real):
    """The table rows of size ``runs`` in ``shard_count`` shards (real runs if ``real``)."""
    exp = (real_experiment if real else experiment)(work, runs)
    flags = ["--quiet", "--replays", "none", "--threads", "2"]
    if not real:
        flags = ["--executor", "fake", *flags]
    rows = []
    whole = None
    if runs <= whole_up_to:
        whole = os.path.join(work, "whole")
        rows.append(("bench", *run(["bench", exp, "--out", whole, *flags])))
        cut_last_row(os.path.join(whole, "runs.csv"))
        rows.append(("bench --resume", *run(["bench", exp, "--out", whole, "--resume", *flags])))
    shards = []
    wall, peak = 0.0, 0.0
    for k in range(1, shard_count + 1):
        out = os.path.join(work, f"shard-{k}")
        w, m = run(["bench", exp, "--out", out, "--shard", f"{k}/{shard_count}", *flags])
        wall, peak = wall + w, max(peak, m)
        shards.append(out)
    rows.append((f"bench ({shard_count} shards, one after another)", wall, peak))
    merged = os.path.join(work, "merged")
    rows.append(("merge", *run(["merge", "--out", merged, *shards])))
    for s in shards:
        shutil.rmtree(s, ignore_errors=True)
    rows.append(("results verify", *run(["results", "verify", merged])))
    rows.append(("results plot", *run(["results", "plot", merged])))
    if whole:
        rows.append(("regress", *run(["regress", whole, merged])))
    else:
        rows.append(("regress (the merged folder against itself)", *run(["regress", merged, merged])))
    with open(os.path.join(merged, "runs.csv"), "rb") as f:
        rows_merged = sum(1 for _ in f) - 1
    if rows_merged != runs:
        raise SystemExit(f"{merged}: {rows_merged} runs, not {runs} (give N as a multiple of a seed's runs)")
    for files in (("runs.parquet", "progress.parquet"), ("runs.csv", "progress.csv")):
        size = sum(os.path.getsize(os.path.join(merged, f)) for f in files)
        rows.append((f"files on disk: {', '.join(files)}", None, size / 1e6))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", nargs="+", default=["10000", "100000"], help="N or N/S: N runs in S shards")
    ap.add_argument("--whole-up-to", type=int, default=WHOLE_UP_TO, help="largest N also run unsharded")
    ap.add_argument("--work", default=None)
    ap.add_argument("--real", action="store_true", help="real planning runs instead of the fake executor's")
    a = ap.parse_args()
    work = a.work or tempfile.mkdtemp(prefix="magbench-scale-")
    base_wall, base_peak = run([])
    print("| runs | command | wall time (s) | peak memory (MB) | peak memory per run (kB) |")
    print("| --- | --- | --- | --- | --- |")
    start = "magbench --version" if BIN else "import magbench (in every row)"
    print(f"| – | {start} | {base_wall:.2f} | {base_peak:.0f} | – |")
    for spec in a.runs:
        n, _, s = spec.partition("/")
        n, s = int(n), int(s or SHARDS)
        d = os.path.join(work, str(n))
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        total, highest = 0.0, 0.0
        for what, wall, peak in measure(d, n, s, a.whole_up_to, a.real):
            if wall is None:
                print(f"| {n} | {what} | – | {peak:.1f} MB on disk | {1e3 * peak / n:.2f} kB on disk |")
            else:
                print(f"| {n} | {what} | {wall:.1f} | {peak:.0f} | {1e3 * (peak - base_peak) / n:.2f} |")
                if not what.startswith("bench") or "shards" in what:
                    total, highest = total + wall, max(highest, peak)
        print(f"| {n} | the sharded path: shards, merge, verify, plot, regress | {total:.1f} | {highest:.0f} | – |")
        shutil.rmtree(d, ignore_errors=True)


if __name__ == "__main__":
    main()

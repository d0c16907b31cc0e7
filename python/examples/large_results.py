"""A large results folder read from its runs.parquet with polars, and a figure drawn from it.

    python python/examples/large_results.py [OUT] [RUNS]   (OUT: results/large, RUNS: 10000)

The cells (``# %%``) open as a notebook in Jupyter or VS Code. The folder is made by the
harness's fake executor, which gives synthetic runs (no planning or tracking) through the whole
sweep machinery: what is shown is the way to a large folder's Parquet, not a benchmark. On a
real folder, skip the first cell and point ``OUT`` at it. CI runs this script.
"""

# %% A results folder of RUNS runs (two fake planners, tracked by a fake tracker).
import json
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import polars as pl  # noqa: E402

import magbench as mb  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "large")
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 10_000
experiment = os.path.join(tempfile.mkdtemp(), "large.toml")
with open(experiment, "w") as f:
    f.write(
        'name = "large"\nscenarios = ["open-field"]\n'
        'planners = ["fake{p=0.9,cost=20}", "fake{p=0.6,cost=12}"]\n'
        f"seeds = {max(1, runs // 2)}\nreplays = \"none\"\n[limits]\niterations = 1000\n"
    )
mb.main(["bench", experiment, "--executor", "fake", "--out", out, "--quiet"])

# %% The runs, typed, with each column's unit from the file's metadata.
path = mb.load_results(out).parquet
frame = pl.read_parquet(path)
units = json.loads(pl.read_parquet_metadata(path)["magbench.columns"])
print(f"{path}: {frame.height} runs, {frame.width} columns, "
      f"{os.path.getsize(path) / frame.height:.0f} bytes per run")

# %% Success, cost and time per planner, aggregated lazily.
summary = (
    pl.scan_parquet(path)
    .group_by("planner")
    .agg(
        pl.len().alias("runs"),
        pl.col("solved").mean().alias("solved"),
        pl.col("cost").median().alias("median cost"),
        pl.col("first_solution_time_s").quantile(0.9).alias("p90 time to a first plan"),
    )
    .sort("planner")
    .collect()
)
print(summary)

# %% The cost of each planner's solved runs: one histogram per planner.
fig, ax = plt.subplots(figsize=(6, 3.5))
for (planner,), runs_of in frame.filter(pl.col("solved")).group_by("planner", maintain_order=True):
    ax.hist(runs_of["cost"].to_numpy(), bins=60, histtype="step", label=planner)
ax.set_xlabel(f"cost ({units['cost']['unit'] or 'objective units'})")
ax.set_ylabel("runs")
ax.legend()
fig.tight_layout()
figure = os.path.join(out, "plots", "cost-histogram-polars.png")
fig.savefig(figure, dpi=120)
print(f"figure: {figure}")

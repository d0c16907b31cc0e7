"""Loads an OMPL benchmark database with Planner Arena's own loader and draws what its tabs
draw, with its own code paths where they are plain functions and its exact plot recipes where
they sit inside Shiny callbacks.

Usage: python check.py DATABASE OUTDIR

- "Overall performance": the box plot of every run attribute Planner Arena offers and the
  status bar chart (`plannerarena.performance.enums_plot`);
- "Progress": for every progress attribute, the rows of the selected planners joined with the
  runs and filtered by the problem parameters exactly as `plannerarena.progress` does, then
  its loess smoother (`geom_smooth(method="loess", span=0.1)`), drawn to PNG;
- "Regression" needs several versions of a library and "Database info" shows tables: both are
  loaded here through the same database.

Raises (exit 1) on the first failure, naming the tab, problem, attribute and the error.
"""

import sys
from pathlib import Path

import plotnine as p9
import polars as pl

from plannerarena.database import load_database
from plannerarena.performance import enums_plot
from plannerarena.widgets import problem_parameter_filter


def progress_frame(data, problem, planners, version):
    """The data frame of plannerarena.progress.progress_server.data() without a parameter
    selection (Planner Arena's default: every parameter widget unset)."""
    runs = data["runs"].filter(pl.col("experiment") == problem)
    joined = data["progress"].join(
        runs.filter(
            (pl.col("version") == version) & (pl.col("planner").is_in(planners))
        ).select(["id", "planner"]),
        left_on="runid",
        right_on="id",
    )
    # With experiment properties Planner Arena filters by each one it has a widget for; the
    # widgets' first value is selected when there is a single value.
    params = {}
    exp = data["experiments"].filter(pl.col("experiment") == problem)
    for p in data["parameters"]:
        values = exp[p].unique().drop_nulls().to_list()
        if len(values) == 1:
            params[p] = str(values[0])
    return problem_parameter_filter(joined, params)


def main(db, out):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    data = load_database(db)
    if not data["problem_names"]:
        raise SystemExit(f"{db}: Planner Arena found no problems")
    if data["parameters"]:
        print(f"note: experiment properties {data['parameters']} (the Progress tab filters by them)")
    drawn = 0
    for problem in data["problem_names"]:
        runs = data["runs"].filter(pl.col("experiment") == problem)
        version = runs["version"].unique().to_list()[-1]
        planners = runs["planner"].unique().to_list()
        # Overall performance: box plots of numeric attributes, the status bar chart.
        for attr in ["time", "best cost", "iterations"]:
            df = runs.filter(pl.col("planner").is_in(planners)).drop_nulls(attr)
            if df.is_empty():
                continue
            plot = p9.ggplot(df, p9.aes(x="planner", y=attr, color="planner")) + p9.geom_boxplot()
            plot.save(out / f"performance-{problem}-{attr}.png", verbose=False, width=6, height=4)
            drawn += 1
        enum = data["enums"].filter(pl.col("name") == "status")
        enums_plot(runs, enum, []).save(out / f"status-{problem}.png", verbose=False, width=6, height=4)
        # Progress: every attribute, every planner (Planner Arena selects the first four).
        if data["progress"].is_empty():
            raise SystemExit(f"{db}: no progress rows")
        attrs = data["progress"].columns[2:]
        for attr in attrs:
            for chosen in [planners[:4], planners]:
                try:
                    df = progress_frame(data, problem, chosen, version)
                except Exception as e:
                    raise SystemExit(f"Progress, {problem}, {attr}: {type(e).__name__}: {e}")
                if df.is_empty():
                    raise SystemExit(f"Progress, {problem}, {attr}: no rows")
                plot = (
                    p9.ggplot(df, p9.aes(x="time", y=attr, color="planner", fill="planner"))
                    + p9.xlab("time (s)")
                    + p9.geom_smooth(na_rm=True, method="loess", span=0.1, se=False)
                )
                try:
                    plot.save(out / f"progress-{problem}-{attr}.png", verbose=False, width=6, height=4)
                except Exception as e:
                    raise SystemExit(f"Progress, {problem}, {attr}: {type(e).__name__}: {e}")
                drawn += 1
    print(f"ok: {len(data['problem_names'])} problems, {drawn} plots drawn")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])

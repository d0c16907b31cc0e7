"""bench, load_results and the command line from Python."""

import json
import os

import numpy as np
import pytest

import magbench as mb

from conftest import ROOT


def small_experiment(tmp_path, trackers='["obc"]', planners='["goal-zoom-rrt", "sst"]'):
    f = tmp_path / "small.toml"
    f.write_text(
        'name = "small"\n'
        'scenarios = ["open-field"]\n'
        f"planners = {planners}\n"
        f"trackers = {trackers}\n"
        'presets = ["realistic"]\n'
        "seeds = 2\n"
        "[limits]\niterations = 2000\n"
    )
    return f


def test_bench_rows_progress_and_pandas(tmp_path):
    out = tmp_path / "out"
    res = mb.bench(small_experiment(tmp_path), out=out, threads=2)
    assert isinstance(res, mb.Results) and len(res) == 4
    assert {r["planner"] for r in res.rows} == {"goal-zoom-rrt", "sst"}
    row = res.rows[0]
    assert isinstance(row["seed"], int) and isinstance(row["solved"], bool)
    assert row["tracker"] == "obc" and row["scenario"] == "open-field"
    it = res.column("iterations")
    assert it.dtype == float and np.all(it <= 2000)
    assert res.column("planner").dtype == object
    with pytest.raises(KeyError):
        res.column("no_such_column")
    assert set(res.progress) == {r["run_id"] for r in res.rows}
    curve = next(iter(res.progress.values()))
    assert curve["iteration"].dtype == np.int64 and np.all(np.diff(curve["iteration"]) >= 0)
    errs = res.agent_errors()
    assert errs.shape == (4, 2) and np.all(np.isfinite(errs))
    assert res.manifest["experiment"]["name"] == "small"
    assert os.path.isdir(out / "plots")


def test_to_pandas():
    pytest.importorskip("pandas")
    res = mb.load_results(os.path.join(ROOT, "results", "baseline"))
    df = res.to_pandas()
    assert len(df) == len(res.rows) and "rms_error_bl" in df.columns
    assert list(df["seed"]) == [r["seed"] for r in res.rows]
    pdf = res.progress_to_pandas()
    assert list(pdf.columns) == ["run", "run_id", "iteration", "time_s", "best_cost"]
    assert len(pdf) == sum(len(c["iteration"]) for c in res.progress.values())
    assert res.progress_parquet is None
    pl = pytest.importorskip("polars")
    frame = res.progress_to_polars()
    assert isinstance(frame, pl.DataFrame) and frame.columns == list(pdf.columns)
    assert frame["run"].to_list() == pdf["run"].tolist()
    assert frame["iteration"].to_list() == pdf["iteration"].tolist()


def test_load_committed_baseline():
    res = mb.load_results(os.path.join(ROOT, "results", "baseline"))
    assert len(res.rows) > 0 and "planner" in res.columns
    assert len(res.progress) == len(res.rows)


def test_load_results_of_a_missing_folder(tmp_path):
    with pytest.raises(FileNotFoundError):
        mb.load_results(tmp_path / "nothing")


def test_bench_writes_the_replays_its_policy_names(tmp_path):
    exp = small_experiment(tmp_path)
    res = mb.bench(exp, out=tmp_path / "all", replays="all")
    pages = sorted(p.name for p in (tmp_path / "all" / "replays").glob("run-*.html"))
    assert len(pages) == len(res) == 4
    assert json.loads((tmp_path / "all" / "manifest.json").read_text())["replays"] == "all"
    mb.bench(exp, out=tmp_path / "none", replays="none")
    assert not list((tmp_path / "none" / "replays").glob("run-*.html"))
    with pytest.raises(mb.InputError) as e:
        mb.bench(exp, out=tmp_path / "bad", replays="some")
    assert "--replays" in str(e.value)


def test_the_parquet_file_holds_the_csv_runs_typed(tmp_path):
    import polars as pl
    import pyarrow.parquet as pa

    res = mb.bench(small_experiment(tmp_path), out=tmp_path / "out")
    assert res.parquet == str(tmp_path / "out" / "runs.parquet")
    table = pa.read_table(res.parquet)
    assert table.column_names == res.columns
    types = {f.name: str(f.type) for f in table.schema}
    assert types["run_id"] == "string" and types["seed"] == "int64"
    assert types["solved"] == "bool" and types["rms_error_bl"] == "double"
    units = json.loads(table.schema.metadata[b"magbench.columns"])
    assert units["rms_error_bl"]["unit"] == "BL" and units["plan_time_s"]["unit"] == "s"
    for csv_row, pq_row in zip(res.rows, table.to_pylist(), strict=True):
        assert {k: (None if v == "" else v) for k, v in pq_row.items()} == csv_row
    df = res.to_pandas()
    assert len(df) == len(res) and str(df["seed"].dtype) == "int64"
    frame = res.to_polars()
    assert isinstance(frame, pl.DataFrame) and frame.shape == (len(res), len(res.columns))
    assert frame["run_id"].to_list() == [r["run_id"] for r in res.rows]


def test_the_progress_parquet_file_holds_the_csv_traces_typed(tmp_path):
    import polars as pl
    import pyarrow.parquet as pa

    res = mb.bench(small_experiment(tmp_path), out=tmp_path / "out")
    assert res.progress_parquet == str(tmp_path / "out" / "progress.parquet")
    table = pa.read_table(res.progress_parquet)
    assert table.column_names == ["run", "run_id", "iteration", "time_s", "best_cost"]
    types = {f.name: str(f.type) for f in table.schema}
    assert types == {"run": "int64", "run_id": "string", "iteration": "int64",
                     "time_s": "double", "best_cost": "double"}
    units = json.loads(table.schema.metadata[b"magbench.columns"])
    assert units["time_s"]["unit"] == "s"
    frame = res.progress_to_polars()
    assert isinstance(frame, pl.DataFrame) and len(frame) == table.num_rows
    # the same points as progress.csv, run by run, in order
    for run_id, curve in res.progress.items():
        one = frame.filter(pl.col("run_id") == run_id)
        assert one["iteration"].to_list() == curve["iteration"].tolist()
        assert one["time_s"].to_list() == curve["time_s"].tolist()
        cost = one["best_cost"].fill_null(float("nan")).to_numpy()
        assert np.array_equal(cost, curve["best_cost"], equal_nan=True)
    runs = {r["run_id"]: r["run"] for r in res.rows}
    assert all(runs[i] == r for i, r in zip(frame["run_id"], frame["run"]))
    pdf = res.progress_to_pandas()
    assert list(pdf.columns) == table.column_names and len(pdf) == table.num_rows


def test_a_torn_parquet_file_is_an_input_error_naming_it(tmp_path):
    pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    pytest.importorskip("polars")
    res = mb.bench(small_experiment(tmp_path), out=tmp_path / "out")
    for path, reads in [
        (res.parquet, [res.to_pandas, res.to_polars]),
        (res.progress_parquet, [res.progress_to_pandas, res.progress_to_polars]),
    ]:
        whole = open(path, "rb").read()
        with open(path, "wb") as f:
            f.write(whole[: len(whole) // 2])
        for read in reads:
            with pytest.raises(mb.InputError) as e:
                read()
            assert e.value.file == path and e.value.field == "Parquet"
            assert "does not read as Parquet" in e.value.reason and path in str(e.value)


def test_bench_bad_experiment(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text('name = "bad"\nscenarios = ["open-field"]\nplanners = ["no-such-planner"]\nseeds = 1\n[limits]\niterations = 10\n')
    with pytest.raises(mb.InputError) as e:
        mb.bench(f, out=tmp_path / "out")
    assert "no-such-planner" in str(e.value)
    with pytest.raises(mb.InputError):
        mb.bench(tmp_path / "missing.toml", out=tmp_path / "out")


def test_main_runs_the_command_line(tmp_path, capfd):
    mb.main(["plan", "open-field", "--planner", "goal-zoom-rrt", "--max-iters", "2000",
             "--out", str(tmp_path / "p")])
    assert (tmp_path / "p" / "plan.json").exists()

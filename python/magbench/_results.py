"""Results folders (``magbench bench --out DIR``) read into Python: the runs of ``runs.csv``,
the progress curves of ``progress.csv`` and the manifest, as plain dicts and numpy arrays
(pandas or polars DataFrames with ``to_pandas()`` / ``to_polars()`` and their ``progress_``
forms, read from the typed ``runs.parquet`` and ``progress.parquet`` of a finished folder when
the library can read Parquet)."""

import csv
import json
import os
import re

import numpy as np

_AGENT_COLUMN = re.compile(r"^(rms|max)_error_(true_)?agent(\d+)_bl$")


def _value(text):
    """A ``runs.csv`` cell as Python: empty -> None, true/false -> bool, numbers, else text."""
    if text == "":
        return None
    if text == "true":
        return True
    if text == "false":
        return False
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def _read_parquet(path, read):
    """``read(path)``, with a file that does not read as Parquet (torn, or not Parquet) raised
    as ``InputError`` naming the file and the reason."""
    try:
        return read(path)
    except (ImportError, MemoryError):
        raise
    except Exception as e:  # the library's own error type (pyarrow's, polars')
        from ._magbench import InputError

        reason = (
            f"does not read as Parquet ({type(e).__name__}: {e}); "
            "`magbench results plot` on the folder writes it again from the CSV files"
        )
        err = InputError(f"{path}: Parquet: {reason}")
        err.file, err.field, err.reason = path, "Parquet", reason
        raise err from e


def _pandas_parquet(path):
    """The Parquet file ``path`` read by pandas, or None when there is no file (``path`` None)
    or pyarrow, which pandas reads Parquet with, is not installed."""
    if path is None:
        return None
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        return None
    import pandas as pd

    return _read_parquet(path, pd.read_parquet)


class Results:
    """A results folder.

    - ``rows`` (also ``runs``): one dict per run, the ``runs.csv`` columns with typed values
      (``None`` where a cell is empty);
    - ``column(name)``: one column as a numpy array (floats with NaN for empty cells, or
      objects for text);
    - ``progress``: run id -> dict of numpy arrays ``iteration``, ``time_s``, ``best_cost``
      (NaN before the first solution): each run's cost-versus-iteration curve;
    - ``agent_errors(kind)``: (runs, agents) array of a per-agent error column;
    - ``manifest``: ``manifest.json`` as a dict (or None);
    - ``parquet``, ``progress_parquet``: the paths of the folder's ``runs.parquet`` and
      ``progress.parquet`` (None before it is finalized);
    - ``to_pandas()`` / ``progress_to_pandas()``: DataFrames (needs pandas);
      ``to_polars()`` / ``progress_to_polars()``: polars DataFrames (needs polars).
    """

    def __init__(self, path):
        self.path = os.fspath(path)
        runs = os.path.join(self.path, "runs.csv")
        if not os.path.isfile(runs):
            raise FileNotFoundError(f"{runs}: no runs.csv (is {self.path} a results folder?)")
        with open(runs, newline="") as f:
            reader = csv.DictReader(f)
            self.columns = list(reader.fieldnames or [])
            self.rows = [{k: _value(v) for k, v in row.items()} for row in reader]
        self.progress = {}
        progress = os.path.join(self.path, "progress.csv")
        if os.path.isfile(progress):
            curves = {}
            with open(progress, newline="") as f:
                for row in csv.DictReader(f):
                    c = curves.setdefault(row["run_id"], ([], [], []))
                    c[0].append(int(row["iteration"]))
                    c[1].append(float(row["time_s"]))
                    c[2].append(float(row["best_cost"]) if row["best_cost"] else np.nan)
            self.progress = {
                k: {
                    "iteration": np.asarray(v[0], dtype=np.int64),
                    "time_s": np.asarray(v[1], dtype=float),
                    "best_cost": np.asarray(v[2], dtype=float),
                }
                for k, v in curves.items()
            }
        manifest = os.path.join(self.path, "manifest.json")
        self.manifest = None
        if os.path.isfile(manifest):
            with open(manifest) as f:
                self.manifest = json.load(f)

    @property
    def runs(self):
        """The runs (same as ``rows``)."""
        return self.rows

    def __len__(self):
        return len(self.rows)

    def column(self, name):
        """Column ``name`` of every run: floats (NaN for empty cells) when every value is a
        number or a bool, else an object array."""
        if name not in self.columns:
            raise KeyError(f"{name!r}: not a runs.csv column (columns: {', '.join(self.columns)})")
        values = [r[name] for r in self.rows]
        if all(v is None or isinstance(v, (int, float, bool)) for v in values):
            return np.asarray([np.nan if v is None else float(v) for v in values], dtype=float)
        return np.asarray(values, dtype=object)

    def agent_errors(self, kind="rms_error"):
        """The per-agent columns ``{kind}_agent{i}_bl`` (``kind``: ``rms_error``,
        ``max_error``, ``rms_error_true``, ``max_error_true``) as a (runs, agents) array,
        NaN for runs without that agent or without tracking."""
        agents = sorted({int(m.group(3)) for c in self.columns if (m := _AGENT_COLUMN.match(c))})
        out = np.full((len(self.rows), len(agents)), np.nan)
        for j, i in enumerate(agents):
            out[:, j] = self.column(f"{kind}_agent{i}_bl")
        return out

    @property
    def parquet(self):
        """The path of ``runs.parquet`` (the runs, typed, with each column's unit in the
        file's ``magbench.columns`` metadata), or None when the folder has none."""
        path = os.path.join(self.path, "runs.parquet")
        return path if os.path.isfile(path) else None

    def to_pandas(self):
        """The runs as a pandas DataFrame (one row per run): read from ``runs.parquet`` when
        the folder has one and pyarrow is installed, else built from ``rows``."""
        import pandas as pd

        df = _pandas_parquet(self.parquet)
        return df if df is not None else pd.DataFrame(self.rows, columns=self.columns)

    def to_polars(self):
        """The runs as a polars DataFrame (one row per run): read from ``runs.parquet`` when
        the folder has one, else built from ``rows``."""
        import polars as pl

        if self.parquet is not None:
            return _read_parquet(self.parquet, pl.read_parquet)
        return pl.DataFrame(self.rows, schema=self.columns, orient="row", infer_schema_length=None)

    @property
    def progress_parquet(self):
        """The path of ``progress.parquet`` (the progress traces, typed, one row a point, with
        each column's unit in the file's ``magbench.columns`` metadata), or None when the folder
        has none."""
        path = os.path.join(self.path, "progress.parquet")
        return path if os.path.isfile(path) else None

    def _progress_columns(self):
        """The progress traces as the columns of a long table: run, run_id, iteration, time_s,
        best_cost (NaN before a run's first solution)."""
        index = {r["run_id"]: r["run"] for r in self.rows}
        curves = list(self.progress.items())
        lengths = [len(v["iteration"]) for _, v in curves]

        def joined(key, dtype):
            return np.concatenate([v[key] for _, v in curves] or [np.zeros(0, dtype)])

        return {
            "run": [index.get(k) for (k, _), n in zip(curves, lengths) for _ in range(n)],
            "run_id": [k for (k, _), n in zip(curves, lengths) for _ in range(n)],
            "iteration": joined("iteration", np.int64),
            "time_s": joined("time_s", float),
            "best_cost": joined("best_cost", float),
        }

    def progress_to_polars(self):
        """The progress traces as a long polars DataFrame (run, run_id, iteration, time_s,
        best_cost): read from ``progress.parquet`` when the folder has one, else built from
        ``progress``."""
        import polars as pl

        if self.progress_parquet is not None:
            return _read_parquet(self.progress_parquet, pl.read_parquet)
        return pl.DataFrame(self._progress_columns())

    def progress_to_pandas(self):
        """The progress traces as a long pandas DataFrame (run, run_id, iteration, time_s,
        best_cost): read from ``progress.parquet`` when the folder has one and pyarrow is
        installed, else built from ``progress``."""
        import pandas as pd

        df = _pandas_parquet(self.progress_parquet)
        return df if df is not None else pd.DataFrame(self._progress_columns())

    def __repr__(self):
        return f"Results({self.path!r}, {len(self.rows)} runs)"


def load_results(path):
    """Reads the results folder ``path`` (``runs.csv``, ``progress.csv``, ``manifest.json``)."""
    return Results(path)

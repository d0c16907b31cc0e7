"""track and bench: thin wrappers that shape what the compiled module returns."""

import json
import os
import warnings

from . import _magbench
from ._results import load_results


class TrackResult:
    """One closed-loop run: ``metrics`` (a dict, the command line's metrics.json fields),
    ``traces`` (a dict of numpy arrays, one row per camera frame) and ``plans`` (every plan
    tracked: a dict with ``leg``, ``start_t_s``, ``reason``, ``solved``, ``planning_time_s``
    and ``plan``). ``result["rms_error_bl"]`` reads a metric."""

    def __init__(self, metrics, traces, plans):
        self.metrics = metrics
        self.traces = traces
        self.plans = plans

    def __getitem__(self, key):
        return self.metrics[key]

    def __contains__(self, key):
        return key in self.metrics

    def keys(self):
        return self.metrics.keys()

    def __repr__(self):
        m = self.metrics
        return (
            f"TrackResult(status={m.get('status')!r}, reached_goal={m.get('reached_goal')}, "
            f"rms_error_bl={m.get('rms_error_bl')}, ticks={len(self.traces['t'])})"
        )


def track(scenario, plan, tracker="obc", preset="realistic", seed=0, params=None,
          planner=None, planner_params=None):
    """Tracks ``plan`` in closed loop on the simulated plant of ``scenario`` under ``preset``
    (``ideal``, ``realistic``, ``hardware`` or a preset file) with ``tracker`` (a built-in or
    a registered Python tracker) and its (and the loop's) ``params``. ``planner`` makes new
    legs and replans (none: no replanning). Returns a :class:`TrackResult`."""
    metrics, traces, plans = _magbench.track(
        scenario, plan, tracker=tracker, preset=preset, seed=seed, params=params,
        planner=planner, planner_params=planner_params)
    return TrackResult(json.loads(metrics), traces, plans)


def main(args):
    """Runs the ``magbench`` command line with ``args`` (a list, without the program name),
    with the registered Python planners and trackers beside the built-ins."""
    _magbench.main([str(a) for a in args])


def bench(experiment, out=None, threads=None, resume=False, quiet=True, shard=None, replays=None):
    """Runs an experiment file (``magbench bench``) into ``out`` (default
    ``results/<experiment name>``) and returns its :class:`Results`. ``replays`` chooses the
    runs that get a replay page, as ``bench --replays`` does (``"all"``, ``"failed"``,
    ``"sample:N"``, ``"failed+sample:N"``, ``"none"``; default: the experiment file's
    ``replays`` key, else ``"failed+sample:30"``). Experiment files may
    name registered Python planners and trackers. Runs that fail (a Python plugin that
    raised) are rows with status ``crash`` and the exception's text in ``error``; they do
    not stop the sweep, and ``bench`` warns about them instead of raising."""
    experiment = os.fspath(experiment)
    if out is None:
        out = os.path.join("results", _magbench.experiment_name(experiment))
    out = os.fspath(out)
    args = ["bench", experiment, "--out", out]
    if threads is not None:
        args += ["--threads", str(threads)]
    if resume:
        args.append("--resume")
    if quiet:
        args.append("--quiet")
    if shard is not None:
        args += ["--shard", str(shard)]
    if replays is not None:
        args += ["--replays", str(replays)]
    try:
        _magbench.main(args)
    except _magbench.MagbenchError as e:
        if "runs crashed" not in str(e) or not os.path.exists(os.path.join(out, "runs.csv")):
            raise
        warnings.warn(str(e), RuntimeWarning, stacklevel=2)
    return load_results(out)

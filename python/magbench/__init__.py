"""magbench from Python: scenarios, planning, tracking and benchmarks of teams of magnetic
microrobots steered by one global field.

A thin layer over the Rust crates (the compiled module ``magbench._magbench``): states are
numpy vectors ``[x0, y0, x1, y1, ...]`` in body lengths (BL), controls are
``[theta_rad, alpha_rad, grad_x_t_per_m, grad_y_t_per_m]``.

    import magbench as mb
    sc = mb.Scenario.load("micro-factory")
    p = mb.plan(sc, "goal-zoom-rrt", seed=0, time_limit_s=5.0, preset="hardware")
    t = mb.track(sc, p, tracker="obc", preset="hardware", seed=0)

See docs/python.md.
"""

from ._magbench import InputError, MagbenchError, Plan, Reference, Scenario, plan
from ._api import TrackResult, track, bench, main
from ._plugins import register_planner, register_tracker, registered, unregister
from ._results import Results, load_results
from .tree import read_tree

__all__ = [
    "InputError",
    "MagbenchError",
    "Plan",
    "Reference",
    "Scenario",
    "TrackResult",
    "Results",
    "bench",
    "load_results",
    "read_tree",
    "main",
    "plan",
    "register_planner",
    "register_tracker",
    "registered",
    "track",
    "unregister",
]

"""Python planners and trackers, registered by name.

A planner class: ``__init__(self, **params)`` (every parameter a keyword with a bool, int,
float or str default: these are its magbench parameters, set by ``params=`` or by an
experiment file's ``name{key=value}``) and ``solve(self, problem) -> magbench.Plan | None``.
``problem`` has the operations of :class:`magbench.Scenario` and ``max_iterations``,
``time_limit_s``, ``seed``, ``should_stop(iteration)``, ``elapsed_s()``,
``report_progress(iteration, best_cost)`` and ``cost(plan)``.

A tracker class: ``__init__(self, **params)``, ``reset(self, problem, plan)`` and
``control(self, observation) -> numpy control``. ``plan`` is the reference being followed
(``t``, ``states``, ``controls``: one row per integration step, NaN controls after the plan's
end; ``duration``, ``plan_end``); ``observation`` has ``t`` (s since the reference started),
``estimate`` (the team state the loop estimates now), ``observed`` (the camera's positions, NaN
where missed) and ``frame_t``.

The registry of a call is built from the classes registered when the call starts; the
built-in registry itself is never changed.
"""

import inspect

from . import _magbench

_PLANNERS = {}
_TRACKERS = {}


def _params(cls):
    """The keyword parameters of ``cls.__init__`` with their defaults and help text."""
    try:
        sig = inspect.signature(cls)
    except (TypeError, ValueError):
        return []
    out = []
    for p in sig.parameters.values():
        if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        if p.default is p.empty:
            raise TypeError(f"{cls.__name__}: parameter {p.name!r} needs a default value")
        if not isinstance(p.default, (bool, int, float, str)):
            raise TypeError(
                f"{cls.__name__}: parameter {p.name!r} has default {p.default!r}: "
                "a bool, int, float or str is needed"
            )
        out.append((p.name, p.default, f"{type(p.default).__name__} parameter of {cls.__name__}"))
    return out


def _summary(cls, summary):
    if summary:
        return summary
    doc = inspect.getdoc(cls) or cls.__name__
    return doc.strip().splitlines()[0]


def _register(table, kind, name, cls, summary, replace, methods):
    if not isinstance(name, str):
        raise TypeError(f"a {kind} name is a str, got {type(name).__name__}")
    if not inspect.isclass(cls):
        raise TypeError(f"register_{kind}: {cls!r} is not a class")
    for m in methods:
        if not callable(getattr(cls, m, None)):
            raise TypeError(f"register_{kind}: {cls.__name__} has no method {m}()")
    if name in table and not replace:
        raise ValueError(f"a Python {kind} named {name!r} is registered already (replace=True)")
    old = table.get(name)
    table[name] = (name, cls, _summary(cls, summary), _params(cls))
    try:
        _magbench.check_plugins()
    except Exception:
        if old is None:
            del table[name]
        else:
            table[name] = old
        raise


def register_planner(name, cls, summary="", replace=False):
    """Registers planner class ``cls`` as ``name``: ``plan``, ``track``, ``bench`` and
    ``main`` can then use it like a built-in (in experiment files too). A name taken by a
    built-in or malformed raises ``InputError``."""
    _register(_PLANNERS, "planner", name, cls, summary, replace, ["solve"])


def register_tracker(name, cls, summary="", replace=False):
    """Registers tracker class ``cls`` as ``name`` (see :func:`register_planner`)."""
    _register(_TRACKERS, "tracker", name, cls, summary, replace, ["reset", "control"])


def unregister(name):
    """Removes the Python planner and/or tracker ``name``."""
    _PLANNERS.pop(name, None)
    _TRACKERS.pop(name, None)


def registered():
    """The names of the registered Python planners and trackers."""
    return {"planners": sorted(_PLANNERS), "trackers": sorted(_TRACKERS)}


def snapshot():
    """The registered classes, as the compiled module reads them."""
    return list(_PLANNERS.values()), list(_TRACKERS.values())

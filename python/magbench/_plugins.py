"""Python planners and trackers, registered by name."""

from . import _magbench

_PLANNERS = {}
_TRACKERS = {}


def register_planner(name, cls, summary=""):
    """Registers a planner class under ``name``; placeholder until plugins are built."""
    raise NotImplementedError("Python planners are not available in this build")


def register_tracker(name, cls, summary=""):
    """Registers a tracker class under ``name``; placeholder until plugins are built."""
    raise NotImplementedError("Python trackers are not available in this build")


def registered():
    """The registered Python planners and trackers."""
    return {"planners": sorted(_PLANNERS), "trackers": sorted(_TRACKERS)}

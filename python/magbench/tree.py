"""Read a planner's search tree written by ``magbench plan --tree FILE`` (pure Python).

The file (format ``magbench-tree``, docs/replay.md) holds one tree per planned leg: each
node's team state, its parent (-1 for the root), and the control ``[theta_rad, alpha_rad,
grad_x_t_per_m, grad_y_t_per_m]`` and duration (s) of the edge into it.

    from magbench.tree import read_tree
    t = read_tree("tree.json")
    leg = t.legs[0]
    for parent, child in leg.edges():
        ...
    nodes = leg.path_to(len(leg) - 1)   # root ... node
"""

import json
from dataclasses import dataclass, field
from typing import List, Tuple

FORMAT = "magbench-tree"
VERSION = 1


class TreeFileError(ValueError):
    """A tree file that cannot be read: names the file, the field and the reason."""

    def __init__(self, path, fld, reason):
        super().__init__(f"{path}: {fld}: {reason}")
        self.path, self.field, self.reason = str(path), fld, reason


@dataclass
class LegTree:
    """One leg's tree; node 0 is the root."""

    leg: int
    states: List[List[Tuple[float, float]]]
    parent: List[int]
    control: List[Tuple[float, float, float, float]]
    duration_s: List[float]
    cost: List[float]
    _children: List[List[int]] = field(default=None, repr=False, compare=False)

    def __len__(self):
        return len(self.parent)

    def edges(self):
        """Every edge as ``(parent, child)``, children in node order."""
        return [(p, c) for c, p in enumerate(self.parent) if p >= 0]

    def children(self, node):
        """The children of ``node``."""
        if self._children is None:
            self._children = [[] for _ in self.parent]
            for p, c in self.edges():
                self._children[p].append(c)
        return list(self._children[node])

    def path_to(self, node):
        """The nodes from the root to ``node``."""
        out = [node]
        while self.parent[out[-1]] >= 0:
            out.append(self.parent[out[-1]])
        out.reverse()
        return out

    def centroids(self):
        """Each node's team centroid ``(x, y)``."""
        return [
            (sum(p[0] for p in s) / len(s), sum(p[1] for p in s) / len(s))
            for s in self.states
        ]


@dataclass
class TreeFile:
    """A tree file: the scenario, the planner and one tree per planned leg."""

    scenario: str
    planner: str
    agents: int
    legs: List[LegTree]


def _leg(path, k, d, agents):
    where = f"legs[{k}]"
    if not isinstance(d, dict):
        raise TreeFileError(path, where, "must be an object")
    cols = ("states", "parent", "control", "duration_s", "cost")
    for c in cols:
        if not isinstance(d.get(c), list):
            raise TreeFileError(path, f"{where}.{c}", "missing or not a list")
    n = len(d["parent"])
    if n == 0:
        raise TreeFileError(path, f"{where}.parent", "a tree has at least its root")
    for c in cols:
        if len(d[c]) != n:
            raise TreeFileError(
                path, f"{where}.{c}", f"has {len(d[c])} entries, parent has {n}"
            )
    for i, p in enumerate(d["parent"]):
        if not isinstance(p, int) or isinstance(p, bool) or not -1 <= p < n or p == i:
            raise TreeFileError(
                path, f"{where}.parent[{i}]", f"{p!r} is not a node of the tree"
            )
        if (p == -1) != (i == 0):
            raise TreeFileError(
                path, f"{where}.parent[{i}]", "only node 0, the root, has parent -1"
            )
    states = []
    for i, s in enumerate(d["states"]):
        if not isinstance(s, list) or len(s) != agents:
            raise TreeFileError(path, f"{where}.states[{i}]", f"must hold {agents} points")
        try:
            states.append([(float(p[0]), float(p[1])) for p in s])
        except (TypeError, ValueError, IndexError):
            raise TreeFileError(path, f"{where}.states[{i}]", "points are [x, y]") from None
    try:
        control = [tuple(float(x) for x in u) for u in d["control"]]
        duration = [float(x) for x in d["duration_s"]]
        cost = [float(x) for x in d["cost"]]
    except (TypeError, ValueError):
        raise TreeFileError(path, where, "controls, durations and costs are numbers") from None
    for i, u in enumerate(control):
        if len(u) != 4:
            raise TreeFileError(path, f"{where}.control[{i}]", "has 4 entries")
    t = LegTree(int(d.get("leg", k + 1)), states, list(d["parent"]), control, duration, cost)
    # every node reaches the root (no cycles)
    depth = [None] * n
    depth[0] = 0
    for i in range(n):
        chain = []
        j = i
        while depth[j] is None:
            chain.append(j)
            j = t.parent[j]
            if len(chain) > n:
                raise TreeFileError(path, f"{where}.parent", f"node {i} is on a cycle")
        for m, c in enumerate(reversed(chain)):
            depth[c] = depth[j] + m + 1
    return t


def read_tree(path):
    """Reads the tree file at ``path``; raises :class:`TreeFileError` on a bad file."""
    try:
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
    except json.JSONDecodeError as e:
        raise TreeFileError(path, "<json>", str(e)) from None
    if not isinstance(d, dict) or d.get("format") != FORMAT:
        raise TreeFileError(path, "format", f"must be {FORMAT!r}")
    if d.get("version") != VERSION:
        raise TreeFileError(path, "version", f"must be {VERSION}, got {d.get('version')!r}")
    agents = d.get("agents")
    if not isinstance(agents, int) or agents < 1:
        raise TreeFileError(path, "agents", "must be a positive integer")
    legs = d.get("legs")
    if not isinstance(legs, list):
        raise TreeFileError(path, "legs", "missing or not a list")
    return TreeFile(
        str(d.get("scenario", "")),
        str(d.get("planner", "")),
        agents,
        [_leg(path, k, leg, agents) for k, leg in enumerate(legs)],
    )

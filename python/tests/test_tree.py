"""The search tree of ``magbench plan --tree`` read from Python (magbench.tree, pure Python)."""

import json
import os
import shutil
import subprocess

import pytest

from magbench.tree import TreeFileError, read_tree

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
# written by: magbench plan open-field --planner goal-zoom-rrt --max-iters 40 --tree FILE
FIXTURE = os.path.join(HERE, "data", "tree-open-field.json")


def magbench_binary():
    """The magbench command: $MAGBENCH_BIN, the workspace's debug build, or PATH."""
    for c in (
        os.environ.get("MAGBENCH_BIN"),
        os.path.join(ROOT, "target", "debug", "magbench"),
        shutil.which("magbench"),
    ):
        if c and os.path.isfile(c):
            return c
    return None


def test_reads_the_tree_of_a_plan():
    t = read_tree(FIXTURE)
    assert (t.scenario, t.planner, t.agents) == ("open-field", "goal-zoom-rrt", 2)
    assert len(t.legs) == 1
    leg = t.legs[0]
    assert len(leg) == 38
    assert leg.parent[0] == -1 and leg.duration_s[0] == 0.0
    assert len(leg.edges()) == len(leg) - 1
    # every edge lasts whole frames of 60 fps, and costs grow along a path
    for _, c in leg.edges():
        frames = leg.duration_s[c] * 60.0
        assert frames > 0 and abs(frames - round(frames)) < 1e-6
    path = leg.path_to(len(leg) - 1)
    assert path[0] == 0 and path[-1] == len(leg) - 1
    assert all(leg.parent[b] == a for a, b in zip(path, path[1:]))
    assert all(c in leg.children(leg.parent[c]) for _, c in leg.edges())
    assert len(leg.centroids()) == len(leg)
    assert len(leg.states[5]) == 2 and len(leg.control[5]) == 4


def test_bad_files_name_the_field(tmp_path):
    good = json.load(open(FIXTURE))
    cases = [
        (lambda d: d.update(format="x"), "format"),
        (lambda d: d.update(version=7), "version"),
        (lambda d: d["legs"][0]["parent"].__setitem__(3, 99), "legs[0].parent[3]"),
        (lambda d: d["legs"][0]["parent"].__setitem__(1, 2) or d["legs"][0]["parent"].__setitem__(2, 1), "legs[0].parent"),
        (lambda d: d["legs"][0]["cost"].pop(), "legs[0].cost"),
        (lambda d: d["legs"][0]["states"].__setitem__(0, [[1, 2]]), "legs[0].states[0]"),
    ]
    for k, (spoil, fld) in enumerate(cases):
        d = json.loads(json.dumps(good))
        spoil(d)
        p = tmp_path / f"bad{k}.json"
        p.write_text(json.dumps(d))
        with pytest.raises(TreeFileError) as e:
            read_tree(p)
        assert e.value.field == fld, (fld, str(e.value))
        assert str(p) in str(e.value)


def test_a_fresh_tree_from_the_command_line(tmp_path):
    exe = magbench_binary()
    if exe is None:
        pytest.skip("no magbench binary (set MAGBENCH_BIN or build the workspace)")
    out = tmp_path / "tree.json"
    r = subprocess.run(
        [exe, "plan", "cargo-delivery", "--planner", "sst", "--max-iters", "3000",
         "--seed", "1", "--tree", str(out)],
        capture_output=True, text=True,
    )
    assert r.returncode == 0, r.stderr
    t = read_tree(out)
    assert t.planner == "sst" and t.legs
    for leg in t.legs:
        assert leg.edges() and all(p < len(leg) for p, _ in leg.edges())
    assert (tmp_path / ("tree-leg1.svg" if len(t.legs) > 1 else "tree.svg")).is_file()

"""Shared fixtures: a small scenario and a plan for it, made once per session."""

import os

import pytest

import magbench as mb

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture(scope="session")
def sc():
    return mb.Scenario.load("open-field")


@pytest.fixture(scope="session")
def plan(sc):
    p = mb.plan(sc, "goal-zoom-rrt", seed=0, max_iterations=3000)
    assert p.solved
    return p

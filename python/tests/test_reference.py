"""A tracker written from docs/python.md alone: `reset(problem, plan)` gets a
`magbench.Reference`, which offers what `magbench.Plan` offers (states, controls, durations)
and the reference resampled for tracking (`t`, `samples`, `sample_controls`)."""

import numpy as np
import pytest

import magbench as mb


@pytest.fixture(autouse=True)
def clean_registry():
    yield
    for kind in mb.registered().values():
        for name in kind:
            mb.unregister(name)


class Schedule:
    """Open loop from the plan's own edges: controls[i] for durations[i] seconds."""

    seen = None

    def reset(self, problem, plan):
        self.ends = np.cumsum(plan.durations)
        self.controls = plan.controls
        Schedule.seen = plan

    def control(self, observation):
        i = int(np.searchsorted(self.ends, observation.t, side="right"))
        if i >= len(self.controls):
            return np.zeros(4)
        return self.controls[i]


def test_a_tracker_written_from_the_docs_gets_the_plan_and_its_resampling(sc, plan):
    mb.register_tracker("schedule", Schedule)
    result = mb.track(sc, plan, tracker="schedule", preset="ideal", seed=0)
    ref = Schedule.seen
    assert isinstance(ref, mb.Reference)
    # what mb.Plan offers
    np.testing.assert_array_equal(ref.states, plan.states)
    np.testing.assert_array_equal(ref.controls, plan.controls)
    np.testing.assert_array_equal(ref.durations, plan.durations)
    assert ref.duration == pytest.approx(plan.duration)
    assert len(ref) == len(plan)
    # the resampled reference: every integration step of each edge, then a settle segment
    k = len(ref.t)
    assert ref.samples.shape == (k, plan.states.shape[1])
    assert ref.sample_controls.shape == (k, 4)
    assert ref.t[0] == 0.0 and np.all(np.diff(ref.t) > 0)
    assert ref.t[ref.plan_end] == pytest.approx(plan.duration)
    np.testing.assert_array_equal(ref.samples[0], plan.states[0])
    np.testing.assert_allclose(ref.samples[ref.plan_end], plan.states[-1], atol=1e-9)
    np.testing.assert_array_equal(ref.sample_controls[0], plan.controls[0])
    assert np.isnan(ref.sample_controls[ref.plan_end:]).all()
    # the plan's schedule, replayed on the ideal plant, reaches the goal
    assert result["reached_goal"], result

"""A PD tracker in Python, with a one-step model inversion through the batched operations.

Each frame it wants the team at the reference one period ahead plus a PD correction of the
tracking error (``kp`` times the error, ``kd`` times its change per frame), and picks, among
the plan's own command and ``angles`` field angles with and without a pull toward the target,
the command whose predicted state one period later (``problem.propagate``, batched) is valid
and closest to what it wants.

    import magbench as mb
    from py_pd import PyPd
    mb.register_tracker("py-pd", PyPd)
    t = mb.track(sc, plan, tracker="py-pd", preset="realistic")
"""

import numpy as np


class PyPd:
    """PD on the team state with a one-step model inversion over candidate commands."""

    def __init__(self, kp=0.5, kd=0.1, angles=24):
        self.kp = float(kp)
        self.kd = float(kd)
        self.angles = int(angles)

    def reset(self, problem, plan):
        self.problem = problem
        self.ref = plan
        self.period = problem.control_period
        self.g = problem.gradient_limit
        self.last_error = None
        theta = np.linspace(-np.pi, np.pi, self.angles, endpoint=False)
        self.grid = np.zeros((self.angles, 4))
        self.grid[:, 0] = theta

    def _at(self, t):
        k = int(np.searchsorted(self.ref.t, t, side="right")) - 1
        return min(max(k, 0), len(self.ref.t) - 1)

    def control(self, observation):
        ref, est = self.ref, observation.estimate
        k = self._at(observation.t)
        ahead = self._at(observation.t + self.period)
        error = ref.samples[k] - est
        change = np.zeros_like(error) if self.last_error is None else error - self.last_error
        self.last_error = error
        want = ref.samples[ahead] + self.kp * error + self.kd * change
        ff = ref.sample_controls[k]
        if np.isnan(ff[0]):
            ff = np.zeros(4)
        # the pull that moves the centroid toward the target (scaled to the gradient limit)
        d = (want - est).reshape(-1, 2).mean(axis=0)
        pull = np.clip(d / max(np.abs(d).max(), 1e-12), -1, 1) * self.g
        candidates = np.vstack([ff, self.grid, self.grid + [0, 0, *pull]])
        candidates[:, 1] = 0.0
        x = self.problem.propagate(est, candidates, self.period)
        cost = ((x - want) ** 2).sum(axis=1)
        cost[~self.problem.is_valid(x)] += 1e6
        return candidates[int(np.argmin(cost))]

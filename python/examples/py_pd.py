"""A PD tracker in Python: the plan's own command (feed-forward) plus a pulling gradient that
steers the team's centroid back to the reference's, proportional to the centroid error and
its rate of change.

    import magbench as mb
    from py_pd import PyPd
    mb.register_tracker("py-pd", PyPd)
    t = mb.track(sc, plan, tracker="py-pd", preset="realistic")
"""

import numpy as np


class PyPd:
    """Feed-forward plus PD on the centroid: ``kp`` (1/BL) is the fraction of the largest
    gradient per BL of centroid error, ``kd`` (s/BL) per BL/s of its rate."""

    def __init__(self, kp=1.0, kd=0.05):
        self.kp = float(kp)
        self.kd = float(kd)

    def reset(self, problem, plan):
        self.ref = plan
        self.g = problem.gradient_limit
        self.last = None

    def control(self, observation):
        ref = self.ref
        k = min(int(np.searchsorted(ref.t, observation.t, side="right")) - 1, len(ref.t) - 1)
        k = max(k, 0)
        u = ref.controls[k].copy()
        if np.isnan(u[0]):
            u = np.zeros(4)  # past the plan's end: hold with the field only
        est = observation.estimate.reshape(-1, 2).mean(axis=0)
        want = ref.states[k].reshape(-1, 2).mean(axis=0)
        err = want - est
        rate = np.zeros(2) if self.last is None else (err - self.last[1]) / max(observation.t - self.last[0], 1e-9)
        self.last = (observation.t, err)
        pull = self.g * (self.kp * err + self.kd * rate)
        u[2:] = np.clip(u[2:] + pull, -self.g, self.g)
        return u

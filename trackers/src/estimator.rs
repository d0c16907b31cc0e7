//! The state estimate a tracker acts on: latency compensation and missed detections.
//!
//! An observation describes the team at its capture time, `latency` seconds ago. The
//! estimator takes its own earlier estimate of that moment (the prior), replaces every detected
//! agent by its measurement (blended by `obs_weight`), keeps the prior for a missed agent, and
//! predicts forward to now through the planning model under the commands sent since the
//! capture — a Smith predictor. A missed detection therefore never leaves a hole: the agent is
//! predicted from the model. A detection on top of another agent (closer than
//! [`MIN_DETECTION_GAP_BL`]: a detection assigned to the wrong agent, as a camera's swaps and
//! misses make when agents are close) is not believed, and an estimate the model cannot predict
//! from is held rather than lost.

use std::collections::VecDeque;

use magbench_env::plant::Observation;
use magbench_env::{Control, PlanningModel, Vec2};

/// How many past estimates and commands are kept (far more than any latency needs).
const HISTORY: usize = 64;

/// Latency-compensating, gap-filling state estimator.
#[derive(Debug, Clone)]
pub struct Estimator {
    model: PlanningModel,
    latency: f64,
    obs_weight: f64,
    fallback: Vec<Vec2>,
    /// (start time, command) in force from that time until the next entry.
    commands: VecDeque<(f64, Control)>,
    /// (time, estimated state) at each update.
    history: VecDeque<(f64, Vec<Vec2>)>,
}

impl Estimator {
    /// An estimator predicting with `model` over `latency` seconds. `fallback` is the prior
    /// for agents missed before any estimate exists (the planned start, say). `obs_weight` in
    /// (0, 1] is how much a measurement moves the prior (1 = take it as it is).
    pub fn new(model: PlanningModel, latency: f64, obs_weight: f64, fallback: &[Vec2]) -> Self {
        Self {
            model,
            latency: latency.max(0.0),
            obs_weight: obs_weight.clamp(1e-3, 1.0),
            fallback: fallback.to_vec(),
            commands: VecDeque::new(),
            history: VecDeque::new(),
        }
    }

    /// Folds in an observation; returns the current time (capture + latency) and the estimate
    /// of the team now.
    pub fn update(&mut self, obs: &Observation) -> (f64, Vec<Vec2>) {
        let now = obs.t + self.latency;
        let prior = self.estimate_at(obs.t);
        let w = self.obs_weight;
        let believed = believable(&obs.agents, prior.as_deref().unwrap_or(&self.fallback));
        let at_capture: Vec<Vec2> = believed
            .iter()
            .enumerate()
            .map(|(i, m)| match (m, &prior) {
                (Some(z), Some(p)) => p[i] + (z - p[i]) * w,
                (Some(z), None) => *z,
                (None, Some(p)) => p[i],
                (None, None) => self.fallback[i],
            })
            .collect();
        let mut est = self.propagate_span(&at_capture, obs.t, now);
        if !finite(&est) {
            // the model cannot predict from here (agents inside each other): hold the
            // positions at capture rather than lose the team
            est = if finite(&at_capture) {
                at_capture
            } else {
                prior.unwrap_or_else(|| self.fallback.clone())
            };
        }
        self.history.push_back((now, est.clone()));
        while self.history.len() > HISTORY {
            self.history.pop_front();
        }
        (now, est)
    }

    /// Records the command sent at time `t` (it holds until the next one).
    pub fn command_sent(&mut self, t: f64, u: &Control) {
        self.commands.push_back((t, *u));
        while self.commands.len() > HISTORY {
            self.commands.pop_front();
        }
    }

    /// The latest estimate, if any.
    pub fn latest(&self) -> Option<&[Vec2]> {
        self.history.back().map(|(_, s)| &s[..])
    }

    /// The estimate at time `t`: the latest estimate at or before `t`, predicted forward to `t`.
    fn estimate_at(&self, t: f64) -> Option<Vec<Vec2>> {
        let (t0, s) = self.history.iter().rev().find(|(ti, _)| *ti <= t + 1e-9)?;
        Some(self.propagate_span(s, *t0, t))
    }

    /// Predicts `s` from `from` to `to` under the recorded commands (no field before the first).
    fn propagate_span(&self, s: &[Vec2], from: f64, to: f64) -> Vec<Vec2> {
        let mut x = s.to_vec();
        let mut out = vec![Vec2::zeros(); x.len()];
        let eps = 1e-9;
        for (j, (tj, u)) in self.commands.iter().enumerate() {
            let end = self.commands.get(j + 1).map_or(f64::INFINITY, |c| c.0);
            let (a, b) = (tj.max(from), end.min(to));
            if b - a > eps {
                self.model.propagate(&x, u, b - a, &mut out);
                x.copy_from_slice(&out);
            }
        }
        x
    }
}

/// Two detections closer than this (BL) cannot be two agents (they are 1 BL across): one of
/// them is a detection assigned to the wrong agent.
pub const MIN_DETECTION_GAP_BL: f64 = 0.5;

/// The detections the estimator believes: a detection within [`MIN_DETECTION_GAP_BL`] of
/// another agent's detection (or, when that one is missed, of its prior) is taken as missed —
/// of a pair of detections, the one that jumped further from its own prior.
fn believable(agents: &[Option<Vec2>], prior: &[Vec2]) -> Vec<Option<Vec2>> {
    let mut out = agents.to_vec();
    let jump = |i: usize, z: Vec2| (z - prior[i]).norm();
    for i in 0..out.len() {
        for j in 0..out.len() {
            let Some(zi) = out[i] else { continue };
            if i == j {
                continue;
            }
            let other = out[j].unwrap_or(prior[j]);
            if (zi - other).norm() >= MIN_DETECTION_GAP_BL {
                continue;
            }
            match out[j] {
                Some(zj) if jump(j, zj) > jump(i, zi) => out[j] = None,
                _ => out[i] = None,
            }
        }
    }
    out
}

fn finite(s: &[Vec2]) -> bool {
    s.iter().all(|p| p.x.is_finite() && p.y.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench_env::PhysicalParams;

    fn obs(t: f64, a: &[Option<Vec2>]) -> Observation {
        Observation {
            t,
            agents: a.to_vec(),
        }
    }

    #[test]
    fn predicts_over_latency_and_fills_misses() {
        let model = PlanningModel::new(&PhysicalParams::default());
        let t = 1.0 / 60.0;
        let start = vec![Vec2::new(10.0, 10.0), Vec2::new(12.5, 10.0)];
        let mut e = Estimator::new(model.clone(), t, 1.0, &start);
        let (now, est) = e.update(&obs(-t, &[Some(start[0]), Some(start[1])]));
        assert!(now.abs() < 1e-12);
        assert_eq!(est, start, "no command yet: nothing moves");
        let u = Control::planar(0.9, 0.08, 0.08);
        e.command_sent(0.0, &u);
        // the frame captured at 0 shows the start; now (t) the team has moved under u
        let (_, est) = e.update(&obs(0.0, &[Some(start[0]), Some(start[1])]));
        let mut want = vec![Vec2::zeros(); 2];
        model.propagate(&start, &u, t, &mut want);
        assert_eq!(est, want);
        e.command_sent(t, &u);
        // agent 1 missed: its prior (the estimate at capture time) is predicted forward
        let (_, est) = e.update(&obs(t, &[Some(want[0]), None]));
        let mut want2 = vec![Vec2::zeros(); 2];
        model.propagate(&want, &u, t, &mut want2);
        assert!((est[1] - want2[1]).norm() < 1e-12);
        assert!(est.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
    }

    #[test]
    fn a_detection_on_top_of_another_agent_is_not_believed() {
        // agent 0 missed, and agent 1's detection lands where agent 0 is (a misassigned
        // detection): believing it would put the two agents inside each other
        let model = PlanningModel::new(&PhysicalParams::default());
        let start = vec![Vec2::new(10.0, 10.0), Vec2::new(8.6, 8.7)];
        let mut e = Estimator::new(model, 2.0 / 60.0, 1.0, &start);
        e.update(&obs(0.0, &[Some(start[0]), Some(start[1])]));
        e.command_sent(0.0, &Control::planar(2.2, -0.085, -0.085));
        let wrong = Vec2::new(10.02, 10.01);
        let (_, est) = e.update(&obs(1.0 / 60.0, &[None, Some(wrong)]));
        assert!(
            est.iter().all(|p| p.x.is_finite() && p.y.is_finite()),
            "{est:?}"
        );
        assert!((est[0] - est[1]).norm() > 1.0, "{est:?}");
        // both detected on top of each other: the one that jumped is dropped
        let (_, est) = e.update(&obs(2.0 / 60.0, &[Some(est[0]), Some(est[0])]));
        assert!((est[0] - est[1]).norm() > 1.0, "{est:?}");
        assert_eq!(
            believable(&[Some(start[0]), Some(wrong)], &start),
            vec![Some(start[0]), None]
        );
        assert_eq!(
            believable(&[Some(start[0]), Some(start[1])], &start),
            vec![Some(start[0]), Some(start[1])]
        );
    }

    #[test]
    fn all_missed_before_any_estimate_uses_fallback() {
        let model = PlanningModel::new(&PhysicalParams::default());
        let start = vec![Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0)];
        let mut e = Estimator::new(model, 0.0, 1.0, &start);
        let (_, est) = e.update(&obs(0.0, &[None, None]));
        assert_eq!(est, start);
    }
}

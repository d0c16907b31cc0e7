//! The reference a tracker follows: a plan resampled at every integration step.
//!
//! A plan holds only its waypoints (edge ends); the agents' planned motion between them is
//! curved. [`Reference::from_plan`] replays each edge through the planning model from the
//! edge's start state — the same arithmetic the planner used — and keeps every integration
//! sample (1/120 s by default), with its time and the control in force. Each agent's planned
//! path is the polyline through its samples; at the default step an agent moves at most
//! ≈ 0.09 BL between samples, so the polyline is within ~1e-3 BL of the continuous curve.

use std::ops::Range;

use magbench_env::model::step_schedule;
use magbench_env::{Control, PlanningModel, Vec2};
use magbench_planners::Plan;

/// A time-indexed, densely sampled reference trajectory of a team.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    agents: usize,
    times: Vec<f64>,
    /// Positions, sample-major: sample `k`, agent `i` at `k * agents + i`.
    states: Vec<Vec2>,
    /// Control in force from sample `k` to `k + 1`.
    controls: Vec<Control>,
    /// Plan edge of the interval from sample `k` to `k + 1`.
    edges: Vec<usize>,
    /// Cumulative path length per agent at each sample, sample-major.
    arc: Vec<f64>,
    /// Bounding circles of each agent's polyline in chunks of [`CHUNK`] segments:
    /// `chunks[i]` holds (centre, radius) of chunk `j` covering samples `CHUNK·j ..= CHUNK·(j+1)`.
    chunks: Vec<Vec<(Vec2, f64)>>,
    /// Bounding circles of [`CHUNK`] consecutive chunks: `groups[i][g]` encloses chunks
    /// `CHUNK·g .. CHUNK·(g+1)` of agent `i`.
    groups: Vec<Vec<(Vec2, f64)>>,
    /// The plan's nodes (its stored waypoint states, start to end), node-major: node `j`,
    /// agent `i` at `j * agents + i`. A settle segment adds none.
    nodes: Vec<Vec2>,
    /// The plan's edges: the control of edge `j` (from node `j` to `j + 1`) and how long it is
    /// held (s).
    plan_edges: Vec<(Control, f64)>,
}

/// Segments per bounding circle of the path-distance index.
const CHUNK: usize = 32;

/// Segments per chunk of [`Reference::chunk_circles`].
pub const CHUNK_SAMPLES: usize = CHUNK;

impl Reference {
    /// Resamples `plan` at every integration step of `model`, solved with the plan's flow.
    ///
    /// Each edge is replayed from the plan's own state at the edge start, so a plan made by the
    /// same model is reproduced bit for bit at its waypoints.
    pub fn from_plan(plan: &Plan, model: &PlanningModel) -> Self {
        let model = &model.with_flow(plan.flow);
        let n = plan.start().len();
        let mut r = Reference::empty(n);
        r.nodes = plan.states.iter().flatten().copied().collect();
        r.plan_edges = plan
            .controls
            .iter()
            .copied()
            .zip(plan.durations.iter().copied())
            .collect();
        r.push_sample(0.0, plan.start());
        let mut t0 = 0.0;
        let mut out = vec![Vec2::zeros(); n];
        for (e, (u, &d)) in plan.controls.iter().zip(&plan.durations).enumerate() {
            let (steps, rest) = step_schedule(d, model.dt);
            let total = steps + usize::from(rest > 0.0);
            let mut k = 0usize;
            let mut samples: Vec<Vec2> = Vec::with_capacity(total * n);
            model.propagate_with(&plan.states[e], u, d, &mut out, |s| {
                samples.extend_from_slice(s);
                true
            });
            for chunk in samples.chunks(n) {
                k += 1;
                let t = if k >= total {
                    t0 + d
                } else {
                    t0 + k as f64 * model.dt
                };
                r.controls.push(*u);
                r.edges.push(e);
                r.push_sample(t, chunk);
            }
            t0 += d;
        }
        r.index();
        r
    }

    /// A reference from explicit samples (times increasing, one state per time); the control
    /// of every interval is `Control::default()`. For tests and recorded trajectories.
    pub fn from_samples(times: &[f64], states: &[Vec<Vec2>]) -> Self {
        assert!(!states.is_empty() && times.len() == states.len());
        let mut r = Reference::empty(states[0].len());
        for (k, (t, s)) in times.iter().zip(states).enumerate() {
            if k > 0 {
                r.controls.push(Control::default());
                r.edges.push(k - 1);
                r.plan_edges.push((Control::default(), t - times[k - 1]));
            }
            r.push_sample(*t, s);
        }
        r.nodes = r.states.clone();
        r.index();
        r
    }

    fn empty(agents: usize) -> Self {
        Reference {
            agents,
            times: vec![],
            states: vec![],
            controls: vec![],
            edges: vec![],
            arc: vec![],
            chunks: vec![vec![]; agents],
            groups: vec![vec![]; agents],
            nodes: vec![],
            plan_edges: vec![],
        }
    }

    /// Rebuilds the bounding circles of the chunks.
    fn index(&mut self) {
        let n = self.agents;
        let last = self.last();
        for i in 0..n {
            let mut v = vec![];
            let mut lo = 0;
            while lo < last.max(1) {
                let hi = (lo + CHUNK).min(last);
                let pts = (lo..=hi).map(|k| self.point(k, i));
                let (mut min, mut max) =
                    (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY));
                for p in pts.clone() {
                    min = min.inf(&p);
                    max = max.sup(&p);
                }
                let c = (min + max) * 0.5;
                let r = pts.map(|p| (p - c).norm()).fold(0.0, f64::max);
                v.push((c, r));
                lo += CHUNK;
            }
            self.groups[i] = v
                .chunks(CHUNK)
                .map(|g| {
                    let (mut min, mut max) =
                        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY));
                    for (c, r) in g {
                        min = min.inf(&c.add_scalar(-r));
                        max = max.sup(&c.add_scalar(*r));
                    }
                    let c = (min + max) * 0.5;
                    (
                        c,
                        g.iter()
                            .map(|(d, r)| (d - c).norm() + r)
                            .fold(0.0, f64::max),
                    )
                })
                .collect();
            self.chunks[i] = v;
        }
    }

    fn push_sample(&mut self, t: f64, s: &[Vec2]) {
        assert_eq!(s.len(), self.agents);
        let n = self.agents;
        if self.times.is_empty() {
            self.arc.extend(std::iter::repeat_n(0.0, n));
        } else {
            let k = self.times.len() - 1;
            for (i, p) in s.iter().enumerate() {
                let d = (p - self.states[k * n + i]).norm();
                self.arc.push(self.arc[k * n + i] + d);
            }
        }
        self.times.push(t);
        self.states.extend_from_slice(s);
    }

    /// Number of agents.
    pub fn agents(&self) -> usize {
        self.agents
    }

    /// Number of samples (at least 1: the start).
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// True when the reference is only its start.
    pub fn is_empty(&self) -> bool {
        self.times.len() <= 1
    }

    /// Index of the last sample.
    pub fn last(&self) -> usize {
        self.times.len() - 1
    }

    /// Total duration (s).
    pub fn duration(&self) -> f64 {
        *self.times.last().expect("at least the start")
    }

    /// Time of sample `k` (s from the reference start).
    pub fn time(&self, k: usize) -> f64 {
        self.times[k.min(self.last())]
    }

    /// Team state at sample `k` (clamped to the last sample).
    pub fn state(&self, k: usize) -> &[Vec2] {
        let k = k.min(self.last());
        &self.states[k * self.agents..(k + 1) * self.agents]
    }

    /// Position of agent `i` at sample `k` (clamped).
    pub fn point(&self, k: usize, i: usize) -> Vec2 {
        self.states[k.min(self.last()) * self.agents + i]
    }

    /// Path length of agent `i` from the start to sample `k` (clamped).
    pub fn arc(&self, k: usize, i: usize) -> f64 {
        self.arc[k.min(self.last()) * self.agents + i]
    }

    /// Appends a settle segment: a straight motion of every agent from the end to `to` at
    /// `speed` BL/s (the agent that moves furthest sets the time), sampled at every `dt`. It has
    /// no plan control ([`Reference::control`] is `None` there): closed-loop trackers follow it
    /// to hold the team at `to`, an open-loop tracker stops at the plan's end.
    pub fn with_settle(mut self, to: &[Vec2], speed: f64, dt: f64) -> Self {
        let from = self.end().to_vec();
        let dist = from
            .iter()
            .zip(to)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        if dist <= 0.0 || speed <= 0.0 {
            return self;
        }
        let steps = ((dist / speed) / dt - 1e-9).ceil().max(1.0) as usize;
        let t0 = self.duration();
        for k in 1..=steps {
            let f = k as f64 / steps as f64;
            let s: Vec<Vec2> = from.iter().zip(to).map(|(a, b)| a + (b - a) * f).collect();
            self.push_sample(t0 + k as f64 * dt, &s);
        }
        self.index();
        self
    }

    /// The plan's edges, in order: the control of edge `j` (from [`Reference::node`] `j` to
    /// `j + 1`) and how long it is held (s). Edges are what the plan stores; the samples
    /// resample them at every integration step.
    pub fn plan_edges(&self) -> &[(Control, f64)] {
        &self.plan_edges
    }

    /// Index of the last sample of the plan proper (before any settle segment).
    pub fn plan_end(&self) -> usize {
        self.controls.len()
    }

    /// Control in force after sample `k`, or `None` at and after the plan's end.
    pub fn control(&self, k: usize) -> Option<&Control> {
        self.controls.get(k)
    }

    /// Plan edge of the interval after sample `k`, or `None` at and after the plan's end.
    pub fn edge(&self, k: usize) -> Option<usize> {
        self.edges.get(k).copied()
    }

    /// The sample at or just before time `t` (clamped to the reference).
    pub fn index_at(&self, t: f64) -> usize {
        let eps = 1e-9;
        match self.times.partition_point(|&x| x <= t + eps) {
            0 => 0,
            p => p - 1,
        }
    }

    /// The first sample at least `dist` BL of path (for the agent that moves most) after `k`.
    pub fn index_ahead(&self, k: usize, dist: f64) -> usize {
        let k = k.min(self.last());
        let mut j = k;
        while j < self.last() {
            j += 1;
            if (0..self.agents).any(|i| self.arc(j, i) - self.arc(k, i) >= dist) {
                break;
            }
        }
        j
    }

    /// Team distance between `s` and sample `k`: the RMS over agents of the agent distances.
    pub fn distance_to_sample(&self, s: &[Vec2], k: usize) -> f64 {
        let r = self.state(k);
        let sum: f64 = s.iter().zip(r).map(|(a, b)| (a - b).norm_squared()).sum();
        (sum / self.agents as f64).sqrt()
    }

    /// The sample in `window` (clamped) nearest to `s` in [`Reference::distance_to_sample`],
    /// and that distance. Ties go to the later sample.
    pub fn nearest_sample(&self, s: &[Vec2], window: Range<usize>) -> (usize, f64) {
        let lo = window.start.min(self.last());
        let hi = window.end.clamp(lo + 1, self.len());
        let mut best = (lo, f64::INFINITY);
        for k in lo..hi {
            let d = self.distance_to_sample(s, k);
            if d <= best.1 {
                best = (k, d);
            }
        }
        best
    }

    /// Distance from `p` to agent `i`'s planned polyline, over the samples in `window`
    /// (clamped), and the parameter of the nearest point as a fractional sample index.
    pub fn distance_to_path_in(&self, i: usize, p: Vec2, window: Range<usize>) -> (f64, f64) {
        let lo = window.start.min(self.last());
        let hi = window.end.clamp(lo + 1, self.len());
        if hi - lo == 1 {
            return ((p - self.point(lo, i)).norm(), lo as f64);
        }
        let mut best = (f64::INFINITY, lo as f64);
        for k in lo..hi - 1 {
            let (d, s) = point_segment(p, self.point(k, i), self.point(k + 1, i));
            if d < best.0 {
                best = (d, k as f64 + s);
            }
        }
        best
    }

    /// Distance from `p` to agent `i`'s whole planned polyline (BL): the nearest chunk of the
    /// group whose bounding circle is nearest first, then every chunk nearer than the best
    /// distance so far, looking into a group only when its circle is nearer. The minimum does
    /// not depend on the order in which chunks are measured.
    pub fn distance_to_path(&self, i: usize, p: Vec2) -> f64 {
        if self.last() == 0 {
            return (p - self.point(0, i)).norm();
        }
        let (chunks, groups) = (&self.chunks[i], &self.groups[i]);
        let bound = |(c, r): &(Vec2, f64)| (p - c).norm() - r;
        let nearest = |items: &[(Vec2, f64)]| {
            items
                .iter()
                .enumerate()
                .map(|(j, c)| (bound(c), j))
                .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a })
                .1
        };
        let chunk = |j: usize| {
            let lo = j * CHUNK;
            let hi = (lo + CHUNK).min(self.last());
            self.distance_to_path_in(i, p, lo..hi + 1).0
        };
        let group = |g: usize| g * CHUNK..((g + 1) * CHUNK).min(chunks.len());
        let g0 = nearest(groups);
        let first = group(g0).start + nearest(&chunks[group(g0)]);
        let mut best = chunk(first);
        for (g, circle) in groups.iter().enumerate() {
            if bound(circle) >= best {
                continue;
            }
            for j in group(g) {
                if j != first && bound(&chunks[j]) < best {
                    best = best.min(chunk(j));
                }
            }
        }
        best
    }

    /// Bounding circles (centre, radius) of agent `i`'s polyline in chunks: chunk `j` encloses
    /// samples `CHUNK_SAMPLES·j ..= min(CHUNK_SAMPLES·(j + 1), last)`, the same for every agent.
    pub fn chunk_circles(&self, i: usize) -> &[(Vec2, f64)] {
        &self.chunks[i]
    }

    /// Agent `i`'s planned polyline.
    pub fn path(&self, i: usize) -> Vec<Vec2> {
        (0..self.len()).map(|k| self.point(k, i)).collect()
    }

    /// Number of plan nodes: the plan's stored waypoint states (every sample of a reference
    /// made [`Reference::from_samples`]).
    pub fn nodes(&self) -> usize {
        self.nodes.len() / self.agents.max(1)
    }

    /// Team state at plan node `j` (`j < nodes()`).
    pub fn node(&self, j: usize) -> &[Vec2] {
        &self.nodes[j * self.agents..(j + 1) * self.agents]
    }

    /// The final state.
    pub fn end(&self) -> &[Vec2] {
        self.state(self.last())
    }
}

/// Distance from `p` to the segment `a`–`b`, and the parameter in [0, 1] of the nearest point.
pub fn point_segment(p: Vec2, a: Vec2, b: Vec2) -> (f64, f64) {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let s = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((a + ab * s - p).norm(), s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench_env::PhysicalParams;
    use magbench_env::physics::LocalView;

    fn plan() -> (Plan, PlanningModel) {
        let model = PlanningModel::new(&PhysicalParams::default());
        let start = LocalView::new(10.0, 8.0, 2.5, 0.2).to_pair().to_vec();
        let mut plan = Plan::at(&start);
        let mut s = start;
        for (u, d) in [
            (Control::planar(1.16, 0.05, 0.02), 0.5),
            (Control::planar(1.9, -0.08, 0.0), 0.25),
        ] {
            let mut out = vec![Vec2::zeros(); 2];
            model.propagate_with(&s, &u, d, &mut out, |_| true);
            plan.push(u, d, out.clone());
            s = out;
        }
        (plan, model)
    }

    #[test]
    fn samples_every_step_and_hits_waypoints_exactly() {
        let (plan, model) = plan();
        let r = Reference::from_plan(&plan, &model);
        assert_eq!(r.len(), 1 + 60 + 30);
        assert_eq!(r.state(60), &plan.states[1][..]);
        assert_eq!(r.nodes(), 3);
        assert_eq!(r.node(1), &plan.states[1][..]);
        let edges: Vec<(Control, f64)> = plan
            .controls
            .iter()
            .copied()
            .zip(plan.durations.iter().copied())
            .collect();
        assert_eq!(r.plan_edges(), &edges[..]);
        // between nodes the polyline is near, the nearest node is not
        let mid = r.state(30).to_vec();
        assert!(crate::scoring::synchronous_error(&r, &mid) < 1e-12);
        assert!(crate::scoring::node_error(&r, &mid) > 0.01);
        assert_eq!(crate::scoring::node_error(&r, &plan.states[1]), 0.0);
        assert_eq!(r.end(), plan.end());
        assert!((r.duration() - 0.75).abs() < 1e-12);
        assert_eq!(r.index_at(0.5), 60);
        assert_eq!(r.index_at(0.5 + 1.0 / 240.0), 60);
        assert_eq!(r.control(60).unwrap(), &plan.controls[1]);
        assert_eq!(r.edge(59), Some(0));
        assert!(r.control(r.last()).is_none());
    }

    #[test]
    fn path_distance_is_zero_on_the_path_and_positive_off_it() {
        let (plan, model) = plan();
        let r = Reference::from_plan(&plan, &model);
        let mid = (r.point(10, 0) + r.point(11, 0)) * 0.5;
        assert!(r.distance_to_path(0, mid) < 1e-12);
        let off = r.point(30, 1) + Vec2::new(0.0, 3.0);
        assert!(r.distance_to_path(1, off) > 1.0);
        // the chunked search agrees with the plain scan
        for k in (0..r.len()).step_by(7) {
            let q = r.point(k, 0) + Vec2::new(0.3 * (k as f64).sin(), 0.2);
            let plain = r.distance_to_path_in(0, q, 0..r.len()).0;
            assert!((r.distance_to_path(0, q) - plain).abs() < 1e-15);
        }
        let (k, d) = r.nearest_sample(r.state(42), 0..r.len());
        assert_eq!((k, d), (42, 0.0));
        assert!(r.index_ahead(0, 0.2) > 0);
    }

    #[test]
    fn settle_segment_has_no_control_and_reaches_its_target() {
        let (plan, model) = plan();
        let r = Reference::from_plan(&plan, &model);
        let n = r.len();
        let to: Vec<Vec2> = r.end().iter().map(|p| p + Vec2::new(0.3, 0.0)).collect();
        let s = r.with_settle(&to, 0.25, model.dt);
        assert_eq!(s.plan_end(), n - 1);
        assert_eq!(s.len(), n + 144, "0.3 BL at 0.25 BL/s is 1.2 s = 144 steps");
        assert_eq!(s.end(), &to[..]);
        assert_eq!(s.nodes(), 3, "a settle segment is no plan node");
        assert!(s.control(n - 1).is_none() && s.control(n - 2).is_some());
        assert!(s.distance_to_path(0, r_mid(&to[0], &plan.end()[0])) < 1e-12);
    }

    fn r_mid(a: &Vec2, b: &Vec2) -> Vec2 {
        (a + b) * 0.5
    }
}

//! The fitted model: a parameter vector, the preset it stands for, and the prediction of logged
//! segments by env's [`Plant`] under that preset (the simulated plant's own dynamics).

use std::sync::Arc;

use rayon::prelude::*;

use magbench_env::plant::{DisturbancePreset, Fitted, Medium, Plant};
use magbench_env::{Coil, CollisionWorld, PhysicalParams, Scenario, TriaxialMaxwell, Vec2};

use super::log::LoggedRun;

/// What a parameter of the fit is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// ln of agent `i`'s moment factor.
    Moment(usize),
    /// ln of agent `i`'s drag factor.
    Drag(usize),
    /// ln of a gradient axis's gain (0 = x, 1 = y).
    GradientGain(usize),
    /// Rotation of the coil frame (radians).
    FieldBias,
    /// Uniform drift along an axis (BL/s).
    Drift(usize),
    /// ln of the field axes' coil time constant (ms).
    FieldTau,
    /// ln of the gradient axes' coil time constant (ms).
    GradientTau,
    /// Camera latency (frames, continuous): frame `k` shows the plant as it was `L` frame
    /// periods before its capture.
    Latency,
}

impl Kind {
    /// The parameter's name in reports.
    pub fn name(&self) -> String {
        match self {
            Kind::Moment(i) => format!("moment[{i}]"),
            Kind::Drag(i) => format!("drag[{i}]"),
            Kind::GradientGain(a) => format!("gradient_gain.{}", ["x", "y"][*a]),
            Kind::FieldBias => "field_bias_deg".into(),
            Kind::Drift(a) => format!("drift_bl_s.{}", ["x", "y"][*a]),
            Kind::FieldTau => "coil_lag.field_tau_ms".into(),
            Kind::GradientTau => "coil_lag.gradient_tau_ms".into(),
            Kind::Latency => "camera.latency.frames".into(),
        }
    }

    /// True for a parameter fitted as a logarithm (its standard error is relative).
    pub fn is_log(&self) -> bool {
        matches!(
            self,
            Kind::Moment(_)
                | Kind::Drag(_)
                | Kind::GradientGain(_)
                | Kind::FieldTau
                | Kind::GradientTau
        )
    }

    /// Finite-difference step in the fitted coordinate.
    pub fn step(&self) -> f64 {
        match self {
            Kind::FieldBias => 1e-4,
            Kind::Drift(_) => 1e-4,
            Kind::FieldTau | Kind::GradientTau => 1e-2,
            Kind::Latency => 0.1,
            _ => 1e-4,
        }
    }

    /// Whether its derivative is a central difference. The latency's is: the prediction's
    /// slope in it jumps at every whole frame, and a forward difference taken at or just below
    /// one sees only the slope beyond it, so the search stops there with a standard error
    /// that measures one side's slope alone; a central difference a tenth of a frame each way
    /// sees both.
    pub fn central(&self) -> bool {
        matches!(self, Kind::Latency)
    }

    /// The lowest value of the fitted coordinate (a central difference reaching below it is
    /// taken forward instead).
    pub fn lowest(&self) -> f64 {
        match self {
            Kind::Latency => 0.0,
            _ => f64::NEG_INFINITY,
        }
    }

    /// The accuracy asked of its value, in the preset's unit: moments and drags 10%,
    /// gradient gains 5%, a coil's τ 30%, the bias 0.5°, a drift 0.005 BL/s, the latency ½
    /// frame (docs/calibration.md's goals; the bias's and the drift's are the tolerances of
    /// `magbench calibrate`'s validation, cli/tests/calibrate.rs).
    pub fn tolerance(&self) -> f64 {
        match self {
            Kind::Moment(_) | Kind::Drag(_) => 0.1,
            Kind::GradientGain(_) => 0.05,
            Kind::FieldTau | Kind::GradientTau => 0.3,
            Kind::FieldBias => 0.5,
            Kind::Drift(_) => 0.005,
            Kind::Latency => 0.5,
        }
    }

    /// The power of the common scale λ this parameter moves by under the symmetry of moments,
    /// drags and gains (moments ×λ, gains ×λ, drags ×λ² leave every prediction as it is): 1, 2
    /// or 0 for the others.
    pub fn scale_power(&self) -> i32 {
        match self {
            Kind::Moment(_) | Kind::GradientGain(_) => 1,
            Kind::Drag(_) => 2,
            _ => 0,
        }
    }

    /// The largest standard error (fitted coordinate) at which the data identify it: 10% for
    /// factors, 1° for the bias, 0.005 BL/s for a drift, 30% for the coil's τ, a quarter frame
    /// for the latency. Above it the value is held (at the base, or at its estimate when the
    /// data reject the base), which suits a value the data barely see; one below it but above
    /// half its [`Kind::tolerance`] is fitted but not claimed to that tolerance
    /// ([`Kind::claimed`]). Thresholds of half the tolerance, which would hold such values
    /// instead, cost more than they save: on `magbench calibrate bench` (seed 0) they left 18
    /// of 20 rigs tracking within 10% of the truth's error against 20 (rigs 14 and 18, 21% and
    /// 11% off), and held seven of the twenty field biases at the base's 0° unfitted.
    pub fn identified_below(&self) -> f64 {
        match self {
            Kind::FieldBias => 1f64.to_radians(),
            Kind::Drift(_) => 0.005,
            Kind::FieldTau | Kind::GradientTau => 0.3,
            Kind::Latency => 0.25,
            _ => 0.1,
        }
    }

    /// [`Kind::identified_below`] in the preset's unit (degrees for the bias), as standard
    /// errors are reported.
    pub fn identified_below_in_unit(&self) -> f64 {
        match self {
            Kind::FieldBias => self.identified_below().to_degrees(),
            _ => self.identified_below(),
        }
    }

    /// Whether a value with standard error `se` (the preset's unit, relative for a factor) is
    /// claimed to its [`Kind::tolerance`]: two standard errors lie within it.
    pub fn claimed(&self, se: f64) -> bool {
        2.0 * se <= self.tolerance()
    }

    /// The value in the preset's unit, from the fitted coordinate.
    pub fn value(&self, x: f64) -> f64 {
        match self {
            Kind::FieldBias => x.to_degrees(),
            k if k.is_log() => x.exp(),
            _ => x,
        }
    }
}

/// Seconds of steady commands before a segment's start when the base has coil dynamics: the
/// prediction starts with the coil settled on the command in force, which holds within
/// e^−3.75 ≈ 2% after 0.15 s for the slowest coil of the
/// range docs/calibration.md covers (τ from 2 to 40 ms).
pub const SETTLE_S: f64 = 0.15;

/// Largest change of the commanded field angle between frames (radians) that still counts as
/// steady. Commands that follow the measured pair direction jitter with its detection noise,
/// `√2 σ/r` per frame and `2σ/r` between frames (3.8° at σ = 0.05 BL, r = 1.5 BL); a step of
/// `rig excite` is at least 35° (0° to 54.74° less a sweep). 15°, four such jitters, lets the
/// jitter pass and stops at every step.
pub const STEADY_DTHETA: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// Largest change of a commanded gradient component between frames (T/m) that still counts as
/// steady: rounding, far below any step (a step is 70% of a coil's limit, ~0.06 T/m).
pub const STEADY_DGRAD: f64 = 1e-9;

/// One stretch of consecutive frames predicted from its first observation.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    /// Index of the run.
    pub run: usize,
    /// Index of the first frame.
    pub start: usize,
    /// Frames predicted.
    pub len: usize,
}

/// One segment's observed and predicted motion, frame by frame.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentTrace {
    /// Capture times (s).
    pub t: Vec<f64>,
    /// Observed positions per frame and agent (`None`: missed).
    pub observed: Vec<Vec<Option<Vec2>>>,
    /// Predicted positions per frame and agent.
    pub predicted: Vec<Vec<Vec2>>,
}

/// The model of the logged runs: the plant's fixed parts and the segments it predicts.
pub struct Model {
    params: PhysicalParams,
    coil: Arc<dyn Coil>,
    collision: Arc<CollisionWorld>,
    centre: Vec2,
    /// The base preset with what a prediction cannot know switched off.
    predict_base: DisturbancePreset,
    /// The runs.
    pub runs: Vec<LoggedRun>,
    /// Agents.
    pub n: usize,
    /// Every parameter, in order.
    pub kinds: Vec<Kind>,
    /// Largest latency the fit may take (frames).
    pub max_latency: usize,
}

impl Model {
    /// The model of `runs` of `scenario` under `base`, with a latency of at most `max_latency`
    /// frames.
    pub fn new(
        scenario: &Scenario,
        base: &DisturbancePreset,
        runs: Vec<LoggedRun>,
        max_latency: usize,
    ) -> Self {
        let params = scenario.physics.clone();
        let mut p = scenario.plant_preset(base);
        // what no prediction can know: per-run draws and random forcing
        p.field_error.angle_jitter_deg = 0.0;
        p.brownian.enabled = false;
        p.flow.enabled = false;
        p.drift.enabled = false;
        p.coil_calibration.enabled = false;
        p.ambient_field.enabled = false;
        p.nonuniform_field.centre_offset_mm = 0.0;
        p.heterogeneity.enabled = false;
        if let Medium::Interface(i) = &mut p.medium {
            i.contact_angle_spread_deg = 0.0;
        }
        let coil: Arc<dyn Coil> =
            Arc::new(TriaxialMaxwell::new(params.gradient_limit()).with_alpha_max_deg(90.0));
        let n = scenario.agents();
        let mut kinds = vec![];
        for i in 0..n {
            kinds.push(Kind::Moment(i));
            kinds.push(Kind::Drag(i));
        }
        kinds.extend([
            Kind::GradientGain(0),
            Kind::GradientGain(1),
            Kind::FieldBias,
            Kind::Drift(0),
            Kind::Drift(1),
        ]);
        if p.coil_lag.enabled && p.coil_lag.field_tau_ms > 0.0 {
            kinds.push(Kind::FieldTau);
        }
        if p.coil_lag.enabled && p.coil_lag.gradient_tau_ms > 0.0 {
            kinds.push(Kind::GradientTau);
        }
        kinds.push(Kind::Latency);
        let w = &scenario.world;
        Self {
            collision: Arc::new(CollisionWorld::new(w, magbench_env::plant::AGENT_RADIUS_BL)),
            centre: Vec2::new(w.width, w.height) * 0.5,
            params,
            coil,
            predict_base: p,
            runs,
            n,
            kinds,
            max_latency,
        }
    }

    /// The base values in the fitted coordinates (what `base` says, or draws on average).
    pub fn base_point(&self, base: &DisturbancePreset) -> Vec<f64> {
        self.kinds
            .iter()
            .map(|k| match k {
                Kind::FieldTau => base.coil_lag.field_tau_ms.max(1e-3).ln(),
                Kind::GradientTau => base.coil_lag.gradient_tau_ms.max(1e-3).ln(),
                Kind::Latency => base
                    .camera
                    .nominal_latency_frames()
                    .clamp(0.0, self.max_latency as f64),
                _ => 0.0,
            })
            .collect()
    }

    /// The preset that the point `x` stands for, on top of `over`.
    pub fn preset_at(&self, over: &DisturbancePreset, x: &[f64]) -> DisturbancePreset {
        let mut p = over.clone();
        let mut f = Fitted {
            enabled: true,
            moment: vec![1.0; self.n],
            drag: vec![1.0; self.n],
            gradient_gain: Some([1.0; 2]),
            field_bias_deg: Some(0.0),
            drift_bl_s: Some([0.0; 2]),
        };
        for (k, &v) in self.kinds.iter().zip(x) {
            let val = k.value(v);
            match *k {
                Kind::Moment(i) => f.moment[i] = val,
                Kind::Drag(i) => f.drag[i] = val,
                Kind::GradientGain(a) => f.gradient_gain.as_mut().expect("set")[a] = val,
                Kind::FieldBias => f.field_bias_deg = Some(val),
                Kind::Drift(a) => f.drift_bl_s.as_mut().expect("set")[a] = val,
                Kind::FieldTau => p.coil_lag.field_tau_ms = val,
                Kind::GradientTau => p.coil_lag.gradient_tau_ms = val,
                Kind::Latency => {
                    p.camera.latency.enabled = true;
                    p.camera.latency.frames = val.clamp(0.0, self.max_latency as f64);
                }
            }
        }
        p.fitted = f;
        p
    }

    /// The base preset with what a prediction cannot know switched off.
    pub fn predict_base(&self) -> &DisturbancePreset {
        &self.predict_base
    }

    /// The highest value of `kind`'s fitted coordinate: [`Model::max_latency`] for the
    /// latency (a segment holds the commands of that many frames before it, no more), none
    /// for the others. A central difference reaching above it is taken backward instead.
    pub fn highest(&self, kind: &Kind) -> f64 {
        match kind {
            Kind::Latency => self.max_latency as f64,
            _ => f64::INFINITY,
        }
    }

    /// The latency (frames) that `preset` states, within the fit's range.
    pub fn latency_of(&self, preset: &DisturbancePreset) -> f64 {
        preset
            .camera
            .nominal_latency_frames()
            .clamp(0.0, self.max_latency as f64)
    }

    /// Segments of up to `len` frames that every latency up to [`Model::max_latency`] can
    /// predict: consecutive frames with the field on from `max_latency + 1` frames before each
    /// step, every agent observed at the start, and, when the prediction has coil dynamics,
    /// commands steady ([`STEADY_DTHETA`], the same gradient and elevation) from [`SETTLE_S`]
    /// before the earliest command a latency can put in force at the start up to the start
    /// itself. The prediction starts with the coil settled on the first command it runs, which
    /// is then the same command, up to its jitter, for every latency: were a step among the
    /// commands of the last `max_latency + 1` frames, a latency just above a whole frame would
    /// start the coil settled on the command before the step and one at that frame on the
    /// command after it, a jump in the residuals at every whole frame that holds the search
    /// there.
    pub fn segments(&self, len: usize) -> Vec<Segment> {
        let back = self.max_latency + 1;
        let mut out = vec![];
        for (r, run) in self.runs.iter().enumerate() {
            let f = &run.frames;
            let period = frame_period(f);
            // without coil dynamics in the prediction there is no coil state to settle, and
            // the commands need not be steady
            let coils = self.predict_base.coil_lag.enabled;
            let settle = (SETTLE_S / period).ceil() as usize;
            let ok_step = |j: usize| {
                j >= back
                    && j + 1 < f.len()
                    && f[j + 1].frame == f[j].frame + 1
                    && f[j].frame == f[j - back].frame + back as u64
                    && (j - back..=j).all(|i| f[i].command.is_some())
            };
            let steady = |k: usize| {
                !coils
                    || (k >= back + settle
                        && f[k].frame == f[k - back - settle].frame + (back + settle) as u64
                        && (k - back - settle..k).all(|i| match (f[i].command, f[i + 1].command) {
                            (Some(a), Some(b)) => {
                                (a.theta - b.theta).abs() <= STEADY_DTHETA
                                    && (a.grad[0] - b.grad[0]).abs() <= STEADY_DGRAD
                                    && (a.grad[1] - b.grad[1]).abs() <= STEADY_DGRAD
                                    && (a.alpha - b.alpha).abs() <= STEADY_DTHETA
                            }
                            _ => false,
                        }))
            };
            let mut k = back;
            while k + 1 < f.len() {
                if f[k].agents.iter().all(Option::is_some) && ok_step(k) && steady(k) {
                    let mut l = 1;
                    while l < len && ok_step(k + l) {
                        l += 1;
                    }
                    out.push(Segment {
                        run: r,
                        start: k,
                        len: l,
                    });
                    k += l;
                } else {
                    k += 1;
                }
            }
        }
        out
    }

    /// One-frame segments at every step that every latency up to [`Model::max_latency`] can
    /// predict (for the detection noise from consecutive residuals; no settling asked).
    pub fn steps(&self) -> Vec<Segment> {
        let back = self.max_latency + 1;
        let mut out = vec![];
        for (r, run) in self.runs.iter().enumerate() {
            let f = &run.frames;
            for k in back..f.len().saturating_sub(1) {
                if f[k].agents.iter().all(Option::is_some)
                    && f[k + 1].frame == f[k].frame + 1
                    && f[k].frame == f[k - back].frame + back as u64
                    && (k - back..=k).all(|i| f[i].command.is_some())
                {
                    out.push(Segment {
                        run: r,
                        start: k,
                        len: 1,
                    });
                }
            }
        }
        out
    }

    /// Residuals (observed − predicted, BL; 0 for a missed detection) of every segment under
    /// `preset`, 2 per agent per predicted frame; segments in which the prediction touched a
    /// wall or stuck are marked in the second vector (their residuals are 0).
    pub fn residuals(&self, preset: &DisturbancePreset, segs: &[Segment]) -> (Vec<f64>, Vec<bool>) {
        let per: Vec<(Vec<f64>, bool)> = segs
            .par_iter()
            .map(|s| self.segment_residuals(preset, s))
            .collect();
        let mut r = Vec::with_capacity(per.iter().map(|p| p.0.len()).sum());
        let mut bad = Vec::with_capacity(per.len());
        for (v, b) in per {
            r.extend(v);
            bad.push(b);
        }
        (r, bad)
    }

    /// Number of residuals of `segs` in a fit with free start states: 2 per agent for the first
    /// frame and for every frame predicted.
    pub fn residual_count(&self, segs: &[Segment]) -> usize {
        segs.iter().map(|s| (s.len + 1) * 2 * self.n).sum()
    }

    /// The prediction of segment `s` under `preset`: the times, observations and predicted
    /// positions of its first frame (predicted = observed) and of every frame it predicts; the
    /// flag is set when the prediction touched a wall or stuck.
    pub fn predict(&self, preset: &DisturbancePreset, s: &Segment) -> (SegmentTrace, bool) {
        self.predict_from(preset, s, &self.observed_start(s))
    }

    /// Every agent's observed position at the first frame of `s` (segments start where every
    /// agent was seen).
    pub fn observed_start(&self, s: &Segment) -> Vec<Vec2> {
        self.runs[s.run].frames[s.start]
            .agents
            .iter()
            .flatten()
            .copied()
            .collect()
    }

    /// [`Model::predict`] with the agents starting at `start` instead of where they were seen.
    pub fn predict_from(
        &self,
        preset: &DisturbancePreset,
        s: &Segment,
        start: &[Vec2],
    ) -> (SegmentTrace, bool) {
        let f = &self.runs[s.run].frames;
        let start = start.to_vec();
        let latency = self.latency_of(preset);
        let whole = latency.floor();
        let (n, phi) = (whole as usize, latency - whole);
        let mut plant = Plant::new(
            &self.params,
            self.coil.clone(),
            self.collision.clone(),
            preset,
            0,
            &start,
        );
        plant.set_coil_centre(self.centre);
        let mut tr = SegmentTrace {
            t: vec![f[s.start].t],
            observed: vec![f[s.start].agents.clone()],
            predicted: vec![start],
        };
        // frame j+1 shows the plant at its capture time less L periods: between frames j and
        // j+1 the command of frame j−n−1 acts for φ of the period, then that of frame j−n
        for j in s.start..s.start + s.len {
            let dt = f[j + 1].t - f[j].t;
            if phi > 0.0
                && let Some(u) = f[j - n - 1].command
            {
                plant.run(&u, phi * dt);
            }
            if let Some(u) = f[j - n].command {
                plant.run(&u, (1.0 - phi) * dt);
            }
            tr.t.push(f[j + 1].t);
            tr.observed.push(f[j + 1].agents.clone());
            tr.predicted.push(plant.positions().to_vec());
        }
        (tr, plant.stuck() || plant.wall_contacts() > 0)
    }

    fn segment_residuals(&self, preset: &DisturbancePreset, s: &Segment) -> (Vec<f64>, bool) {
        let (mut rows, bad) = self.segment_rows(preset, s, &self.observed_start(s));
        rows.drain(..2 * self.n);
        (rows, bad)
    }

    /// Residual rows (observed − predicted, BL; 0 for a missed detection) of segment `s`
    /// predicted from `start` under `preset`: 2 per agent for its first frame (observed −
    /// `start`) and for every frame it predicts; all 0 when the prediction touched a wall or
    /// stuck (the flag).
    pub fn segment_rows(
        &self,
        preset: &DisturbancePreset,
        s: &Segment,
        start: &[Vec2],
    ) -> (Vec<f64>, bool) {
        let (tr, bad) = self.predict_from(preset, s, start);
        let mut out = Vec::with_capacity((s.len + 1) * 2 * self.n);
        for (obs, pred) in tr.observed.iter().zip(&tr.predicted) {
            for (o, p) in obs.iter().zip(pred) {
                match o {
                    Some(o) if !bad => out.extend([o.x - p.x, o.y - p.y]),
                    _ => out.extend([0.0, 0.0]),
                }
            }
        }
        (out, bad)
    }
}

/// The median frame period of a run (s); 1/60 s when it has no two consecutive frames.
pub fn frame_period(f: &[super::log::LoggedFrame]) -> f64 {
    let mut d: Vec<f64> = f
        .windows(2)
        .filter(|w| w[1].frame == w[0].frame + 1)
        .map(|w| w[1].t - w[0].t)
        .filter(|d| *d > 0.0)
        .collect();
    if d.is_empty() {
        return 1.0 / 60.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::log::{LoggedFrame, LoggedRun};
    use magbench_env::Control;

    /// A run of 60 fps frames: both agents seen except on `unseen`, the field at 0 rad until
    /// frame `step` and at 1 rad from it.
    fn run(frames: u64, step: u64, unseen: std::ops::Range<u64>) -> LoggedRun {
        LoggedRun {
            source: "test".into(),
            frames: (0..frames)
                .map(|k| LoggedFrame {
                    frame: k,
                    t: k as f64 / 60.0,
                    agents: if unseen.contains(&k) {
                        vec![None, None]
                    } else {
                        vec![Some(Vec2::new(9.0, 7.5)), Some(Vec2::new(11.0, 7.5))]
                    },
                    command: Some(Control::planar(if k < step { 0.0 } else { 1.0 }, 0.0, 0.0)),
                })
                .collect(),
        }
    }

    /// Where the agents are seen again just after a step of the field, the next segment starts
    /// only once the commands of every latency's reach are steady again: not on the first frame
    /// seen, which a latency of 2 frames or more would start before the step. Without coil
    /// dynamics it starts there.
    #[test]
    fn no_segment_starts_within_a_latency_of_a_step() {
        let scenario = Scenario::load("open-field").unwrap();
        let mut base = DisturbancePreset::hardware();
        base.coil_lag.enabled = true;
        base.coil_lag.field_tau_ms = 20.0;
        let (step, seen_again) = (200, 202);
        let model = Model::new(&scenario, &base, vec![run(400, step, 150..seen_again)], 4);
        let back = (model.max_latency + 1) as u64;
        let settle = (SETTLE_S * 60.0).ceil() as u64;
        let starts: Vec<u64> = model
            .segments(80)
            .iter()
            .map(|s| model.runs[0].frames[s.start].frame)
            .collect();
        assert!(starts.iter().any(|&k| k > step), "{starts:?}");
        for k in starts {
            assert!(
                k < step || k >= step + back + settle,
                "a segment starts at frame {k}, {} after the step: {}",
                k - step,
                "its latencies would start the coil on either side of it"
            );
        }
        // without coil dynamics there is no coil state to start, and the first frame seen
        // starts a segment
        base.coil_lag.enabled = false;
        let model = Model::new(&scenario, &base, vec![run(400, step, 150..seen_again)], 4);
        assert!(
            model
                .segments(80)
                .iter()
                .any(|s| s.start == seen_again as usize)
        );
    }
}

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
        }
    }

    /// True for a parameter fitted as a logarithm (its standard error is relative).
    pub fn is_log(&self) -> bool {
        matches!(
            self,
            Kind::Moment(_) | Kind::Drag(_) | Kind::GradientGain(_) | Kind::FieldTau
        )
    }

    /// Finite-difference step in the fitted coordinate.
    pub fn step(&self) -> f64 {
        match self {
            Kind::FieldBias => 1e-4,
            Kind::Drift(_) => 1e-4,
            Kind::FieldTau => 1e-2,
            _ => 1e-4,
        }
    }

    /// The largest standard error (fitted coordinate) at which the data identify it: 10% for
    /// factors, 1° for the bias, 0.005 BL/s for a drift, a factor e^0.5 for the coil's τ.
    pub fn identified_below(&self) -> f64 {
        match self {
            Kind::FieldBias => 1f64.to_radians(),
            Kind::Drift(_) => 0.005,
            Kind::FieldTau => 0.5,
            _ => 0.1,
        }
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
}

impl Model {
    /// The model of `runs` of `scenario` under `base`.
    pub fn new(scenario: &Scenario, base: &DisturbancePreset, runs: Vec<LoggedRun>) -> Self {
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
        }
    }

    /// The base values in the fitted coordinates (what `base` says, or draws on average).
    pub fn base_point(&self, base: &DisturbancePreset) -> Vec<f64> {
        self.kinds
            .iter()
            .map(|k| match k {
                Kind::FieldTau => base.coil_lag.field_tau_ms.max(1e-3).ln(),
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
            }
        }
        p.fitted = f;
        p
    }

    /// The base preset with what a prediction cannot know switched off.
    pub fn predict_base(&self) -> &DisturbancePreset {
        &self.predict_base
    }

    /// Segments of up to `len` frames with `latency` frames between a command and the frames
    /// it moves: consecutive frames, every agent observed at the start, the field on.
    pub fn segments(&self, len: usize, latency: usize) -> Vec<Segment> {
        let mut out = vec![];
        for (r, run) in self.runs.iter().enumerate() {
            let f = &run.frames;
            let mut k = latency;
            while k + 1 < f.len() {
                let ok_step = |j: usize| {
                    j + 1 < f.len()
                        && f[j + 1].frame == f[j].frame + 1
                        && f[j - latency].command.is_some()
                };
                if f[k].agents.iter().all(Option::is_some) && ok_step(k) {
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

    /// Residuals (observed − predicted, BL; 0 for a missed detection) of every segment under
    /// `preset`, 2 per agent per predicted frame; segments in which the prediction touched a
    /// wall or stuck are marked in the second vector (their residuals are 0).
    pub fn residuals(
        &self,
        preset: &DisturbancePreset,
        segs: &[Segment],
        latency: usize,
    ) -> (Vec<f64>, Vec<bool>) {
        let per: Vec<(Vec<f64>, bool)> = segs
            .par_iter()
            .map(|s| self.segment_residuals(preset, s, latency))
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
    pub fn predict(
        &self,
        preset: &DisturbancePreset,
        s: &Segment,
        latency: usize,
    ) -> (SegmentTrace, bool) {
        self.predict_from(preset, s, latency, &self.observed_start(s))
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
        latency: usize,
        start: &[Vec2],
    ) -> (SegmentTrace, bool) {
        let f = &self.runs[s.run].frames;
        let start = start.to_vec();
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
        for j in s.start..s.start + s.len {
            if let Some(u) = f[j - latency].command {
                plant.run(&u, f[j + 1].t - f[j].t);
            }
            tr.t.push(f[j + 1].t);
            tr.observed.push(f[j + 1].agents.clone());
            tr.predicted.push(plant.positions().to_vec());
        }
        (tr, plant.stuck() || plant.wall_contacts() > 0)
    }

    fn segment_residuals(
        &self,
        preset: &DisturbancePreset,
        s: &Segment,
        latency: usize,
    ) -> (Vec<f64>, bool) {
        let (mut rows, bad) = self.segment_rows(preset, s, latency, &self.observed_start(s));
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
        latency: usize,
        start: &[Vec2],
    ) -> (Vec<f64>, bool) {
        let (tr, bad) = self.predict_from(preset, s, latency, start);
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

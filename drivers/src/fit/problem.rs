//! The least-squares problem of one fit, for the `levenberg-marquardt` crate: free parameters
//! in, residuals of every segment out (with the segments' start states profiled out, see
//! [`super::starts`], or predicted from the observed starts), Jacobian by finite differences
//! (forward, central where [`super::model::Kind::central`] asks).
//! With a scale convention ([`Problem::pin_scale`]) one more residual row holds the geometric
//! mean of the moment factors at 1.

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt, MinimizationReport};
use magbench_env::plant::DisturbancePreset;
use nalgebra034::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;

use super::model::{Model, Segment};
use super::starts::StartBasis;

/// A fit of the free parameters of `model` on `segs`.
pub struct Problem<'a> {
    model: &'a Model,
    segs: Vec<Segment>,
    /// Every parameter (fitted coordinates); the held ones stay at their start.
    x: Vec<f64>,
    free: Vec<usize>,
    base: DisturbancePreset,
    /// Whether each segment's start state is free (profiled out) or the observed one.
    free_starts: bool,
    /// Parameters whose mean the scale convention holds at 0 (the ln of the moment factors).
    pin: Vec<usize>,
}

/// Weight of the scale convention's row (1/BL): a mean ln-moment off by 10⁻³ costs as much as
/// a residual of 1 BL, far beyond what the data pull along a direction they do not see.
const PIN_WEIGHT: f64 = 1e3;

/// The residual (BL) of every row of a segment whose prediction touches a wall or sticks at
/// the parameters tried. A fit starts from segments every start predicts
/// ([`super::usable_segments`]); were a failed prediction to count as no error, a step that
/// loses segments would lower the cost. One segment's rows at 1 BL each outweigh the whole
/// data's residuals at the detection noise (≤ 0.08 BL), so such a step is refused.
pub const FAILED_PREDICTION_BL: f64 = 1.0;

/// A finite difference: the preset one step up, the preset one step down (central) or `None`
/// (forward from the point itself), and the distance between the two.
type Step = (DisturbancePreset, Option<DisturbancePreset>, f64);

/// One segment's residual rows and their derivatives in some parameters.
struct Block {
    r: Vec<f64>,
    cols: Vec<Vec<f64>>,
    /// Whether the segment took part (its prediction touched no wall and did not stick); the
    /// rows of one that did not are [`FAILED_PREDICTION_BL`] and its derivatives 0.
    used: bool,
}

impl<'a> Problem<'a> {
    /// The problem starting at `x`, fitting the parameters marked in `free`; with
    /// `free_starts`, each segment's start state is free as well.
    pub fn new(
        model: &'a Model,
        segs: Vec<Segment>,
        x: Vec<f64>,
        free: Vec<bool>,
        free_starts: bool,
    ) -> Self {
        let base = model.predict_base().clone();
        Self {
            model,
            segs,
            free: (0..x.len()).filter(|&i| free[i]).collect(),
            x,
            base,
            free_starts,
            pin: vec![],
        }
    }

    /// Holds the geometric mean of the parameters `idx` (ln moment factors) at 1 by one more
    /// residual row: the convention that fixes the moment/drag/gain scale when the data do not.
    pub fn pin_scale(&mut self, idx: Vec<usize>) {
        self.pin = idx;
    }

    /// The scale convention's residual row (empty without one).
    fn pin_row(&self, x: &[f64]) -> Vec<f64> {
        if self.pin.is_empty() {
            return vec![];
        }
        let m = self.pin.iter().map(|&i| x[i]).sum::<f64>() / self.pin.len() as f64;
        vec![PIN_WEIGHT * m]
    }

    /// The scale convention's row of the Jacobian in the free parameters.
    fn pin_jacobian(&self) -> Vec<f64> {
        let w = PIN_WEIGHT / self.pin.len().max(1) as f64;
        self.free
            .iter()
            .map(|i| if self.pin.contains(i) { w } else { 0.0 })
            .collect()
    }

    /// Residual rows of segment `s` at `x`, and their differences along each of `steps`, all projected off the start-state directions when those are free.
    fn block(&self, s: &Segment, at: &DisturbancePreset, steps: &[Step]) -> Block {
        let (mut r, bad) = self
            .model
            .segment_rows(at, s, &self.model.observed_start(s));
        let failed = |r: &[f64]| Block {
            r: vec![FAILED_PREDICTION_BL; r.len()],
            cols: vec![vec![0.0; r.len()]; steps.len()],
            used: false,
        };
        if bad {
            return failed(&r);
        }
        let basis = if self.free_starts {
            match StartBasis::new(self.model, at, s, &r) {
                Some(b) => Some(b),
                None => return failed(&r),
            }
        } else {
            None
        };
        let cols = steps
            .iter()
            .map(|(plus, minus, h)| {
                let start = self.model.observed_start(s);
                let (rh, _) = self.model.segment_rows(plus, s, &start);
                let below = minus
                    .as_ref()
                    .map(|m| self.model.segment_rows(m, s, &start).0);
                let rl = below.as_ref().unwrap_or(&r);
                let mut c: Vec<f64> = rh.iter().zip(rl).map(|(a, b)| (a - b) / h).collect();
                if let Some(b) = &basis {
                    b.project(&mut c);
                }
                c
            })
            .collect();
        if let Some(b) = &basis {
            b.project(&mut r);
        }
        Block {
            r,
            cols,
            used: true,
        }
    }

    /// Residuals at `x` and their forward differences in the free parameters (when asked),
    /// with the number of segments used.
    fn evaluate(&self, x: &[f64], jacobian: bool) -> (Vec<f64>, Option<DMatrix<f64>>, usize) {
        let at = self.model.preset_at(&self.base, x);
        let steps: Vec<Step> = if jacobian {
            self.free
                .iter()
                .map(|&i| {
                    let kind = &self.model.kinds[i];
                    let h = kind.step();
                    let mut xh = x.to_vec();
                    xh[i] += h;
                    let plus = self.model.preset_at(&self.base, &xh);
                    // central where the kind asks for it and the point below is allowed
                    let below = x[i] - h;
                    if kind.central() && below >= kind.lowest() {
                        xh[i] = below;
                        let minus = self.model.preset_at(&self.base, &xh);
                        (plus, Some(minus), 2.0 * h)
                    } else {
                        (plus, None, h)
                    }
                })
                .collect()
        } else {
            vec![]
        };
        let blocks: Vec<Block> = self
            .segs
            .par_iter()
            .map(|s| self.block(s, &at, &steps))
            .collect();
        let rows: usize = blocks.iter().map(|b| b.r.len()).sum();
        let used = blocks.iter().filter(|b| b.used).count();
        let mut r = Vec::with_capacity(rows);
        let mut j = jacobian.then(|| DMatrix::zeros(rows, steps.len()));
        for b in blocks {
            if let Some(j) = j.as_mut() {
                for (c, col) in b.cols.iter().enumerate() {
                    for (k, v) in col.iter().enumerate() {
                        j[(r.len() + k, c)] = *v;
                    }
                }
            }
            r.extend(b.r);
        }
        (r, j, used)
    }

    /// Every parameter, in the fitted coordinates.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// Segments fitted.
    pub fn segments(&self) -> &[Segment] {
        &self.segs
    }

    fn residuals_at(&self, x: &[f64]) -> Vec<f64> {
        self.evaluate(x, false).0
    }

    /// The residuals of the data and the scale convention's row, and their Jacobian (when
    /// asked), with the number of segments used.
    fn evaluate_all(&self, x: &[f64], jacobian: bool) -> (Vec<f64>, Option<DMatrix<f64>>, usize) {
        let (mut r, j, used) = self.evaluate(x, jacobian);
        let pin = self.pin_row(x);
        if pin.is_empty() {
            return (r, j, used);
        }
        r.extend(pin);
        let j = j.map(|j| {
            let rows = j.nrows();
            let mut j = j.insert_row(rows, 0.0);
            for (c, v) in self.pin_jacobian().into_iter().enumerate() {
                j[(rows, c)] = v;
            }
            j
        });
        (r, j, used)
    }

    /// Each segment's residuals at the current parameters (start states profiled out when
    /// free), `None` for a segment whose prediction touched a wall or stuck.
    pub fn segment_residuals(&self) -> Vec<Option<Vec<f64>>> {
        let at = self.model.preset_at(&self.base, &self.x);
        self.segs
            .par_iter()
            .map(|s| {
                let b = self.block(s, &at, &[]);
                b.used.then_some(b.r)
            })
            .collect()
    }

    /// Mean squared residual (BL²) over the observed coordinates.
    pub fn mean_square(&self) -> f64 {
        let r = self.residuals_at(&self.x);
        let n = r.iter().filter(|v| **v != 0.0).count().max(1);
        r.iter().map(|v| v * v).sum::<f64>() / n as f64
    }

    /// Residual RMS per agent (BL, over both coordinates).
    pub fn rms_per_agent(&self) -> Vec<f64> {
        let r = self.residuals_at(&self.x);
        let n = self.model.n;
        (0..n)
            .map(|i| {
                let v: Vec<f64> = r
                    .chunks(2 * n)
                    .flat_map(|c| [c[2 * i], c[2 * i + 1]])
                    .filter(|v| *v != 0.0)
                    .collect();
                (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
            })
            .collect()
    }

    /// The Jacobian of the residuals in the free parameters.
    fn jacobian_free(&self) -> DMatrix<f64> {
        self.evaluate_all(&self.x, true).1.expect("asked for")
    }

    /// Standard error of every parameter (fitted coordinates): `σ_r² (JᵀJ)⁻¹` over the free
    /// ones (the scale convention's row included); infinite for a free parameter along a
    /// singular direction, NaN for a held one. The degrees of freedom discount the free start
    /// states (2 per agent per segment). With `along`, a direction in every parameter (0 on
    /// the held ones), the last entry is the standard error of the coordinate along it when
    /// it replaces the free parameter it moves most (the other free ones free as well).
    pub fn standard_errors_along(&self, along: Option<&[f64]>) -> Vec<f64> {
        let mut se = vec![f64::NAN; self.x.len() + usize::from(along.is_some())];
        if self.free.is_empty() {
            return se;
        }
        let (r, j, used) = self.evaluate_all(&self.x, true);
        let mut j = j.expect("asked for");
        let m = r.iter().filter(|v| **v != 0.0).count();
        let starts = if self.free_starts {
            used * 2 * self.model.n
        } else {
            0
        };
        let dof = m.saturating_sub(self.free.len() + starts).max(1);
        let s2 = r.iter().map(|v| v * v).sum::<f64>() / dof as f64;
        for (c, &i) in self.free.iter().enumerate() {
            se[i] = (variance(&j, c) * s2).sqrt();
        }
        // the direction replaces the free column it moves most: J·B, B = I with that column v
        let swap = along.and_then(|v| {
            let c = (0..self.free.len())
                .max_by(|a, b| v[self.free[*a]].abs().total_cmp(&v[self.free[*b]].abs()))?;
            (v[self.free[c]] != 0.0).then_some(c)
        });
        if let (Some(v), Some(c)) = (along, swap) {
            let vf = DVector::from_iterator(self.free.len(), self.free.iter().map(|&i| v[i]));
            let col = &j * vf;
            j.set_column(c, &col);
            se[self.x.len()] = (variance(&j, c) * s2).sqrt();
        }
        se
    }

    /// The standard error of the coordinate along `along` (a direction in every parameter, 0
    /// on the held ones) from the data alone: [`Problem::standard_errors_along`] without the
    /// scale convention's row.
    pub fn data_standard_error_along(&mut self, along: &[f64]) -> f64 {
        let pin = std::mem::take(&mut self.pin);
        let se = self.standard_errors_along(Some(along)).pop();
        self.pin = pin;
        se.unwrap_or(f64::NAN)
    }

    /// White detection noise σ (BL per coordinate) from one-frame residuals, −cov(e_k, e_k+1),
    /// with its standard error (the products taken as independent); `None` when the process
    /// noise hides it (the covariance is not negative).
    pub fn detection_noise(&self) -> Option<(f64, f64)> {
        let segs = self.model.steps();
        let preset = self.model.preset_at(&self.base, &self.x);
        let (r, bad) = self.model.residuals(&preset, &segs);
        let w = 2 * self.model.n;
        let (mut sum, mut sq, mut count) = (0.0, 0.0, 0usize);
        for k in 0..segs.len().saturating_sub(1) {
            let (a, b) = (segs[k], segs[k + 1]);
            if a.run != b.run || b.start != a.start + 1 || bad[k] || bad[k + 1] {
                continue;
            }
            for c in 0..w {
                let (x, y) = (r[k * w + c], r[(k + 1) * w + c]);
                if x != 0.0 && y != 0.0 {
                    sum += x * y;
                    sq += (x * y).powi(2);
                    count += 1;
                }
            }
        }
        let c = count.max(1) as f64;
        let cov = sum / c;
        let se_cov = ((sq / c - cov * cov).max(0.0) / c).sqrt();
        (count > 0 && cov < 0.0).then(|| {
            let s = (-cov).sqrt();
            (s, se_cov / (2.0 * s))
        })
    }
}

/// The variance factor `((JᵀJ)⁻¹)_cc` of column `c`, as `Σ_k V_ck² / λ_k` over the eigenpairs
/// of `JᵀJ`: a direction the data do not see (λ_k ≈ 0) makes it infinite.
fn variance(j: &DMatrix<f64>, c: usize) -> f64 {
    let eig = (j.transpose() * j).symmetric_eigen();
    let lmax = eig.eigenvalues.max().max(0.0);
    let mut v = 0.0;
    for (k, &l) in eig.eigenvalues.iter().enumerate() {
        let w = eig.eigenvectors[(c, k)].powi(2);
        if l <= lmax * 1e-14 {
            if w > 1e-12 {
                return f64::INFINITY;
            }
        } else {
            v += w / l;
        }
    }
    v
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    /// Takes the solver's point, each coordinate raised to its lowest value (the latency's 0
    /// frames): the solver has no bounds, and below 0 the prediction no longer changes, which
    /// would leave the latency's derivative 0 and its standard error infinite.
    fn set_params(&mut self, p: &DVector<f64>) {
        for (c, &i) in self.free.iter().enumerate() {
            self.x[i] = p[c].max(self.model.kinds[i].lowest());
        }
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(self.free.len(), self.free.iter().map(|&i| self.x[i]))
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.evaluate_all(&self.x, false).0;
        r.iter()
            .all(|v| v.is_finite())
            .then(|| DVector::from_vec(r))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let j = self.jacobian_free();
        j.iter().all(|v| v.is_finite()).then_some(j)
    }
}

/// Minimises `p` with at most about `iterations` Jacobians.
pub fn solve(p: Problem<'_>, iterations: usize) -> (Problem<'_>, MinimizationReport<f64>) {
    if p.free.is_empty() {
        let report = MinimizationReport {
            termination: levenberg_marquardt::TerminationReason::Converged {
                ftol: true,
                xtol: true,
            },
            number_of_evaluations: 0,
            objective_function: 0.5 * p.mean_square(),
        };
        return (p, report);
    }
    let patience = iterations.max(1);
    LevenbergMarquardt::new()
        .with_patience(patience)
        .with_ftol(1e-8)
        .with_xtol(1e-8)
        .minimize(p)
}

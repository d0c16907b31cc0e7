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
use std::ops::Range;

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

/// Standard errors at a fit's optimum ([`Problem::standard_errors_with`]), fitted
/// coordinates, NaN for a held parameter.
pub struct StandardErrors {
    /// Every parameter's: the larger of the white-residual and the segment-clustered one.
    pub params: Vec<f64>,
    /// Each combination's, the same way.
    pub combos: Vec<f64>,
    /// Every parameter's were the residuals white.
    pub white: Vec<f64>,
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
    /// with the rows of each segment used.
    fn evaluate(&self, x: &[f64], jacobian: bool) -> Evaluation {
        let at = self.model.preset_at(&self.base, x);
        let steps: Vec<Step> = if jacobian {
            self.free
                .iter()
                .map(|&i| {
                    let kind = &self.model.kinds[i];
                    let h = kind.step();
                    let mut xh = x.to_vec();
                    // up a step, or at the highest value the point itself
                    let above = x[i] + h <= self.model.highest(kind);
                    if above {
                        xh[i] += h;
                    }
                    let plus = self.model.preset_at(&self.base, &xh);
                    // central where the kind asks for it and the point below is allowed;
                    // backward at the highest value
                    let below = x[i] - h;
                    if (kind.central() || !above) && below >= kind.lowest() {
                        xh[i] = below;
                        let minus = self.model.preset_at(&self.base, &xh);
                        (plus, Some(minus), if above { 2.0 * h } else { h })
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
        let mut r = Vec::with_capacity(rows);
        let mut j = jacobian.then(|| DMatrix::zeros(rows, steps.len()));
        let mut segments = vec![];
        for b in blocks {
            if let Some(j) = j.as_mut() {
                for (c, col) in b.cols.iter().enumerate() {
                    for (k, v) in col.iter().enumerate() {
                        j[(r.len() + k, c)] = *v;
                    }
                }
            }
            if b.used {
                segments.push(r.len()..r.len() + b.r.len());
            }
            r.extend(b.r);
        }
        Evaluation { r, j, segments }
    }

    /// Every parameter, in the fitted coordinates.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// Whether each segment's start state is free (profiled out).
    pub fn free_starts(&self) -> bool {
        self.free_starts
    }

    /// Segments fitted.
    pub fn segments(&self) -> &[Segment] {
        &self.segs
    }

    fn residuals_at(&self, x: &[f64]) -> Vec<f64> {
        self.evaluate(x, false).r
    }

    /// The residuals of the data and the scale convention's row (last), and their Jacobian
    /// (when asked), with the rows of each segment used.
    fn evaluate_all(&self, x: &[f64], jacobian: bool) -> Evaluation {
        let mut e = self.evaluate(x, jacobian);
        let pin = self.pin_row(x);
        if pin.is_empty() {
            return e;
        }
        e.r.extend(pin);
        e.j = e.j.map(|j| {
            let rows = j.nrows();
            let mut j = j.insert_row(rows, 0.0);
            for (c, v) in self.pin_jacobian().into_iter().enumerate() {
                j[(rows, c)] = v;
            }
            j
        });
        e
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
        self.evaluate_all(&self.x, true).j.expect("asked for")
    }

    /// The data's residuals and Jacobian at the current parameters, the observed residuals'
    /// count and their degrees of freedom (the free parameters' and, when free, the segments'
    /// start states, 2 per agent per segment, discounted).
    fn variance_inputs(&self) -> (Evaluation, usize, usize) {
        self.residual_inputs(true)
    }

    /// [`Problem::variance_inputs`], the Jacobian only when asked.
    fn residual_inputs(&self, jacobian: bool) -> (Evaluation, usize, usize) {
        let e = self.evaluate_all(&self.x, jacobian);
        let observed = e.r.iter().filter(|v| **v != 0.0).count();
        let starts = if self.free_starts {
            e.segments.len() * 2 * self.model.n
        } else {
            0
        };
        let dof = observed.saturating_sub(self.free.len() + starts).max(1);
        (e, observed, dof)
    }

    /// The standard error of the coordinate along `along` (a direction in every parameter, 0 on
    /// the held ones) when it replaces the free parameter it moves most, the other free ones
    /// free as well: the larger of the white-residual one and the one robust to residuals
    /// correlated within a segment ([`variances`]; the scale convention's row is in `JᵀJ` but
    /// not among the segments); infinite along a singular direction, NaN when no free
    /// parameter moves along it.
    fn standard_error_along(&self, along: &[f64]) -> f64 {
        let k = self.free.len();
        // the direction replaces the free column it moves most: J·B, B = I with that column v
        let Some(c) = (0..k)
            .max_by(|a, b| {
                along[self.free[*a]]
                    .abs()
                    .total_cmp(&along[self.free[*b]].abs())
            })
            .filter(|&c| along[self.free[c]] != 0.0)
        else {
            return f64::NAN;
        };
        let (e, observed, dof) = self.variance_inputs();
        let mut j = e.j.expect("asked for");
        let vf = DVector::from_iterator(k, self.free.iter().map(|&i| along[i]));
        let col = &j * vf;
        j.set_column(c, &col);
        let unit = DMatrix::from_fn(k, 1, |r, _| f64::from(u8::from(r == c)));
        variances(&j, &e.r, &e.segments, observed, dof, &unit)[0].sqrt()
    }

    /// The standard error of each combination `Σ_i a_i x_i` of the parameters in `combos`
    /// (each a vector over every parameter; its entries on held parameters are not used),
    /// the larger of the white-residual and the segment-clustered one ([`variances`]): infinite for a
    /// combination with weight on a direction the data do not see, NaN with no free parameter.
    pub fn combination_standard_errors(&self, combos: &[Vec<f64>]) -> Vec<f64> {
        self.standard_errors_with(combos).combos
    }

    /// Every parameter's standard error (fitted coordinates; NaN for a held one), and each
    /// combination's of `combos`, as [`Problem::combination_standard_errors`] gives them, from
    /// one Jacobian.
    pub fn standard_errors_with(&self, combos: &[Vec<f64>]) -> StandardErrors {
        let mut params = vec![f64::NAN; self.x.len()];
        let mut white = params.clone();
        if self.free.is_empty() {
            let combos = vec![f64::NAN; combos.len()];
            return StandardErrors {
                params,
                combos,
                white,
            };
        }
        let (e, observed, dof) = self.variance_inputs();
        let k = self.free.len();
        // the free parameters' unit vectors, then the combinations
        let a = DMatrix::from_fn(k, k + combos.len(), |c, m| match m.checked_sub(k) {
            None => f64::from(u8::from(c == m)),
            Some(m) => combos[m][self.free[c]],
        });
        let j = e.j.expect("asked for");
        let (both, only_white) = variances_and_white(&j, &e.r, &e.segments, observed, dof, &a);
        let mut sd = both.into_iter().map(f64::sqrt);
        for (c, &i) in self.free.iter().enumerate() {
            params[i] = sd.next().expect("one per free parameter");
            white[i] = only_white[c].sqrt();
        }
        StandardErrors {
            params,
            combos: sd.collect(),
            white,
        }
    }

    /// The residuals' sum of squares (BL², the scale convention's row included) and the
    /// variance of one residual, that sum over the degrees of freedom
    /// ([`Problem::variance_inputs`]).
    pub fn sum_of_squares(&self) -> (f64, f64) {
        let (e, _, dof) = self.residual_inputs(false);
        let ssr = e.r.iter().map(|v| v * v).sum::<f64>();
        (ssr, ssr / dof as f64)
    }

    /// The standard error of the coordinate along `along` (a direction in every parameter, 0
    /// on the held ones) from the data alone: [`Problem::standard_error_along`] without the
    /// scale convention's row.
    pub fn data_standard_error_along(&mut self, along: &[f64]) -> f64 {
        let pin = std::mem::take(&mut self.pin);
        let se = self.standard_error_along(along);
        self.pin = pin;
        se
    }

    /// White detection noise σ (BL per coordinate) from one-frame residuals, −cov(e_k, e_k+1),
    /// with its standard error (see `noise_from_products`); `None` when the process noise hides
    /// it (the covariance is not negative).
    pub fn detection_noise(&self) -> Option<(f64, f64)> {
        let segs = self.model.steps();
        let preset = self.model.preset_at(&self.base, &self.x);
        let (r, bad) = self.model.residuals(&preset, &segs);
        let w = 2 * self.model.n;
        // z[k·w + c]: the product of coordinate c's residuals of steps k and k + 1
        let mut z = vec![None; segs.len() * w];
        for k in 0..segs.len().saturating_sub(1) {
            let (a, b) = (segs[k], segs[k + 1]);
            if a.run != b.run || b.start != a.start + 1 || bad[k] || bad[k + 1] {
                continue;
            }
            for c in 0..w {
                let (x, y) = (r[k * w + c], r[(k + 1) * w + c]);
                if x != 0.0 && y != 0.0 {
                    z[k * w + c] = Some(x * y);
                }
            }
        }
        noise_from_products(&z, w)
    }
}

/// σ and its standard error from `z`, the products `e_k e_k+1` of one-frame residuals of
/// consecutive steps (`z[k·w + c]`, coordinate c of step k, `None` where not both were
/// predicted): σ² is minus their mean. The products are not independent: `z_k` and `z_k+1`
/// share `e_k+1`, and under white noise alone (`e_k = n_k+1 − n_k`, a moving average of order 1)
/// a product's covariance with the next is σ⁴ against its variance of 5σ⁴, while products
/// further apart share nothing. The mean's variance is therefore `(γ₀ + 2γ₁) / count` from the
/// products' own variance γ₀ and the covariance γ₁ of each with the next step's of its
/// coordinate (the truncated-kernel estimator for a moving average of known order: Hansen and
/// Hodrick, "Forward exchange rates as optimal predictors of future spot rates", J. Political
/// Economy 88, 1980), and never below `γ₀ / count`.
fn noise_from_products(z: &[Option<f64>], w: usize) -> Option<(f64, f64)> {
    let all = || z.iter().flatten();
    let count = all().count();
    let c = count.max(1) as f64;
    let cov = all().sum::<f64>() / c;
    let gamma0 = all().map(|v| (v - cov).powi(2)).sum::<f64>() / c;
    let gamma1 = z
        .iter()
        .zip(z.iter().skip(w))
        .filter_map(|(a, b)| Some((a.as_ref()? - cov) * (b.as_ref()? - cov)))
        .sum::<f64>()
        / c;
    let se_cov = ((gamma0 + 2.0 * gamma1).max(gamma0) / c).sqrt();
    (count > 0 && cov < 0.0).then(|| {
        let s = (-cov).sqrt();
        (s, se_cov / (2.0 * s))
    })
}

/// The residuals and Jacobian of one evaluation.
struct Evaluation {
    /// Every residual row: the segments' in order, then the scale convention's when pinned.
    r: Vec<f64>,
    /// Their derivatives in the free parameters, when asked for.
    j: Option<DMatrix<f64>>,
    /// The rows of each segment whose prediction took part.
    segments: Vec<Range<usize>>,
}

/// The variance of each combination `aᵀβ` of the columns' coefficients `β` (`a` a column of
/// `combos`): the larger of the white-residual one ([`white_variances`], `dof` degrees of
/// freedom) and the segment-clustered one ([`segment_robust_variances`]). The clustered one is
/// right when residuals within a segment are correlated, but with a few tens of segments it is
/// itself noisy and on average low (Angrist and Pischke, "Mostly Harmless Econometrics", 2009,
/// §8.2.3, take the larger of the two for that reason).
fn variances(
    j: &DMatrix<f64>,
    r: &[f64],
    clusters: &[Range<usize>],
    observed: usize,
    dof: usize,
    combos: &DMatrix<f64>,
) -> Vec<f64> {
    variances_and_white(j, r, clusters, observed, dof, combos).0
}

/// [`variances`], and the white-residual ones alone.
fn variances_and_white(
    j: &DMatrix<f64>,
    r: &[f64],
    clusters: &[Range<usize>],
    observed: usize,
    dof: usize,
    combos: &DMatrix<f64>,
) -> (Vec<f64>, Vec<f64>) {
    let inverse = InformationInverse::new(j);
    let white = white_variances(&inverse, r, dof, combos);
    let robust = segment_robust_variances(&inverse, j, r, clusters, observed, combos);
    let larger = white.iter().zip(&robust).map(|(a, b)| a.max(*b)).collect();
    (larger, white)
}

/// `(JᵀJ)⁻¹` over the directions the rows of `J` see (its eigenpairs with
/// `λ > 10⁻¹⁴ λ_max`), and the directions they do not.
struct InformationInverse {
    /// `Σ v vᵀ / λ` over the seen eigenpairs.
    b: DMatrix<f64>,
    /// The unseen eigenvectors.
    unseen: Vec<DVector<f64>>,
}

impl InformationInverse {
    fn new(j: &DMatrix<f64>) -> Self {
        let k = j.ncols();
        let eig = (j.transpose() * j).symmetric_eigen();
        let lmax = eig.eigenvalues.max().max(0.0);
        let mut b = DMatrix::<f64>::zeros(k, k);
        let mut unseen = vec![];
        for (l, &lambda) in eig.eigenvalues.iter().enumerate() {
            let v = eig.eigenvectors.column(l);
            if lambda <= lmax * 1e-14 {
                unseen.push(v.into_owned());
            } else {
                b += v * v.transpose() / lambda;
            }
        }
        Self { b, unseen }
    }

    /// Whether the combination `a` has weight on a direction the rows do not see (more than
    /// 10⁻¹² of its squared length).
    fn blind_to(&self, a: &DVector<f64>) -> bool {
        let aa = a.norm_squared();
        self.unseen.iter().any(|v| v.dot(a).powi(2) > 1e-12 * aa)
    }
}

/// The variance of each combination (a column of `combos`) were the residuals independent with
/// one variance: `σ² aᵀ(JᵀJ)⁻¹a`, `σ²` the residuals' sum of squares over `dof`; infinite for a
/// combination along a direction the rows do not see.
fn white_variances(
    inverse: &InformationInverse,
    r: &[f64],
    dof: usize,
    combos: &DMatrix<f64>,
) -> Vec<f64> {
    let s2 = r.iter().map(|v| v * v).sum::<f64>() / dof.max(1) as f64;
    combos
        .column_iter()
        .map(|a| {
            let a = a.into_owned();
            if inverse.blind_to(&a) {
                f64::INFINITY
            } else {
                (a.transpose() * &inverse.b * &a)[0] * s2
            }
        })
        .collect()
}

/// The variance of each combination (a column `a` of `combos`) of the columns' coefficients,
/// robust to any correlation of the residuals within a cluster of rows and to a variance that
/// differs between clusters: `aᵀ B M B a`, the sandwich with `B = (JᵀJ)⁻¹` over every row and
/// `M = Σ_s J_sᵀ r_s r_sᵀ J_s` over the clusters' rows (rows in no cluster, the scale
/// convention's, shape `B` only), times `G/(G−1) · (N−1)/(N−K)` for `G` clusters, `N` observed
/// rows and `K` columns (the CR1 estimator of Cameron & Miller, "A Practitioner's Guide to
/// Cluster-Robust Inference", J. Human Resources 50(2), 2015). A segment's prediction errors
/// share the process noise since its start, so they are not independent, but segments are,
/// their start states fitted. Infinite for a combination along a direction the rows do not
/// see, and when fewer than two clusters leave nothing to compare.
fn segment_robust_variances(
    inverse: &InformationInverse,
    j: &DMatrix<f64>,
    r: &[f64],
    clusters: &[Range<usize>],
    observed: usize,
    combos: &DMatrix<f64>,
) -> Vec<f64> {
    let (k, m) = (j.ncols(), combos.ncols());
    let (g, n) = (clusters.len(), observed);
    if g < 2 || n <= k {
        return vec![f64::INFINITY; m];
    }
    // each combination's weights on the rows' scores: aᵀB
    let ab = combos.transpose() * &inverse.b;
    let mut var = vec![0.0; m];
    for rows in clusters {
        let score = j.rows(rows.start, rows.len()).transpose()
            * DVector::from_column_slice(&r[rows.clone()]);
        for (c, u) in (&ab * score).iter().enumerate() {
            var[c] += u * u;
        }
    }
    let small_sample = g as f64 / (g - 1) as f64 * (n - 1) as f64 / (n - k) as f64;
    var.iter()
        .zip(combos.column_iter())
        .map(|(v, a)| {
            if inverse.blind_to(&a.into_owned()) {
                f64::INFINITY
            } else {
                v * small_sample
            }
        })
        .collect()
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    /// Takes the solver's point, each coordinate within its lowest and highest values (the
    /// latency's 0 frames and [`Model::max_latency`]): the solver has no bounds, and beyond
    /// them the prediction no longer changes, which would leave the latency's derivative 0 and
    /// its standard error infinite.
    fn set_params(&mut self, p: &DVector<f64>) {
        for (c, &i) in self.free.iter().enumerate() {
            let kind = &self.model.kinds[i];
            self.x[i] = p[c].max(kind.lowest()).min(self.model.highest(kind));
        }
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(self.free.len(), self.free.iter().map(|&i| self.x[i]))
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.evaluate_all(&self.x, false).r;
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};

    /// The segment-clustered variance of each column's coefficient.
    fn clustered(j: &DMatrix<f64>, r: &[f64], clusters: &[Range<usize>], n: usize) -> Vec<f64> {
        let k = j.ncols();
        let inverse = InformationInverse::new(j);
        segment_robust_variances(&inverse, j, r, clusters, n, &DMatrix::identity(k, k))
    }

    #[test]
    fn the_detection_noise_s_standard_error_is_the_spread_of_its_estimates() {
        // white detection noise of σ on 2 coordinates over 600 frames, observed by one-frame
        // residuals e_k = n_k+1 − n_k; 400 logs
        let (sigma, w, steps) = (0.02, 2, 600);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (mut estimates, mut errors) = (vec![], vec![]);
        for _ in 0..400 {
            let n: Vec<f64> = (0..(steps + 1) * w)
                .map(|_| {
                    let x: f64 = StandardNormal.sample(&mut rng);
                    sigma * x
                })
                .collect();
            let e: Vec<f64> = (0..steps * w).map(|i| n[i + w] - n[i]).collect();
            let z: Vec<Option<f64>> = (0..steps * w)
                .map(|i| (i + w < e.len()).then(|| e[i] * e[i + w]))
                .collect();
            let (s, se) = noise_from_products(&z, w).expect("noise");
            estimates.push(s);
            errors.push(se);
        }
        let mean = estimates.iter().sum::<f64>() / 400.0;
        let spread = (estimates.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / 399.0).sqrt();
        let se = errors.iter().sum::<f64>() / 400.0;
        assert!((mean / sigma - 1.0).abs() < 0.01, "mean {mean}");
        // the spread's own estimate is within about 4% (400 draws); products taken as
        // independent give a standard error √(5/7) of it, 15% low
        assert!(
            (se / spread - 1.0).abs() < 0.08,
            "standard error {se} against spread {spread}"
        );
    }

    #[test]
    fn one_column_s_variance_is_its_scores_squared_over_the_squared_information() {
        // rows x = (1, 2 | 3), residuals (1, −1 | 2), clusters {0, 1} and {2}
        let j = DMatrix::from_column_slice(3, 1, &[1.0, 2.0, 3.0]);
        let r = [1.0, -1.0, 2.0];
        let v = clustered(&j, &r, &[0..2, 2..3], 3);
        // scores −1 and 6; information 14; G/(G−1) = 2, (N−1)/(N−K) = 1
        let want = 2.0 * (1.0 + 36.0) / (14.0 * 14.0);
        assert!((v[0] - want).abs() < 1e-12, "{} against {want}", v[0]);
    }

    #[test]
    fn a_column_no_row_sees_is_infinite_and_a_row_outside_the_clusters_only_shapes_the_bread() {
        let j = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 2.0, 0.0, 1.0, 0.0]);
        let v = clustered(&j, &[1.0, -1.0, 0.5], &[0..1, 1..3], 3);
        assert!(v[0].is_finite() && v[1].is_infinite(), "{v:?}");
        // a convention's row on the second column makes it finite and, with no residual of its
        // own, certain
        let mut pinned = j.insert_row(3, 0.0);
        pinned[(3, 1)] = 1e3;
        let v = clustered(&pinned, &[1.0, -1.0, 0.5, 0.0], &[0..1, 1..3], 3);
        assert!(v[1] == 0.0, "{v:?}");
    }

    #[test]
    fn a_combination_the_rows_see_is_finite_though_its_parameters_are_not() {
        // two columns the rows only ever see summed: the sum's coefficient has the regressor
        // (1, 2, 1), information 6; either column alone, or their difference, is unseen
        let j = DMatrix::from_row_slice(3, 2, &[1.0, 1.0, 2.0, 2.0, 1.0, 1.0]);
        let combos = DMatrix::from_column_slice(2, 3, &[1.0, 1.0, 1.0, 0.0, 1.0, -1.0]);
        let v = white_variances(&InformationInverse::new(&j), &[1.0, -1.0, 1.0], 2, &combos);
        // σ² = 3/2 over 2 degrees of freedom, times 1/6
        assert!((v[0] - 0.25).abs() < 1e-12, "{v:?}");
        assert!(v[1].is_infinite() && v[2].is_infinite(), "{v:?}");
    }

    #[test]
    fn the_larger_of_the_white_and_the_clustered_variance_is_taken() {
        // residuals that cancel within each cluster: the clustered variance is 0, the white
        // one 4/3 (4 residuals of 1 over 3 degrees of freedom) over the information 4
        let j = DMatrix::from_column_slice(4, 1, &[1.0; 4]);
        let r = [1.0, -1.0, 1.0, -1.0];
        let clusters = [0..2, 2..4];
        assert_eq!(clustered(&j, &r, &clusters, 4), vec![0.0]);
        let v = variances(&j, &r, &clusters, 4, 3, &DMatrix::identity(1, 1));
        assert!((v[0] - 1.0 / 3.0).abs() < 1e-12, "{v:?}");
    }

    /// Least squares of `y = b x` on clusters whose errors are a random walk along the
    /// cluster and whose regressor shares a level per cluster: the white-noise standard error
    /// covers `b` far less often than 95%, the cluster-robust one about 95% of the time.
    #[test]
    fn segment_robust_standard_errors_cover_where_white_ones_do_not() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (g, m, reps) = (40, 20, 400);
        let (mut robust, mut white) = (0, 0);
        for _ in 0..reps {
            let mut x = Vec::with_capacity(g * m);
            let mut y = Vec::with_capacity(g * m);
            for _ in 0..g {
                let level: f64 = StandardNormal.sample(&mut rng);
                let mut walk = 0.0;
                for k in 0..m {
                    let step: f64 = StandardNormal.sample(&mut rng);
                    walk += step / (m as f64).sqrt();
                    let xk = level + k as f64 / m as f64;
                    x.push(xk);
                    y.push(xk + walk);
                }
            }
            let sxx: f64 = x.iter().map(|v| v * v).sum();
            let b = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>() / sxx;
            let r: Vec<f64> = x.iter().zip(&y).map(|(a, c)| c - b * a).collect();
            let j = DMatrix::from_column_slice(g * m, 1, &x);
            let clusters: Vec<Range<usize>> = (0..g).map(|s| s * m..(s + 1) * m).collect();
            let se = clustered(&j, &r, &clusters, g * m)[0].sqrt();
            let s2 = r.iter().map(|v| v * v).sum::<f64>() / (g * m - 1) as f64;
            let se_white = (s2 / sxx).sqrt();
            robust += usize::from((b - 1.0).abs() <= 2.0 * se);
            white += usize::from((b - 1.0).abs() <= 2.0 * se_white);
        }
        let (robust, white) = (robust as f64 / reps as f64, white as f64 / reps as f64);
        assert!((0.90..=0.99).contains(&robust), "robust covers {robust}");
        assert!(white < 0.8, "white covers {white}");
    }
}

//! The least-squares problem of one fit, for the `levenberg-marquardt` crate: free parameters
//! in, residuals of every segment out, Jacobian by forward differences.

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt, MinimizationReport};
use nalgebra034::{DMatrix, DVector, Dyn, Owned};

use super::model::{Model, Segment};

/// A fit of the free parameters of `model` on `segs`.
pub struct Problem<'a> {
    model: &'a Model,
    segs: Vec<Segment>,
    latency: usize,
    /// Every parameter (fitted coordinates); the held ones stay at their start.
    x: Vec<f64>,
    free: Vec<usize>,
    base: magbench_env::plant::DisturbancePreset,
}

impl<'a> Problem<'a> {
    /// The problem starting at `x`, fitting the parameters marked in `free`.
    pub fn new(
        model: &'a Model,
        segs: Vec<Segment>,
        latency: usize,
        x: Vec<f64>,
        free: Vec<bool>,
    ) -> Self {
        let base = model.predict_base().clone();
        Self {
            model,
            segs,
            latency,
            free: (0..x.len()).filter(|&i| free[i]).collect(),
            x,
            base,
        }
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
        let preset = self.model.preset_at(&self.base, x);
        self.model.residuals(&preset, &self.segs, self.latency).0
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
        let r0 = self.residuals_at(&self.x);
        let mut j = DMatrix::zeros(r0.len(), self.free.len());
        for (c, &i) in self.free.iter().enumerate() {
            let h = self.model.kinds[i].step();
            let mut x = self.x.clone();
            x[i] += h;
            let r = self.residuals_at(&x);
            for (row, (a, b)) in r.iter().zip(&r0).enumerate() {
                j[(row, c)] = (a - b) / h;
            }
        }
        j
    }

    /// Standard error of every parameter (fitted coordinates): `σ_r² (JᵀJ)⁻¹` over the free
    /// ones; infinite for a free parameter along a singular direction, NaN for a held one.
    pub fn standard_errors(&self) -> Vec<f64> {
        let mut se = vec![f64::NAN; self.x.len()];
        if self.free.is_empty() {
            return se;
        }
        let j = self.jacobian_free();
        let r = self.residuals_at(&self.x);
        let m = r.iter().filter(|v| **v != 0.0).count();
        let dof = m.saturating_sub(self.free.len()).max(1);
        let s2 = r.iter().map(|v| v * v).sum::<f64>() / dof as f64;
        // var_i = s² Σ_k V_ik² / λ_k over the eigenpairs of JᵀJ: a direction the data do not
        // see (λ_k ≈ 0) makes the variance of every parameter along it huge
        let eig = (j.transpose() * &j).symmetric_eigen();
        let lmax = eig.eigenvalues.max().max(0.0);
        for (c, &i) in self.free.iter().enumerate() {
            let mut v = 0.0;
            for (k, &l) in eig.eigenvalues.iter().enumerate() {
                let w = eig.eigenvectors[(c, k)].powi(2);
                if l <= lmax * 1e-14 {
                    if w > 1e-12 {
                        v = f64::INFINITY;
                    }
                } else {
                    v += w / l;
                }
            }
            se[i] = (v * s2).sqrt();
        }
        se
    }

    /// White detection noise σ (BL per coordinate) from one-frame residuals: −cov(e_k, e_k+1);
    /// `None` when the process noise hides it (the covariance is not negative).
    pub fn detection_noise(&self) -> Option<f64> {
        let segs = self.model.segments(1, self.latency);
        let preset = self.model.preset_at(&self.base, &self.x);
        let (r, bad) = self.model.residuals(&preset, &segs, self.latency);
        let w = 2 * self.model.n;
        let (mut sum, mut count) = (0.0, 0usize);
        for k in 0..segs.len().saturating_sub(1) {
            let (a, b) = (segs[k], segs[k + 1]);
            if a.run != b.run || b.start != a.start + 1 || bad[k] || bad[k + 1] {
                continue;
            }
            for c in 0..w {
                let (x, y) = (r[k * w + c], r[(k + 1) * w + c]);
                if x != 0.0 && y != 0.0 {
                    sum += x * y;
                    count += 1;
                }
            }
        }
        let cov = sum / count.max(1) as f64;
        (count > 0 && cov < 0.0).then(|| (-cov).sqrt())
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, p: &DVector<f64>) {
        for (c, &i) in self.free.iter().enumerate() {
            self.x[i] = p[c];
        }
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(self.free.len(), self.free.iter().map(|&i| self.x[i]))
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.residuals_at(&self.x);
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

//! Coil calibration: the actuation matrix between channel currents and field plus gradient.
//!
//! The field vector is `q = (Bx, By, Bz, Gx, Gy)` in T and T/m, with the gradient diagonal
//! `diag(Gx, Gy, −Gx−Gy)` of [`magbench_env::TriaxialMaxwell`]. Currents `I` (A, one per channel)
//! produce `q = A I`. A per-axis calibration is a diagonal `A` over five channels; a full matrix
//! may have more channels (5 to 32), and currents are its least-norm solution `I = A⁺ q`.

use nalgebra::{DMatrix, DVector};

/// Field and gradient `(Bx, By, Bz, Gx, Gy)` in T and T/m.
pub type FieldVector = [f64; 5];

/// Why an actuation matrix cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CalibrationError {
    /// The rows are not independent: some field cannot be produced.
    #[error("has rank {rank}; it needs rank 5 to produce every field and gradient")]
    Rank {
        /// The matrix's numerical rank.
        rank: usize,
    },
    /// The pseudo-inverse could not be computed.
    #[error("{0}")]
    PseudoInverse(&'static str),
}

/// The actuation matrix and its pseudo-inverse.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    a: DMatrix<f64>,
    a_pinv: DMatrix<f64>,
}

impl Calibration {
    /// Five channels (Helmholtz x, y, z; Maxwell x, y) with one constant each: mT/A for the
    /// field, mT/m per A for the gradient.
    pub fn per_axis(field_mt_per_a: [f64; 3], gradient_mt_per_m_per_a: [f64; 2]) -> Self {
        let d = [
            field_mt_per_a[0],
            field_mt_per_a[1],
            field_mt_per_a[2],
            gradient_mt_per_m_per_a[0],
            gradient_mt_per_m_per_a[1],
        ];
        let a = DMatrix::from_diagonal(&DVector::from_iterator(5, d.iter().map(|x| x * 1e-3)));
        let a_pinv = DMatrix::from_diagonal(&DVector::from_iterator(5, d.iter().map(|x| 1e3 / x)));
        Self { a, a_pinv }
    }

    /// A full actuation matrix: 5 rows (Bx, By, Bz in mT/A; Gx, Gy in mT/m/A), one column per
    /// channel. Fails when the rows are not independent (some field cannot be produced).
    pub fn matrix(rows: &[Vec<f64>]) -> Result<Self, CalibrationError> {
        let n = rows[0].len();
        let a = DMatrix::from_fn(5, n, |i, j| rows[i][j] * 1e-3);
        let svd = a.clone().svd(true, true);
        let smax = svd.singular_values.max();
        let rank = svd
            .singular_values
            .iter()
            .filter(|s| **s > smax * 1e-9)
            .count();
        if rank < 5 {
            return Err(CalibrationError::Rank { rank });
        }
        let a_pinv = svd
            .pseudo_inverse(smax * 1e-12)
            .map_err(CalibrationError::PseudoInverse)?;
        Ok(Self { a, a_pinv })
    }

    /// Number of current channels.
    pub fn channels(&self) -> usize {
        self.a.ncols()
    }

    /// Currents (A) that produce `q` (least-norm when there are more than five channels).
    pub fn currents(&self, q: &FieldVector) -> Vec<f64> {
        (&self.a_pinv * DVector::from_column_slice(q))
            .iter()
            .copied()
            .collect()
    }

    /// The field and gradient that currents `i` (A) produce.
    pub fn field(&self, i: &[f64]) -> FieldVector {
        let q = &self.a * DVector::from_column_slice(i);
        [q[0], q[1], q[2], q[3], q[4]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn per_axis_round_trips() {
        let c = Calibration::per_axis([1.0, 2.0, 0.5], [20.0, 25.0]);
        let q = [3e-3, -4e-3, 1e-3, 0.05, -0.02];
        let i = c.currents(&q);
        assert!(
            (i[0] - 3.0).abs() < 1e-12 && (i[1] + 2.0).abs() < 1e-12 && (i[3] - 2.5).abs() < 1e-12
        );
        let back = c.field(&i);
        for k in 0..5 {
            assert!((back[k] - q[k]).abs() < 1e-15);
        }
    }

    #[test]
    fn a_full_matrix_with_more_channels_round_trips() {
        let rows: Vec<Vec<f64>> = (0..5)
            .map(|i| {
                (0..8)
                    .map(|j| ((i * 8 + j) as f64 * 0.7).sin() + if i == j { 2.0 } else { 0.0 })
                    .collect()
            })
            .collect();
        let c = Calibration::matrix(&rows).unwrap();
        assert_eq!(c.channels(), 8);
        let q = [3e-3, -4e-3, 1e-3, 0.05, -0.02];
        let back = c.field(&c.currents(&q));
        for k in 0..5 {
            assert!(
                (back[k] - q[k]).abs() < 1e-12,
                "{k}: {} vs {}",
                back[k],
                q[k]
            );
        }
    }

    #[test]
    fn a_rank_deficient_matrix_is_rejected() {
        let mut rows: Vec<Vec<f64>> = (0..5)
            .map(|i| (0..5).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
            .collect();
        rows[4] = rows[3].clone();
        assert_eq!(
            Calibration::matrix(&rows),
            Err(CalibrationError::Rank { rank: 4 })
        );
    }
}

//! The distance between team states: what nearest-neighbour queries and EXTEND minimise.
//!
//! Every metric here is a Euclidean distance after a linear map of the stacked agent positions
//! into `R^{2N}` ([`Distance::embed`]), so a k-d tree answers its queries exactly.

use magbench_env::{MAX_AGENTS, Vec2};

/// Relative and absolute margin (BL²) by which a bound from [`Distance::centroid_floor`] must
/// exceed a squared distance before a state is ruled out by it; rounding of either is below
/// 1e-12 for any state the planners reach.
pub const FLOOR_MARGIN: f64 = 1e-9;

/// Whether a state whose squared distance is at least `floor` is surely farther than `best`
/// (a squared distance), by more than rounding ([`FLOOR_MARGIN`]).
#[inline]
pub fn floor_exceeds(floor: f64, best: f64) -> bool {
    floor > best * (1.0 + FLOOR_MARGIN) + FLOOR_MARGIN
}

/// Largest `centroid-shape` weight. The largest distance of any scenario, between two teams of
/// [`MAX_AGENTS`] agents at opposite corners of the largest world
/// ([`magbench_env::scenario::MAX_WORLD_BL`] a side), is then at most
/// `1e6 · √(8 · 2) · 1e4 ≈ 4e10` and its square 1.6e21: no sum of squared distances overflows.
pub const MAX_WEIGHT: f64 = 1e6;

/// Smallest `centroid-shape` weight: the square of a 1e-12 BL displacement (the planners'
/// rounding) under it is 1e-36, far above where squares underflow.
pub const MIN_WEIGHT: f64 = 1e-6;

/// Largest embedding dimension (two coordinates per agent).
pub const MAX_DIMS: usize = 2 * MAX_AGENTS;

/// A distance on team states `(P_1, …, P_N)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Distance {
    /// The seed's DISTANCE ρ: Euclidean distance on the stacked agent positions,
    /// `‖P̃‖ = (Σ_i ‖P_i − Q_i‖²)^{1/2}`. EXTEND minimises its square, as in Algorithm 3.
    #[default]
    Positions,
    /// Centroid and shape weighted apart: `(w_c² N ‖Δc‖² + w_s² Σ_i ‖Δ(P_i − c)‖²)^{1/2}`,
    /// with `c` the centroid. Equal to [`Distance::Positions`] when both weights are 1; a larger
    /// shape weight makes separation and heading count more (the seed's remark on weighting
    /// separation and pair heading in the distance).
    CentroidShape {
        /// Weight of the centroid displacement.
        centroid: f64,
        /// Weight of the shape (positions relative to the centroid) displacement.
        shape: f64,
    },
}

/// Why a metric's text was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DistanceError {
    /// A weight is not a number.
    #[error("bad {which} weight {text:?}")]
    BadWeight {
        /// `centroid` or `shape`.
        which: &'static str,
        /// The text given.
        text: String,
    },
    /// `centroid-shape` with other than two weights.
    #[error("expected centroid-shape:W_CENTROID:W_SHAPE")]
    WeightCount,
    /// A weight outside [[`MIN_WEIGHT`], [`MAX_WEIGHT`]].
    #[error(
        "{which} weight {text} must be in [{min:e}, {max:e}] (a larger weight can overflow a distance, a smaller one underflow it)",
        min = MIN_WEIGHT,
        max = MAX_WEIGHT
    )]
    WeightOutOfRange {
        /// `centroid` or `shape`.
        which: &'static str,
        /// The text given.
        text: String,
    },
    /// No metric of that name.
    #[error("unknown metric {0:?} (expected positions or centroid-shape:W_C:W_S)")]
    Unknown(String),
}

impl Distance {
    /// Parses `positions` or `centroid-shape:W_C:W_S` (e.g. `centroid-shape:1:2`).
    pub fn parse(s: &str) -> Result<Distance, DistanceError> {
        if s == "positions" {
            return Ok(Distance::Positions);
        }
        if let Some(rest) = s.strip_prefix("centroid-shape") {
            let parts: Vec<&str> = rest.split(':').skip(1).collect();
            let (wc, ws) = match parts.as_slice() {
                [] => (1.0, 1.0),
                [a, b] => (weight("centroid", a)?, weight("shape", b)?),
                _ => return Err(DistanceError::WeightCount),
            };
            return Ok(Distance::CentroidShape {
                centroid: wc,
                shape: ws,
            });
        }
        Err(DistanceError::Unknown(s.to_string()))
    }

    /// The metric's name as [`Distance::parse`] reads it.
    pub fn name(&self) -> String {
        match self {
            Distance::Positions => "positions".into(),
            Distance::CentroidShape { centroid, shape } => {
                format!("centroid-shape:{centroid}:{shape}")
            }
        }
    }

    /// Writes the `2N` embedding coordinates of state `s` into `out[..2N]`: the distance of two
    /// states is the Euclidean distance of their embeddings.
    #[inline]
    pub fn embed(&self, s: &[Vec2], out: &mut [f64]) {
        let n = s.len();
        match *self {
            Distance::Positions => {
                for (i, p) in s.iter().enumerate() {
                    out[2 * i] = p.x;
                    out[2 * i + 1] = p.y;
                }
            }
            Distance::CentroidShape { centroid, shape } => {
                // An orthonormal (Helmert) basis: √N·c, then h_k = (Σ_{i<k} P_i − (k−1) P_k)/√(k(k−1)).
                let mut sum = Vec2::zeros();
                for (k, p) in s.iter().enumerate() {
                    if k > 0 {
                        let kk = (k + 1) as f64;
                        let h = (sum - p * (kk - 1.0)) / (kk * (kk - 1.0)).sqrt() * shape;
                        out[2 * k] = h.x;
                        out[2 * k + 1] = h.y;
                    }
                    sum += p;
                }
                let c = sum / (n as f64).sqrt() * centroid;
                out[0] = c.x;
                out[1] = c.y;
            }
        }
    }

    /// Squared distance between two states.
    #[inline]
    pub fn distance_squared(&self, a: &[Vec2], b: &[Vec2]) -> f64 {
        match self {
            Distance::Positions => a.iter().zip(b).map(|(p, q)| (p - q).norm_squared()).sum(),
            _ => {
                let n = 2 * a.len();
                let (mut ea, mut eb) = ([0.0; MAX_DIMS], [0.0; MAX_DIMS]);
                self.embed(a, &mut ea);
                self.embed(b, &mut eb);
                ea[..n]
                    .iter()
                    .zip(&eb[..n])
                    .map(|(x, y)| (x - y) * (x - y))
                    .sum()
            }
        }
    }

    /// A lower bound of [`Distance::distance_squared`] between two states of `n` agents from
    /// their centroids `a` and `b` alone: the centroid term `w_c² N ‖Δc‖²` (`w_c = 1` for
    /// positions), the shape term being at least zero.
    #[inline]
    pub fn centroid_floor(&self, n: usize, a: Vec2, b: Vec2) -> f64 {
        let w = match *self {
            Distance::Positions => 1.0,
            Distance::CentroidShape { centroid, .. } => centroid * centroid,
        };
        w * n as f64 * (a - b).norm_squared()
    }

    /// Distance between two states.
    #[inline]
    pub fn distance(&self, a: &[Vec2], b: &[Vec2]) -> f64 {
        self.distance_squared(a, b).sqrt()
    }
}

/// The `which` weight of `centroid-shape` written `text`: a number in
/// [[`MIN_WEIGHT`], [`MAX_WEIGHT`]].
fn weight(which: &'static str, text: &str) -> Result<f64, DistanceError> {
    let w = text.parse::<f64>().map_err(|_| DistanceError::BadWeight {
        which,
        text: text.to_string(),
    })?;
    if !(MIN_WEIGHT..=MAX_WEIGHT).contains(&w) {
        return Err(DistanceError::WeightOutOfRange {
            which,
            text: text.to_string(),
        });
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn team(v: &[(f64, f64)]) -> Vec<Vec2> {
        v.iter().map(|&(x, y)| Vec2::new(x, y)).collect()
    }

    #[test]
    fn centroid_shape_with_unit_weights_is_positions() {
        let a = team(&[(1.0, 2.0), (3.0, 1.5), (0.2, -1.0), (4.0, 4.0)]);
        let b = team(&[(1.5, 2.5), (2.0, 1.0), (0.7, -0.2), (3.0, 5.0)]);
        let cs = Distance::CentroidShape {
            centroid: 1.0,
            shape: 1.0,
        };
        for n in 2..=4 {
            let (p, q) = (
                Distance::Positions.distance(&a[..n], &b[..n]),
                cs.distance(&a[..n], &b[..n]),
            );
            assert!((p - q).abs() < 1e-12, "n = {n}: {p} vs {q}");
        }
    }

    #[test]
    fn shape_weight_scales_only_relative_motion() {
        let a = team(&[(1.0, 2.0), (3.0, 2.0)]);
        let moved = team(&[(2.0, 2.0), (4.0, 2.0)]); // pure translation by 1
        let spread = team(&[(0.5, 2.0), (3.5, 2.0)]); // pure widening
        let m = Distance::CentroidShape {
            centroid: 1.0,
            shape: 3.0,
        };
        assert!((m.distance(&a, &moved) - Distance::Positions.distance(&a, &moved)).abs() < 1e-12);
        assert!(
            (m.distance(&a, &spread) - 3.0 * Distance::Positions.distance(&a, &spread)).abs()
                < 1e-12
        );
    }

    #[test]
    fn weights_that_could_overflow_a_distance_are_refused() {
        for text in [
            "centroid-shape:1e308:1",
            "centroid-shape:1:1e200",
            "centroid-shape:1e-300:1",
            "centroid-shape:1:1e7",
        ] {
            let e = Distance::parse(text).unwrap_err().to_string();
            assert!(e.contains("must be in [1e-6, 1e6]"), "{text}: {e}");
        }
        // the largest weights accepted keep the largest distance of any scenario finite: two
        // teams of the most agents at opposite corners of the largest world
        let m = Distance::parse("centroid-shape:1e6:1e6").unwrap();
        let side = magbench_env::scenario::MAX_WORLD_BL;
        let a = vec![Vec2::new(0.0, 0.0); MAX_AGENTS];
        let b: Vec<Vec2> = (0..MAX_AGENTS)
            .map(|i| Vec2::new(side, if i % 2 == 0 { side } else { 0.0 }))
            .collect();
        assert!(m.distance_squared(&a, &b).is_finite());
        assert!(m.distance_squared(&a, &b) > 0.0);
    }

    #[test]
    fn parses_names() {
        assert_eq!(Distance::parse("positions"), Ok(Distance::Positions));
        assert_eq!(
            Distance::parse("centroid-shape:1:2"),
            Ok(Distance::CentroidShape {
                centroid: 1.0,
                shape: 2.0
            })
        );
        assert!(Distance::parse("centroid-shape:0:2").is_err());
        assert!(Distance::parse("manhattan").is_err());
        let m = Distance::CentroidShape {
            centroid: 0.5,
            shape: 2.0,
        };
        assert_eq!(Distance::parse(&m.name()), Ok(m));
    }
}

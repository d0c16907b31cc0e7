//! Statistics for benchmark results: quantiles, the Mann–Whitney U test, proportions
//! (two-proportion z test, Wilson and Clopper–Pearson intervals), intervals of a difference of
//! rates (Newcombe, Tango), distribution-free shift intervals (Hodges–Lehmann with the rank
//! tests' intervals) and Holm's adjustment. Distributions come from `statrs`.

pub mod holm;
pub mod mann_whitney;
pub mod proportion;
pub mod quantile;
pub mod rank_null;
pub mod rate_diff;
pub mod shift;

pub use holm::holm;
pub use mann_whitney::{MannWhitney, mann_whitney_u};
pub use proportion::{clopper_pearson, two_proportion_z, wilson};
pub use quantile::{Summary, median, quantile_sorted};

/// The alternative hypothesis of a test about two samples `x` and `y`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Alternative {
    /// `x` and `y` differ in either direction.
    TwoSided,
    /// `x` tends to be smaller than `y`.
    Less,
    /// `x` tends to be greater than `y`.
    Greater,
}

/// The standard normal distribution's quantile at `p` (e.g. 1.96 at 0.975).
pub fn normal_quantile(p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    Normal::standard().inverse_cdf(p)
}

/// The standard normal survival function `P(Z > z)`.
pub fn normal_sf(z: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    Normal::standard().sf(z)
}

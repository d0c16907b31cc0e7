//! Statistics for benchmark results: quantiles, proportions (Wilson and Clopper–Pearson
//! intervals), intervals of a difference of
//! rates (Newcombe, Tango), distribution-free shift intervals (Hodges–Lehmann with the rank
//! tests' intervals) and Holm's adjustment. Distributions come from `statrs`.

pub mod holm;
pub mod proportion;
pub mod quantile;
pub mod rank_null;
pub mod rate_diff;
pub mod shift;

pub use holm::holm;
pub use proportion::{clopper_pearson, wilson, wilson_z};
pub use quantile::{Summary, median, quantile_sorted};

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

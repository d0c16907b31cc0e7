//! Why a fit could not be made.

use magbench_env::InputError;

/// A failure of `magbench calibrate`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// A log does not fit the scenario (its file, field and reason).
    #[error(transparent)]
    Input(#[from] InputError),
    /// No stretch of the logs can be predicted: no consecutive frames with every agent observed
    /// and the field on.
    #[error(
        "no segment of consecutive frames with every agent observed and the field on in {0} (a run with the field off, or every agent missed?)"
    )]
    NoSegments(String),
}

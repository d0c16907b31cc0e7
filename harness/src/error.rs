//! The library's error: bad input (file, field, reason) or a failure that is not the input's.
//! The crates' typed errors become an [`Error`] here, by their kind: bad input keeps its file,
//! field and reason; every other failure becomes its message. The command line exits 2 on bad
//! input and 1 on anything else ([`Error::exit_code`]); Python raises `magbench.InputError` (a
//! `ValueError`) or `magbench.MagbenchError` (a `RuntimeError`).

use magbench_drivers::hardware::HardwareError;
use magbench_drivers::redetect::RedetectError;
use magbench_drivers::rigs::{OpenError, StartError};
use magbench_env::InputError;
use magbench_env::input::Rejection;
use magbench_env::registry::RegistryError;
use magbench_plot::plot::PlotError;

/// An error of a magbench library call or command.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input (file, field, reason); exit code 2.
    #[error("{0}")]
    Input(#[from] InputError),
    /// A failure that is not the user's input (I/O, a broken rig, ...); exit code 1.
    #[error("{0}")]
    Failed(String),
}

impl Error {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input(_) => 2,
            Error::Failed(_) => 1,
        }
    }

    /// A bad command-line value.
    pub fn arg(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Input(InputError::new("<command line>", field, reason))
    }

    /// A command-line value refused by a check that does not know the option: the
    /// rejection's field goes under `option` (an empty field becomes `option`).
    pub fn rejected(option: &str, r: Rejection) -> Self {
        Error::Input(r.under(option).in_file("<command line>"))
    }
}

/// Failures that are never the user's input: exit code 1 with their message.
macro_rules! failed_from {
    ($($t:ty),* $(,)?) => {$(
        impl From<$t> for Error {
            fn from(e: $t) -> Self {
                Error::Failed(e.to_string())
            }
        }
    )*};
}

failed_from!(
    std::io::Error,
    HardwareError,
    StartError,
    RegistryError,
    PlotError,
);

impl From<magbench_store::Error> for Error {
    fn from(e: magbench_store::Error) -> Self {
        match e {
            magbench_store::Error::Input(e) => Error::Input(e),
            magbench_store::Error::Failed(e) => Error::Failed(e),
        }
    }
}

/// The harness's part of a store operation (a merge's replay pages and report) fails the
/// operation with its kind.
impl From<Error> for magbench_store::Error {
    fn from(e: Error) -> Self {
        match e {
            Error::Input(e) => magbench_store::Error::Input(e),
            Error::Failed(e) => magbench_store::Error::Failed(e),
        }
    }
}

impl From<OpenError> for Error {
    fn from(e: OpenError) -> Self {
        match e {
            OpenError::Input(e) => Error::Input(e),
            e @ (OpenError::Hardware(_) | OpenError::Failed(_)) => Error::Failed(e.to_string()),
        }
    }
}

impl From<RedetectError> for Error {
    fn from(e: RedetectError) -> Self {
        match e {
            RedetectError::NoStart { ref dir } => Error::Input(InputError::new(
                dir.display().to_string(),
                "",
                "the recording has no true positions; give --scenario for the agents' start",
            )),
            e => Error::Failed(e.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_come_from_the_error_kind() {
        let input: Error = OpenError::Input(InputError::new("r.toml", "coil", "bad")).into();
        assert_eq!(
            (input.exit_code(), input.to_string().as_str()),
            (2, "r.toml: coil: bad")
        );
        let failed: Error = OpenError::Failed("no link".into()).into();
        assert_eq!(failed.exit_code(), 1);
        let start: Error = StartError::InvalidStart.into();
        assert_eq!(start.exit_code(), 1);
        let dir = std::path::PathBuf::from("frames");
        let redetect: Error = RedetectError::NoStart { dir: dir.clone() }.into();
        assert_eq!(redetect.exit_code(), 2);
        assert_eq!(
            redetect.to_string(),
            RedetectError::NoStart { dir }.to_string(),
            "the same text as the library's"
        );
    }
}

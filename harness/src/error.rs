//! Command errors and their exit codes: 2 for bad input, 1 for anything else. The libraries'
//! typed errors become a [`CliError`] here, by their kind: bad input keeps its file, field and
//! reason; every other failure becomes its message.

use magbench_drivers::hardware::HardwareError;
use magbench_drivers::replay::ReplayError;
use magbench_drivers::rigs::{OpenError, StartError};
use magbench_env::InputError;
use magbench_env::check::Rejection;
use magbench_env::registry::RegistryError;

/// An error that ends a `magbench` command.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad input (file, field, reason); exit code 2.
    #[error("{0}")]
    Input(#[from] InputError),
    /// A failure that is not the user's input (I/O, a broken rig, ...); exit code 1.
    #[error("{0}")]
    Failed(String),
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failed(_) => 1,
        }
    }

    /// A bad command-line value.
    pub fn arg(field: impl Into<String>, reason: impl Into<String>) -> Self {
        CliError::Input(InputError::new("<command line>", field, reason))
    }

    /// A command-line value refused by a check that does not know the option: the
    /// rejection's field goes under `option` (an empty field becomes `option`).
    pub fn rejected(option: &str, r: Rejection) -> Self {
        CliError::Input(r.under(option).in_file("<command line>"))
    }
}

/// Failures that are never the user's input: exit code 1 with their message.
macro_rules! failed_from {
    ($($t:ty),* $(,)?) => {$(
        impl From<$t> for CliError {
            fn from(e: $t) -> Self {
                CliError::Failed(e.to_string())
            }
        }
    )*};
}

failed_from!(std::io::Error, HardwareError, StartError, RegistryError,);

impl From<OpenError> for CliError {
    fn from(e: OpenError) -> Self {
        match e {
            OpenError::Input(e) => CliError::Input(e),
            e @ (OpenError::Hardware(_) | OpenError::Failed(_)) => CliError::Failed(e.to_string()),
        }
    }
}

impl From<ReplayError> for CliError {
    fn from(e: ReplayError) -> Self {
        match e {
            ReplayError::NoStart { ref dir } => CliError::Input(InputError::new(
                dir.display().to_string(),
                "",
                "the recording has no true positions; give --scenario for the agents' start",
            )),
            e => CliError::Failed(e.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_come_from_the_error_kind() {
        let input: CliError = OpenError::Input(InputError::new("r.toml", "coil", "bad")).into();
        assert_eq!(
            (input.exit_code(), input.to_string().as_str()),
            (2, "r.toml: coil: bad")
        );
        let failed: CliError = OpenError::Failed("no link".into()).into();
        assert_eq!(failed.exit_code(), 1);
        let start: CliError = StartError::InvalidStart.into();
        assert_eq!(start.exit_code(), 1);
        let dir = std::path::PathBuf::from("frames");
        let replay: CliError = ReplayError::NoStart { dir: dir.clone() }.into();
        assert_eq!(replay.exit_code(), 2);
        assert_eq!(
            replay.to_string(),
            ReplayError::NoStart { dir }.to_string(),
            "the same text as the library's"
        );
    }
}

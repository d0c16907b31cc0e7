//! Command errors and their exit codes: 2 for bad input, 1 for anything else.

use magbench_env::InputError;

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
}

impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        CliError::Failed(e.to_string())
    }
}

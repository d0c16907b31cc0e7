//! The store's error: bad input (a results folder or file that is not what it should be: file,
//! field, reason) or a failure that is not the input's (I/O).

use magbench_env::InputError;

/// An error of reading, writing or checking a results folder.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input (file, field, reason).
    #[error("{0}")]
    Input(#[from] InputError),
    /// A failure that is not the input's (I/O, ...).
    #[error("{0}")]
    Failed(String),
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::Failed(e.to_string())
    }
}

impl Error {
    /// The process exit code of a command that fails with this error: 2 for bad input, 1 for
    /// anything else.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input(_) => 2,
            Error::Failed(_) => 1,
        }
    }
}

//! What can stop the emulator: a bad setting, or an endpoint or file it cannot open.

/// A failure of the emulator.
#[derive(Debug, thiserror::Error)]
pub enum EmulatorError {
    /// The speed factor is not a finite number > 0.
    #[error("speed must be a finite number > 0, got {0}")]
    Speed(f64),
    /// An endpoint, the log or the recording could not be opened or written.
    #[error("{what}: {source}")]
    Io {
        /// What was being opened or written (`camera listen 127.0.0.1:7701`, a path, ...).
        what: String,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A pseudo-terminal endpoint on a system without them.
    #[error("pseudo-terminals need a Unix system")]
    NoPty,
}

impl EmulatorError {
    /// An I/O failure of `what`.
    pub fn io(what: impl Into<String>, source: std::io::Error) -> Self {
        EmulatorError::Io {
            what: what.into(),
            source,
        }
    }
}

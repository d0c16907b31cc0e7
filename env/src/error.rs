//! The one error type for bad input: it names the file, the field and the reason.

use std::fmt;

/// Bad user input (a scenario, experiment or rig file, or a command-line value).
///
/// Displayed as `FILE: FIELD: REASON`. Command-line tools exit with code 2 on it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError {
    /// The file (or `<command line>`, `<built-in NAME>`) the input came from.
    pub file: String,
    /// The dotted path of the offending field, e.g. `world.obstacles[2].polygon`.
    pub field: String,
    /// Why the value was rejected.
    pub reason: String,
}

impl InputError {
    /// Builds an error from its three parts.
    pub fn new(
        file: impl Into<String>,
        field: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            field: field.into(),
            reason: reason.into(),
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}: {}", self.file, self.reason)
        } else {
            write!(f, "{}: {}: {}", self.file, self.field, self.reason)
        }
    }
}

impl std::error::Error for InputError {}

//! A rejected value (its field path and the reason) and the file it came from.

use std::fmt;

use crate::error::InputError;

/// A rejected value: the dotted field path (`camera.misses.prob`, `legs[1].goal`) and why.
///
/// Checks that do not know their file return it; [`InputChecks`] or [`Rejection::in_file`] turn it
/// into an [`InputError`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rejection {
    /// The path of the offending field.
    pub field: String,
    /// Why the value was rejected.
    pub reason: String,
}

impl Rejection {
    /// A rejection of `field` for `reason`.
    pub fn new(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Rejection {
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// The same rejection with its field under `prefix` (`physics` + `r_min` → `physics.r_min`).
    pub fn under(mut self, prefix: &str) -> Self {
        self.field = join(prefix, &self.field);
        self
    }

    /// The input error of this rejection in `file`.
    pub fn in_file(self, file: &str) -> InputError {
        InputError::new(file, self.field, self.reason)
    }
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.field, self.reason)
    }
}

/// `prefix.field` (an index `[i]` joins without a dot; an empty part drops out).
pub fn join(prefix: &str, field: &str) -> String {
    match (prefix.is_empty(), field.is_empty()) {
        (true, _) => field.to_string(),
        (_, true) => prefix.to_string(),
        _ if field.starts_with('[') => format!("{prefix}{field}"),
        _ => format!("{prefix}.{field}"),
    }
}

/// The checks of one input file: each failure becomes an [`InputError`] naming it.
#[derive(Debug, Clone, Copy)]
pub struct InputChecks<'a> {
    /// The file (or `<command line>`) being checked.
    pub file: &'a str,
}

impl<'a> InputChecks<'a> {
    /// The checks of `file`.
    pub fn new(file: &'a str) -> Self {
        InputChecks { file }
    }

    /// An error at `field` for `reason`.
    pub fn err(&self, field: impl Into<String>, reason: impl Into<String>) -> InputError {
        InputError::new(self.file, field, reason)
    }

    /// Puts a rejection of a file-less check into this file.
    pub fn at<T>(&self, r: Result<T, Rejection>) -> Result<T, InputError> {
        r.map_err(|e| e.in_file(self.file))
    }

    /// `v` at `field` must be finite.
    pub fn finite(&self, field: &str, v: f64) -> Result<f64, InputError> {
        self.at(super::bounds::finite(field, v)).map(|()| v)
    }

    /// `v` at `field` must be finite and > 0.
    pub fn positive(&self, field: &str, v: f64) -> Result<f64, InputError> {
        self.at(super::bounds::positive(field, v)).map(|()| v)
    }

    /// `v` at `field` must be finite and ≥ 0.
    pub fn non_negative(&self, field: &str, v: f64) -> Result<f64, InputError> {
        self.at(super::bounds::non_negative(field, v)).map(|()| v)
    }

    /// `v` at `field` must lie within `bound`.
    pub fn bound(&self, field: &str, v: f64, bound: &Bound) -> Result<f64, InputError> {
        self.at(bound.check(field, v))
    }
}

use super::bounds::Bound;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_join_with_dots_and_brackets() {
        assert_eq!(join("planners[0]", "k"), "planners[0].k");
        assert_eq!(join("legs", "[2]"), "legs[2]");
        assert_eq!(join("", "k"), "k");
        assert_eq!(join("physics", ""), "physics");
        let e = Rejection::new("r_min", "too small")
            .under("physics")
            .in_file("s.toml");
        assert_eq!(e.to_string(), "s.toml: physics.r_min: too small");
    }
}

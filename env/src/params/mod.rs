//! Parameters declared once, as OMPL's `declareParam` declares them: a name, a default, the
//! values allowed, a help line and a typed setter, in one place ([`declare_params!`]). Listing
//! (`magbench plan --list`), parsing `key=value` text, validation and the defaults all come from
//! that declaration; planners and trackers use the same one.
//!
//! - [`ParamSet`]: what a declared struct can do (list, set by text, check together);
//! - [`ParamType`]: how one value type parses and what values it allows ([`Reals`], a range of
//!   whole numbers, a flag, a named choice);
//! - [`apply`] and [`split_assignment`]: the one way `key=value` text reaches a [`ParamSet`],
//!   with one error convention (`FILE: param.KEY: REASON`);
//!
//! The registries that name planners and trackers are in [`crate::registry`].

mod declare;
mod types;

pub use types::{BadValue, ParamType, Reals, Value, choose};

use std::borrow::Cow;

use crate::InputError;
use crate::input::Rejection;

/// One parameter as listed: its key, help line, allowed values and current value.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamInfo {
    /// Its key, as given in `key=value`.
    pub name: Cow<'static, str>,
    /// What it does, with its unit (the doc comment of its declaration).
    pub help: Cow<'static, str>,
    /// The values it takes, e.g. `[0, 1]`, `1..=100000`, `true|false`.
    pub range: String,
    /// Its current value.
    pub value: Value,
}

impl ParamInfo {
    /// The parameter as one indented line of a listing: key, value and range left-aligned in
    /// columns of `widths`, then its help.
    pub fn listing_line(&self, widths: [usize; 3]) -> String {
        let [name, value, range] = widths;
        format!(
            "    {:<name$} {:<value$} {:<range$} {}\n",
            self.name,
            self.value.to_string(),
            self.range,
            self.help
        )
    }
}

/// Why a parameter was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// No parameter of that name.
    #[error("unknown parameter {0:?}")]
    Unknown(String),
    /// The value does not parse or is out of range.
    #[error(transparent)]
    BadValue(#[from] BadValue),
}

/// A struct of declared parameters (made by [`declare_params!`]). The defaults are a set with
/// no parameters (`impl ParamSet for MyTestDouble {}`).
pub trait ParamSet {
    /// Every parameter with its current value, in declaration order.
    fn params(&self) -> Vec<ParamInfo> {
        Vec::new()
    }
    /// Sets parameter `key` from its text `value`; the error says why it is refused.
    fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        let _ = value;
        Err(ParamError::Unknown(key.to_string()))
    }
    /// Checks the parameters together, once all are set (e.g. a duration range). The
    /// rejection's field is relative to the set (empty when no one parameter is to blame).
    fn check_params(&self) -> Result<(), Rejection> {
        Ok(())
    }
}

/// Two parameter sets as one: keys are looked up in the first, then in the second (a tracker's
/// own parameters and the loop's).
pub struct Both<'a, A: ?Sized, B: ?Sized>(pub &'a mut A, pub &'a mut B);

impl<A: ParamSet + ?Sized, B: ParamSet + ?Sized> ParamSet for Both<'_, A, B> {
    fn params(&self) -> Vec<ParamInfo> {
        let mut v = self.0.params();
        v.extend(self.1.params());
        v
    }

    fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        match self.0.set_param(key, value) {
            Err(ParamError::Unknown(_)) => self.1.set_param(key, value),
            r => r,
        }
    }

    fn check_params(&self) -> Result<(), Rejection> {
        self.0.check_params()?;
        self.1.check_params()
    }
}

/// Sets `params` (key, text) on `set`, then checks them together. Errors name `source` (a file
/// or `<command line>`), the field `param.KEY` (or `param` for a check of several) and the
/// reason; `owner` (a planner or tracker name) says whose parameters they are.
pub fn apply<P: ParamSet + ?Sized>(
    source: &str,
    owner: &str,
    set: &mut P,
    params: &[(String, String)],
) -> Result<(), InputError> {
    for (key, value) in params {
        set.set_param(key, value).map_err(|e| {
            let reason = match e {
                ParamError::Unknown(_) => {
                    let known: Vec<String> = set
                        .params()
                        .into_iter()
                        .map(|p| p.name.into_owned())
                        .collect();
                    format!(
                        "{owner} has no parameter {key:?} (known: {}){}",
                        known.join(", "),
                        crate::input::suggest::hint(key, known.iter().map(String::as_str))
                    )
                }
                ParamError::BadValue(r) => r.to_string(),
            };
            InputError::new(source, format!("param.{key}"), reason)
        })?;
    }
    set.check_params().map_err(|r| {
        let r = r.under("param");
        InputError::new(source, r.field, format!("{owner}: {}", r.reason))
    })
}

/// Key-value pairs as the owned strings [`apply`] and the registries take.
pub fn owned(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// Splits `key=value` text (a `--param` option); an error names `source`, the field `param`
/// and the text.
pub fn split_assignment(source: &str, text: &str) -> Result<(String, String), InputError> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(InputError::new(
            source,
            "param",
            format!("{text:?} is not key=value"),
        )),
    }
}

/// Splits every `key=value` text of a list (see [`split_assignment`]).
pub fn split_all(source: &str, list: &[String]) -> Result<Vec<(String, String)>, InputError> {
    list.iter().map(|t| split_assignment(source, t)).collect()
}

/// The parameters of `now` whose value differs from `fresh` (the same set with its defaults),
/// as `key=value`.
pub fn changed(now: &[ParamInfo], fresh: &[ParamInfo]) -> Vec<String> {
    now.iter()
        .zip(fresh)
        .filter(|(a, b)| a.value != b.value)
        .map(|(a, _)| format!("{}={}", a.name, a.value))
        .collect()
}

#[cfg(test)]
mod tests;

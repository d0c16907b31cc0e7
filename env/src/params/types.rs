//! The value types of declared parameters: how each parses from text and what values it
//! allows.

use std::fmt;
use std::ops::RangeInclusive;

use serde::Serialize;

/// A parameter's value, for listings, labels and JSON.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Value {
    /// A real number.
    Real(f64),
    /// A whole number.
    Whole(u64),
    /// A flag.
    Flag(bool),
    /// One of a fixed set of names.
    Name(&'static str),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Real(x) => write!(f, "{x}"),
            Value::Whole(n) => write!(f, "{n}"),
            Value::Flag(b) => write!(f, "{b}"),
            Value::Name(s) => f.write_str(s),
        }
    }
}

/// Why a parameter's text was refused (the reason of an error naming the parameter).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BadValue {
    /// The text is not a real number.
    #[error("{text:?} is not a number")]
    NotANumber {
        /// The text given.
        text: String,
    },
    /// The text is not a whole number.
    #[error("{text:?} is not a whole number")]
    NotWhole {
        /// The text given.
        text: String,
    },
    /// The number lies outside the allowed values.
    #[error("must be in {allowed}, got {text}")]
    OutOfRange {
        /// The allowed values, e.g. `[0, 1]`.
        allowed: String,
        /// The text given.
        text: String,
    },
    /// The text names none of the choices.
    #[error("{text:?} is not one of {}", options.join(", "))]
    NotOneOf {
        /// The text given.
        text: String,
        /// The names allowed.
        options: Vec<String>,
    },
    /// The text is not of the kind the parameter takes (a parameter declared at run time).
    #[error("{key}: expected {expected}, got {text:?}")]
    Expected {
        /// The parameter's key.
        key: String,
        /// What it takes, e.g. `a finite number`.
        expected: &'static str,
        /// The text given.
        text: String,
    },
}

/// A type a parameter can have.
pub trait ParamType: Sized {
    /// What values of the type the parameter allows (`()` when every value is allowed).
    type Domain;
    /// Parses `text`, or says why not (the reason of an error naming the parameter).
    fn parse(text: &str, domain: &Self::Domain) -> Result<Self, BadValue>;
    /// The value, for listings.
    fn value(&self) -> Value;
    /// The allowed values, e.g. `[0, 1]`.
    fn describe(domain: &Self::Domain) -> String;
}

/// Finite real numbers between `min` and `max` (`min` itself excluded when `above`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reals {
    /// The smallest value (or the bound above which values lie, when `above`).
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// `min` is excluded.
    pub above: bool,
}

impl Reals {
    /// Every finite number greater than zero.
    pub const POSITIVE: Reals = Reals {
        min: 0.0,
        max: f64::MAX,
        above: true,
    };

    /// `[min, max]`.
    pub const fn closed(min: f64, max: f64) -> Reals {
        Reals {
            min,
            max,
            above: false,
        }
    }
}

impl ParamType for f64 {
    type Domain = Reals;

    fn parse(text: &str, d: &Reals) -> Result<f64, BadValue> {
        let v: f64 = text.trim().parse().map_err(|_| BadValue::NotANumber {
            text: text.to_string(),
        })?;
        let low = if d.above { v <= d.min } else { v < d.min };
        if !v.is_finite() || low || v > d.max {
            return Err(BadValue::OutOfRange {
                allowed: f64::describe(d),
                text: text.to_string(),
            });
        }
        Ok(v)
    }

    fn value(&self) -> Value {
        Value::Real(*self)
    }

    fn describe(d: &Reals) -> String {
        match (d.above, d.max == f64::MAX) {
            (true, true) => format!("> {}", d.min),
            (true, false) => format!("({}, {}]", d.min, d.max),
            (false, true) => format!(">= {}", d.min),
            (false, false) => format!("[{}, {}]", d.min, d.max),
        }
    }
}

/// Largest whole number written as a real (`5.0`) that is accepted: 2^53, where reals stop
/// holding every whole number.
const EXACT_WHOLE: f64 = 9_007_199_254_740_992.0;

impl ParamType for usize {
    type Domain = RangeInclusive<usize>;

    /// A whole number, also written as a real with no fraction (`48.0`, as TOML floats and
    /// older experiment files give it).
    fn parse(text: &str, d: &RangeInclusive<usize>) -> Result<usize, BadValue> {
        let t = text.trim();
        let v = match t.parse::<usize>() {
            Ok(v) => v,
            Err(_) => match t.parse::<f64>() {
                Ok(x) if x.fract() == 0.0 && (0.0..=EXACT_WHOLE).contains(&x) => x as usize,
                _ => {
                    return Err(BadValue::NotWhole {
                        text: text.to_string(),
                    });
                }
            },
        };
        if !d.contains(&v) {
            return Err(BadValue::OutOfRange {
                allowed: usize::describe(d),
                text: text.to_string(),
            });
        }
        Ok(v)
    }

    fn value(&self) -> Value {
        Value::Whole(*self as u64)
    }

    fn describe(d: &RangeInclusive<usize>) -> String {
        format!("[{}, {}]", d.start(), d.end())
    }
}

impl ParamType for bool {
    type Domain = ();

    /// `true` or `false` (also `1`/`0`, `yes`/`no`).
    fn parse(text: &str, _: &()) -> Result<bool, BadValue> {
        choose(text, &[("true", true), ("false", false)]).or_else(|e| {
            choose(
                text,
                &[("1", true), ("0", false), ("yes", true), ("no", false)],
            )
            .map_err(|_| e)
        })
    }

    fn value(&self) -> Value {
        Value::Flag(*self)
    }

    fn describe(_: &()) -> String {
        "true|false".into()
    }
}

/// The value of `text` among named `options` (for a parameter that names one of a few
/// choices); the error lists the names.
pub fn choose<T: Copy>(text: &str, options: &[(&str, T)]) -> Result<T, BadValue> {
    let t = text.trim();
    options
        .iter()
        .find(|(name, _)| *name == t)
        .map(|(_, v)| *v)
        .ok_or_else(|| BadValue::NotOneOf {
            text: text.to_string(),
            options: options.iter().map(|(n, _)| n.to_string()).collect(),
        })
}

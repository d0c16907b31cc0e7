//! Parsing `key=value` planner parameters.

use crate::planner::ParamError;

/// Parses a finite number in `[lo, hi]`.
pub fn number(key: &str, value: &str, lo: f64, hi: f64) -> Result<f64, ParamError> {
    let v: f64 = value
        .trim()
        .parse()
        .map_err(|_| ParamError::BadValue(format!("{key}: {value:?} is not a number")))?;
    if !v.is_finite() || v < lo || v > hi {
        return Err(ParamError::BadValue(format!(
            "{key}: {value} is outside [{lo}, {hi}]"
        )));
    }
    Ok(v)
}

/// Parses a positive number (> 0, finite).
pub fn positive(key: &str, value: &str) -> Result<f64, ParamError> {
    let v = number(key, value, 0.0, f64::MAX)?;
    if v <= 0.0 {
        return Err(ParamError::BadValue(format!("{key}: {value} must be > 0")));
    }
    Ok(v)
}

/// Parses a whole number in `[lo, hi]`.
pub fn whole(key: &str, value: &str, lo: u64, hi: u64) -> Result<u64, ParamError> {
    let v: u64 = value
        .trim()
        .parse()
        .map_err(|_| ParamError::BadValue(format!("{key}: {value:?} is not a whole number")))?;
    if v < lo || v > hi {
        return Err(ParamError::BadValue(format!(
            "{key}: {value} is outside [{lo}, {hi}]"
        )));
    }
    Ok(v)
}

/// Parses `true` or `false`.
pub fn boolean(key: &str, value: &str) -> Result<bool, ParamError> {
    match value.trim() {
        "true" | "1" | "yes" => Ok(true),
        "false" | "0" | "no" => Ok(false),
        _ => Err(ParamError::BadValue(format!(
            "{key}: {value:?} is not true or false"
        ))),
    }
}

/// Durations are given in seconds and used in whole control periods of `period` seconds:
/// the nearest whole number of periods, at least one.
pub fn to_periods(seconds: f64, period: f64) -> u32 {
    ((seconds / period).round() as u32).max(1)
}

/// Checks that a duration range is ordered.
pub fn check_durations(min: f64, max: f64) -> Result<(), ParamError> {
    if min > max {
        return Err(ParamError::BadValue(format!(
            "min_duration {min} exceeds max_duration {max}"
        )));
    }
    Ok(())
}

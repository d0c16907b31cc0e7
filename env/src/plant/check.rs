//! Range checks for preset values: each failure names the field and the reason.

/// A rejected preset value: the dotted field path and why.
pub type Rejection = (&'static str, String);

/// `v` must be a finite number ≥ 0.
pub fn non_negative(field: &'static str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err((field, format!("must be a finite number ≥ 0, got {v}")))
    }
}

/// `v` must be a finite number > 0.
pub fn positive(field: &'static str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err((field, format!("must be a finite number > 0, got {v}")))
    }
}

/// `v` must be a finite number in `[lo, hi]`.
pub fn within(field: &'static str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), Rejection> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err((field, format!("must be in [{lo}, {hi}]{unit}, got {v}")))
    }
}

/// `v` must be a probability.
pub fn probability(field: &'static str, v: f64) -> Result<(), Rejection> {
    within(field, v, 0.0, 1.0, "")
}

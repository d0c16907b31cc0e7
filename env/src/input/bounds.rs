//! Number checks, and the bounds that keep every accepted input within a time and memory
//! budget. A bound that is a choice (not a law of physics) carries its reason, and its
//! message says both: `must be in (0, 1000] px per BL (a 16384-pixel sensor ...), got 1e308`.

use super::rejection::Rejection;

/// The memory an accepted input may make a command allocate (bytes): 2 GiB, what a laptop
/// spares for one run. Every bound below that sizes an allocation is derived from it.
pub const MEMORY_BUDGET_BYTES: u64 = 2 << 30;

/// A closed or half-open interval of accepted values, with its unit and the reason for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// Lowest value.
    pub lo: f64,
    /// Whether `lo` itself is refused (`(lo, hi]`).
    pub lo_open: bool,
    /// Highest value (accepted).
    pub hi: f64,
    /// The unit written after the interval (`" px"`, `" s"`, or empty).
    pub unit: &'static str,
    /// Why the interval is what it is (empty for an interval physics sets).
    pub why: &'static str,
}

impl Bound {
    /// `[lo, hi]` in `unit`, chosen for `why`.
    pub const fn closed(lo: f64, hi: f64, unit: &'static str, why: &'static str) -> Bound {
        Bound {
            lo,
            lo_open: false,
            hi,
            unit,
            why,
        }
    }

    /// `(lo, hi]` in `unit`, chosen for `why`.
    pub const fn above(lo: f64, hi: f64, unit: &'static str, why: &'static str) -> Bound {
        Bound {
            lo,
            lo_open: true,
            hi,
            unit,
            why,
        }
    }

    /// Whether `v` lies within (NaN never does).
    pub fn contains(&self, v: f64) -> bool {
        let low = if self.lo_open {
            v > self.lo
        } else {
            v >= self.lo
        };
        low && v <= self.hi
    }

    /// `v` at `field`, refused outside the bound with the bound and its reason.
    pub fn check(&self, field: &str, v: f64) -> Result<f64, Rejection> {
        if self.contains(v) {
            return Ok(v);
        }
        let open = if self.lo_open { '(' } else { '[' };
        let why = if self.why.is_empty() {
            String::new()
        } else {
            format!(": {}", self.why)
        };
        Err(Rejection::new(
            field,
            format!(
                "must be in {open}{}, {}]{}{why}, got {}",
                number(self.lo),
                number(self.hi),
                self.unit,
                number(v)
            ),
        ))
    }

    /// A whole number `n` at `field` within the bound.
    pub fn check_count(&self, field: &str, n: u64) -> Result<u64, Rejection> {
        self.check(field, n as f64).map(|_| n)
    }
}

/// `v` as a message shows it: plainly when short, else in scientific notation (`1e308`, not
/// 309 digits).
pub fn number(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 12 {
        plain
    } else {
        format!("{v:e}")
    }
}

/// `v` must be a finite number.
pub fn finite(field: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Rejection::new(
            field,
            format!("must be a finite number, got {v}"),
        ))
    }
}

/// `v` must be a finite number ≥ 0.
pub fn non_negative(field: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(Rejection::new(
            field,
            format!("must be a finite number ≥ 0, got {v}"),
        ))
    }
}

/// `v` must be a finite number > 0.
pub fn positive(field: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Rejection::new(
            field,
            format!("must be a finite number > 0, got {v}"),
        ))
    }
}

/// `v` must be a finite number in `[lo, hi]` (`unit` follows the interval in the message).
pub fn within(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), Rejection> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(Rejection::new(
            field,
            format!("must be in [{lo}, {hi}]{unit}, got {v}"),
        ))
    }
}

/// `v` must be a probability.
pub fn probability(field: &str, v: f64) -> Result<(), Rejection> {
    within(field, v, 0.0, 1.0, "")
}

/// Most worker threads: a few per core is all that helps; beyond it the OS refuses threads
/// or the machine thrashes.
pub const THREADS_PER_CORE: usize = 8;

/// The most threads a command starts on this machine: [`THREADS_PER_CORE`] per core.
pub fn max_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get()) * THREADS_PER_CORE
}

// the reason in `thread_bound` says 8
const _: () = assert!(THREADS_PER_CORE == 8);

/// The thread counts this machine accepts: 1 to [`max_threads`].
pub fn thread_bound() -> Bound {
    Bound::closed(
        1.0,
        max_threads() as f64,
        " threads",
        "8 per core of this machine; more only slow it down, and the OS refuses threads beyond its limit",
    )
}

/// `n` threads at `field`: 1 to [`max_threads`].
pub fn threads(field: &str, n: usize) -> Result<usize, Rejection> {
    thread_bound().check_count(field, n as u64).map(|_| n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_say_their_interval_and_reason() {
        let b = Bound::above(0.0, 1000.0, " px", "a sensor is at most 16384 px wide");
        assert_eq!(b.check("x", 3.0), Ok(3.0));
        let e = b.check("x", 1e308).unwrap_err();
        assert_eq!(
            e.reason,
            "must be in (0, 1000] px: a sensor is at most 16384 px wide, got 1e308"
        );
        assert!(b.check("x", 0.0).is_err());
        assert!(b.check("x", f64::NAN).is_err());
        assert!(Bound::closed(0.0, 1.0, "", "").check("x", 0.0).is_ok());
        assert!(threads("--threads", 100_000).is_err());
        assert!(threads("--threads", 1).is_ok());
        assert!(positive("p", 5e-324).is_ok());
        assert!(non_negative("p", -0.5).is_err());
    }
}

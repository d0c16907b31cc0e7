//! The planner limits of the command line (`--max-iters`, `--time-limit`), shared by `plan`,
//! `track` and `rig run`.

use clap::Args;
use magbench_planners::Limits;

use crate::CliError;
use crate::run::spec::time_limit;

/// `--max-iters` and `--time-limit`.
#[derive(Debug, Clone, Args)]
pub struct LimitArgs {
    /// Planner iteration limit of every planning call.
    #[arg(long)]
    pub max_iters: Option<u64>,
    /// Planner wall-time limit of every planning call (s). Results are reproducible only with
    /// an iteration limit.
    #[arg(long)]
    pub time_limit: Option<f64>,
}

impl LimitArgs {
    /// The limits, or `None` when neither is given; exit 2 on a bad value.
    pub fn limits(&self) -> Result<Option<Limits>, CliError> {
        if self.max_iters == Some(0) {
            return Err(CliError::arg("--max-iters", "must be at least 1, got 0"));
        }
        let time_limit = match self.time_limit {
            Some(t) => Some(time_limit(t).map_err(|r| CliError::arg("--time-limit", r))?),
            None => None,
        };
        Ok(
            (self.max_iters.is_some() || time_limit.is_some()).then_some(Limits {
                max_iterations: self.max_iters,
                time_limit,
            }),
        )
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn huge_zero_and_negative_limits_are_refused() {
        for t in [1e20, f64::INFINITY, f64::NAN, 0.0, -1.0, 1e300] {
            let a = LimitArgs {
                max_iters: None,
                time_limit: Some(t),
            };
            let e = a.limits().unwrap_err();
            assert_eq!(e.exit_code(), 2);
            assert!(e.to_string().contains("--time-limit"), "{e}");
        }
        let a = LimitArgs {
            max_iters: Some(0),
            time_limit: None,
        };
        assert!(a.limits().unwrap_err().to_string().contains("--max-iters"));
        let a = LimitArgs {
            max_iters: Some(5),
            time_limit: Some(2.5),
        };
        let l = a.limits().unwrap().unwrap();
        assert_eq!(l.max_iterations, Some(5));
        assert_eq!(l.time_limit, Some(Duration::from_millis(2500)));
    }
}

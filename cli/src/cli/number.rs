//! Command-line numbers checked against their [`Bound`]: a refusal names the option, the
//! interval, its unit and why (`<command line>: --max-iters: must be in [1, 2097152]
//! iterations: …, got 1e19`).

use magbench_env::input::Bound;

use crate::Error;

/// `v` given to option `name`, within `bound`.
pub(crate) fn checked(name: &str, bound: &Bound, v: f64) -> Result<f64, Error> {
    bound.check(name, v).map_err(|r| Error::arg(name, r.reason))
}

/// The whole number `n` given to option `name`, within `bound`.
pub(crate) fn count(name: &str, bound: &Bound, n: u64) -> Result<u64, Error> {
    bound
        .check_count(name, n)
        .map_err(|r| Error::arg(name, r.reason))
}

/// The worker threads of `--threads`: the given number within the machine's bound, else one
/// per core.
pub(crate) fn threads(given: Option<usize>) -> Result<usize, Error> {
    match given {
        Some(n) => magbench_env::input::bounds::threads("--threads", n)
            .map_err(|r| Error::arg("--threads", r.reason)),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

//! The Rust cost of the calls the Python operations make, timed in Rust, so that a benchmark
//! can subtract it from the time of the Python call (`python/bench/overhead.py`).

use std::hint::black_box;
use std::time::Instant;

use magbench_env::{MAX_AGENTS, Vec2};
use magbench_planners::motion::propagate_valid;
use pyo3::prelude::*;

use crate::arrays::{ArrayIn, check_duration, read_control, read_state};
use crate::errors::bad_arg;
use crate::scenario::Scenario;

/// Seconds per call of `op` (`propagate` or `motion_valid`) from `x0` under `u` for
/// `duration_s` on `scenario`, over `calls` calls made in Rust.
#[pyfunction]
pub fn rust_call_cost(
    py: Python<'_>,
    scenario: &Scenario,
    op: &str,
    x0: ArrayIn,
    u: ArrayIn,
    duration_s: f64,
    calls: u32,
) -> PyResult<f64> {
    let n = scenario.agents();
    let mut start = [Vec2::zeros(); MAX_AGENTS];
    let x = x0.as_array();
    if x.ndim() != 1 {
        return Err(bad_arg(py, "x0", "expected one state"));
    }
    read_state(
        py,
        "x0",
        x.into_dimensionality().expect("one dimension"),
        &mut start[..n],
    )?;
    let uv = u.as_array();
    if uv.ndim() != 1 {
        return Err(bad_arg(py, "u", "expected one control"));
    }
    let u = read_control(py, "u", uv.into_dimensionality().expect("one dimension"))?;
    let d = check_duration(py, duration_s)?;
    let problem = &scenario.problem;
    let mut out = [Vec2::zeros(); MAX_AGENTS];
    let calls = calls.max(1);
    let t0 = Instant::now();
    match op {
        "propagate" => {
            for _ in 0..calls {
                problem.model.propagate(
                    black_box(&start[..n]),
                    black_box(&u),
                    black_box(d),
                    &mut out[..n],
                );
                black_box(&out);
            }
        }
        "motion_valid" => {
            for _ in 0..calls {
                black_box(propagate_valid(
                    problem,
                    black_box(&start[..n]),
                    black_box(&u),
                    black_box(d),
                    &mut out[..n],
                ));
            }
        }
        _ => return Err(bad_arg(py, "op", "propagate or motion_valid")),
    }
    Ok(t0.elapsed().as_secs_f64() / calls as f64)
}

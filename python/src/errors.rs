//! Python exceptions for magbench's errors, and the guard that turns a Rust panic into one.

use std::panic::{AssertUnwindSafe, catch_unwind};

use magbench::Error;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    magbench,
    InputError,
    PyValueError,
    "Bad input (a scenario, plan, experiment or preset file, or an argument): `file`, `field` and `reason` say which and why; the message is the command line's `FILE: FIELD: REASON`."
);
pyo3::create_exception!(
    magbench,
    MagbenchError,
    PyRuntimeError,
    "A failure that is not bad input (I/O, an invalid plan from a planner, an internal error)."
);

/// The `InputError` exception of `e`, with its `file`, `field` and `reason` attributes.
pub fn input_error(py: Python<'_>, e: &magbench_env::InputError) -> PyErr {
    let err = InputError::new_err(e.to_string());
    let value = err.value(py);
    // setting attributes on a fresh exception instance does not fail
    let _ = value.setattr("file", &e.file);
    let _ = value.setattr("field", &e.field);
    let _ = value.setattr("reason", &e.reason);
    err
}

/// An `InputError` built from its parts (for arguments checked by the binding itself).
pub fn bad_arg(py: Python<'_>, field: &str, reason: impl Into<String>) -> PyErr {
    input_error(
        py,
        &magbench_env::InputError::new("<python>", field, reason),
    )
}

/// The Python exception of a command error.
pub fn cli_error(py: Python<'_>, e: Error) -> PyErr {
    match e {
        Error::Input(e) => input_error(py, &e),
        Error::Failed(m) => MagbenchError::new_err(m),
    }
}

/// Runs `f`, turning a panic into `MagbenchError` naming `what`, so that no Rust panic reaches
/// the interpreter.
pub fn guarded<T>(what: &str, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let msg = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("unknown panic");
            Err(MagbenchError::new_err(format!(
                "internal error in {what}: {msg}"
            )))
        }
    }
}

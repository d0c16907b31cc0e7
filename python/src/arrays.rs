//! numpy arrays in and out: a state is `[x0, y0, x1, y1, …]` (BL), a control is
//! `[theta_rad, alpha_rad, grad_x_t_per_m, grad_y_t_per_m]`, as in plan CSV files. A batch is
//! a 2-D array with one of them per row.

use magbench_env::{Control, Vec2};
use numpy::ndarray::{Array2, ArrayView1, ArrayView2, ArrayViewD, Ix1, Ix2};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors::bad_arg;

/// Any array-like of floats (numpy array, list, nested list). A float64 numpy array is read
/// in place; anything else is converted by numpy first.
pub enum ArrayIn<'py> {
    /// A float64 numpy array, read in place.
    Direct(Bound<'py, PyArrayDyn<f64>>),
    /// Any other array-like, converted to a float64 array.
    Converted(PyArrayLikeDyn<'py, f64, AllowTypeChange>),
}

impl<'a, 'py> FromPyObject<'a, 'py> for ArrayIn<'py> {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(a) = ob.cast::<PyArrayDyn<f64>>() {
            return Ok(ArrayIn::Direct(a.to_owned()));
        }
        Ok(ArrayIn::Converted(ob.extract()?))
    }
}

impl ArrayIn<'_> {
    /// A view of the numbers.
    pub fn as_array(&self) -> ArrayViewD<'_, f64> {
        match self {
            // SAFETY: the view is read while the GIL is held and no Python code runs (the
            // operations never call into Python or release the GIL while they read it), so
            // nothing can write the array meanwhile. This skips numpy's borrow tracking,
            // which costs about 0.5 µs per array.
            ArrayIn::Direct(a) => unsafe { a.as_array() },
            ArrayIn::Converted(a) => a.as_array(),
        }
    }
}

/// Numbers in a control.
pub const CONTROL_LEN: usize = 4;

/// The names of a control's components.
pub const CONTROL_NAMES: [&str; CONTROL_LEN] =
    ["theta_rad", "alpha_rad", "grad_x_t_per_m", "grad_y_t_per_m"];

/// The longest duration one call may propagate (s): a plan file's longest plan.
pub const MAX_DURATION_S: f64 = magbench_trackers::plan_file::MAX_PLAN_DURATION_S;

/// The names of a state's components for `agents` agents.
pub fn state_names(agents: usize) -> Vec<String> {
    (0..agents)
        .flat_map(|i| [format!("x{i}"), format!("y{i}")])
        .collect()
}

/// One row or a batch of rows.
pub enum Rows<'a> {
    /// A single vector.
    One(ArrayView1<'a, f64>),
    /// One vector per row.
    Many(ArrayView2<'a, f64>),
}

impl<'a> Rows<'a> {
    /// `a` as a vector of `width` numbers or an (n × `width`) batch; `what` names it in errors.
    pub fn new(
        py: Python<'_>,
        what: &str,
        a: ArrayViewD<'a, f64>,
        width: usize,
        unit: &str,
    ) -> PyResult<Self> {
        let shape = a.shape().to_vec();
        let bad = || {
            bad_arg(
                py,
                what,
                format!(
                    "expected {width} numbers ({unit}) or an (n, {width}) array, got shape {shape:?}"
                ),
            )
        };
        match a.ndim() {
            1 if shape[0] == width => Ok(Rows::One(
                a.into_dimensionality::<Ix1>().map_err(|_| bad())?,
            )),
            2 if shape[1] == width => Ok(Rows::Many(
                a.into_dimensionality::<Ix2>().map_err(|_| bad())?,
            )),
            _ => Err(bad()),
        }
    }

    /// The number of rows of a batch.
    pub fn batch(&self) -> Option<usize> {
        match self {
            Rows::One(_) => None,
            Rows::Many(m) => Some(m.nrows()),
        }
    }

    /// Row `i` (the single vector for every `i`).
    pub fn row(&self, i: usize) -> ArrayView1<'_, f64> {
        match self {
            Rows::One(v) => v.view(),
            Rows::Many(m) => m.row(i),
        }
    }
}

/// Durations: one number for every row, or one per row.
pub enum Durations<'a> {
    /// The same duration for every row.
    One(f64),
    /// One duration per row.
    Many(ArrayView1<'a, f64>),
}

impl Durations<'_> {
    /// The number of rows of a batch.
    pub fn batch(&self) -> Option<usize> {
        match self {
            Durations::One(_) => None,
            Durations::Many(v) => Some(v.len()),
        }
    }

    /// Duration `i`, checked: finite, at least 0, at most [`MAX_DURATION_S`].
    pub fn get(&self, py: Python<'_>, i: usize) -> PyResult<f64> {
        let d = match self {
            Durations::One(d) => *d,
            Durations::Many(v) => v[i],
        };
        check_duration(py, d)
    }
}

/// A duration, checked: finite, at least 0, at most [`MAX_DURATION_S`].
#[inline]
pub fn check_duration(py: Python<'_>, d: f64) -> PyResult<f64> {
    if d.is_finite() && (0.0..=MAX_DURATION_S).contains(&d) {
        Ok(d)
    } else {
        Err(bad_arg(
            py,
            "duration_s",
            format!("must be in [0, {MAX_DURATION_S}] s, got {d}"),
        ))
    }
}

/// The common batch size of the arguments, if any is a batch; differing sizes are an error.
pub fn batch_size(py: Python<'_>, sizes: &[(&str, Option<usize>)]) -> PyResult<Option<usize>> {
    let mut n: Option<(&str, usize)> = None;
    for (what, s) in sizes {
        if let Some(s) = *s {
            match n {
                Some((first, m)) if m != s => {
                    return Err(bad_arg(py, what, format!("{s} rows, but {first} has {m}")));
                }
                _ => n = Some((what, s)),
            }
        }
    }
    Ok(n.map(|(_, s)| s))
}

/// Reads a state of `out.len()` agents from `row` into `out`; `what` names it in errors.
#[inline]
pub fn read_state(
    py: Python<'_>,
    what: &str,
    row: ArrayView1<f64>,
    out: &mut [Vec2],
) -> PyResult<()> {
    let n = out.len();
    if row.len() != 2 * n {
        return Err(bad_arg(
            py,
            what,
            format!(
                "a state of {n} agents has {} numbers (x, y per agent), got {}",
                2 * n,
                row.len()
            ),
        ));
    }
    for (i, p) in out.iter_mut().enumerate() {
        let (x, y) = (row[2 * i], row[2 * i + 1]);
        if !(x.is_finite() && y.is_finite()) {
            return Err(bad_arg(
                py,
                what,
                format!("agent {i}'s position ({x}, {y}) is not finite"),
            ));
        }
        *p = Vec2::new(x, y);
    }
    Ok(())
}

/// Reads a control from `row`; `what` names it in errors.
#[inline]
pub fn read_control(py: Python<'_>, what: &str, row: ArrayView1<f64>) -> PyResult<Control> {
    if row.len() != CONTROL_LEN {
        return Err(bad_arg(
            py,
            what,
            format!(
                "a control has {CONTROL_LEN} numbers ({}), got {}",
                CONTROL_NAMES.join(", "),
                row.len()
            ),
        ));
    }
    let u = Control {
        theta: row[0],
        alpha: row[1],
        grad: [row[2], row[3]],
    };
    if !u.is_finite() {
        return Err(bad_arg(
            py,
            what,
            format!("{:?} is not finite", [row[0], row[1], row[2], row[3]]),
        ));
    }
    Ok(u)
}

/// A state as a flat vector.
pub fn state_vec(s: &[Vec2]) -> Vec<f64> {
    s.iter().flat_map(|p| [p.x, p.y]).collect()
}

/// A control as a flat array.
pub fn control_arr(u: &Control) -> [f64; CONTROL_LEN] {
    [u.theta, u.alpha, u.grad[0], u.grad[1]]
}

/// A state as a numpy vector.
pub fn state_out<'py>(py: Python<'py>, s: &[Vec2]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, state_vec(s))
}

/// Rows of states as an (n × 2·agents) numpy array.
pub fn states_out<'py>(
    py: Python<'py>,
    rows: &[Vec<Vec2>],
    agents: usize,
) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.iter().flat_map(|s| state_vec(s)).collect();
    let a = Array2::from_shape_vec((rows.len(), 2 * agents), flat).expect("rows of one width");
    PyArray2::from_owned_array(py, a)
}

/// Controls as an (n × 4) numpy array.
pub fn controls_out<'py>(py: Python<'py>, us: &[Control]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = us.iter().flat_map(control_arr).collect();
    let a = Array2::from_shape_vec((us.len(), CONTROL_LEN), flat).expect("rows of one width");
    PyArray2::from_owned_array(py, a)
}

//! `magbench.Reference`: what a Python tracker's `reset(problem, plan)` receives as `plan`. It
//! offers what `magbench.Plan` offers (the plan's `states`, `controls`, `durations`,
//! `duration`, `len`) and the reference the tracking loop follows: the plan resampled at every
//! integration step (`t`, `samples`, `sample_controls`), then, when the plan ends in the goal
//! region, a settle segment onto the goal's centre (`plan_end` is where the plan proper ends).

use magbench_trackers::reference::Reference as RustReference;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::{control_arr, controls_out, state_vec};

/// The plan a tracker follows, and its resampling. Its arrays are made once per reset and
/// shared by every access.
#[pyclass(module = "magbench", name = "Reference", frozen)]
pub struct Reference {
    states: Py<PyArray2<f64>>,
    controls: Py<PyArray2<f64>>,
    durations: Py<PyArray1<f64>>,
    t: Py<PyArray1<f64>>,
    samples: Py<PyArray2<f64>>,
    sample_controls: Py<PyArray2<f64>>,
    duration: f64,
    plan_end: usize,
    edges: usize,
    len: usize,
}

impl Reference {
    /// The Python view of `r`.
    pub fn of(py: Python<'_>, r: &RustReference) -> PyResult<Reference> {
        let n = r.agents();
        let rows = |flat: Vec<f64>, width: usize| -> PyResult<Py<PyArray2<f64>>> {
            let k = flat.len() / width.max(1);
            let a = numpy::ndarray::Array2::from_shape_vec((k, width), flat)
                .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
            Ok(PyArray2::from_owned_array(py, a).unbind())
        };
        let nodes: Vec<f64> = (0..r.nodes()).flat_map(|j| state_vec(r.node(j))).collect();
        let edges = r.plan_edges();
        let controls: Vec<_> = edges.iter().map(|(u, _)| *u).collect();
        let durations: Vec<f64> = edges.iter().map(|(_, d)| *d).collect();
        let k = r.len();
        let samples: Vec<f64> = (0..k).flat_map(|i| state_vec(r.state(i))).collect();
        let sample_controls: Vec<f64> = (0..k)
            .flat_map(|i| r.control(i).map_or([f64::NAN; 4], control_arr))
            .collect();
        Ok(Reference {
            states: rows(nodes, 2 * n)?,
            controls: controls_out(py, &controls).unbind(),
            duration: durations.iter().sum(),
            durations: PyArray1::from_vec(py, durations).unbind(),
            t: PyArray1::from_vec(py, (0..k).map(|i| r.time(i)).collect()).unbind(),
            samples: rows(samples, 2 * n)?,
            sample_controls: rows(sample_controls, 4)?,
            plan_end: r.plan_end(),
            edges: edges.len(),
            len: k,
        })
    }
}

#[pymethods]
impl Reference {
    /// The plan's waypoints, (m+1, 2·agents), as `Plan.states`.
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.states.bind(py).clone()
    }

    /// The controls of the plan's edges, (m, 4), as `Plan.controls`.
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.controls.bind(py).clone()
    }

    /// The durations of the plan's edges (s), (m,), as `Plan.durations`.
    #[getter]
    fn durations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.durations.bind(py).clone()
    }

    /// The plan's total duration (s), as `Plan.duration`.
    #[getter]
    fn duration(&self) -> f64 {
        self.duration
    }

    /// Times of the resampled reference (s), (k,): 0, every integration step of each edge, each
    /// edge's end, then the settle segment's.
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.t.bind(py).clone()
    }

    /// The team at each time of `t`, (k, 2·agents).
    #[getter]
    fn samples<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.samples.bind(py).clone()
    }

    /// The plan's control in force after each sample, (k, 4): NaN rows from `plan_end` on.
    #[getter]
    fn sample_controls<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.sample_controls.bind(py).clone()
    }

    /// Index in `t` of the plan's end: later samples are the settle segment onto the goal.
    #[getter]
    fn plan_end(&self) -> usize {
        self.plan_end
    }

    /// The number of the plan's edges, as `len(plan)`.
    fn __len__(&self) -> usize {
        self.edges
    }

    fn __repr__(&self) -> String {
        format!(
            "Reference({} edges, {:.3} s, {} samples)",
            self.edges, self.duration, self.len
        )
    }
}

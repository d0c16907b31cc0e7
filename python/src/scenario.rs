//! `magbench.Scenario`: a scenario and the operations of one of its legs, as the planners see
//! them (the default planning setup of `magbench plan`).

use std::sync::Arc;

use magbench_env::coil::Planar;
use magbench_env::{Control, MAX_AGENTS, Vec2};
use magbench_planners::motion::{propagate_valid, random_control, random_elevated_control};
use magbench_planners::{PlanningSetup, Problem, Rng};
use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2};
use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use rand::SeedableRng;

use crate::arrays::{
    ArrayIn, CONTROL_LEN, CONTROL_NAMES, Durations, Rows, batch_size, check_duration, control_arr,
    read_control, read_state, state_names, state_out,
};
use crate::errors::{bad_arg, guarded, input_error};

/// A scenario (a built-in name or a TOML file) and the operations of one leg.
///
/// States are numpy vectors `[x0, y0, x1, y1, …]` in body lengths; controls are
/// `[theta_rad, alpha_rad, grad_x_t_per_m, grad_y_t_per_m]`. The batched forms take an
/// (n, d) array (or one row for every row of another argument) and return one result per row.
#[pyclass(module = "magbench", frozen, subclass)]
pub struct Scenario {
    /// The scenario, when loaded (a plugin's problem has only the leg's operations).
    pub scenario: Option<Arc<magbench_env::Scenario>>,
    /// The leg whose operations these are.
    pub leg: usize,
    /// The leg's planning problem under the default setup.
    pub problem: Problem,
    /// The setup the problem was made under.
    pub setup: PlanningSetup,
    /// Whether planners may tilt the field out of the plane here (`planar = auto`).
    pub elevation_free: bool,
}

impl Scenario {
    /// The number of agents.
    pub fn agents(&self) -> usize {
        self.problem.agents()
    }

    /// The loaded scenario; a plugin's problem has none.
    pub fn full(&self, py: Python<'_>) -> PyResult<&Arc<magbench_env::Scenario>> {
        self.scenario.as_ref().ok_or_else(|| {
            bad_arg(
                py,
                "scenario",
                "a plugin's problem is not a loaded scenario: use magbench.Scenario.load",
            )
        })
    }

    /// A view of one planning problem (a plugin's): its operations, without the scenario.
    pub fn of_problem(problem: Problem, elevation_free: bool) -> Scenario {
        Scenario {
            scenario: None,
            leg: 0,
            problem,
            setup: PlanningSetup::default(),
            elevation_free,
        }
    }
}

/// A duration argument as given: a number, or an array of one per row.
enum DurIn<'py> {
    Scalar(f64),
    Arr(ArrayIn<'py>),
}

impl<'py> DurIn<'py> {
    /// Reads `d`: a float is the fast path.
    fn new(d: &Bound<'py, PyAny>) -> PyResult<Self> {
        match d.extract::<f64>() {
            Ok(v) => Ok(DurIn::Scalar(v)),
            Err(_) => Ok(DurIn::Arr(d.extract::<ArrayIn>()?)),
        }
    }

    /// The durations, one for all rows or one per row.
    fn view(&self, py: Python<'_>) -> PyResult<Durations<'_>> {
        match self {
            DurIn::Scalar(v) => Ok(Durations::One(*v)),
            DurIn::Arr(a) => {
                let v = a.as_array();
                match v.ndim() {
                    0 => Ok(Durations::One(v.iter().next().copied().unwrap_or(f64::NAN))),
                    1 => Ok(Durations::Many(
                        v.into_dimensionality().expect("one dimension"),
                    )),
                    _ => Err(bad_arg(
                        py,
                        "duration_s",
                        format!("expected a number or a vector, got shape {:?}", v.shape()),
                    )),
                }
            }
        }
    }
}

#[pymethods]
impl Scenario {
    /// Loads a built-in scenario by name, or a scenario file by path; `leg` picks the leg whose
    /// goal, map and checks the operations use. Bad input raises `InputError`.
    #[staticmethod]
    #[pyo3(signature = (name_or_path, leg = 0))]
    pub fn load(py: Python<'_>, name_or_path: &str, leg: usize) -> PyResult<Scenario> {
        guarded("Scenario.load", || {
            let s = magbench_env::Scenario::load(name_or_path).map_err(|e| input_error(py, &e))?;
            if leg >= s.legs.len() {
                return Err(bad_arg(
                    py,
                    "leg",
                    format!(
                        "scenario {} has {} leg(s), got leg {leg}",
                        s.name,
                        s.legs.len()
                    ),
                ));
            }
            let setup = PlanningSetup::default();
            let problem = setup.problem(&s, leg, None, 0);
            let elevation_free = setup.elevation(&s, Planar::Auto).0;
            Ok(Scenario {
                scenario: Some(Arc::new(s)),
                leg,
                problem,
                setup,
                elevation_free,
            })
        })
    }

    /// The scenario's name.
    #[getter]
    fn name(&self) -> &str {
        &self.problem.scenario
    }

    /// Where it came from (a path, or `built-in:NAME`).
    #[getter]
    fn source(&self) -> Option<&str> {
        self.scenario.as_ref().map(|s| s.source.as_str())
    }

    /// Its description.
    #[getter]
    fn description(&self) -> Option<&str> {
        self.scenario.as_ref().map(|s| s.description.as_str())
    }

    /// The leg whose operations these are (0-based).
    #[getter]
    fn leg(&self) -> usize {
        self.leg
    }

    /// The number of legs (1 for a plugin's problem).
    #[getter]
    pub fn legs(&self) -> usize {
        self.scenario.as_ref().map_or(1, |s| s.legs.len())
    }

    /// The number of agents.
    #[getter(agents)]
    fn agents_py(&self) -> usize {
        self.agents()
    }

    /// The start state (of the leg, for a plugin's problem).
    #[getter]
    fn start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        state_out(py, &self.problem.start)
    }

    /// The leg's goal centres, as a state.
    #[getter]
    fn goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        state_out(py, &self.problem.goal.agents)
    }

    /// The radius of each agent's goal disk (BL).
    #[getter]
    fn goal_tolerance(&self) -> f64 {
        self.problem.goal.tolerance
    }

    /// The world's width and height (BL); positions are in [0, width] × [0, height].
    #[getter]
    fn bounds(&self) -> (f64, f64) {
        (self.problem.world.width, self.problem.world.height)
    }

    /// What each state component is: `x0, y0, x1, y1, …` (BL).
    #[getter]
    fn state_names(&self) -> Vec<String> {
        state_names(self.agents())
    }

    /// What each control component is.
    #[getter]
    fn control_names(&self) -> Vec<&'static str> {
        CONTROL_NAMES.to_vec()
    }

    /// Edge durations of a plan are whole multiples of this (s): one camera frame.
    #[getter]
    fn control_period(&self) -> f64 {
        self.problem.control_period
    }

    /// The largest gradient command along x or y (T/m).
    #[getter]
    fn gradient_limit(&self) -> f64 {
        self.problem.model.coil.gradient_limit()
    }

    /// Whether plans may tilt the field out of the plane (alpha > 0) here.
    #[getter]
    fn elevation_free(&self) -> bool {
        self.elevation_free
    }

    /// The largest field elevation a plan may command when it is free (rad).
    #[getter]
    fn alpha_max(&self) -> f64 {
        self.problem.alpha_max
    }

    /// The state after holding control `u` for `duration_s` from `x0`, by the planning model
    /// (the exact pair flow or RK4). Batched: `x0` (n, d), `u` (n, 4) and/or `duration_s` (n,)
    /// give an (n, d) array.
    fn propagate<'py>(
        &self,
        py: Python<'py>,
        x0: ArrayIn<'py>,
        u: ArrayIn<'py>,
        duration_s: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let model = &self.problem.model;
        let (rows, _, ends) =
            self.each_motion(py, x0, u, duration_s, "propagate", true, |s, u, d, out| {
                model.propagate(s, u, d, out);
                true
            })?;
        let n = self.agents();
        Ok(match rows {
            None => PyArray1::from_vec(py, ends).into_any(),
            Some(rows) => {
                let a = Array2::from_shape_vec((rows, 2 * n), ends).expect("rows of one width");
                PyArray2::from_owned_array(py, a).into_any()
            }
        })
    }

    /// Whether a state is valid: every agent inside the world and clear of obstacles, every
    /// pair's separation inside the proximity range. Batched: an (n, d) array gives n answers.
    fn is_valid<'py>(&self, py: Python<'py>, x: ArrayIn<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = &self.problem.world;
        let inside = |p: &Vec2| w.contains(*p);
        self.per_state(py, x, "x", |s| {
            s.iter().all(inside) && self.problem.checker.is_valid(s)
        })
    }

    /// Whether a state is inside the leg's goal region. Batched like `is_valid`.
    fn in_goal<'py>(&self, py: Python<'py>, x: ArrayIn<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.per_state(py, x, "x", |s| self.problem.goal.contains(s))
    }

    /// The largest agent distance from its goal centre (BL). Batched like `is_valid`.
    fn goal_distance<'py>(&self, py: Python<'py>, x: ArrayIn<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.per_state(py, x, "x", |s| self.problem.goal.distance(s))
    }

    /// Whether the motion from `x0` under `u` for `duration_s` is valid all along: the edge
    /// check the planners use (the exact pair motion's separation range and obstacle
    /// clearance, or every RK4 sample's). With `return_state=True`, `(valid, end_state)` (the
    /// end state is the first invalid sample of an RK4 motion). Batched like `propagate`.
    #[pyo3(signature = (x0, u, duration_s, return_state = false))]
    fn motion_valid<'py>(
        &self,
        py: Python<'py>,
        x0: ArrayIn<'py>,
        u: ArrayIn<'py>,
        duration_s: &Bound<'py, PyAny>,
        return_state: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let problem = &self.problem;
        let (rows, oks, ends) = self.each_motion(
            py,
            x0,
            u,
            duration_s,
            "motion_valid",
            return_state,
            |s, u, d, out| propagate_valid(problem, s, u, d, out),
        )?;
        let n = self.agents();
        match rows {
            None if return_state => (oks[0], PyArray1::from_vec(py, ends)).into_bound_py_any(py),
            None => oks[0].into_bound_py_any(py),
            Some(rows) => {
                let valid = PyArray1::from_vec(py, oks);
                if return_state {
                    let a = Array2::from_shape_vec((rows, 2 * n), ends).expect("rows of one width");
                    (valid, PyArray2::from_owned_array(py, a)).into_bound_py_any(py)
                } else {
                    Ok(valid.into_any())
                }
            }
        }
    }

    /// A random admissible control from a random stream seeded by `rng_seed`: θ_B uniform in
    /// [−π, π), each gradient uniform in [−G, G], and α uniform in [0, alpha_max] where the
    /// elevation is free (0 otherwise). With `n`, an (n, 4) array of such controls.
    #[pyo3(signature = (rng_seed, n = None))]
    fn sample_control<'py>(
        &self,
        py: Python<'py>,
        rng_seed: u64,
        n: Option<usize>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut rng = Rng::seed_from_u64(rng_seed);
        let g = self.problem.model.coil.gradient_limit();
        let mut draw = || {
            control_arr(&if self.elevation_free {
                random_elevated_control(&mut rng, g, self.problem.alpha_max)
            } else {
                random_control(&mut rng, g)
            })
        };
        match n {
            None => Ok(PyArray1::from_vec(py, draw().to_vec()).into_any()),
            Some(n) if n <= 10_000_000 => {
                let flat: Vec<f64> = (0..n).flat_map(|_| draw()).collect();
                let a = Array2::from_shape_vec((n, CONTROL_LEN), flat).expect("rows of one width");
                Ok(PyArray2::from_owned_array(py, a).into_any())
            }
            Some(n) => Err(bad_arg(
                py,
                "n",
                format!("at most 10000000 controls, got {n}"),
            )),
        }
    }

    /// A check of a duration argument, as the operations check it (for plugins).
    #[staticmethod]
    fn check_duration(py: Python<'_>, duration_s: f64) -> PyResult<f64> {
        check_duration(py, duration_s)
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario({:?}, agents={}, leg={} of {})",
            self.problem.scenario,
            self.agents(),
            self.leg,
            self.legs()
        )
    }
}

impl Scenario {
    /// `f` of one state, or of every row of a batch (a numpy vector of answers).
    fn per_state<'py, T>(
        &self,
        py: Python<'py>,
        x: ArrayIn<'py>,
        what: &str,
        f: impl Fn(&[Vec2]) -> T,
    ) -> PyResult<Bound<'py, PyAny>>
    where
        T: numpy::Element + IntoPyObject<'py>,
    {
        let n = self.agents();
        let mut buf = [Vec2::zeros(); MAX_AGENTS];
        match Rows::new(py, what, x.as_array(), 2 * n, "x, y per agent")? {
            Rows::One(v) => {
                read_state(py, what, v, &mut buf[..n])?;
                f(&buf[..n]).into_bound_py_any(py)
            }
            Rows::Many(m) => {
                let mut out = Vec::with_capacity(m.nrows());
                for row in m.rows() {
                    read_state(py, what, row, &mut buf[..n])?;
                    out.push(f(&buf[..n]));
                }
                Ok(PyArray1::from_vec(py, out).into_any())
            }
        }
    }

    /// `motion` (from a start, under a control, for a duration, into an end state) of one
    /// (x0, u, duration_s) or of every row of a batch: the rows (`None` for one motion), each
    /// motion's flag and, with `keep_ends`, the end states flattened (`2n` numbers a row).
    #[allow(clippy::too_many_arguments)]
    fn each_motion<'py>(
        &self,
        py: Python<'py>,
        x0: ArrayIn<'py>,
        u: ArrayIn<'py>,
        duration_s: &Bound<'py, PyAny>,
        what: &str,
        keep_ends: bool,
        mut motion: impl FnMut(&[Vec2], &Control, f64, &mut [Vec2]) -> bool,
    ) -> PyResult<(Option<usize>, Vec<bool>, Vec<f64>)> {
        let n = self.agents();
        let xs = Rows::new(py, "x0", x0.as_array(), 2 * n, "x, y per agent")?;
        let us = Rows::new(py, "u", u.as_array(), CONTROL_LEN, "a control")?;
        let d_in = DurIn::new(duration_s)?;
        let ds = d_in.view(py)?;
        let rows = batch_size(
            py,
            &[
                ("x0", xs.batch()),
                ("u", us.batch()),
                ("duration_s", ds.batch()),
            ],
        )?;
        let count = rows.unwrap_or(1);
        let mut start = [Vec2::zeros(); MAX_AGENTS];
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let mut flags = Vec::with_capacity(count);
        let mut ends = Vec::with_capacity(if keep_ends { count * 2 * n } else { 0 });
        guarded(what, || {
            for i in 0..count {
                if i == 0 || xs.batch().is_some() {
                    read_state(py, "x0", xs.row(i), &mut start[..n])?;
                }
                let u = read_control(py, "u", us.row(i))?;
                let d = ds.get(py, i)?;
                flags.push(motion(&start[..n], &u, d, &mut out[..n]));
                if keep_ends {
                    ends.extend(out[..n].iter().flat_map(|p| [p.x, p.y]));
                }
            }
            Ok(())
        })?;
        Ok((rows, flags, ends))
    }
}

//! `magbench.Plan`: states, controls and durations as numpy arrays, with what the planner
//! reported when a planner made it.

use std::path::PathBuf;

use magbench_env::model::Flow;
use magbench_env::{Control, Vec2};
use magbench_planners::PlannerResult;
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{ArrayIn, CONTROL_LEN, Rows, controls_out, read_control, states_out};
use crate::errors::{bad_arg, input_error};
use crate::scenario::Scenario;

/// A plan: `states[0]` is the start, and `controls[i]` held for `durations[i]` seconds takes
/// `states[i]` to `states[i + 1]` under the planning model.
#[pyclass(module = "magbench", name = "Plan")]
#[derive(Clone)]
pub struct Plan {
    /// The plan.
    pub plan: magbench_planners::Plan,
    /// The planner's result (without its plan), when a planner made it.
    pub result: Option<PlannerResult>,
    /// Why the planner stopped unsolved, when it said.
    pub stop_reason: Option<String>,
    /// The planner's name, when a planner made it.
    pub planner: Option<String>,
    /// The scenario it was made for, when known.
    pub scenario: Option<String>,
}

impl Plan {
    /// A plan made by `planner` for `scenario`.
    pub fn from_result(mut result: PlannerResult, planner: &str, scenario: &str) -> Plan {
        let plan = std::mem::take(&mut result.plan);
        Plan {
            plan,
            result: Some(result),
            stop_reason: None,
            planner: Some(planner.to_string()),
            scenario: Some(scenario.to_string()),
        }
    }

    /// A plan built from the numbers of a Python plan (states (k+1, d), controls (k, 4),
    /// durations (k,)); `source` names it in errors.
    pub fn from_arrays(
        py: Python<'_>,
        states: ArrayIn,
        controls: ArrayIn,
        durations: ArrayIn,
        flow: &str,
        alpha_max: Option<f64>,
    ) -> PyResult<magbench_planners::Plan> {
        let flow = Flow::from_name(flow)
            .ok_or_else(|| bad_arg(py, "flow", format!("pair-exact or rk4, got {flow:?}")))?;
        let s = states.as_array();
        if s.ndim() != 2 || s.shape()[1] % 2 != 0 || s.shape()[0] == 0 || s.shape()[1] == 0 {
            return Err(bad_arg(
                py,
                "states",
                format!(
                    "expected a (k+1, 2·agents) array, got shape {:?}",
                    s.shape()
                ),
            ));
        }
        let agents = s.shape()[1] / 2;
        let k = s.shape()[0] - 1;
        let mut out_states = Vec::with_capacity(k + 1);
        for (i, row) in s.outer_iter().enumerate() {
            let mut st = vec![Vec2::zeros(); agents];
            crate::arrays::read_state(
                py,
                &format!("states[{i}]"),
                row.into_dimensionality().expect("a row"),
                &mut st,
            )?;
            out_states.push(st);
        }
        let c = controls.as_array();
        let c_ok = (c.ndim() == 2 && c.shape()[1] == CONTROL_LEN && c.shape()[0] == k)
            || (k == 0 && c.is_empty());
        if !c_ok {
            return Err(bad_arg(
                py,
                "controls",
                format!(
                    "expected a ({k}, {CONTROL_LEN}) array for {} states, got shape {:?}",
                    k + 1,
                    c.shape()
                ),
            ));
        }
        let mut out_controls: Vec<Control> = Vec::with_capacity(k);
        if k > 0 {
            if let Rows::Many(m) = Rows::new(py, "controls", c, CONTROL_LEN, "a control per row")? {
                for (i, row) in m.rows().into_iter().enumerate() {
                    out_controls.push(read_control(py, &format!("controls[{i}]"), row)?);
                }
            }
        }
        let d = durations.as_array();
        if !(d.ndim() == 1 && d.len() == k || k == 0 && d.is_empty()) {
            return Err(bad_arg(
                py,
                "durations",
                format!("expected {k} durations, got shape {:?}", d.shape()),
            ));
        }
        let out_durations: Vec<f64> = d.iter().copied().collect();
        if let Some((i, v)) = out_durations
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(bad_arg(
                py,
                &format!("durations[{i}]"),
                format!("must be finite and at least 0, got {v}"),
            ));
        }
        if let Some(a) = alpha_max {
            if !(a.is_finite() && (0.0..=std::f64::consts::FRAC_PI_2).contains(&a)) {
                return Err(bad_arg(
                    py,
                    "alpha_max",
                    format!("must be in [0, π/2] rad, got {a}"),
                ));
            }
        }
        Ok(magbench_planners::Plan {
            flow,
            alpha_max,
            states: out_states,
            controls: out_controls,
            durations: out_durations,
            made_for: None,
        })
    }
}

#[pymethods]
impl Plan {
    /// A plan built in Python: `states` (k+1, 2·agents), `controls` (k, 4), `durations` (k,)
    /// in seconds; `flow` is how the planning model solves its edges (`pair-exact` or `rk4`),
    /// `alpha_max` the largest elevation it may command (rad) when the elevation is free.
    #[new]
    #[pyo3(signature = (states, controls, durations, *, flow = "pair-exact", alpha_max = None))]
    fn new(
        py: Python<'_>,
        states: ArrayIn,
        controls: ArrayIn,
        durations: ArrayIn,
        flow: &str,
        alpha_max: Option<f64>,
    ) -> PyResult<Plan> {
        Ok(Plan {
            plan: Plan::from_arrays(py, states, controls, durations, flow, alpha_max)?,
            result: None,
            stop_reason: None,
            planner: None,
            scenario: None,
        })
    }

    /// Reads a plan file (JSON, as written by `save`, `magbench plan --out` or `track --out`)
    /// for `scenario`'s team. Bad files raise `InputError`.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf, scenario: &Scenario) -> PyResult<Plan> {
        let plan = magbench_trackers::plan_file::read_plan(&path, scenario.agents())
            .map_err(|e| input_error(py, &e))?;
        Ok(Plan {
            plan,
            result: None,
            stop_reason: None,
            planner: None,
            scenario: None,
        })
    }

    /// The waypoints, (k+1, 2·agents).
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        states_out(py, &self.plan.states, self.plan.states[0].len())
    }

    /// The controls of the edges, (k, 4).
    #[getter]
    fn controls<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        controls_out(py, &self.plan.controls)
    }

    /// The durations of the edges (s), (k,).
    #[getter]
    fn durations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.plan.durations)
    }

    /// The flow its edges are solved with (`pair-exact` or `rk4`).
    #[getter]
    fn flow(&self) -> &'static str {
        self.plan.flow.name()
    }

    /// Whether the plan reaches the goal region: the planner's word, or `None` for a plan
    /// built in Python.
    #[getter]
    fn solved(&self) -> Option<bool> {
        self.result.as_ref().map(|r| r.solved)
    }

    /// The planner that made it, if any.
    #[getter]
    fn planner(&self) -> Option<&str> {
        self.planner.as_deref()
    }

    /// The scenario it was made for, if known.
    #[getter]
    fn scenario(&self) -> Option<&str> {
        self.scenario.as_deref()
    }

    /// Total duration (s).
    #[getter]
    fn duration(&self) -> f64 {
        self.plan.duration()
    }

    /// What the planner reported (iterations, nodes, time_s, cost, goal_distance,
    /// first_solution_iteration, first_solution_time_s, and stop_reason: why it stopped
    /// unsolved, when it said, else `None`), or `None` for a plan built in Python.
    #[getter]
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(r) = &self.result else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("solved", r.solved)?;
        d.set_item("approximate", r.approximate)?;
        d.set_item("iterations", r.iterations)?;
        d.set_item("nodes", r.nodes)?;
        d.set_item("time_s", r.time_s)?;
        d.set_item("cost", r.cost)?;
        d.set_item("goal_distance", r.goal_distance)?;
        d.set_item("first_solution_iteration", r.first_solution.map(|f| f.0))?;
        d.set_item("first_solution_time_s", r.first_solution.map(|f| f.1))?;
        d.set_item("stop_reason", self.stop_reason.as_deref())?;
        Ok(Some(d))
    }

    /// The planner's progress trace: a dict of numpy arrays `iteration`, `time_s`,
    /// `best_cost` (NaN before the first solution); empty arrays for a plan built in Python.
    #[getter]
    fn progress<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self
            .result
            .as_ref()
            .map(|r| r.progress.as_slice())
            .unwrap_or(&[]);
        let d = PyDict::new(py);
        d.set_item(
            "iteration",
            PyArray1::from_vec(py, p.iter().map(|q| q.iteration).collect()),
        )?;
        d.set_item(
            "time_s",
            PyArray1::from_vec(py, p.iter().map(|q| q.time_s).collect()),
        )?;
        d.set_item(
            "best_cost",
            PyArray1::from_vec(
                py,
                p.iter().map(|q| q.best_cost.unwrap_or(f64::NAN)).collect(),
            ),
        )?;
        Ok(d)
    }

    /// Writes the plan: CSV when `path` ends in `.csv`, else JSON (the plan file format that
    /// `magbench track --plan` and `Plan.load` read).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        let text = if path.extension().is_some_and(|e| e == "csv") {
            self.plan.to_csv()
        } else {
            magbench_trackers::plan_file::plan_json(&self.plan)
        };
        std::fs::write(&path, text)
            .map_err(|e| PyOSError::new_err(format!("{}: {e}", path.display())))
    }

    /// The number of edges.
    fn __len__(&self) -> usize {
        self.plan.edges()
    }

    fn __repr__(&self) -> String {
        format!(
            "Plan({} edges, {:.3} s{}{})",
            self.plan.edges(),
            self.plan.duration(),
            self.planner
                .as_ref()
                .map(|p| format!(", planner={p:?}"))
                .unwrap_or_default(),
            self.result
                .as_ref()
                .map(|r| format!(", solved={}", r.solved))
                .unwrap_or_default(),
        )
    }
}

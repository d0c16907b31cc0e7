//! Python classes as planners and trackers: Rust [`Planner`] and [`Tracker`] impls that hold
//! the class and take the GIL for each call into Python. They run inside the same harness as
//! the built-ins (timing, plan validation, results, plots). A Python exception becomes a panic
//! whose message is the exception's text: the sweep turns it into a failed run row, and the
//! module's functions into `MagbenchError`.
//!
//! The GIL lets one thread run Python at a time: a Python plugin's registry entry is serial, so
//! a sweep runs its runs one at a time (beside the Rust runs) and its report says so.

use std::collections::HashSet;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use magbench::Registry;
use magbench_env::coil::Planar;
use magbench_env::input::Rejection;
use magbench_env::params::{BadValue, ParamError, ParamInfo, ParamSet, Value};
use magbench_env::{Control, Vec2};
use magbench_planners::objective::objective_by_name;
use magbench_planners::registry::Entry as PlannerEntry;
use magbench_planners::{
    Distance, Limits, Planner, PlannerResult, PlanningSetup, Problem, ProgressPoint, plan_cost,
};
use magbench_trackers::registry::Entry as TrackerEntry;
use magbench_trackers::{Tick, Tracker, TrackerContext, TrackerStatus};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::arrays::{ArrayIn, read_control, state_vec};
use crate::errors::bad_arg;
use crate::plan::Plan;
use crate::scenario::Scenario;

/// The kind of a plugin parameter, from its default value in Python.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Real,
    Whole,
    Flag,
    Text,
}

/// One parameter of a plugin class: a keyword argument of its `__init__` with a default.
#[derive(Debug, Clone)]
struct ParamSpec {
    name: String,
    help: String,
    kind: Kind,
    default: String,
}

/// A registered Python class: its registry name, the class and its parameters.
#[derive(Clone)]
pub struct PluginClass {
    name: String,
    summary: String,
    cls: Arc<Py<PyAny>>,
    params: Arc<Vec<ParamSpec>>,
}

/// The Python plugins registered now (`magbench._plugins.snapshot()`): planners, trackers.
pub fn snapshot(py: Python<'_>) -> PyResult<(Vec<PluginClass>, Vec<PluginClass>)> {
    let snap = py.import("magbench._plugins")?.call_method0("snapshot")?;
    let (planners, trackers): (Vec<Bound<PyAny>>, Vec<Bound<PyAny>>) = snap.extract()?;
    let read = |items: Vec<Bound<PyAny>>| -> PyResult<Vec<PluginClass>> {
        items.into_iter().map(|t| plugin_class(py, &t)).collect()
    };
    Ok((read(planners)?, read(trackers)?))
}

/// One registered class as the snapshot gives it: name, class, summary, and each
/// parameter's name, default and help.
type Snapshot<'py> = (
    String,
    Bound<'py, PyAny>,
    String,
    Vec<(String, Bound<'py, PyAny>, String)>,
);

/// One `(name, cls, summary, [(param, default, help)…])` of the snapshot.
fn plugin_class(py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<PluginClass> {
    let (name, cls, summary, params): Snapshot = t.extract()?;
    let mut specs = vec![];
    for (p, default, help) in params {
        let (kind, text) = if default.is_instance_of::<pyo3::types::PyBool>() {
            (Kind::Flag, default.extract::<bool>()?.to_string())
        } else if default.is_instance_of::<pyo3::types::PyInt>() {
            match default.extract::<u64>() {
                Ok(n) => (Kind::Whole, n.to_string()),
                Err(_) => (Kind::Real, default.extract::<f64>()?.to_string()),
            }
        } else if default.is_instance_of::<pyo3::types::PyFloat>() {
            (Kind::Real, default.extract::<f64>()?.to_string())
        } else if default.is_instance_of::<pyo3::types::PyString>() {
            (Kind::Text, default.extract::<String>()?)
        } else {
            return Err(bad_arg(
                py,
                &format!("{name}.{p}"),
                "a plugin parameter's default must be a bool, int, float or str",
            ));
        };
        specs.push(ParamSpec {
            name: p,
            help,
            kind,
            default: text,
        });
    }
    Ok(PluginClass {
        name,
        summary,
        cls: Arc::new(cls.unbind()),
        params: Arc::new(specs),
    })
}

/// The built-in registry plus the registered Python plugins, whose runs go one at a time in a
/// sweep (they hold the GIL; the report says so).
pub fn registry(py: Python<'_>) -> PyResult<Registry> {
    let (planners, trackers) = snapshot(py)?;
    let mut reg = Registry::builtin();
    for c in planners {
        let summary = format!("{} (Python)", c.summary);
        let name = c.name.clone();
        let entry = PlannerEntry::new(&name, &summary, move || {
            Box::new(PyPlanner::new(c.clone())) as Box<dyn Planner>
        });
        reg.add_planner_entry(entry.serial())
            .map_err(|e| bad_arg(py, "planner", format!("{name}: {e}")))?;
    }
    for c in trackers {
        let summary = format!("{} (Python)", c.summary);
        let name = c.name.clone();
        let entry = TrackerEntry::new(&name, &summary, move || {
            Box::new(PyTracker::new(c.clone())) as Box<dyn Tracker>
        });
        reg.add_tracker_entry(entry.serial())
            .map_err(|e| bad_arg(py, "tracker", format!("{name}: {e}")))?;
    }
    Ok(reg)
}

/// `text` as a `&'static str`, each distinct text leaked once (parameter values of plugins).
fn intern(text: &str) -> &'static str {
    static SEEN: OnceLock<Mutex<HashSet<&'static str>>> = OnceLock::new();
    let mut seen = SEEN
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    match seen.get(text) {
        Some(s) => s,
        None => {
            let s: &'static str = Box::leak(text.to_string().into_boxed_str());
            seen.insert(s);
            s
        }
    }
}

/// A plugin's parameter values (text, checked by kind) and the Python objects they become.
#[derive(Clone)]
struct Values {
    class: PluginClass,
    values: Vec<String>,
}

impl Values {
    fn new(class: PluginClass) -> Self {
        let values = class.params.iter().map(|p| p.default.clone()).collect();
        Values { class, values }
    }

    fn params(&self) -> Vec<ParamInfo> {
        self.class
            .params
            .iter()
            .zip(&self.values)
            .map(|(p, v)| ParamInfo {
                name: p.name.clone().into(),
                help: p.help.clone().into(),
                range: match p.kind {
                    Kind::Real => "real",
                    Kind::Whole => "integer ≥ 0",
                    Kind::Flag => "true|false",
                    Kind::Text => "text",
                }
                .to_string(),
                value: match p.kind {
                    Kind::Real => Value::Real(v.parse().unwrap_or(f64::NAN)),
                    Kind::Whole => Value::Whole(v.parse().unwrap_or(0)),
                    Kind::Flag => Value::Flag(v == "true"),
                    Kind::Text => Value::Name(intern(v)),
                },
            })
            .collect()
    }

    fn set(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        let Some(i) = self.class.params.iter().position(|p| p.name == key) else {
            return Err(ParamError::Unknown(key.to_string()));
        };
        let ok = match self.class.params[i].kind {
            Kind::Real => value.parse::<f64>().is_ok_and(f64::is_finite),
            Kind::Whole => value.parse::<u64>().is_ok(),
            Kind::Flag => value == "true" || value == "false",
            Kind::Text => true,
        };
        if !ok {
            let expected = match self.class.params[i].kind {
                Kind::Real => "a finite number",
                Kind::Whole => "a whole number ≥ 0",
                _ => "true or false",
            };
            return Err(ParamError::BadValue(BadValue::Expected {
                key: key.to_string(),
                expected,
                text: value.to_string(),
            }));
        }
        self.values[i] = value.to_string();
        Ok(())
    }

    /// A new instance of the class with the parameters as keyword arguments.
    fn instance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let kwargs = PyDict::new(py);
        for (p, v) in self.class.params.iter().zip(&self.values) {
            match p.kind {
                Kind::Real => kwargs.set_item(&p.name, v.parse::<f64>().unwrap_or(f64::NAN))?,
                Kind::Whole => kwargs.set_item(&p.name, v.parse::<u64>().unwrap_or(0))?,
                Kind::Flag => kwargs.set_item(&p.name, v == "true")?,
                Kind::Text => kwargs.set_item(&p.name, v)?,
            }
        }
        self.class.cls.bind(py).call((), Some(&kwargs))
    }

    /// Checks the values by making an instance; the rejection's reason is the exception's
    /// text.
    fn check(&self) -> Result<(), Rejection> {
        Python::attach(|py| {
            self.instance(py)
                .map(|_| ())
                .map_err(|e| Rejection::new("", describe(py, &e)))
        })
    }
}

/// A Python exception as one line: `Type: message`.
fn describe(py: Python<'_>, e: &PyErr) -> String {
    let kind = e
        .get_type(py)
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "Exception".into());
    format!("{kind}: {}", e.value(py))
}

/// A registered Python planner class. Its solutions go through the run's post-processing
/// (`shortcut`, `straighten`) as every planner's do: the registry wraps it
/// ([`magbench_planners::PostProcessed`]).
pub struct PyPlanner {
    values: Values,
}

impl PyPlanner {
    fn new(class: PluginClass) -> Self {
        PyPlanner {
            values: Values::new(class),
        }
    }
}

/// Implements [`ParamSet`] for plugin types by their `values` field.
macro_rules! param_set_by_values {
    ($($t:ty),+) => {$(
        impl ParamSet for $t {
            fn params(&self) -> Vec<ParamInfo> {
                self.values.params()
            }
            fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
                self.values.set(key, value)
            }
            fn check_params(&self) -> Result<(), Rejection> {
                self.values.check()
            }
        }
    )+};
}

param_set_by_values!(PyTracker, PyPlanner);

/// Whether a team on `model` may tilt the field (`planar = auto`).
fn elevation_free(agents: usize, model: &magbench_env::PlanningModel) -> bool {
    !Planar::Auto.is_planar(agents, model.carries_fz)
}

/// What a Python planner's `solve` gets: the operations of the problem (those of
/// `magbench.Scenario`) plus its limits and a way to report progress.
#[pyclass(module = "magbench", name = "Problem", extends = Scenario, frozen)]
pub struct PlanProblem {
    t0: Instant,
    limits: Limits,
    max_iterations: u64,
    seed: u64,
    progress: Mutex<Vec<ProgressPoint>>,
}

#[pymethods]
impl PlanProblem {
    /// The wall-time limit (s), or None.
    #[getter]
    fn time_limit_s(&self) -> Option<f64> {
        self.limits.time_limit.map(|d| d.as_secs_f64())
    }

    /// The largest number of iterations (a huge number when only time limits).
    #[getter]
    fn max_iterations(&self) -> u64 {
        self.max_iterations
    }

    /// The seed of the planner's random stream.
    #[getter]
    fn seed(&self) -> u64 {
        self.seed
    }

    /// Seconds since `solve` was called.
    fn elapsed_s(&self) -> f64 {
        self.t0.elapsed().as_secs_f64()
    }

    /// True once `iteration` reaches the iteration limit or the time limit has passed.
    fn should_stop(&self, iteration: u64) -> bool {
        iteration >= self.max_iterations
            || self
                .limits
                .time_limit
                .is_some_and(|t| self.t0.elapsed() >= t)
    }

    /// Records a point of the progress trace: iterations done and the best cost of an exact
    /// solution so far (None before the first). The points become the run's progress curve.
    #[pyo3(signature = (iteration, best_cost = None))]
    fn report_progress(&self, iteration: u64, best_cost: Option<f64>) {
        let p = ProgressPoint {
            iteration,
            time_s: self.t0.elapsed().as_secs_f64(),
            best_cost: best_cost.filter(|c| c.is_finite()),
        };
        let mut v = self.progress.lock().unwrap_or_else(|e| e.into_inner());
        if v.len() < 1_000_000 {
            v.push(p);
        }
    }

    /// The cost of `plan` under the problem's objective (path length by default).
    fn cost(slf: &Bound<'_, Self>, plan: &Plan) -> f64 {
        let sc = slf.as_super().get();
        if plan.plan.states.first().map(Vec::len) != Some(sc.problem.agents()) {
            return f64::NAN;
        }
        let mut p = plan.plan.clone();
        p.flow = sc.problem.model.flow;
        plan_cost(&sc.problem, &p)
    }
}

impl Planner for PyPlanner {
    fn name(&self) -> &str {
        &self.values.class.name
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let t0 = Instant::now();
        let free = elevation_free(problem.agents(), &problem.model);
        let outcome = Python::attach(|py| -> Result<_, String> {
            let init = PyClassInitializer::from(Scenario::of_problem(problem.clone(), free))
                .add_subclass(PlanProblem {
                    t0,
                    limits: problem.limits,
                    max_iterations: problem.max_iterations(),
                    seed: problem.seed,
                    progress: Mutex::new(vec![]),
                });
            let prob = Bound::new(py, init).map_err(|e| describe(py, &e))?;
            let planner = self.values.instance(py).map_err(|e| describe(py, &e))?;
            let r = planner
                .call_method1("solve", (prob.clone(),))
                .map_err(|e| describe(py, &e))?;
            let plan = if r.is_none() {
                None
            } else {
                let p = r.cast::<Plan>().map_err(|_| {
                    format!(
                        "solve returned {}, not a magbench.Plan or None",
                        r.get_type()
                            .name()
                            .map(|n| n.to_string())
                            .unwrap_or_default()
                    )
                })?;
                Some(p.borrow().plan.clone())
            };
            let progress = std::mem::take(
                &mut *prob
                    .get()
                    .progress
                    .lock()
                    .unwrap_or_else(|e| e.into_inner()),
            );
            Ok((plan, progress))
        });
        let (plan, mut progress) = match outcome {
            Ok(o) => o,
            Err(msg) => panic!("Python planner {}: {msg}", self.values.class.name),
        };
        let mut plan = plan.unwrap_or_else(|| magbench_planners::Plan::at(&problem.start));
        plan.flow = problem.model.flow;
        if free && plan.alpha_max.is_none() {
            plan.alpha_max = Some(problem.alpha_max);
        }
        let agents_ok = plan.states.first().map(Vec::len) == Some(problem.agents());
        let solved = agents_ok && plan.edges() > 0 && problem.goal.contains(plan.end());
        let iterations = progress.iter().map(|p| p.iteration).max().unwrap_or(0);
        let search_s = t0.elapsed().as_secs_f64();
        let cost = solved.then(|| plan_cost(problem, &plan));
        let first_solution = progress
            .iter()
            .find(|p| p.best_cost.is_some())
            .map(|p| (p.iteration, p.time_s))
            .or(solved.then_some((iterations, search_s)));
        if progress
            .last()
            .is_none_or(|p| p.best_cost.is_none() && solved)
        {
            progress.push(ProgressPoint {
                iteration: iterations,
                time_s: search_s,
                best_cost: cost,
            });
        }
        let time_s = t0.elapsed().as_secs_f64();
        PlannerResult {
            solved,
            approximate: !solved && plan.edges() > 0,
            goal_distance: if agents_ok {
                problem.goal.distance(plan.end())
            } else {
                f64::NAN
            },
            plan,
            iterations,
            nodes: 0,
            time_s,
            cost,
            first_solution,
            progress,
        }
    }
}

/// A registered Python tracker class.
pub struct PyTracker {
    values: Values,
    instance: Option<Py<PyAny>>,
    namespace: Option<Py<PyAny>>,
}

impl PyTracker {
    fn new(class: PluginClass) -> Self {
        PyTracker {
            values: Values::new(class),
            instance: None,
            namespace: None,
        }
    }

    /// A `types.SimpleNamespace` with `kwargs` as attributes.
    fn namespace<'py>(
        &mut self,
        py: Python<'py>,
        kwargs: &Bound<'py, PyDict>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if self.namespace.is_none() {
            self.namespace = Some(py.import("types")?.getattr("SimpleNamespace")?.unbind());
        }
        let ns = self.namespace.as_ref().expect("set above").bind(py);
        ns.call((), Some(kwargs))
    }

    fn fail(&self, what: &str, msg: String) -> ! {
        panic!("Python tracker {} ({what}): {msg}", self.values.class.name)
    }
}

/// The problem a tracker sees: the leg's world (bounds and obstacles) and operations.
fn tracker_problem(ctx: &TrackerContext) -> Problem {
    let model = ctx.model.clone();
    Problem {
        scenario: String::new(),
        world: ctx.world.clone(),
        start: ctx.reference.state(0).to_vec(),
        goal: ctx.goal.clone(),
        objective: objective_by_name("path-length", &model).expect("a known objective"),
        model,
        checker: ctx.checker.clone(),
        control_period: ctx.period,
        limits: Limits::default(),
        seed: 0,
        metric: Distance::Positions,
        alpha_max: PlanningSetup::default().alpha_max_deg.to_radians(),
    }
}

impl Tracker for PyTracker {
    fn name(&self) -> &str {
        &self.values.class.name
    }

    fn reset(&mut self, ctx: &TrackerContext) {
        let r = Python::attach(|py| -> PyResult<()> {
            if self.instance.is_none() {
                self.instance = Some(self.values.instance(py)?.unbind());
            }
            let problem = tracker_problem(ctx);
            let free = elevation_free(problem.agents(), &problem.model);
            let sc = Bound::new(py, Scenario::of_problem(problem, free))?;
            let plan = Bound::new(py, crate::reference::Reference::of(py, ctx.reference)?)?;
            let inst = self.instance.as_ref().expect("made above").bind(py);
            inst.call_method1("reset", (sc, plan))?;
            Ok(())
        });
        if let Err(e) = r {
            let msg = Python::attach(|py| describe(py, &e));
            self.fail("reset", msg);
        }
    }

    fn command(&mut self, _ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = Python::attach(|py| -> Result<Control, String> {
            let e = |e: PyErr| describe(py, &e);
            let kw = PyDict::new(py);
            kw.set_item("t", tick.t).map_err(e)?;
            kw.set_item("estimate", PyArray1::from_vec(py, state_vec(tick.estimate)))
                .map_err(e)?;
            let observed: Vec<f64> = tick
                .observation
                .agents
                .iter()
                .flat_map(|p| p.map_or([f64::NAN; 2], |p: Vec2| [p.x, p.y]))
                .collect();
            kw.set_item("observed", PyArray1::from_vec(py, observed))
                .map_err(e)?;
            kw.set_item("frame_t", tick.observation.t).map_err(e)?;
            let obs = self.namespace(py, &kw).map_err(e)?;
            let Some(inst) = self.instance.as_ref() else {
                return Err("control called before reset".into());
            };
            let u = inst.bind(py).call_method1("control", (obs,)).map_err(e)?;
            let a: ArrayIn = u.extract().map_err(e)?;
            let v = a.as_array();
            if v.ndim() != 1 {
                return Err(format!("control returned shape {:?}, not (4,)", v.shape()));
            }
            read_control(
                py,
                "control",
                v.into_dimensionality().expect("one dimension"),
            )
            .map_err(|err| describe(py, &err))
        });
        match r {
            Ok(u) => u,
            Err(msg) => self.fail("control", msg),
        }
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: "python",
            progress: 0,
            targets: None,
        }
    }
}

/// Checks the registered plugins by building the registry (a clash with a built-in name, a
/// malformed name, a bad default).
#[pyfunction]
pub fn check_plugins(py: Python<'_>) -> PyResult<()> {
    registry(py).map(|_| ())
}

/// The planners and trackers of the registry (built-ins and registered Python plugins):
/// `{"planners": [(name, summary, [(param, value, range, help)…])…], "trackers": …}`.
#[pyfunction]
pub fn list_registry<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let reg = registry(py)?;
    let d = PyDict::new(py);
    let items = |list: Vec<(&str, &str, Vec<ParamInfo>)>| -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for (name, summary, params) in list {
            let ps: Vec<(String, String, String, String)> = params
                .into_iter()
                .map(|p| {
                    (
                        p.name.into_owned(),
                        p.value.to_string(),
                        p.range,
                        p.help.into_owned(),
                    )
                })
                .collect();
            out.append(PyTuple::new(
                py,
                [
                    name.into_pyobject(py)?.into_any(),
                    summary.into_pyobject(py)?.into_any(),
                    ps.into_pyobject(py)?.into_any(),
                ],
            )?)?;
        }
        Ok(out)
    };
    d.set_item("planners", items(reg.planners().list())?)?;
    d.set_item("trackers", items(reg.trackers().list())?)?;
    Ok(d)
}

//! A planner followed by the run's post-processing: what the registry makes of every planner,
//! a plugin's included, so that no planner calls the passes itself.

use magbench_env::input::Rejection;
use magbench_env::params::{ParamError, ParamInfo, ParamSet, Value};

use crate::post_process::{PostProcess, default_max_duration};
use crate::tree::Tree;
use crate::{Planner, PlannerResult, Problem};

/// `inner`, its solved results passed through [`PostProcess`]. Its parameters are the inner
/// planner's and the passes' `shortcut`, `straighten` and `trajopt`, except a key the inner planner
/// declares itself: that one stays the planner's, and its pass does not run.
pub struct PostProcessed {
    inner: Box<dyn Planner>,
    post: PostProcess,
}

impl PostProcessed {
    /// `inner` with no pass set.
    pub fn new(inner: Box<dyn Planner>) -> Self {
        PostProcessed {
            inner,
            post: PostProcess::default(),
        }
    }

    /// The passes that run: those set whose key the inner planner does not declare.
    pub fn passes(&self) -> PostProcess {
        let own = |key: &str| self.inner.params().iter().any(|p| p.name == key);
        PostProcess {
            shortcut: if own("shortcut") {
                0
            } else {
                self.post.shortcut
            },
            straighten: !own("straighten") && self.post.straighten,
            trajopt: if own("trajopt") { 0 } else { self.post.trajopt },
        }
    }

    /// Whether `key` is a pass's rather than the inner planner's.
    fn is_pass_key(&self, key: &str) -> bool {
        !self.inner.params().iter().any(|p| p.name == key)
            && self.post.params().iter().any(|p| p.name == key)
    }

    /// The longest steered edge of the shortcut pass (s): the inner planner's `max_duration`
    /// when it declares one, else [`default_max_duration`].
    fn max_duration(&self) -> f64 {
        self.inner
            .params()
            .iter()
            .find_map(|p| match (&*p.name, &p.value) {
                ("max_duration", Value::Real(x)) => Some(*x),
                _ => None,
            })
            .unwrap_or_else(default_max_duration)
    }
}

impl ParamSet for PostProcessed {
    fn params(&self) -> Vec<ParamInfo> {
        let mut params = self.inner.params();
        params.extend(
            self.post
                .params()
                .into_iter()
                .filter(|p| self.is_pass_key(&p.name)),
        );
        params
    }

    fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        if self.is_pass_key(key) {
            return self.post.set_param(key, value);
        }
        self.inner.set_param(key, value)
    }

    fn check_params(&self) -> Result<(), Rejection> {
        self.post.check_params()?;
        self.inner.check_params()
    }
}

impl Planner for PostProcessed {
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let result = self.inner.solve(problem);
        self.passes().result(problem, result, self.max_duration())
    }

    fn tree(&self) -> Option<&Tree> {
        self.inner.tree()
    }

    fn stop_reason(&self) -> Option<&str> {
        self.inner.stop_reason()
    }
}

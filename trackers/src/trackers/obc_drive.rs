//! Driving the team with the OBC optimizer, as `obc` and `lookahead` both do: its weights (parameters
//! of both trackers), the optimizer of the reference being followed, the last command and the
//! targets it aimed at.

use magbench_env::{Control, Vec2, declare_params};

use crate::optimizer::{ObcOptimizer, ObcWeights};
use crate::tracker::TrackerContext;

declare_params! {
    /// The OBC optimizer as a tracker drives it.
    #[derive(Debug, Clone)]
    pub struct ObcDrive {
        /// The optimizer's weights and search settings.
        #[params]
        pub weights: ObcWeights,
        opt: Option<ObcOptimizer> = None,
        last: Option<Control> = None,
        targets: Vec<Vec2> = vec![],
    }
}

impl ObcDrive {
    /// A new reference is followed: the optimizer for its model, checker and control period.
    pub fn reset(&mut self, ctx: &TrackerContext) {
        self.opt = Some(ObcOptimizer::new(
            ctx.model.clone(),
            ctx.checker.clone(),
            ctx.period,
            self.weights.clone(),
        ));
    }

    /// The optimizer of the reference being followed.
    pub fn optimizer(&self) -> &ObcOptimizer {
        self.opt.as_ref().expect("reset before command")
    }

    /// The command whose prediction from `x` one horizon ahead best reaches the per-agent
    /// `target` (walls judged along `path`, the agents' own path points; `hint`, an extra
    /// candidate). It is remembered as the last command, and `target` as the targets.
    pub fn command(
        &mut self,
        x: &[Vec2],
        target: &[Vec2],
        path: &[Vec2],
        hint: Option<&Control>,
    ) -> Control {
        let sol = self
            .optimizer()
            .solve_along(x, target, path, self.last.as_ref(), hint);
        self.targets = target.to_vec();
        self.last = Some(sol.control);
        sol.control
    }

    /// The targets of the last command.
    pub fn targets(&self) -> Vec<Vec2> {
        self.targets.clone()
    }
}

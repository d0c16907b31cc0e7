//! `com-p`: follow the plan's field angle and gradient on its schedule, plus a proportional
//! correction of the team's centre of mass toward where the plan has it now.
//!
//! ```text
//! k        ← the reference sample at time t
//! planned  ← the plan's command at k (the last one past the end)
//! error    ← centroid of the reference at k − centroid of the estimate
//! gradient ← planned gradient + gain · G · error      (per axis, signed by the field angle,
//!                                                       clamped to ±G, the coil's limit)
//! command  ← (planned field angle and elevation, gradient)
//! ```
//!
//! With the tri-axial coil the pull along x scales with cos θ and along y with sin θ, so the
//! correction along an axis takes the sign of that factor.

use magbench::prelude::*;

declare_params! {
    /// A proportional centre-of-mass tracker.
    #[derive(Debug, Clone)]
    pub struct ComP {
        /// Gradient added per BL of centre-of-mass error, as a fraction of the coil's limit.
        #[param("gain", Reals::closed(0.0, 100.0))]
        pub gain: f64 = 2.0,
        /// The reference sample of the last command (for the logs).
        progress: usize = 0,
    }
}

/// The centre of mass of a team state.
fn centroid(s: &[Vec2]) -> Vec2 {
    s.iter().sum::<Vec2>() / s.len() as f64
}

impl Tracker for ComP {
    fn name(&self) -> &str {
        "com-p"
    }

    fn reset(&mut self, _ctx: &TrackerContext) {
        self.progress = 0;
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = ctx.reference;
        self.progress = r.index_at(tick.t);
        let last_edge = r.last().saturating_sub(1);
        let planned = r
            .control(self.progress)
            .or_else(|| r.control(last_edge))
            .copied()
            .unwrap_or_default();
        let error = centroid(r.state(self.progress)) - centroid(tick.estimate);
        let g = ctx.model.coil.gradient_limit();
        let axis = |planned: f64, error: f64, factor: f64| {
            (planned + self.gain * g * error * factor.signum()).clamp(-g, g)
        };
        Control {
            theta: planned.theta,
            alpha: planned.alpha,
            grad: [
                axis(planned.grad[0], error.x, planned.theta.cos()),
                axis(planned.grad[1], error.y, planned.theta.sin()),
            ],
        }
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: "follow",
            progress: self.progress,
            targets: None,
        }
    }
}

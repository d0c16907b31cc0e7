//! A plan: states, the coil controls between them, and their durations.

use magbench_env::{Control, Vec2};
use serde::{Deserialize, Serialize};

/// A kinodynamic plan, like OMPL's `PathControl`: `states[0]` is the start, and control
/// `controls[i]` held for `durations[i]` seconds takes `states[i]` to `states[i + 1]` under the
/// planning model. The control is what the coil applies (θ_B, α, gradient), not the local ψ.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Plan {
    /// Agent positions at each waypoint (BL); one more than there are controls.
    pub states: Vec<Vec<Vec2>>,
    /// Control of each edge.
    pub controls: Vec<Control>,
    /// Duration of each edge (s).
    pub durations: Vec<f64>,
}

impl Plan {
    /// A plan that stays at `start`.
    pub fn at(start: &[Vec2]) -> Self {
        Plan {
            states: vec![start.to_vec()],
            controls: vec![],
            durations: vec![],
        }
    }

    /// Number of edges.
    pub fn edges(&self) -> usize {
        self.controls.len()
    }

    /// Total duration (s).
    pub fn duration(&self) -> f64 {
        self.durations.iter().sum()
    }

    /// The start state.
    pub fn start(&self) -> &[Vec2] {
        &self.states[0]
    }

    /// The final state.
    pub fn end(&self) -> &[Vec2] {
        self.states
            .last()
            .expect("a plan has at least its start state")
    }

    /// Appends an edge.
    pub fn push(&mut self, control: Control, duration: f64, end: Vec<Vec2>) {
        self.controls.push(control);
        self.durations.push(duration);
        self.states.push(end);
    }
}

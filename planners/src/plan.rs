//! A plan: states, the coil controls between them, and their durations.

use magbench_env::model::Flow;
use magbench_env::{Control, Vec2};
use serde::{Deserialize, Serialize};

/// A kinodynamic plan, like OMPL's `PathControl`: `states[0]` is the start, and control
/// `controls[i]` held for `durations[i]` seconds takes `states[i]` to `states[i + 1]` under the
/// planning model with the plan's [`Flow`]. The control is what the coil applies (θ_B, α,
/// gradient), not the local ψ.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// The scenario, leg and team the plan was made for; absent in plan files written before
    /// plans named their scenario (those are checked by their start alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub made_for: Option<MadeFor>,
    /// How the planning model solved the edges (`pair-adaptive`, `pair-exact` or `rk4`); replay
    /// uses the same.
    /// Plan files written before the exact flow have no such field and are `rk4`.
    #[serde(default = "legacy_flow")]
    pub flow: Flow,
    /// The largest field elevation |α| the planner could command (rad) when the elevation was
    /// free (a team of three or more at an interface, or `planar = false`); absent when the
    /// planner kept the field in the plane (and in plan files that predate the field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_max: Option<f64>,
    /// Agent positions at each waypoint (BL); one more than there are controls.
    pub states: Vec<Vec<Vec2>>,
    /// Control of each edge.
    pub controls: Vec<Control>,
    /// Duration of each edge (s).
    pub durations: Vec<f64>,
}

/// What a plan was made for: a scenario (by name and [`content hash`]), its leg and its team.
///
/// [`content hash`]: magbench_env::Scenario::content_hash
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MadeFor {
    /// The scenario's name.
    pub scenario: String,
    /// The scenario's content hash.
    pub scenario_hash: String,
    /// The leg (1 for the first).
    pub leg: usize,
    /// The number of agents.
    pub agents: usize,
}

impl MadeFor {
    /// Leg `leg` (1 for the first) of `scenario`.
    pub fn new(scenario: &magbench_env::Scenario, leg: usize) -> Self {
        MadeFor {
            scenario: scenario.name.clone(),
            scenario_hash: scenario.content_hash(),
            leg,
            agents: scenario.agents(),
        }
    }
}

/// The flow of a plan file that does not name one: every plan before the exact flow was RK4.
fn legacy_flow() -> Flow {
    Flow::Rk4
}

impl Plan {
    /// A plan that stays at `start`, made with the default flow.
    pub fn at(start: &[Vec2]) -> Self {
        Plan {
            made_for: None,
            flow: Flow::default(),
            alpha_max: None,
            states: vec![start.to_vec()],
            controls: vec![],
            durations: vec![],
        }
    }

    /// Whether the planner could tilt the field out of the plane.
    pub fn elevation_free(&self) -> bool {
        self.alpha_max.is_some()
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

impl Plan {
    /// The plan as CSV: one row per waypoint with its time (s) and agent positions (BL), then
    /// the control (θ_B and α in radians, gradients in T/m) and duration (s) of the edge that
    /// leaves it (empty on the last row).
    pub fn to_csv(&self) -> String {
        let n = self.states.first().map_or(0, |s| s.len());
        let mut w = csv::Writer::from_writer(Vec::new());
        let mut header = vec!["waypoint".to_string(), "t_s".to_string()];
        for i in 0..n {
            header.push(format!("x{i}"));
            header.push(format!("y{i}"));
        }
        header.extend(
            [
                "theta_rad",
                "alpha_rad",
                "grad_x_t_per_m",
                "grad_y_t_per_m",
                "duration_s",
            ]
            .map(String::from),
        );
        w.write_record(&header).expect("writing to memory");
        let mut t = 0.0;
        for (k, s) in self.states.iter().enumerate() {
            let mut row = vec![k.to_string(), format!("{t}")];
            for p in s {
                row.push(format!("{}", p.x));
                row.push(format!("{}", p.y));
            }
            match (self.controls.get(k), self.durations.get(k)) {
                (Some(u), Some(d)) => {
                    row.extend(
                        [u.theta, u.alpha, u.grad[0], u.grad[1], *d].map(|v| format!("{v}")),
                    );
                    t += d;
                }
                _ => row.extend(std::iter::repeat_n(String::new(), 5)),
            }
            w.write_record(&row).expect("writing to memory");
        }
        String::from_utf8(w.into_inner().expect("flushing to memory")).expect("CSV is UTF-8")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_has_one_row_per_waypoint_and_round_trips_numbers() {
        let mut p = Plan::at(&[Vec2::new(1.0, 2.0), Vec2::new(3.5, 2.0)]);
        p.push(
            Control::planar(0.1, 0.02, -0.03),
            0.5,
            vec![Vec2::new(1.1, 2.0), Vec2::new(3.4, 2.1)],
        );
        let csv = p.to_csv();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("waypoint,t_s,x0,y0,x1,y1,theta_rad"));
        assert_eq!(lines[1], "0,0,1,2,3.5,2,0.1,0,0.02,-0.03,0.5");
        assert_eq!(lines[2], "1,0.5,1.1,2,3.4,2.1,,,,,");
    }
}

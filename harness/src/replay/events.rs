//! The moments a replay marks: contacts (two agents touching, an agent touching a wall or an
//! obstacle) found in the positions it shows, and the replans and new legs of the run.

use magbench_env::{Scenario, Vec2};
use serde::Serialize;

/// Most events one replay keeps (the first ones).
pub const MAX_EVENTS: usize = 500;

/// Centre distance (BL) at or below which two agents touch: one diameter.
pub const TOUCH_BL: f64 = 1.0;

/// One marked moment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Event {
    /// Time (s since the first tick).
    pub t: f64,
    /// `contact` (two agents), `wall`, `replan` or `leg`.
    pub kind: &'static str,
    /// The agent (for `wall`), the first of the pair (for `contact`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agent: Option<usize>,
    /// Where (BL): the agent, the pair's midpoint or the team's centroid.
    pub at: [f64; 2],
    /// A short description.
    pub note: String,
}

/// Contact onsets in `frames` (time, leg, every agent's position): a pair of agents whose
/// centres come within [`TOUCH_BL`], an agent whose centre comes within its radius of a wall or
/// an obstacle of its leg's map. Each onset is one event; staying in contact is not.
pub fn contacts<'a>(
    s: &Scenario,
    frames: impl Iterator<Item = (f64, usize, &'a [Vec2])>,
) -> Vec<Event> {
    let checkers: Vec<_> = (0..s.legs.len()).map(|k| s.checker_for_leg(k)).collect();
    let n = s.agents();
    let mut touching = vec![false; n * n];
    let mut at_wall = vec![false; n];
    let mut out = vec![];
    for (t, leg, pos) in frames {
        let checker = &checkers[leg.min(checkers.len() - 1)];
        for i in 0..pos.len() {
            for j in (i + 1)..pos.len() {
                let now = (pos[j] - pos[i]).norm() <= TOUCH_BL;
                if now && !touching[i * n + j] {
                    let m = (pos[i] + pos[j]) / 2.0;
                    out.push(Event {
                        t: super::scene::r3(t),
                        kind: "contact",
                        agent: Some(i),
                        at: super::scene::xy(m),
                        note: format!("agents {} and {} touch", i + 1, j + 1),
                    });
                }
                touching[i * n + j] = now;
            }
            let now = checker.collision.clearance(pos[i]) <= 0.0;
            if now && !at_wall[i] {
                out.push(Event {
                    t: super::scene::r3(t),
                    kind: "wall",
                    agent: Some(i),
                    at: super::scene::xy(pos[i]),
                    note: format!("agent {} touches a wall", i + 1),
                });
            }
            at_wall[i] = now;
        }
        if out.len() >= MAX_EVENTS {
            out.truncate(MAX_EVENTS);
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn onsets_only() {
        let s = Scenario::load("open-field").unwrap();
        let far = [Vec2::new(5.0, 5.0), Vec2::new(9.0, 5.0)];
        let near = [Vec2::new(5.0, 5.0), Vec2::new(5.9, 5.0)];
        let wall = [Vec2::new(0.2, 5.0), Vec2::new(9.0, 5.0)];
        let frames: Vec<(f64, usize, &[Vec2])> = vec![
            (0.0, 0, &far),
            (0.1, 0, &near),
            (0.2, 0, &near),
            (0.3, 0, &far),
            (0.4, 0, &wall),
            (0.5, 0, &wall),
        ];
        let e = contacts(&s, frames.into_iter());
        let kinds: Vec<(f64, &str)> = e.iter().map(|e| (e.t, e.kind)).collect();
        assert_eq!(kinds, [(0.1, "contact"), (0.4, "wall")]);
        assert_eq!(e[1].agent, Some(0));
    }
}

//! Contact detection: agent–agent contact (a failed run) and wall contact events.
//!
//! A simulated rig knows the truth and reports both itself ([`GroundTruth`]). A physical rig
//! does not; there contact is inferred from the camera: two detected agents whose centres are
//! within [`TOUCH_DISTANCE_BL`] for [`CONTACT_FRAMES`] frames in a row have touched (and stuck,
//! as two magnetised spheres do), and an agent whose detected centre has no clearance from a
//! wall or obstacle starts a wall contact event.

use magbench_env::ValidityChecker;
use magbench_env::plant::Observation;

use crate::rig::GroundTruth;

/// Centre distance (BL) at or below which two detected agents count as touching: one diameter
/// (1 BL) plus 5% for the detector's noise, so that a pair that touches is seen touching.
pub const TOUCH_DISTANCE_BL: f64 = 1.05;

/// Frames in a row two agents must be seen touching before it counts as contact: a single
/// frame within [`TOUCH_DISTANCE_BL`] can be detector noise on a close pass.
pub const CONTACT_FRAMES: usize = 3;

/// Contact state of one run.
#[derive(Debug, Clone)]
pub struct ContactDetector {
    agent_contact: bool,
    wall_contacts: usize,
    touching_frames: usize,
    at_wall: Vec<bool>,
}

impl ContactDetector {
    /// No contact yet, for a team of `agents`.
    pub fn new(agents: usize) -> Self {
        Self {
            agent_contact: false,
            wall_contacts: 0,
            touching_frames: 0,
            at_wall: vec![false; agents],
        }
    }

    /// Two agents have touched (and stuck).
    pub fn agent_contact(&self) -> bool {
        self.agent_contact
    }

    /// Wall contact events so far.
    pub fn wall_contacts(&self) -> usize {
        self.wall_contacts
    }

    /// Folds in one tick: the rig's truth when it has one, else the observation against the
    /// current leg's walls and obstacles.
    pub fn update(
        &mut self,
        truth: Option<&GroundTruth>,
        obs: &Observation,
        checker: &ValidityChecker,
    ) {
        match truth {
            Some(g) => {
                self.wall_contacts = g.wall_contacts;
                self.agent_contact |= g.agent_contact;
            }
            None => self.observed(obs, checker),
        }
    }

    /// Contact as the camera sees it.
    fn observed(&mut self, obs: &Observation, checker: &ValidityChecker) {
        let n = obs.agents.len();
        let mut touching = false;
        for i in 0..n {
            for j in (i + 1)..n {
                if let (Some(a), Some(b)) = (obs.agents[i], obs.agents[j]) {
                    touching |= (b - a).norm() <= TOUCH_DISTANCE_BL;
                }
            }
        }
        self.touching_frames = if touching {
            self.touching_frames + 1
        } else {
            0
        };
        self.agent_contact |= self.touching_frames >= CONTACT_FRAMES;
        for (i, p) in obs.agents.iter().enumerate() {
            if let Some(p) = p {
                let t = checker.collision.clearance(*p) <= 0.0;
                if t && !self.at_wall[i] {
                    self.wall_contacts += 1;
                }
                self.at_wall[i] = t;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use magbench_env::{CollisionWorld, Vec2, World};

    use super::*;

    fn checker() -> ValidityChecker {
        let w = World {
            width: 20.0,
            height: 10.0,
            obstacles: vec![],
        };
        ValidityChecker::new(Arc::new(CollisionWorld::new(&w, 0.5)), 1.2, 6.0)
    }

    fn obs(a: [f64; 2], b: Option<[f64; 2]>) -> Observation {
        Observation {
            t: 0.0,
            agents: vec![
                Some(Vec2::new(a[0], a[1])),
                b.map(|b| Vec2::new(b[0], b[1])),
            ],
        }
    }

    #[test]
    fn touching_counts_after_the_named_number_of_frames() {
        let c = checker();
        let mut d = ContactDetector::new(2);
        let close = obs([5.0, 5.0], Some([5.0 + TOUCH_DISTANCE_BL, 5.0]));
        for _ in 1..CONTACT_FRAMES {
            d.update(None, &close, &c);
            assert!(!d.agent_contact());
        }
        // a missed detection breaks the run of touching frames
        d.update(None, &obs([5.0, 5.0], None), &c);
        for _ in 0..CONTACT_FRAMES {
            assert!(!d.agent_contact());
            d.update(None, &close, &c);
        }
        assert!(d.agent_contact());
    }

    #[test]
    fn a_wall_contact_is_one_event_until_the_agent_leaves() {
        let c = checker();
        let mut d = ContactDetector::new(2);
        for _ in 0..3 {
            d.update(None, &obs([0.4, 5.0], Some([5.0, 5.0])), &c);
        }
        assert_eq!(d.wall_contacts(), 1);
        d.update(None, &obs([2.0, 5.0], Some([5.0, 5.0])), &c);
        d.update(None, &obs([0.4, 5.0], Some([5.0, 5.0])), &c);
        assert_eq!(d.wall_contacts(), 2);
    }

    #[test]
    fn the_truth_wins_when_the_rig_knows_it() {
        let c = checker();
        let mut d = ContactDetector::new(2);
        let g = GroundTruth {
            positions: vec![],
            wall_contacts: 4,
            agent_contact: true,
        };
        d.update(Some(&g), &obs([0.4, 5.0], None), &c);
        assert!(d.agent_contact());
        assert_eq!(d.wall_contacts(), 4);
    }
}

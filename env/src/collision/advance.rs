//! Conservative advancement: continuous collision checking of a motion known in closed form.
//!
//! An agent whose disk is `d` clear of every obstacle at time `t`, and whose speed is at most
//! `v` over `[t, t + d/v]`, cannot touch anything in that interval. So each agent is checked
//! only at the times it could first touch something, and the motion is valid when every agent
//! is known clear through its end. The speed bound of a step comes from the motion's state at
//! the step's two ends ([`Motion::bound`]), so it is tight where the motion is slow. A contact
//! stops the march: the agent's clearance falls to [`CONTACT`] as the checks converge on it. The
//! check is continuous along the true curve (no chords between samples); the march gives up,
//! counting the motion as colliding, after [`MAX_STEPS`] steps, which only a motion sliding
//! within ~1e-7 BL of a wall can reach.
//!
//! The march converges onto a contact only geometrically (each step closes a fraction of the
//! gap, the approach speed over the speed bound), so two exact shortcuts find contacts sooner:
//! the end of the motion is checked first, and an agent closer than [`PROBE`] to a wall is
//! also looked at [`PROBE_STEPS`] steps ahead. Either finds a contact only where there is one.

use super::CollisionWorld;
use crate::math::{MAX_AGENTS, Vec2};

/// Clearance (BL) at or below which an agent counts as touching.
pub const CONTACT: f64 = 1e-9;

/// Largest number of steps of one motion.
pub const MAX_STEPS: usize = 20_000;

/// Clearance (BL) below which the march also looks ahead for a contact.
pub const PROBE: f64 = 0.05;

/// How far ahead it looks, in steps of the current size.
pub const PROBE_STEPS: f64 = 16.0;

/// A motion the march can follow.
pub trait Motion {
    /// What [`Motion::bound`] needs to know of the motion at one time.
    type Summary: Copy;
    /// The number of agents.
    fn agents(&self) -> usize;
    /// Writes the positions at time `t` into `out` and returns the summary there.
    fn at(&self, t: f64, out: &mut [Vec2]) -> Self::Summary;
    /// A bound on every agent's speed over an interval, from the summaries at its two ends.
    /// It must also bound the speed over every sub-interval that shares the first end.
    fn bound(&self, a: &Self::Summary, b: &Self::Summary) -> f64;
}

/// The latest state evaluated by the march.
struct Sample<S> {
    t: f64,
    pos: [Vec2; MAX_AGENTS],
    summary: S,
}

/// True when the agents moving along `motion` over `[0, duration]` keep clear of every
/// obstacle and wall.
pub fn clear_along<M: Motion>(world: &CollisionWorld, motion: &M, duration: f64) -> bool {
    let n = motion.agents();
    assert!(n <= MAX_AGENTS);
    if !duration.is_finite() {
        return false;
    }
    let mut end = [Vec2::zeros(); MAX_AGENTS];
    let summary = motion.at(duration, &mut end[..n]);
    clear_along_from(world, motion, duration, &end[..n], summary)
}

/// [`clear_along`] given the motion's end: `end` and `summary` are what [`Motion::at`] gives at
/// `duration` (for a caller that has evaluated the end already).
pub fn clear_along_from<M: Motion>(
    world: &CollisionWorld,
    motion: &M,
    duration: f64,
    end: &[Vec2],
    summary: M::Summary,
) -> bool {
    let n = motion.agents();
    assert!(n <= MAX_AGENTS && end.len() == n);
    if !duration.is_finite() {
        return false;
    }
    let eval = |t: f64| {
        let mut pos = [Vec2::zeros(); MAX_AGENTS];
        let summary = motion.at(t, &mut pos[..n]);
        Sample { t, pos, summary }
    };
    // each agent is known clear until `safe[i]`
    let mut safe = [0.0f64; MAX_AGENTS];
    // the bound is exact below `NEAR` and at least `NEAR` (above `CONTACT`) otherwise, so it
    // decides touching exactly as the exact clearance would
    let touches = |s: &Sample<M::Summary>, i: usize| {
        let d = world.clearance_bound(s.pos[i]);
        d.is_nan() || d <= CONTACT
    };
    let mut last = Sample {
        t: duration,
        pos: [Vec2::zeros(); MAX_AGENTS],
        summary,
    };
    last.pos[..n].copy_from_slice(end);
    if (0..n).any(|i| touches(&last, i)) {
        return false;
    }
    let mut now = eval(0.0);
    let mut ahead = None::<Sample<M::Summary>>;
    for _ in 0..MAX_STEPS {
        let (j, t) = (0..n)
            .map(|i| (i, safe[i]))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        if t >= duration {
            return true;
        }
        if now.t != t {
            now = match ahead.take() {
                Some(s) if s.t == t => s,
                _ => eval(t),
            };
        }
        let d = world.clearance_bound(now.pos[j]);
        if d.is_nan() || d <= CONTACT {
            return false;
        }
        // step by the clearance over the speed at the step's start, then check the speed over
        // the whole step; if it is faster, shorten the step to match (the bound of the longer
        // step holds on the shorter one)
        let v0 = motion.bound(&now.summary, &now.summary);
        let mut end = (t + d / v0).min(duration);
        let probe = eval(end);
        let v = motion.bound(&now.summary, &probe.summary);
        if !(v.is_finite() && v > 0.0) {
            return false;
        }
        if v * (end - t) > d {
            end = t + d / v;
        } else {
            ahead = Some(probe);
        }
        if d < PROBE {
            let far = (t + PROBE_STEPS * (end - t)).min(duration);
            if far > end && touches(&eval(far), j) {
                return false;
            }
        }
        safe[j] = end;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Obstacle, World};

    fn post() -> CollisionWorld {
        let w = World {
            width: 20.0,
            height: 10.0,
            obstacles: vec![Obstacle::Circle {
                center: Vec2::new(10.0, 5.0),
                radius: 1.0,
            }],
        };
        CollisionWorld::new(&w, 0.5)
    }

    /// A straight line at unit speed past the post at height `y`.
    struct Line(f64);

    impl Motion for Line {
        type Summary = ();
        fn agents(&self) -> usize {
            1
        }
        fn at(&self, t: f64, out: &mut [Vec2]) {
            out[0] = Vec2::new(5.0 + t, self.0);
        }
        fn bound(&self, _: &(), _: &()) -> f64 {
            1.0
        }
    }

    #[test]
    fn passes_clear_and_catches_a_graze() {
        let w = post();
        // the disk (radius 0.5) clears the post (radius 1) when |y − 5| > 1.5
        assert!(clear_along(&w, &Line(6.6), 10.0));
        assert!(!clear_along(&w, &Line(6.49), 10.0));
        assert!(!clear_along(&w, &Line(5.0), 10.0));
        // a graze 1e-6 BL deep is caught, a pass 1e-4 BL clear is not flagged
        assert!(!clear_along(&w, &Line(6.5 - 1e-6), 10.0));
        assert!(clear_along(&w, &Line(6.5 + 1e-4), 10.0));
    }

    #[test]
    fn stops_at_the_end_of_the_motion() {
        let w = post();
        // the contact would be at t ≈ 3.5; a motion ending at 3 is clear
        assert!(clear_along(&w, &Line(5.0), 3.0));
        assert!(!clear_along(&w, &Line(5.0), 4.0));
    }
}

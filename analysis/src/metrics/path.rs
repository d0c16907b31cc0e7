//! Path-quality metrics of a plan, after Bench-MR (Heiden et al., "Bench-MR: A Motion Planning
//! Benchmark for Wheeled Mobile Robots", RA-L 2021: path length, curvature, smoothness,
//! clearance, cusps) and OMPL's benchmark (`solution length`, `solution smoothness`,
//! `solution clearance`).
//!
//! Each agent's path is the polyline through its positions at the plan's waypoints
//! (`Plan::states`), with repeated points dropped; team figures add up the agents'. Clearance and
//! the proximity margin are measured at points [`STEP`] BL apart along the chords between
//! waypoints (the chord, not the curved edge the flow integrates). The field-angle figures read
//! the commanded in-plane field angle θ_B of each edge's control.

use std::f64::consts::FRAC_PI_2;

use magbench_env::collision::{CollisionWorld, ValidityChecker};
use magbench_env::math::wrap_angle;
use magbench_env::{Control, Vec2};
use magbench_planners::Plan;

/// Largest spacing (BL) of the points at which clearance and proximity are measured.
pub const STEP: f64 = 0.1;

/// Controls that differ by less than this (rad, T/m) are the same control.
const SAME_CONTROL: f64 = 1e-9;

/// Agent `a`'s polyline: its waypoint positions without repeats.
fn polyline(plan: &Plan, a: usize) -> Vec<Vec2> {
    let mut out: Vec<Vec2> = vec![];
    for s in &plan.states {
        let p = s[a];
        if out.last().is_none_or(|q| (p - q).norm() > 1e-12) {
            out.push(p);
        }
    }
    out
}

fn agents(plan: &Plan) -> usize {
    plan.states.first().map_or(0, Vec::len)
}

/// The exterior angle (rad, in [0, π]) between segments `a→b` and `b→c`.
fn turn(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    let (u, v) = (b - a, c - b);
    let cos = (u.dot(&v) / (u.norm() * v.norm())).clamp(-1.0, 1.0);
    cos.acos()
}

/// Sum over agents of the length of each agent's polyline (BL).
pub fn length(plan: &Plan) -> f64 {
    (0..agents(plan))
        .map(|a| {
            polyline(plan, a)
                .windows(2)
                .map(|w| (w[1] - w[0]).norm())
                .sum::<f64>()
        })
        .sum()
}

/// The seed's node error of a team exactly on the plan (BL): moving uniformly along each edge's
/// chords, the team is `λ h_e` (team RMS) from the node it left at fraction λ of edge `e`, `h_e`
/// the edge's team RMS length, and `min(λ, 1 − λ)²` averages 1/12 over the edge; so
/// `sqrt(Σ t_e h_e² / 12 / Σ t_e)`, `t_e` the edge's duration. The part of `rms_error_node_bl`
/// that is the plan's node spacing rather than the tracking; `None` for a plan without motion.
pub fn node_floor(plan: &Plan) -> Option<f64> {
    let n = agents(plan).max(1) as f64;
    let (mut weighted, mut time) = (0.0, 0.0);
    for (w, t) in plan.states.windows(2).zip(&plan.durations) {
        let h2 = w[0]
            .iter()
            .zip(&w[1])
            .map(|(a, b)| (b - a).norm_squared())
            .sum::<f64>()
            / n;
        weighted += t * h2 / 12.0;
        time += t;
    }
    (time > 0.0).then(|| (weighted / time).sqrt())
}

/// Sum over agents of the turning angles at the interior vertices of each agent's polyline
/// (rad): Bench-MR's total curvature of a polyline.
pub fn turning(plan: &Plan) -> f64 {
    (0..agents(plan))
        .map(|a| {
            polyline(plan, a)
                .windows(3)
                .map(|w| turn(w[0], w[1], w[2]))
                .sum::<f64>()
        })
        .sum()
}

/// OMPL's smoothness (`PathGeometric::smoothness`), summed over agents: for each pair of
/// consecutive segments of lengths `a`, `b` meeting at exterior angle `φ`, `(2φ / (a + b))²`.
/// A straight path has 0; sharper and shorter turns count more (1/BL²).
pub fn smoothness(plan: &Plan) -> f64 {
    (0..agents(plan))
        .map(|a| {
            polyline(plan, a)
                .windows(3)
                .map(|w| {
                    let k = 2.0 * turn(w[0], w[1], w[2])
                        / ((w[1] - w[0]).norm() + (w[2] - w[1]).norm());
                    k * k
                })
                .sum::<f64>()
        })
        .sum()
}

/// Cusps, summed over agents: interior vertices where an agent's direction turns by more than
/// 90° (it reverses), Bench-MR's cusp count.
pub fn cusps(plan: &Plan) -> usize {
    (0..agents(plan))
        .map(|a| {
            polyline(plan, a)
                .windows(3)
                .filter(|w| turn(w[0], w[1], w[2]) > FRAC_PI_2)
                .count()
        })
        .sum()
}

/// The team at the waypoints and at points along the chords between them, no agent moving more
/// than [`STEP`] BL from one to the next.
fn samples(plan: &Plan) -> Vec<Vec<Vec2>> {
    let mut out = vec![];
    for (i, s) in plan.states.iter().enumerate() {
        let Some(next) = plan.states.get(i + 1) else {
            out.push(s.clone());
            break;
        };
        let far = s
            .iter()
            .zip(next)
            .map(|(p, q)| (q - p).norm())
            .fold(0.0, f64::max);
        let n = (far / STEP).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push(s.iter().zip(next).map(|(p, q)| p + (q - p) * t).collect());
        }
    }
    out
}

/// The smallest and the mean clearance (BL) of the agents' disks to walls and obstacles
/// (`CollisionWorld::clearance`) over the sampled points of every agent's path.
pub fn clearance(plan: &Plan, world: &CollisionWorld) -> (f64, f64) {
    let (mut min, mut sum, mut n) = (f64::INFINITY, 0.0, 0usize);
    for s in samples(plan) {
        for p in s {
            let c = world.clearance(p);
            min = min.min(c);
            sum += c;
            n += 1;
        }
    }
    (min, sum / n.max(1) as f64)
}

/// The smallest margin (BL) to the proximity range over the sampled points: for each pair of
/// agents, `min(d − r_min, r_max − d)` of their distance `d`; how close the team came to
/// contact or to losing each other. `None` for a single agent.
pub fn proximity_margin(plan: &Plan, checker: &ValidityChecker) -> Option<f64> {
    let mut best: Option<f64> = None;
    for s in samples(plan) {
        for i in 0..s.len() {
            for j in (i + 1)..s.len() {
                let d = (s[j] - s[i]).norm();
                let m = (d - checker.r_min).min(checker.r_max - d);
                best = Some(best.map_or(m, |b: f64| b.min(m)));
            }
        }
    }
    best
}

/// The change of field angle θ_B (rad, wrapped to (−π, π]) between each edge's control and the
/// next's.
fn angle_steps(controls: &[Control]) -> impl Iterator<Item = f64> + '_ {
    controls
        .windows(2)
        .map(|w| wrap_angle(w[1].theta - w[0].theta))
}

/// Field flips: consecutive edges whose field angle θ_B differs by more than 90°.
pub fn field_flips(plan: &Plan) -> usize {
    angle_steps(&plan.controls)
        .filter(|d| d.abs() > FRAC_PI_2)
        .count()
}

/// The total variation of the field angle θ_B over the plan, `Σ |Δθ_B|` between consecutive
/// edges (rad), per second of plan; `None` for a plan of zero duration.
pub fn field_variation_rate(plan: &Plan) -> Option<f64> {
    let tv: f64 = angle_steps(&plan.controls).map(f64::abs).sum();
    let d = plan.duration();
    (d > 0.0).then(|| tv / d)
}

/// Control switches: consecutive edges whose controls differ (θ_B, α or a gradient).
pub fn control_switches(plan: &Plan) -> usize {
    plan.controls
        .windows(2)
        .filter(|w| {
            let (a, b) = (w[0], w[1]);
            wrap_angle(b.theta - a.theta).abs() > SAME_CONTROL
                || (b.alpha - a.alpha).abs() > SAME_CONTROL
                || (0..2).any(|k| (b.grad[k] - a.grad[k]).abs() > SAME_CONTROL)
        })
        .count()
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;
    use std::sync::Arc;

    use magbench_env::world::World;

    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    /// A one-agent plan through `points`, each edge with field angle `theta[i]` for 1 s.
    fn one(points: &[Vec2], theta: &[f64]) -> Plan {
        let mut p = Plan::at(&[points[0]]);
        for (i, q) in points[1..].iter().enumerate() {
            p.push(Control::planar(theta[i], 0.0, 0.0), 1.0, vec![*q]);
        }
        p
    }

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() < 1e-9, "{a} != {b}");
    }

    #[test]
    fn the_node_floor_weighs_each_edge_by_its_time() {
        // a pair: edge 1 moves both agents 3 BL in 1 s (team RMS 3), edge 2 one agent 4 BL in
        // 3 s (team RMS √8): (1·9 + 3·8) / 12 / 4
        let mut p = Plan::at(&[v(0.0, 0.0), v(0.0, 2.0)]);
        p.push(Control::default(), 1.0, vec![v(3.0, 0.0), v(3.0, 2.0)]);
        p.push(Control::default(), 3.0, vec![v(3.0, 4.0), v(3.0, 2.0)]);
        close(node_floor(&p).unwrap(), (33.0f64 / 48.0).sqrt());
        assert_eq!(node_floor(&Plan::at(&[v(0.0, 0.0)])), None);
    }

    #[test]
    fn a_square_with_a_reversal() {
        // (0,0) → (3,0) → (3,4) → (3,4) (repeat, dropped) → (3,1): a 90° turn and a reversal
        let p = one(
            &[
                v(0.0, 0.0),
                v(3.0, 0.0),
                v(3.0, 4.0),
                v(3.0, 4.0),
                v(3.0, 1.0),
            ],
            &[0.0; 4],
        );
        close(length(&p), 3.0 + 4.0 + 3.0);
        close(turning(&p), FRAC_PI_2 + PI);
        assert_eq!(cusps(&p), 1);
        // OMPL: (2·(π/2)/(3+4))² + (2·π/(4+3))²
        close(
            smoothness(&p),
            (PI / 7.0).powi(2) + (2.0 * PI / 7.0).powi(2),
        );
    }

    #[test]
    fn a_straight_path_is_smooth_and_teams_add_up() {
        let mut p = Plan::at(&[v(0.0, 0.0), v(0.0, 2.0)]);
        p.push(
            Control::planar(0.0, 0.0, 0.0),
            2.0,
            vec![v(1.0, 0.0), v(1.0, 2.0)],
        );
        p.push(
            Control::planar(0.0, 0.0, 0.0),
            2.0,
            vec![v(2.0, 0.0), v(2.0, 2.0)],
        );
        close(length(&p), 4.0);
        close(turning(&p), 0.0);
        close(smoothness(&p), 0.0);
        assert_eq!(cusps(&p), 0);
        assert_eq!(control_switches(&p), 0);
    }

    #[test]
    fn field_angle_flips_and_variation() {
        // θ: 0 → 0.5 → 0.5 + π (a flip) → −3 (across ±π: a step of 0.358..., no flip)
        let th = [0.0, 0.5, 0.5 + PI, -3.0];
        let pts: Vec<Vec2> = (0..5).map(|i| v(i as f64, 0.0)).collect();
        let p = one(&pts, &th);
        assert_eq!(field_flips(&p), 1);
        let last = wrap_angle(-3.0 - (0.5 + PI)).abs();
        close(last, 3.5 - PI);
        close(field_variation_rate(&p).unwrap(), (0.5 + PI + last) / 4.0);
        assert_eq!(control_switches(&p), 3);
        assert_eq!(field_variation_rate(&Plan::at(&[v(0.0, 0.0)])), None);
        // the same angle with another gradient is a switch, not a flip
        let mut g = one(&pts[..3], &[1.0, 1.0]);
        g.controls[1].grad[0] = 0.1;
        assert_eq!((control_switches(&g), field_flips(&g)), (1, 0));
    }

    #[test]
    fn clearance_and_proximity_against_walls() {
        // a 100 × 20 box, agent radius 0.5: at height y the nearest wall is y away
        let world = World {
            width: 100.0,
            height: 20.0,
            obstacles: vec![],
        };
        let cw = Arc::new(CollisionWorld::new(&world, 0.5));
        // one agent climbs from y = 5 to y = 9: clearance y − 0.5, from 4.5 to 8.5
        let p = one(&[v(50.0, 5.0), v(50.0, 9.0)], &[0.0]);
        let (min, mean) = clearance(&p, &cw);
        close(min, 4.5);
        close(mean, 6.5);
        // a pair 3 BL apart closing to 2 BL, range (1.5, 6): margin min(2 − 1.5, 6 − 2)
        let checker = ValidityChecker::new(cw.clone(), 1.5, 6.0);
        let mut pair = Plan::at(&[v(40.0, 10.0), v(43.0, 10.0)]);
        pair.push(
            Control::planar(0.0, 0.0, 0.0),
            1.0,
            vec![v(41.0, 10.0), v(43.0, 10.0)],
        );
        close(proximity_margin(&pair, &checker).unwrap(), 0.5);
        assert_eq!(proximity_margin(&p, &checker), None);
    }
}

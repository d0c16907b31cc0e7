//! The tracking error of one frame against a reference, in the four ways a rig can score it.
//!
//! All four measure the positions `p_i` of the N agents against the plan being followed (after
//! a replan or a new leg, the new plan's), in BL. The first three use its reference `r_i(s)`,
//! the polyline through its integration samples ([`Reference`]); the fourth uses its nodes.
//!
//! - **path error** of agent i: `d_i = min_s |p_i − r_i(s)|`, each agent against any point of
//!   its *own* path (a tracker that falls behind but stays on its path scores zero);
//! - **team-synchronous error**: `e_sync = min_s sqrt((1/N) Σ_i |p_i − r_i(s)|²)`, the team
//!   against *one common* point of the team path — the nearest point of the reference in the
//!   joint space of all agents' positions (the polyline through the team samples). It is the
//!   seed's `‖q_a − q_iτ‖` with the nearest node replaced by the nearest point between the
//!   samples; taking the nearest point rather than the point a tracker says it follows keeps
//!   the figure the same whatever tracker ran, so trackers can be compared by it;
//! - **time-indexed error**: `e_time(t) = sqrt((1/N) Σ_i |p_i − r_i(t − t₀)|²)`, the team
//!   against the reference at the same elapsed time since the plan was adopted at `t₀`
//!   (clamped to the reference's ends), linear between samples;
//! - **node error**: `e_node = min_j sqrt((1/N) Σ_i |p_i − n_{j,i}|²)`, the seed's
//!   `‖q_a − q_iτ‖` (Sec. III-B) exactly: `q_iτ` is the plan node `n_j` (a waypoint state the
//!   plan stores, start and end included; not a settle segment) nearest to the team
//!   configuration `q_a` in joint space — one node for the whole team, not one per agent —
//!   and each agent is measured against its own position at that node.
//!
//! Per frame `(1/N) Σ d_i² ≤ e_sync² ≤ e_time²` and `e_sync ≤ e_node`: the synchronous error
//! adds the agents' being out of step with one another, the time-indexed error adds the
//! team's being early or late, the node error adds the distance to the nearest node along
//! the path (up to half the node spacing for a team exactly on its path).

use magbench_env::Vec2;

use crate::reference::{CHUNK_SAMPLES, Reference};

/// The path error of each agent (see the module documentation).
pub fn path_errors(reference: &Reference, positions: &[Vec2]) -> Vec<f64> {
    positions
        .iter()
        .enumerate()
        .map(|(i, &p)| reference.distance_to_path(i, p))
        .collect()
}

/// The team-synchronous error: the RMS over agents of the distances to the nearest point of the
/// team path in joint space (see the module documentation). Chunks of the path whose bounding
/// circles put them farther than the best point so far are skipped; the minimum is exact.
pub fn synchronous_error(reference: &Reference, positions: &[Vec2]) -> f64 {
    let n = positions.len() as f64;
    let last = reference.last();
    if last == 0 {
        return reference.distance_to_sample(positions, 0);
    }
    // a lower bound of the mean square distance over chunk j: each agent at least its
    // distance to the chunk's circle
    let chunks = reference.chunk_circles(0).len();
    let bound = |j: usize| -> f64 {
        positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let (c, r) = reference.chunk_circles(i)[j];
                ((p - c).norm() - r).max(0.0).powi(2)
            })
            .sum::<f64>()
            / n
    };
    let exact = |j: usize| -> f64 {
        let lo = j * CHUNK_SAMPLES;
        let hi = (lo + CHUNK_SAMPLES).min(last);
        (lo..hi)
            .map(|k| segment_msq(reference, positions, k))
            .fold(f64::INFINITY, f64::min)
    };
    let bounds: Vec<f64> = (0..chunks).map(bound).collect();
    let first = (0..chunks)
        .min_by(|&a, &b| bounds[a].total_cmp(&bounds[b]))
        .expect("at least one chunk");
    let mut best = exact(first);
    for (j, &b) in bounds.iter().enumerate() {
        if j != first && b < best {
            best = best.min(exact(j));
        }
    }
    best.sqrt()
}

/// The smallest mean square distance (over agents) from `positions` to a point of the team
/// path's joint-space segment from sample `k` to `k + 1`: the `s ∈ [0, 1]` minimising
/// `Σ_i |a_i + s(b_i − a_i) − p_i|²`.
fn segment_msq(reference: &Reference, positions: &[Vec2], k: usize) -> f64 {
    let (a, b) = (reference.state(k), reference.state(k + 1));
    let (mut num, mut den) = (0.0, 0.0);
    for (p, (a, b)) in positions.iter().zip(a.iter().zip(b)) {
        num += (p - a).dot(&(b - a));
        den += (b - a).norm_squared();
    }
    let s = if den > 0.0 {
        (num / den).clamp(0.0, 1.0)
    } else {
        0.0
    };
    positions
        .iter()
        .zip(a.iter().zip(b))
        .map(|(p, (a, b))| (a + (b - a) * s - p).norm_squared())
        .sum::<f64>()
        / positions.len() as f64
}

/// The team-synchronous error by a scan of every segment (the definition; for tests).
pub fn synchronous_error_scan(reference: &Reference, positions: &[Vec2]) -> f64 {
    if reference.last() == 0 {
        return reference.distance_to_sample(positions, 0);
    }
    (0..reference.last())
        .map(|k| segment_msq(reference, positions, k))
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// The node error: the RMS over agents of the distances to their own positions at the plan node
/// nearest to the team in joint space (see the module documentation).
pub fn node_error(reference: &Reference, positions: &[Vec2]) -> f64 {
    if reference.nodes() == 0 {
        return reference.distance_to_sample(positions, 0);
    }
    let msq = |j: usize| -> f64 {
        positions
            .iter()
            .zip(reference.node(j))
            .map(|(p, n)| (p - n).norm_squared())
            .sum::<f64>()
            / positions.len() as f64
    };
    (0..reference.nodes())
        .map(msq)
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// The time-indexed error: the RMS over agents of the distances to the reference at time `t`
/// (s since the plan was adopted; clamped to the reference), linear between samples.
pub fn time_indexed_error(reference: &Reference, t: f64, positions: &[Vec2]) -> f64 {
    let at = reference_at(reference, t);
    let sum: f64 = positions
        .iter()
        .zip(&at)
        .map(|(p, r)| (p - r).norm_squared())
        .sum();
    (sum / positions.len() as f64).sqrt()
}

/// The team's reference positions at time `t` (clamped), linear between samples.
pub fn reference_at(reference: &Reference, t: f64) -> Vec<Vec2> {
    let k = reference.index_at(t.max(0.0));
    if k >= reference.last() {
        return reference.end().to_vec();
    }
    let (t0, t1) = (reference.time(k), reference.time(k + 1));
    let f = if t1 > t0 {
        ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    reference
        .state(k)
        .iter()
        .zip(reference.state(k + 1))
        .map(|(a, b)| a + (b - a) * f)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::TeamAccumulator;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    /// Two agents moving right along y = 0 and y = 2 at 1 BL/s for 4 s.
    fn straight() -> Reference {
        let times: Vec<f64> = (0..=4).map(f64::from).collect();
        let states: Vec<Vec<Vec2>> = times.iter().map(|&t| vec![v(t, 0.0), v(t, 2.0)]).collect();
        Reference::from_samples(&times, &states)
    }

    #[test]
    fn on_the_path_but_late_scores_only_in_time() {
        let r = straight();
        // the team sits exactly at the reference of t = 1 while the clock says t = 3
        let p = [v(1.0, 0.0), v(1.0, 2.0)];
        assert_eq!(path_errors(&r, &p), vec![0.0, 0.0]);
        assert!(synchronous_error(&r, &p) < 1e-12);
        assert!((time_indexed_error(&r, 3.0, &p) - 2.0).abs() < 1e-12);
        // between samples: t = 1.5 is x = 1.5
        assert!((time_indexed_error(&r, 1.5, &p) - 0.5).abs() < 1e-12);
        // clamped at both ends
        assert!((time_indexed_error(&r, -1.0, &p) - 1.0).abs() < 1e-12);
        assert!((time_indexed_error(&r, 99.0, &p) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn agents_out_of_step_score_in_the_synchronous_error() {
        let r = straight();
        // each agent on its own path, one 2 BL ahead of the other
        let p = [v(1.0, 0.0), v(3.0, 2.0)];
        assert_eq!(path_errors(&r, &p), vec![0.0, 0.0]);
        // the nearest common point is x = 2: each agent 1 BL away
        assert!((synchronous_error(&r, &p) - 1.0).abs() < 1e-12);
        assert!((time_indexed_error(&r, 2.0, &p) - 1.0).abs() < 1e-12);
        let t0 = time_indexed_error(&r, 0.0, &p);
        assert!((t0 - ((1.0 + 9.0) / 2.0f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn off_the_path_scores_the_same_everywhere_when_in_step() {
        let r = straight();
        // both agents 0.3 BL off their paths, in step with each other and the clock
        let p = [v(2.0, 0.3), v(2.0, 1.7)];
        let d = path_errors(&r, &p);
        assert!(d.iter().all(|d| (d - 0.3).abs() < 1e-12));
        assert!((synchronous_error(&r, &p) - 0.3).abs() < 1e-12);
        assert!((time_indexed_error(&r, 2.0, &p) - 0.3).abs() < 1e-12);
    }

    #[test]
    fn pruned_search_equals_the_scan() {
        // two agents on a long spiral (many chunks), out of step
        let times: Vec<f64> = (0..2000).map(|k| k as f64 * 0.01).collect();
        let states: Vec<Vec<Vec2>> = times
            .iter()
            .map(|&t| {
                let a = 0.3 * t;
                vec![v((1.0 + t) * a.cos(), (1.0 + t) * a.sin()), v(t, 0.5 * t)]
            })
            .collect();
        let r = Reference::from_samples(&times, &states);
        for k in 0..200 {
            let x = k as f64 * 0.173;
            let p = [v(x.sin() * 9.0, (1.3 * x).cos() * 9.0), v(x, 0.4 * x - 1.0)];
            let (fast, scan) = (synchronous_error(&r, &p), synchronous_error_scan(&r, &p));
            assert!((fast - scan).abs() < 1e-12, "{fast} vs {scan} at {p:?}");
        }
    }

    #[test]
    fn node_error_by_hand() {
        // nodes every 1 BL: agent 0 at (j, 0), agent 1 at (j, 2), j = 0..=4
        let r = straight();
        assert_eq!(r.nodes(), 5);
        // between nodes 1 and 2, on the path: 0.5 BL from either node, 0 from the polyline
        let a = [v(1.5, 0.0), v(1.5, 2.0)];
        assert!((node_error(&r, &a) - 0.5).abs() < 1e-12);
        assert!(synchronous_error(&r, &a) < 1e-12);
        // at node 1, both 0.3 BL off
        let b = [v(1.0, 0.3), v(1.0, 1.7)];
        assert!((node_error(&r, &b) - 0.3).abs() < 1e-12);
        // out of step: each agent sits on a node of its own (0 and 3), but the team has one
        // node: j = 1 (or 2) gives distances 1 and 2, mean square 2.5
        let c = [v(0.0, 0.0), v(3.0, 2.0)];
        assert!((node_error(&r, &c) - 2.5f64.sqrt()).abs() < 1e-12);
        // the run's RMS over frames = over frames and agents: (0.25·2 + 0.09·2 + 1 + 4) / 6
        let mut acc = TeamAccumulator::default();
        for p in [&a, &b, &c] {
            acc.add(node_error(&r, p));
        }
        assert!(
            (acc.rms() - (5.68f64 / 6.0).sqrt()).abs() < 1e-12,
            "{}",
            acc.rms()
        );
    }

    #[test]
    fn ordering_holds_on_arbitrary_points() {
        let r = straight();
        for (k, p) in [
            [v(0.3, -0.4), v(2.2, 2.9)],
            [v(-1.0, 1.0), v(5.0, 0.0)],
            [v(3.7, 0.1), v(0.2, 2.2)],
        ]
        .iter()
        .enumerate()
        {
            let d = path_errors(&r, p);
            let path = (d.iter().map(|d| d * d).sum::<f64>() / 2.0).sqrt();
            let sync = synchronous_error(&r, p);
            let time = time_indexed_error(&r, k as f64, p);
            assert!(path <= sync + 1e-12 && sync <= time + 1e-12, "{p:?}");
            assert!(sync <= node_error(&r, p) + 1e-12, "{p:?}");
        }
    }
}

//! Polygon well-formedness: enough vertices, non-zero area, no self-intersection.

use crate::math::Vec2;

/// Signed area (positive when the vertices run counter-clockwise).
pub fn signed_area(v: &[Vec2]) -> f64 {
    let n = v.len();
    (0..n).map(|i| v[i].perp(&v[(i + 1) % n])).sum::<f64>() * 0.5
}

/// Two non-adjacent edges closer than this times the polygon's largest coordinate (at least
/// 1 BL) touch. Far above the rounding of coordinates written in decimal (a vertex typed onto
/// an edge is about 1e-17 times its coordinates off it), far below any gap a map means.
pub const TOUCH_TOLERANCE: f64 = 1e-9;

/// Most vertices of one polygon. Far more than any map needs; the bound keeps a checked
/// scenario's collision queries fast and the self-intersection check's worst case small.
pub const MAX_POLYGON_VERTICES: usize = 2000;

/// Why a list of vertices is not a simple polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum PolygonError {
    /// Fewer than 3 vertices.
    #[error("a polygon needs at least 3 vertices, got {0}")]
    TooFew(usize),
    /// More than [`MAX_POLYGON_VERTICES`] vertices.
    #[error(
        "a polygon has at most {MAX_POLYGON_VERTICES} vertices, got {0}: simplify it or split it into several obstacles"
    )]
    TooMany(usize),
    /// Two consecutive vertices coincide.
    #[error("degenerate polygon: vertices {0} and {1} coincide")]
    Coincident(usize, usize),
    /// Two non-adjacent edges touch.
    #[error("self-intersecting polygon: edge {0} crosses edge {1}")]
    Crossing(usize, usize),
    /// The vertices enclose no area.
    #[error("degenerate polygon: zero area")]
    ZeroArea,
}

/// Checks that `v` is a simple polygon: at most [`MAX_POLYGON_VERTICES`] vertices, ≥ 3
/// distinct ones, non-zero area, and no two non-adjacent edges touching. Returns the reason
/// when it is not.
///
/// Two edges touch when they cross (exact orientation tests) or come closer than
/// [`TOUCH_TOLERANCE`] times the largest coordinate: a vertex on another edge, or two lobes
/// meeting at a point, is refused alike whether its coordinates are binary-exact or decimal.
///
/// Edges are swept in order of their smallest x: only edges whose x-ranges overlap are tested
/// against each other, so an ordinary polygon is checked in about n log n.
pub fn check_polygon(v: &[Vec2]) -> Result<(), PolygonError> {
    let n = v.len();
    if n < 3 {
        return Err(PolygonError::TooFew(n));
    }
    if n > MAX_POLYGON_VERTICES {
        return Err(PolygonError::TooMany(n));
    }
    for i in 0..n {
        if (v[i] - v[(i + 1) % n]).norm() < 1e-9 {
            return Err(PolygonError::Coincident(i, (i + 1) % n));
        }
    }
    let scale = v
        .iter()
        .fold(1.0_f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let tol = TOUCH_TOLERANCE * scale;
    let x_range = |i: usize| {
        let (a, b) = (v[i].x, v[(i + 1) % n].x);
        (a.min(b), a.max(b))
    };
    let y_range = |i: usize| {
        let (a, b) = (v[i].y, v[(i + 1) % n].y);
        (a.min(b), a.max(b))
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| x_range(a).0.total_cmp(&x_range(b).0));
    // edges whose x-range still reaches the sweep position
    let mut active: Vec<usize> = Vec::new();
    for &j in &order {
        let xj0 = x_range(j).0;
        let (yj0, yj1) = y_range(j);
        active.retain(|&i| x_range(i).1 >= xj0 - tol);
        for &i in &active {
            let (a, b) = (i.min(j), i.max(j));
            if b == a + 1 || (a == 0 && b == n - 1) {
                continue; // adjacent edges share a vertex
            }
            let (yi0, yi1) = y_range(i);
            if yi1 < yj0 - tol || yj1 < yi0 - tol {
                continue;
            }
            if segments_touch([v[a], v[a + 1]], [v[b], v[(b + 1) % n]], tol) {
                return Err(PolygonError::Crossing(a, b));
            }
        }
        active.push(j);
    }
    if signed_area(v).abs() < 1e-9 {
        return Err(PolygonError::ZeroArea);
    }
    Ok(())
}

/// Whether the segments `s` and `t` cross or come within `tol` of each other: a proper
/// crossing by the signs of exact orientations ([`robust::orient2d`]), anything else by the
/// distance of an end to the other segment (the closest two segments that do not cross come).
pub fn segments_touch(s: [Vec2; 2], t: [Vec2; 2], tol: f64) -> bool {
    let orient = |a: Vec2, b: Vec2, c: Vec2| {
        let p = |q: Vec2| robust::Coord { x: q.x, y: q.y };
        robust::orient2d(p(a), p(b), p(c))
    };
    let opposite = |x: f64, y: f64| (x > 0.0 && y < 0.0) || (x < 0.0 && y > 0.0);
    if opposite(orient(s[0], s[1], t[0]), orient(s[0], s[1], t[1]))
        && opposite(orient(t[0], t[1], s[0]), orient(t[0], t[1], s[1]))
    {
        return true;
    }
    let near = |p: Vec2, [a, b]: [Vec2; 2]| {
        let ab = b - a;
        let along = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
        (a + ab * along - p).norm() <= tol
    };
    near(t[0], s) || near(t[1], s) || near(s[0], t) || near(s[1], t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(a: &[[f64; 2]]) -> Vec<Vec2> {
        a.iter().map(|p| Vec2::new(p[0], p[1])).collect()
    }

    #[test]
    fn accepts_simple_rejects_bowtie_and_flat() {
        assert!(
            check_polygon(&pts(&[
                [0.0, 0.0],
                [2.0, 0.0],
                [2.0, 1.0],
                [1.0, 0.5],
                [0.0, 1.0]
            ]))
            .is_ok()
        );
        let bowtie = check_polygon(&pts(&[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]));
        assert!(matches!(bowtie, Err(PolygonError::Crossing(..))));
        let flat = check_polygon(&pts(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]));
        assert_eq!(flat, Err(PolygonError::ZeroArea));
        assert!(check_polygon(&pts(&[[0.0, 0.0], [1.0, 0.0]])).is_err());
    }

    /// Two lobes, `V B G E` and `A V H`, that touch where the vertex `V` of one lies halfway
    /// along the edge `A B` of the other, in decimal coordinates and in binary-exact ones: in
    /// binary floating point (0.1, 0.3) is not exactly on the edge from (0, 0.2) to (0.2, 0.4),
    /// while (0.125, 0.375) is exactly on the one from (0, 0.25) to (0.25, 0.5).
    const TOUCHING_LOBES: [[[f64; 2]; 6]; 2] = [
        [
            [0.0, 0.2],
            [0.2, 0.4],
            [0.3, 0.3],
            [0.25, 0.25],
            [0.1, 0.3],
            [0.15, 0.15],
        ],
        [
            [0.0, 0.25],
            [0.25, 0.5],
            [0.375, 0.375],
            [0.3125, 0.3125],
            [0.125, 0.375],
            [0.1875, 0.1875],
        ],
    ];

    #[test]
    fn lobes_touching_at_a_vertex_are_refused_in_decimal_and_binary_coordinates() {
        for lobes in TOUCHING_LOBES {
            for scale in [1.0, 10.0, 1000.0] {
                let v: Vec<Vec2> = pts(&lobes).iter().map(|p| p * scale).collect();
                let r = check_polygon(&v);
                assert!(
                    matches!(r, Err(PolygonError::Crossing(0, 3 | 4))),
                    "{v:?}: {r:?}"
                );
            }
        }
        // the touching vertex moved a hundredth of a body length off the edge: simple
        let mut apart = pts(&TOUCHING_LOBES[0]);
        apart[4].x += 0.01;
        assert_eq!(check_polygon(&apart), Ok(()));
    }

    /// A vertex halfway along a non-adjacent edge, at random decimal coordinates (hundredths),
    /// is a touch wherever it lies.
    #[test]
    fn a_vertex_on_another_edge_is_a_touch_at_any_decimal_coordinates() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let tenth = |rng: &mut rand_chacha::ChaCha8Rng, lo: i32, hi: i32| {
            rng.random_range(lo..=hi) as f64 / 10.0
        };
        for _ in 0..2000 {
            let v = Vec2::new(tenth(&mut rng, -50, 50), tenth(&mut rng, -50, 50));
            let d = Vec2::new(tenth(&mut rng, 1, 9), tenth(&mut rng, -9, 9));
            let n = Vec2::new(d.y, -d.x) * 2.0;
            let lobes = [v - d, v + d, v + d + n, v + n + d * 0.5, v, v + n - d * 0.5];
            // written as a file gives them: each coordinate the double nearest its decimal
            let typed: Vec<Vec2> = lobes
                .iter()
                .map(|p| {
                    let r = |x: f64| format!("{x:.2}").parse::<f64>().unwrap();
                    Vec2::new(r(p.x), r(p.y))
                })
                .collect();
            let r = check_polygon(&typed);
            assert!(
                matches!(r, Err(PolygonError::Crossing(..))),
                "{typed:?}: {r:?}"
            );
        }
    }

    /// A regular polygon of `n` vertices, optionally with vertex `k` pulled across the centre.
    fn star(n: usize, bad: Option<usize>) -> Vec<Vec2> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let r = if Some(i) == bad { -20.0 } else { 10.0 };
                Vec2::new(20.0 + r * a.cos(), 20.0 + r * a.sin())
            })
            .collect()
    }

    #[test]
    fn large_polygons_are_checked_or_bounded() {
        assert!(check_polygon(&star(MAX_POLYGON_VERTICES, None)).is_ok());
        let e = check_polygon(&star(MAX_POLYGON_VERTICES, Some(7))).unwrap_err();
        assert!(matches!(e, PolygonError::Crossing(..)), "{e}");
        let e = check_polygon(&star(10_000, None)).unwrap_err();
        assert!(e.to_string().contains("at most 2000 vertices"), "{e}");
    }

    #[test]
    fn the_sweep_finds_what_the_all_pairs_check_finds() {
        use parry2d_f64::math::Vector;
        use parry2d_f64::utils::segments_intersection2d;
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for _ in 0..2000 {
            let n = rng.random_range(3..9);
            let v: Vec<Vec2> = (0..n)
                .map(|_| Vec2::new(rng.random_range(0..5) as f64, rng.random_range(0..5) as f64))
                .collect();
            let pairs = (0..n).any(|i| {
                ((i + 1)..n).any(|j| {
                    let adjacent = j == i + 1 || (i == 0 && j == n - 1);
                    let q = |k: usize| Vector::new(v[k % n].x, v[k % n].y);
                    !adjacent
                        && segments_intersection2d(q(i), q(i + 1), q(j), q(j + 1), 1e-12).is_some()
                })
            });
            let r = check_polygon(&v);
            let degenerate = (0..n).any(|i| (v[i] - v[(i + 1) % n]).norm() < 1e-9);
            if !degenerate {
                assert_eq!(
                    matches!(r, Err(PolygonError::Crossing(..))),
                    pairs,
                    "{v:?}: {r:?}"
                );
            }
        }
    }
}

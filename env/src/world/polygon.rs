//! Polygon well-formedness: enough vertices, non-zero area, no self-intersection.

use crate::math::Vec2;
use parry2d_f64::math::Vector;
use parry2d_f64::utils::segments_intersection2d;

/// Signed area (positive when the vertices run counter-clockwise).
pub fn signed_area(v: &[Vec2]) -> f64 {
    let n = v.len();
    (0..n).map(|i| v[i].perp(&v[(i + 1) % n])).sum::<f64>() * 0.5
}

/// Checks that `v` is a simple polygon: ≥ 3 distinct vertices, non-zero area, and no two
/// non-adjacent edges touching. Returns the reason when it is not.
pub fn check_polygon(v: &[Vec2]) -> Result<(), String> {
    let n = v.len();
    if n < 3 {
        return Err(format!("a polygon needs at least 3 vertices, got {n}"));
    }
    for i in 0..n {
        if (v[i] - v[(i + 1) % n]).norm() < 1e-9 {
            return Err(format!(
                "degenerate polygon: vertices {i} and {} coincide",
                (i + 1) % n
            ));
        }
    }
    let p = |i: usize| Vector::new(v[i % n].x, v[i % n].y);
    for i in 0..n {
        for j in (i + 1)..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if adjacent {
                continue;
            }
            if segments_intersection2d(p(i), p(i + 1), p(j), p(j + 1), 1e-12).is_some() {
                return Err(format!(
                    "self-intersecting polygon: edge {i} crosses edge {j}"
                ));
            }
        }
    }
    if signed_area(v).abs() < 1e-9 {
        return Err("degenerate polygon: zero area".into());
    }
    Ok(())
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
        assert!(bowtie.unwrap_err().contains("self-intersecting"));
        let flat = check_polygon(&pts(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]));
        assert!(flat.unwrap_err().contains("degenerate"));
        assert!(check_polygon(&pts(&[[0.0, 0.0], [1.0, 0.0]])).is_err());
    }
}

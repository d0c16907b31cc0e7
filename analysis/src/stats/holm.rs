//! Holm's step-down adjustment of p-values (family-wise error control).

/// Holm-adjusted `p`: rejecting where the adjusted value is below α keeps the chance of one or
/// more false rejections over the whole family at most α.
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut idx: Vec<usize> = (0..m).collect();
    idx.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut adj = vec![0.0; m];
    let mut running: f64 = 0.0;
    for (k, &i) in idx.iter().enumerate() {
        running = running.max(((m - k) as f64 * p[i]).min(1.0));
        adj[i] = running;
    }
    adj
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adjusts_step_down() {
        // p = (0.01, 0.04, 0.03, 0.005) → sorted 0.005, 0.01, 0.03, 0.04 → 0.02, 0.03, 0.06, 0.06.
        let a = holm(&[0.01, 0.04, 0.03, 0.005]);
        let want = [0.03, 0.06, 0.06, 0.02];
        for (x, y) in a.iter().zip(want) {
            assert!((x - y).abs() < 1e-12, "{a:?}");
        }
    }
}

//! Adaptive Simpson quadrature (Lyness's rule with Richardson extrapolation).

/// Deepest bisection of one interval.
const MAX_DEPTH: u32 = 24;

/// `∫_a^b f` to a relative tolerance `tol` of the whole (adaptive Simpson: an interval is
/// halved until its two halves agree with it within `15 × ` its share of the tolerance, then
/// extrapolated). Deterministic: the same calls in the same order for the same inputs.
pub(super) fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    if a == b {
        return 0.0;
    }
    let (fa, fb) = (f(a), f(b));
    let m = 0.5 * (a + b);
    let fm = f(m);
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    let abs_tol = tol * whole.abs().max(f64::MIN_POSITIVE);
    halves(&f, [a, m, b], [fa, fm, fb], whole, abs_tol, MAX_DEPTH)
}

fn halves(f: &impl Fn(f64) -> f64, x: [f64; 3], y: [f64; 3], whole: f64, tol: f64, depth: u32) -> f64 {
    let [a, m, b] = x;
    let [fa, fm, fb] = y;
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol {
        return left + right + delta / 15.0;
    }
    halves(f, [a, lm, m], [fa, flm, fm], left, 0.5 * tol, depth - 1)
        + halves(f, [m, rm, b], [fm, frm, fb], right, 0.5 * tol, depth - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_smooth_and_kinked_functions() {
        let exact = 1.0 - (-2.0f64).exp();
        let got = simpson(|x| 2.0 * (-2.0 * x).exp(), 0.0, 1.0, 1e-12);
        assert!((got - exact).abs() < 1e-11, "{got}");
        // |x − 0.3| on [0, 1]: a kink inside
        let got = simpson(|x| (x - 0.3f64).abs(), 0.0, 1.0, 1e-10);
        assert!((got - 0.29).abs() < 1e-9, "{got}");
        // reversed limits give the negative
        let got = simpson(|x| x * x, 1.0, 0.0, 1e-12);
        assert!((got + 1.0 / 3.0).abs() < 1e-12, "{got}");
    }
}

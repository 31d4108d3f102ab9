//! Extrapolation and interpolation polynomials of the coupling variables, handed to the FMUs as
//! Taylor coefficients at the communication point T_N (fmi2SetRealInputDerivatives).
//!
//! Through k+1 points (t_i, u_i) passes one polynomial of degree k (Lagrange). We need its value and
//! first k derivatives at the anchor T_N, which is always one of the points, so the value is exact.
//! Divided differences give the Newton form; expanding it about the anchor gives the derivatives.

/// Derivatives 1..=k of the polynomial through `points` (times need not be uniform), evaluated at
/// `anchor`. Returns `[d1, d2]` (entries beyond the degree are 0). At most 3 points (degree 2).
pub fn taylor_derivatives(points: &[(f64, f64)], anchor: f64) -> [f64; 2] {
    match points {
        [] | [_] => [0.0, 0.0],
        [(t0, u0), (t1, u1)] => [(u1 - u0) / (t1 - t0), 0.0],
        [(t0, u0), (t1, u1), (t2, u2), ..] => {
            // Newton form p(t) = u0 + a (t - t0) + b (t - t0)(t - t1).
            let a = (u1 - u0) / (t1 - t0);
            let a12 = (u2 - u1) / (t2 - t1);
            let b = (a12 - a) / (t2 - t0);
            // p'(t) = a + b (2t - t0 - t1), p'' = 2b.
            [a + b * (2.0 * anchor - t0 - t1), 2.0 * b]
        }
    }
}

/// Value of the Taylor polynomial `u0 + d1 s + d2 s^2 / 2` at `s = t - anchor`.
pub fn taylor_value(u0: f64, d: [f64; 2], s: f64) -> f64 {
    u0 + s * (d[0] + s * d[1] / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_polynomials_of_its_degree_exactly() {
        let p = |t: f64| 3.0 - 2.0 * t + 0.7 * t * t;
        let dp = |t: f64| -2.0 + 1.4 * t;
        // Non-uniform points; anchor at the last (extrapolation) and at the first (interpolation).
        let pts = [(0.1, p(0.1)), (0.25, p(0.25)), (0.3, p(0.3))];
        for anchor in [0.3, 0.1, 0.25] {
            let d = taylor_derivatives(&pts, anchor);
            assert!((d[0] - dp(anchor)).abs() < 1e-12, "{d:?}");
            assert!((d[1] - 1.4).abs() < 1e-9);
            // The Taylor form about the anchor reproduces p elsewhere.
            assert!((taylor_value(p(anchor), d, 0.5 - anchor) - p(0.5)).abs() < 1e-12);
        }
        let lin = taylor_derivatives(&[(1.0, 2.0), (1.5, 3.0)], 1.5);
        assert_eq!(lin, [2.0, 0.0]);
        assert_eq!(taylor_derivatives(&[(1.0, 2.0)], 1.0), [0.0, 0.0]);
    }

    #[test]
    fn extrapolation_error_has_the_expected_order() {
        // Extrapolating sin over one step h from k+1 past points: error O(h^{k+1}).
        let f = |t: f64| t.sin();
        let mut errs = vec![];
        for &h in &[0.1, 0.05] {
            let t = 1.0;
            let pts: Vec<(f64, f64)> = (0..3)
                .rev()
                .map(|i| (t - i as f64 * h, f(t - i as f64 * h)))
                .collect();
            let d = taylor_derivatives(&pts, t);
            errs.push((taylor_value(f(t), d, h) - f(t + h)).abs());
        }
        let order = (errs[0] / errs[1]).log2();
        assert!((order - 3.0).abs() < 0.2, "observed order {order}");
    }
}

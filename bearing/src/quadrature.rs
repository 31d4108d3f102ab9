//! 3-point Gauss-Legendre rule on [-1, 1] (exact for polynomials up to degree 5).

/// Abscissae.
pub const GAUSS3_X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
/// Weights.
pub const GAUSS3_W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_quintics_exactly_and_not_sextics() {
        let rule = |f: &dyn Fn(f64) -> f64| -> f64 {
            (0..3).map(|q| GAUSS3_W[q] * f(GAUSS3_X[q])).sum::<f64>()
        };
        for k in 0..=5 {
            let exact = if k % 2 == 0 {
                2.0 / (k + 1) as f64
            } else {
                0.0
            };
            let got = rule(&|x: f64| x.powi(k));
            assert!((got - exact).abs() < 1e-15, "x^{k}: {got} vs {exact}");
        }
        let got = rule(&|x: f64| x.powi(6));
        assert!((got - 2.0 / 7.0).abs() > 1e-3, "x^6 should not be exact");
    }
}

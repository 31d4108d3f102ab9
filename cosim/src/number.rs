//! Numbers in messages: as written where they are ordinary, with an exponent where they are tiny
//! or huge (Rust's `{}` prints 1e300 as 301 digits and 1e-300 as 302 characters).

/// `x` for a message: `{}` between 1e-4 and 1e9 in magnitude (and for 0, inf, NaN), else `{:e}`
/// ("1e300", "2.5e-7").
pub fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e9).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn tiny_and_huge_numbers_take_an_exponent() {
        assert_eq!(super::short(1e300), "1e300");
        assert_eq!(super::short(-1e-300), "-1e-300");
        assert_eq!(super::short(2.5e-7), "2.5e-7");
        assert_eq!(super::short(50e-6), "5e-5");
        assert_eq!(super::short(2.5e-4), "0.00025");
        assert_eq!(super::short(2000.0), "2000");
        assert_eq!(super::short(f64::NAN), "NaN");
    }
}

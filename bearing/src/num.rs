//! Numbers in messages, as an engineer reads them: 0.00004 and 1500, but 1e300 and 5.12e-14
//! instead of 300 digits or a run of zeros (the values the libraries refuse are often extreme).

use std::fmt;

/// `x` printed plainly between 1e-4 and 1e9, with an exponent outside; seven significant
/// digits at most.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if !x.is_finite() || x == 0.0 {
            return write!(f, "{x}");
        }
        // Rounded to seven significant digits first: 0.000000000000051200000000000024 is
        // 5.12e-14, and 24.999999999999996 is 25.
        let x: f64 = format!("{x:.6e}").parse().unwrap_or(x);
        if (1e-4..1e9).contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extreme_values_print_short() {
        for (x, s) in [
            (1e300, "1e300"),
            (-1e-300, "-1e-300"),
            (0.000000000000051200000000000024, "5.12e-14"),
            (-0.0000016506350946109746, "-1.650635e-6"),
            (4e-5, "4e-5"),
            (0.0004, "0.0004"),
            (1500.0, "1500"),
            (-5000.0, "-5000"),
            (24.999999999999996, "25"),
            (0.0, "0"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(Num(x).to_string(), s, "{x:e}");
        }
    }
}

//! Reproducible random numbers for the unit tests (random fields, band matrices): xorshift64*,
//! no dependency, the same sequence on every platform.

/// Uniform numbers in [0, 1) from `seed` (which must not be 0), advancing it.
pub fn uniform(seed: &mut u64) -> f64 {
    *seed ^= *seed >> 12;
    *seed ^= *seed << 25;
    *seed ^= *seed >> 27;
    (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
}

/// Uniform numbers in [-1, 1).
pub fn symmetric(seed: &mut u64) -> f64 {
    2.0 * uniform(seed) - 1.0
}

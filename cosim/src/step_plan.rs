//! Long macro steps in given time windows: the caller knows where the coupled system is calm
//! (for the run-up: where every mode of the linearized rotor is well damped) and lets the run take
//! an integer multiple of the macro step there.
//!
//! The run keeps its grid of base macro steps (k h, so checkpoints, resume and output times stay
//! what they are); a long step covers `factor` grid intervals at once. It starts only on a grid
//! point that is a multiple of `factor` (so the same plan gives the same steps after a resume)
//! and only when the whole step lies inside a window and before the last grid point. The run
//! closes the rest of a window at the first step inside it that is rejected or discarded (the
//! caller's judgement of calm was wrong there; `execution`), and keeps that in its checkpoints.

/// Windows [start, end] of simulated time [s] in which macro steps of `factor` base steps are
/// taken. Checked by [`LongSteps::new`]: factor 1..=64, windows finite, ordered, not overlapping.
#[derive(Clone, Debug, PartialEq)]
pub struct LongSteps {
    factor: u64,
    windows_s: Vec<(f64, f64)>,
}

/// Largest `factor` accepted: 64 base steps per macro step.
pub const MAX_FACTOR: u64 = 64;

impl LongSteps {
    pub fn new(factor: u64, windows_s: Vec<(f64, f64)>) -> Result<Self, String> {
        if !(1..=MAX_FACTOR).contains(&factor) {
            return Err(format!("factor {factor} is not in 1..={MAX_FACTOR}"));
        }
        let mut end_before = f64::NEG_INFINITY;
        for &(a, b) in &windows_s {
            if !(a.is_finite() && b.is_finite() && a >= 0.0 && a < b) {
                return Err(format!(
                    "window [{a}, {b}] s: needs finite 0 <= start < end"
                ));
            }
            if a < end_before {
                return Err(format!(
                    "window [{a}, {b}] s starts before the previous one ends ({end_before} s): \
                     windows must be ordered and must not overlap"
                ));
            }
            end_before = b;
        }
        Ok(LongSteps { factor, windows_s })
    }

    pub fn factor(&self) -> u64 {
        self.factor
    }

    pub fn windows_s(&self) -> &[(f64, f64)] {
        &self.windows_s
    }

    /// Base steps the macro step from grid point `k` covers (1 or `factor`), for base step `h`
    /// and `n_steps` grid intervals in the run.
    pub fn base_steps_from(&self, k: u64, h: f64, n_steps: u64) -> u64 {
        let f = self.factor;
        if f == 1 || !k.is_multiple_of(f) || k + f > n_steps {
            return 1;
        }
        let (t0, t1) = (k as f64 * h, (k + f) as f64 * h);
        // Grid times are k h exactly; a window's ends get a rounding allowance of 1e-9 h.
        let eps = 1e-9 * h;
        if self
            .windows_s
            .iter()
            .any(|&(a, b)| t0 >= a - eps && t1 <= b + eps)
        {
            f
        } else {
            1
        }
    }

    /// The window holding time `t_s` (ends included, to 1e-9 of `h`).
    pub fn window_at(&self, t_s: f64, h: f64) -> Option<(f64, f64)> {
        let eps = 1e-9 * h;
        self.windows_s
            .iter()
            .copied()
            .find(|&(a, b)| t_s >= a - eps && t_s <= b + eps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steps (grid point, base steps covered) a run from grid point `k` to `n` takes.
    fn walk(plan: &LongSteps, mut k: u64, h: f64, n: u64) -> Vec<(u64, u64)> {
        let mut steps = vec![];
        while k < n {
            let m = plan.base_steps_from(k, h, n);
            steps.push((k, m));
            k += m;
        }
        assert_eq!(k, n, "the steps end on the last grid point");
        steps
    }

    #[test]
    fn long_steps_start_on_multiples_and_stay_inside_windows() {
        let h = 50e-6;
        let plan = LongSteps::new(2, vec![(0.0, 0.001), (0.00205, 0.0031)]).unwrap();
        let n = 80;
        let steps = walk(&plan, 0, h, n);
        for &(k, m) in &steps {
            if m == 2 {
                assert_eq!(k % 2, 0);
                let (t0, t1) = (k as f64 * h, (k + 2) as f64 * h);
                assert!(
                    plan.windows_s()
                        .iter()
                        .any(|&(a, b)| t0 >= a - 1e-12 && t1 <= b + 1e-12),
                    "step {k}: [{t0}, {t1}]"
                );
            }
        }
        // [0, 1 ms] = grid 0..20: ten long steps; [2.05, 3.1 ms] = grid 41..62: the long steps
        // start at the even points 42..=60 (the last one ends on the window's end, 3.1 ms).
        let long: Vec<u64> = steps.iter().filter(|s| s.1 == 2).map(|s| s.0).collect();
        let expect: Vec<u64> = (0..20).step_by(2).chain((42..=60).step_by(2)).collect();
        assert_eq!(long, expect);
        assert_eq!(steps.len(), 60);
        // A resumed run at any grid point the plan reached continues with the same steps.
        assert_eq!(walk(&plan, steps[15].0, h, n), steps[15..]);
    }

    #[test]
    fn the_last_grid_interval_is_never_skipped() {
        let plan = LongSteps::new(4, vec![(0.0, 1.0)]).unwrap();
        // 10 intervals: long steps from 0 and 4; 8 + 4 > 10, so 8 and 9 are single steps.
        assert_eq!(plan.base_steps_from(8, 0.01, 10), 1);
        assert_eq!(walk(&plan, 0, 0.01, 10), [(0, 4), (4, 4), (8, 1), (9, 1)]);
        assert_eq!(
            LongSteps::new(1, vec![(0.0, 1.0)])
                .unwrap()
                .base_steps_from(0, 0.1, 10),
            1
        );
    }

    #[test]
    fn bad_plans_are_refused_with_a_reason() {
        assert!(LongSteps::new(0, vec![]).unwrap_err().contains("factor"));
        assert!(LongSteps::new(65, vec![]).is_err());
        assert!(LongSteps::new(2, vec![(0.2, 0.1)])
            .unwrap_err()
            .contains("start < end"));
        assert!(LongSteps::new(2, vec![(0.0, f64::NAN)]).is_err());
        assert!(LongSteps::new(2, vec![(0.0, 0.5), (0.4, 0.6)])
            .unwrap_err()
            .contains("overlap"));
    }
}

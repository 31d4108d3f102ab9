//! Macro-step control by the coupling error: the tolerance, what the control did over a run,
//! and the constants of its refinement.

/// Deepest refinement: 1/2^MAX_HALVINGS of the macro step (0.31 us at 20 us).
pub const MAX_HALVINGS: u32 = 6;

/// Relax the refinement by one level when the largest error ratio of a macro step is below this
/// (halving the step divides an order-1 extrapolation error by 4: the coarser level then still
/// keeps the error below 1/2 of the tolerance).
pub(crate) const RELAX_BELOW: f64 = 0.125;

/// Macro steps with a state save at every step after a rejection or a Discard (see `save_burst`).
pub(crate) const SAVE_BURST_STEPS: u64 = 1000;

/// Macro steps between state saves otherwise. A save copies the factorized Jacobians that changed
/// since the last one (~3 MB for two films after a few hundred steps, ~0.4 ms); a Discard replays
/// at most this many steps (~0.5 s of wall time), and trouble then switches to a save per step.
pub(crate) const SAVE_EVERY: usize = 1000;

/// Tolerance of the coupling error |extrapolated input - actual output| at T_N+1, in the units of
/// the extrapolated inputs (forces in N for the run-up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepControl {
    pub rtol: f64,
    pub atol: f64,
}

impl StepControl {
    /// The one check of a tolerance pair, for system files and command-line flags alike.
    pub fn new(rtol: f64, atol: f64) -> Result<Self, &'static str> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if ok(rtol) && ok(atol) && rtol + atol > 0.0 {
            Ok(StepControl { rtol, atol })
        } else {
            Err("rtol and atol must be finite, >= 0 and not both 0")
        }
    }
}

/// What the macro-step control did over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ControlStats {
    /// Attempts rejected for their coupling error.
    pub rejected: u64,
    /// Macro steps covered by more than one sub-step.
    pub refined_macro_steps: u64,
    /// Deepest refinement level used (sub-step = macro step / 2^level).
    pub deepest_level: u32,
    /// Largest error ratio of an accepted attempt.
    pub max_error_ratio: f64,
    /// Accepted sub-steps of the refined macro steps.
    pub sub_steps: u64,
    /// Length of the rejected attempts, in macro steps: the work the control threw away.
    pub rejected_work_macro_steps: f64,
    /// Macro steps by the deepest level they used (index 0: one sub-step, the nominal step).
    pub macro_steps_by_level: [u64; MAX_HALVINGS as usize + 1],
}

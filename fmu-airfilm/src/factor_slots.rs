//! Which factorized Newton matrix a lobe's sub-step uses: the reuse policy of the film's
//! modified Newton, apart from the integrator that applies it.
//!
//! The Newton matrix of a lobe is J = c0 M + K(P, gap): c0 is the BDF coefficient of the
//! sub-step (~1.5 / h). Under a master's macro step the film's step control often alternates
//! between one sub-step of the macro step and two of half of it (for a 50 us macro step in a
//! large whirl: 50, 25 + 25, 50, ...), so c0 jumps by ~2x at every switch. With one factorized
//! matrix per lobe, every switch refactored all lobes. Each lobe therefore keeps
//! [`SLOTS_PER_LOBE`] factorized matrices; a sub-step uses the one whose c0 is nearest its own,
//! as long as it is within [`C0_RATIO_RANGE`] and younger than the age limit, and refactors only
//! when none is: into an empty slot, else into the one past the age limit nearest in c0 (it
//! served this step size), else into the least recently used one (a step size no longer taken,
//! e.g. the start-up's; never the matrix of the other size of an alternation).

/// Factorized Newton matrices kept per lobe.
pub const SLOTS_PER_LOBE: usize = 2;

/// A factorized matrix serves a sub-step whose c0 over the matrix's c0 lies in this range.
pub const C0_RATIO_RANGE: std::ops::RangeInclusive<f64> = 0.67..=1.5;

/// What one slot holds, as the policy sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlotInfo {
    /// The slot holds a factorized matrix that may be used.
    pub valid: bool,
    /// c0 the matrix was assembled with, 1/s.
    pub c0_per_s: f64,
    /// Accepted sub-steps since it was factorized.
    pub age: u32,
    /// Accepted sub-steps since a sub-step last used it.
    pub idle: u32,
}

/// The policy's answer for one lobe and one sub-step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SlotChoice {
    /// Index into the lobe's slots.
    pub slot: usize,
    /// The matrix must be assembled and factorized (again) before use.
    pub refactor: bool,
}

/// Chooses the slot for a sub-step with coefficient `c0_per_s` among one lobe's `slots`;
/// matrices at `max_age` or older are not used.
pub fn choose(slots: &[SlotInfo], c0_per_s: f64, max_age: u32) -> SlotChoice {
    // |ln ratio|: a matrix at half the c0 is as far as one at twice it.
    let distance = |s: &SlotInfo| (c0_per_s / s.c0_per_s).ln().abs();
    let usable = |s: &SlotInfo| {
        s.valid && s.age < max_age && C0_RATIO_RANGE.contains(&(c0_per_s / s.c0_per_s))
    };
    let nearest = |pred: &dyn Fn(&SlotInfo) -> bool| {
        slots
            .iter()
            .enumerate()
            .filter(|(_, s)| pred(s))
            .min_by(|(_, a), (_, b)| distance(a).total_cmp(&distance(b)))
            .map(|(i, _)| i)
    };
    if let Some(slot) = nearest(&usable) {
        return SlotChoice {
            slot,
            refactor: false,
        };
    }
    let least_recently_used = || {
        slots
            .iter()
            .enumerate()
            .max_by_key(|(i, s)| (s.idle, std::cmp::Reverse(*i)))
            .map(|(i, _)| i)
    };
    let slot = slots
        .iter()
        .position(|s| !s.valid)
        .or_else(|| nearest(&|s| s.age >= max_age))
        .or_else(least_recently_used)
        .expect("a lobe has at least one slot");
    SlotChoice {
        slot,
        refactor: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A valid slot used `age` steps ago, right after it was factorized.
    fn slot(c0_per_s: f64, age: u32) -> SlotInfo {
        SlotInfo {
            valid: true,
            c0_per_s,
            age,
            idle: age,
        }
    }
    fn used(idle: u32, s: SlotInfo) -> SlotInfo {
        SlotInfo { idle, ..s }
    }
    const EMPTY: SlotInfo = SlotInfo {
        valid: false,
        c0_per_s: 0.0,
        age: 0,
        idle: 0,
    };
    const MAX_AGE: u32 = 40;

    fn reuse(slot: usize) -> SlotChoice {
        SlotChoice {
            slot,
            refactor: false,
        }
    }
    fn refactor(slot: usize) -> SlotChoice {
        SlotChoice {
            slot,
            refactor: true,
        }
    }

    #[test]
    fn empty_lobe_factorizes_into_its_first_slot() {
        assert_eq!(choose(&[EMPTY, EMPTY], 3e4, MAX_AGE), refactor(0));
    }

    #[test]
    fn a_new_step_size_fills_the_empty_slot_and_keeps_the_other() {
        // 50 us steps (c0 3e4) factorized in slot 0; a switch to 25 us (c0 5.3e4, ratio 1.78).
        assert_eq!(choose(&[slot(3e4, 3), EMPTY], 5.33e4, MAX_AGE), refactor(1));
    }

    #[test]
    fn alternating_step_sizes_reuse_both_matrices() {
        let slots = [slot(3e4, 5), slot(6e4, 4)];
        assert_eq!(choose(&slots, 3.33e4, MAX_AGE), reuse(0)); // 50 us after 25 us
        assert_eq!(choose(&slots, 5.33e4, MAX_AGE), reuse(1)); // 25 us after 50 us
        assert_eq!(choose(&slots, 6e4, MAX_AGE), reuse(1));
    }

    #[test]
    fn the_nearest_usable_matrix_wins_when_both_are_in_range() {
        let slots = [slot(4e4, 1), slot(5e4, 1)];
        assert_eq!(choose(&slots, 4.4e4, MAX_AGE), reuse(0));
        assert_eq!(choose(&slots, 4.6e4, MAX_AGE), reuse(1));
    }

    #[test]
    fn range_limits_are_inclusive_and_symmetric_in_the_ratio() {
        assert_eq!(choose(&[slot(1e4, 0)], 1.5e4, MAX_AGE), reuse(0));
        assert_eq!(choose(&[slot(1e4, 0)], 1.5001e4, MAX_AGE), refactor(0));
        assert_eq!(choose(&[slot(1e4, 0)], 0.67e4, MAX_AGE), reuse(0));
        assert_eq!(choose(&[slot(1e4, 0)], 0.6699e4, MAX_AGE), refactor(0));
    }

    #[test]
    fn an_old_matrix_is_refactorized_in_place_and_the_other_size_kept() {
        // Slot 0 is at the age limit; slot 1 serves the other step size.
        let slots = [slot(3e4, MAX_AGE), slot(6e4, 2)];
        assert_eq!(choose(&slots, 3e4, MAX_AGE), refactor(0));
    }

    #[test]
    fn a_matrix_of_a_step_size_no_longer_taken_makes_room() {
        // Slot 0 still holds a start-up step's matrix (c0 2e5), slot 1 serves 50 us steps and
        // was used last. A 25 us step (c0 5.33e4, nearer to slot 1's) evicts the start-up's.
        let slots = [used(1, slot(2e5, 3)), used(0, slot(3.33e4, 0))];
        assert_eq!(choose(&slots, 5.33e4, MAX_AGE), refactor(0));
        // Once old, an unused matrix goes first even if it was used more recently.
        let slots = [used(0, slot(1e7, MAX_AGE)), used(1, slot(3.33e4, 1))];
        assert_eq!(choose(&slots, 6e4, MAX_AGE), refactor(0));
    }

    #[test]
    fn an_old_matrix_goes_before_the_least_recently_used_one() {
        // Slot 0 (50 us) just used and at the age limit; slot 1 (25 us) used a step before.
        let slots = [used(0, slot(3.33e4, MAX_AGE)), used(1, slot(6e4, 5))];
        assert_eq!(choose(&slots, 3.33e4, MAX_AGE), refactor(0));
    }

    #[test]
    fn a_third_step_size_replaces_the_least_recently_used_matrix() {
        let slots = [used(2, slot(3e4, 5)), used(1, slot(6e4, 5))];
        assert_eq!(choose(&slots, 1.5e4, MAX_AGE), refactor(0));
        assert_eq!(choose(&slots, 1.5e5, MAX_AGE), refactor(0));
        let slots = [used(0, slot(3e4, 5)), used(1, slot(6e4, 5))];
        assert_eq!(choose(&slots, 1.5e4, MAX_AGE), refactor(1));
    }

    #[test]
    fn invalid_slots_are_never_reused() {
        let stale = SlotInfo {
            valid: false,
            ..slot(3e4, 0)
        };
        assert_eq!(choose(&[stale, slot(9e4, 0)], 3e4, MAX_AGE), refactor(0));
    }

    #[test]
    fn one_slot_behaves_like_a_single_matrix() {
        assert_eq!(choose(&[slot(3e4, 39)], 3.1e4, MAX_AGE), reuse(0));
        assert_eq!(choose(&[slot(3e4, 40)], 3.1e4, MAX_AGE), refactor(0));
        assert_eq!(choose(&[slot(3e4, 0)], 6e4, MAX_AGE), refactor(0));
    }
}

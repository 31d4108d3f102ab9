//! When to step a group's members on the pool's threads and when one after the other: a small
//! policy object that measures instead of assuming.
//!
//! Two threads pay on a quiet machine (the two air films take about as long each), and lose badly on
//! a busy one: a worker that waits for its next job competes with the other process for a core, and
//! a descheduled worker stalls the master's macro step (17x slower seen on a 2-core machine). So the
//! run alternates short probe windows of both ways, keeps the faster one (parallel only when it is
//! clearly faster), holds it for a while, and probes again: the choice follows the machine's load
//! through a run. Results do not depend on the choice (the members are stepped with the same inputs
//! either way); only the wall time does.

use std::time::Duration;

/// How the members of a group are stepped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stepping {
    Parallel,
    Serial,
}

/// The tuning of the choice (defaults measured on a 2-core machine with the run-up's two air films;
/// another system may want others). Part of `AlgorithmConfig`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChoiceTuning {
    /// Group steps per probe window, the first few of which are not timed (a parked worker's wake-up).
    pub probe_steps: u32,
    pub probe_warmup: u32,
    /// Group steps a choice is held before the next probe, at first and at most (doubled each time a
    /// probe confirms the choice).
    pub hold_min: u64,
    pub hold_max: u64,
    /// While parallel is held: once its steps have cost this many serial steps' worth of time beyond
    /// `stall_slack` serial steps each (summed over the hold, a sum that never goes below zero), the
    /// hold ends at once (another process arrived: a stalled worker costs 10-20x per step). Ending
    /// it after 8 slower steps in a row fails on a busy machine, whose scheduling alternates stalled
    /// steps with fast ones (path 1 under one busy loop stepped 455 groups in parallel that way; its
    /// last parallel probe took 2.7 ms per step, serial 0.13 ms).
    pub excess_to_reprobe: f64,
    /// What a held parallel step may take before it counts towards that excess, in serial steps: on a
    /// quiet machine a step where a film refreshes its Newton matrices takes longer than the probe's
    /// mean, and clusters of them must not end a hold that pays (a stall under load is 10-20x).
    pub stall_slack: f64,
    /// Parallel must beat serial by this factor: on a tie, one thread leaves a core to others.
    pub parallel_margin: f64,
    /// A parallel probe ends early, after this many steps beyond its first, once those have cost
    /// twice what serial steps would have: on a busy machine a parallel step can take 10x a serial
    /// one, and a whole window of them would cost more than the choice saves. The first step is left
    /// out: it wakes a worker that parked while the group stepped serially (a futex wake-up, 50-150
    /// us). Were it counted, with film steps this cheap (29 us serially on a 10 x 3 graded mesh) no
    /// parallel probe would survive its first two steps: a run that started serially would stay
    /// serial.
    pub probe_abort_after: u32,
    /// A parallel probe also ends at its first step when that took more than this many serial
    /// steps: a parked worker's wake-up costs 50-150 us on a quiet machine (2-6 serial steps of a
    /// film step of ~26 us), but beside a busy process the worker waits milliseconds for a core
    /// (path 1 beside one busy loop: ~3 ms per parallel step, over 100 serial steps), and so does
    /// each further step of the probe: waiting out three such steps cost ~1.3 % of such a run.
    pub first_step_stall: f64,
}

impl Default for ChoiceTuning {
    fn default() -> Self {
        ChoiceTuning {
            probe_steps: 40,
            probe_warmup: 8,
            hold_min: 2_000,
            hold_max: 16_000,
            excess_to_reprobe: 16.0,
            stall_slack: 2.0,
            parallel_margin: 0.95,
            probe_abort_after: 2,
            first_step_stall: 20.0,
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Timing `mode` for `probe_steps`; `then` is the other mode still to probe (None: decide).
    Probe {
        mode: Stepping,
        done: u32,
        timed: Duration,
        /// All steps of the window but the first, warm-up included (for the early end of a
        /// losing parallel probe).
        spent: Duration,
        then: Option<Stepping>,
    },
    Hold {
        mode: Stepping,
        left: u64,
        /// Parallel only: the time its steps cost beyond `stall_slack` times the last serial
        /// probe's mean, summed over the hold and floored at zero [us].
        excess_us: f64,
    },
}

/// What the choice did over a run (summary.json `group_stepping`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SteppingStats {
    pub parallel_steps: u64,
    pub serial_steps: u64,
    /// Times the held choice changed after a probe.
    pub switches: u64,
    /// The choice held at the end (None: never decided, the run was shorter than two probes).
    pub choice: Option<Stepping>,
    /// The last probe's mean wall time per group step [us], each way.
    pub last_probe_parallel_us: Option<f64>,
    pub last_probe_serial_us: Option<f64>,
}

#[derive(Clone, Debug)]
pub struct SteppingChoice {
    tuning: ChoiceTuning,
    phase: Phase,
    hold: u64,
    means: [Option<f64>; 2],
    stats: SteppingStats,
}

impl Default for SteppingChoice {
    fn default() -> Self {
        Self::new(ChoiceTuning::default())
    }
}

fn index(m: Stepping) -> usize {
    match m {
        Stepping::Parallel => 0,
        Stepping::Serial => 1,
    }
}

fn other(m: Stepping) -> Stepping {
    match m {
        Stepping::Parallel => Stepping::Serial,
        Stepping::Serial => Stepping::Parallel,
    }
}

impl SteppingChoice {
    pub fn new(tuning: ChoiceTuning) -> Self {
        SteppingChoice {
            tuning,
            // Serial first: its mean bounds what the parallel probe may cost.
            phase: Phase::Probe {
                mode: Stepping::Serial,
                done: 0,
                timed: Duration::ZERO,
                spent: Duration::ZERO,
                then: Some(Stepping::Parallel),
            },
            hold: tuning.hold_min,
            means: [None; 2],
            stats: SteppingStats::default(),
        }
    }

    /// How to step the next group.
    pub fn next(&self) -> Stepping {
        match self.phase {
            Phase::Probe { mode, .. } | Phase::Hold { mode, .. } => mode,
        }
    }

    pub fn stats(&self) -> SteppingStats {
        self.stats
    }

    /// The group stepped the way `next` said and took `wall`.
    pub fn record(&mut self, wall: Duration) {
        let mode = self.next();
        match mode {
            Stepping::Parallel => self.stats.parallel_steps += 1,
            Stepping::Serial => self.stats.serial_steps += 1,
        }
        self.phase = match self.phase {
            Phase::Probe {
                mode,
                done,
                timed,
                spent,
                then,
            } => {
                let timed = if done >= self.tuning.probe_warmup {
                    timed + wall
                } else {
                    timed
                };
                let spent = if done == 0 { spent } else { spent + wall };
                let serial_us = self.means[index(Stepping::Serial)];
                let stalled_first = mode == Stepping::Parallel
                    && done == 0
                    && serial_us.is_some_and(|s| {
                        wall.as_secs_f64() * 1e6 > self.tuning.first_step_stall * s
                    });
                let done = done + 1;
                let after_first = done - 1;
                let losing = mode == Stepping::Parallel
                    && after_first >= self.tuning.probe_abort_after
                    && serial_us.is_some_and(|s| {
                        spent.as_secs_f64() * 1e6 > 2.0 * s * f64::from(after_first)
                    });
                if stalled_first {
                    self.means[index(mode)] = Some(wall.as_secs_f64() * 1e6);
                    self.decide()
                } else if losing {
                    self.means[index(mode)] =
                        Some(spent.as_secs_f64() * 1e6 / f64::from(after_first));
                    self.decide()
                } else if done < self.tuning.probe_steps {
                    Phase::Probe {
                        mode,
                        done,
                        timed,
                        spent,
                        then,
                    }
                } else {
                    let mean_us = timed.as_secs_f64() * 1e6
                        / f64::from(self.tuning.probe_steps - self.tuning.probe_warmup);
                    self.means[index(mode)] = Some(mean_us);
                    match then {
                        Some(next) => Phase::Probe {
                            mode: next,
                            done: 0,
                            timed: Duration::ZERO,
                            spent: Duration::ZERO,
                            then: None,
                        },
                        None => self.decide(),
                    }
                }
            }
            Phase::Hold {
                mode,
                left,
                excess_us,
            } if left > 1 => {
                let serial_us =
                    self.means[index(Stepping::Serial)].filter(|_| mode == Stepping::Parallel);
                let excess_us = serial_us.map_or(0.0, |s| {
                    (excess_us + wall.as_secs_f64() * 1e6 - self.tuning.stall_slack * s).max(0.0)
                });
                if serial_us.is_some_and(|s| excess_us > self.tuning.excess_to_reprobe * s) {
                    Phase::Probe {
                        mode: Stepping::Serial,
                        done: 0,
                        timed: Duration::ZERO,
                        spent: Duration::ZERO,
                        then: Some(Stepping::Parallel),
                    }
                } else {
                    Phase::Hold {
                        mode,
                        left: left - 1,
                        excess_us,
                    }
                }
            }
            // Probe the other way first, then the held one again, so both means are fresh.
            Phase::Hold { mode, .. } => Phase::Probe {
                mode: other(mode),
                done: 0,
                timed: Duration::ZERO,
                spent: Duration::ZERO,
                then: Some(mode),
            },
        };
    }

    fn decide(&mut self) -> Phase {
        let [p, s] = self.means;
        self.stats.last_probe_parallel_us = p;
        self.stats.last_probe_serial_us = s;
        let choice = match (p, s) {
            (Some(p), Some(s)) if p < self.tuning.parallel_margin * s => Stepping::Parallel,
            _ => Stepping::Serial,
        };
        match self.stats.choice {
            Some(prev) if prev == choice => self.hold = (2 * self.hold).min(self.tuning.hold_max),
            Some(_) => {
                self.stats.switches += 1;
                self.hold = self.tuning.hold_min;
            }
            None => {}
        }
        self.stats.choice = Some(choice);
        Phase::Hold {
            mode: choice,
            left: self.hold,
            excess_us: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives the choice with a cost per group step for each way.
    fn run(choice: &mut SteppingChoice, steps: u64, cost_us: impl Fn(u64, Stepping) -> u64) {
        for k in 0..steps {
            let m = choice.next();
            choice.record(Duration::from_micros(cost_us(k, m)));
        }
    }

    #[test]
    fn keeps_parallel_while_it_is_clearly_faster() {
        let mut c = SteppingChoice::default();
        run(&mut c, 50_000, |_, m| match m {
            Stepping::Parallel => 100,
            Stepping::Serial => 160,
        });
        let s = c.stats();
        assert_eq!(s.choice, Some(Stepping::Parallel));
        assert_eq!(s.switches, 0);
        // Probes cost a small share of the run: serial only in probe windows.
        assert!(s.serial_steps < 50_000 / 50, "{s:?}");
        assert_eq!(s.last_probe_parallel_us, Some(100.0));
    }

    #[test]
    fn falls_back_to_serial_on_a_tie_and_when_parallel_loses() {
        let mut c = SteppingChoice::default();
        run(&mut c, 5_000, |_, _| 100);
        assert_eq!(c.stats().choice, Some(Stepping::Serial), "a tie");
        let mut c = SteppingChoice::default();
        run(&mut c, 5_000, |_, m| match m {
            Stepping::Parallel => 1_700,
            Stepping::Serial => 200,
        });
        let s = c.stats();
        assert_eq!(s.choice, Some(Stepping::Serial));
        // Each parallel probe ends after a few steps: the losing way costs almost nothing.
        assert!(s.parallel_steps < 20, "{s:?}");
    }

    /// A parallel probe's first step wakes a parked worker (here 6x a serial step); when the
    /// steps after it pay, parallel is chosen, also where serial steps are cheap.
    #[test]
    fn a_parked_workers_wake_up_does_not_end_a_probe_that_pays() {
        let mut c = SteppingChoice::default();
        let mut last = None;
        for _ in 0..10_000 {
            let m = c.next();
            let woke = m == Stepping::Parallel && last != Some(Stepping::Parallel);
            let us = match m {
                Stepping::Parallel if woke => 180,
                Stepping::Parallel => 20,
                Stepping::Serial => 30,
            };
            c.record(Duration::from_micros(us));
            last = Some(m);
        }
        let s = c.stats();
        assert_eq!(s.choice, Some(Stepping::Parallel), "{s:?}");
        assert!(s.parallel_steps > 9_000, "{s:?}");
    }

    #[test]
    fn follows_the_load_through_a_run() {
        // Quiet (parallel pays) for 20 000 steps, then busy (parallel loses 10x), then quiet again.
        let cost = |k: u64, m: Stepping| {
            let busy = (20_000..60_000).contains(&k);
            match (m, busy) {
                (Stepping::Parallel, false) => 100,
                (Stepping::Serial, _) => 170,
                (Stepping::Parallel, true) => 1_000,
            }
        };
        let mut c = SteppingChoice::default();
        let mut choices = vec![];
        for k in 0..120_000u64 {
            let m = c.next();
            c.record(Duration::from_micros(cost(k, m)));
            if k % 1_000 == 999 {
                choices.push((k, c.stats().choice));
            }
        }
        let at = |k: u64| choices.iter().find(|(j, _)| *j >= k).unwrap().1;
        assert_eq!(at(19_000), Some(Stepping::Parallel));
        // Stalled parallel steps end the hold at once: serial within a thousand steps.
        assert_eq!(at(21_000), Some(Stepping::Serial));
        assert_eq!(at(119_000), Some(Stepping::Parallel));
        assert!(c.stats().switches >= 2);
    }

    /// Beside one busy process (path 1 on 2 cores: parallel steps ~3 ms against ~26 us serially)
    /// each parallel probe ends at its first step, the parked worker's wake-up, which stalls too:
    /// a probe used to take three such steps.
    #[test]
    fn a_stalled_wake_up_ends_a_parallel_probe_at_once() {
        let mut c = SteppingChoice::default();
        run(&mut c, 54_400, |_, m| match m {
            Stepping::Parallel => 3_000,
            Stepping::Serial => 26,
        });
        let s = c.stats();
        assert_eq!(s.choice, Some(Stepping::Serial), "{s:?}");
        // One parallel step per probe: the first, at the start, then after holds of 2 000, 4 000,
        // 8 000, 16 000 and 16 000 steps.
        assert_eq!(s.parallel_steps, 6, "{s:?}");
    }

    /// Under load a parallel step stalls now and then, between fast ones (the scheduler gives the
    /// competing process its time slices): the hold ends after the second stall, although no
    /// two come in a row, and the run ends up stepping serially.
    #[test]
    fn intermittent_stalls_end_a_parallel_hold() {
        // Quiet for 10 000 steps (parallel pays), then every third parallel step stalls.
        let cost = |k: u64, m: Stepping| match m {
            Stepping::Serial => 170,
            Stepping::Parallel if k >= 10_000 && k.is_multiple_of(3) => 2_700,
            Stepping::Parallel => 100,
        };
        let mut c = SteppingChoice::default();
        let mut parallel_after = 0;
        for k in 0..60_000u64 {
            let m = c.next();
            c.record(Duration::from_micros(cost(k, m)));
            parallel_after += u64::from(k >= 10_000 && m == Stepping::Parallel);
        }
        let s = c.stats();
        assert_eq!(s.choice, Some(Stepping::Serial), "{s:?}");
        // A few stalled steps end the hold; later probes lose within their first steps.
        assert!(
            parallel_after < 100,
            "{parallel_after} parallel steps under load: {s:?}"
        );
    }
}

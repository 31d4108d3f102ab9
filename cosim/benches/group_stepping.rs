//! Hand-written benchmark (harness = false): two members of ~150 us each (the air films' cost per
//! 20 us macro step) stepped as a group, always in the pool's threads, always serially, and as
//! `parallel_choice` decides, on a quiet machine and with a competing busy thread per core minus
//! one (what another process does to a run-up). Per mode the median of three runs' mean wall time
//! per group step (the mean, because a stalled step is what load costs).
//! Run: cargo bench -p cosim --bench group_stepping

use cosim::parallel::{Step, StepPool};
use cosim::parallel_choice::{Stepping, SteppingChoice};
use fmi_core::CallError;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// A member that does a fixed amount of arithmetic (like a film's Newton iterations): ~150 us on an
/// idle core, longer when it has to share one.
struct Busy(u64);

fn work(n: u64) -> f64 {
    let mut x = 1.0f64;
    for _ in 0..n {
        x = std::hint::black_box(x * 1.000_000_1 + 1e-9);
    }
    x
}

impl Step for Busy {
    fn step(&mut self, _t: f64, _h: f64) -> Result<(), CallError> {
        std::hint::black_box(work(self.0));
        Ok(())
    }
}

/// Iterations of `work` that take ~150 us here (calibrated on the quiet machine).
fn calibrate() -> u64 {
    let n = 100_000;
    let mut best = f64::INFINITY;
    for _ in 0..20 {
        let t = Instant::now();
        std::hint::black_box(work(n));
        best = best.min(t.elapsed().as_secs_f64());
    }
    (n as f64 * 150e-6 / best) as u64
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

#[derive(Clone, Copy, Debug)]
enum Mode {
    Threads,
    Serial,
    Measured,
}

/// Mean wall time [us] per group step over `steps` steps (the mean: stalls are what load costs).
fn run(mode: Mode, steps: usize, n_work: u64) -> (f64, Option<Stepping>) {
    let pool = StepPool::new(2);
    let mut members = [Busy(n_work), Busy(n_work)];
    let mut choice = SteppingChoice::default();
    let mut walls = Vec::with_capacity(steps);
    for k in 0..steps {
        let way = match mode {
            Mode::Threads => Stepping::Parallel,
            Mode::Serial => Stepping::Serial,
            Mode::Measured => choice.next(),
        };
        let t = Instant::now();
        match way {
            Stepping::Parallel => {
                let [a, b] = &mut members;
                let mut refs = [a, b];
                for r in pool.step(&mut refs, k as f64, 1.0) {
                    r.expect("a busy member does not fail");
                }
            }
            Stepping::Serial => {
                for m in &mut members {
                    m.step(k as f64, 1.0).expect("a busy member does not fail");
                }
            }
        }
        let wall = t.elapsed();
        choice.record(wall);
        walls.push(wall.as_secs_f64() * 1e6);
    }
    let decided = matches!(mode, Mode::Measured)
        .then(|| choice.stats().choice)
        .flatten();
    (mean(&walls), decided)
}

fn main() {
    let n_work = calibrate();
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    for load in [false, true] {
        // Competing busy threads on all cores but one: the run-up has one core to itself.
        let stop = Arc::new(AtomicBool::new(false));
        let competitors: Vec<_> = (0..if load {
            cores.saturating_sub(1).max(1)
        } else {
            0
        })
            .map(|_| {
                let stop = stop.clone();
                std::thread::spawn(move || {
                    let mut x = 1u64;
                    while !stop.load(Ordering::Relaxed) {
                        x = std::hint::black_box(
                            x.wrapping_mul(6364136223846793005).wrapping_add(1),
                        );
                    }
                })
            })
            .collect();
        let label = if load {
            "busy machine"
        } else {
            "quiet machine"
        };
        // A B C A B C: alternated so drift hits every mode alike.
        let mut res: Vec<(Mode, Vec<f64>, Option<Stepping>)> =
            [Mode::Threads, Mode::Serial, Mode::Measured]
                .into_iter()
                .map(|m| (m, vec![], None))
                .collect();
        for _ in 0..3 {
            for r in &mut res {
                let (us, decided) = run(r.0, 2000, n_work);
                r.1.push(us);
                r.2 = decided.or(r.2);
            }
        }
        for (mode, us, decided) in res {
            println!(
                "{label:14} {:8}: {:7.1} us per group step (median of 3 runs' means, 2000 steps each){}",
                format!("{mode:?}"),
                median(us),
                decided.map_or(String::new(), |d| format!(", chose {d:?}"))
            );
        }
        stop.store(true, Ordering::Relaxed);
        for c in competitors {
            let _ = c.join();
        }
    }
}

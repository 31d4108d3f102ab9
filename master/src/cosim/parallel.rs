//! A small pool of persistent worker threads that step the members of one group (the two air
//! films) in parallel.
//!
//! Why not rayon or scoped threads: a macro step lasts ~0.2 ms, and waking a parked thread costs
//! tens of microseconds, which alone would break the master's 2 % overhead budget. The workers spin
//! for a short while after each job (the next one comes within microseconds: only the rotor steps in
//! between) and park only when the master is idle for longer.

use super::gauss_seidel::Subsystem;
use fmi2::importer::CallError;
use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

const IDLE: u8 = 0;
const READY: u8 = 1;
const DONE: u8 = 2;
const QUIT: u8 = 3;

/// How long a worker spins for the next job before it parks. Longer than the gap between two
/// jobs in a whirl (the other film's ~1 ms step plus the rotor's): a parked worker costs a futex
/// wake-up of 50-100 us on the next job, which was 5 % of a path-1 run-up with 100 us here.
const SPIN: Duration = Duration::from_millis(2);

struct Job {
    sub: *mut Subsystem,
    t: f64,
    h: f64,
    result: Option<Result<(), CallError>>,
}

struct Slot {
    state: AtomicU8,
    job: UnsafeCell<Job>,
}

// SAFETY: `job` is written only by the master while `state` is IDLE/DONE and only by the worker while
// it is READY; the Release/Acquire pairs on `state` order those accesses. The Subsystem behind
// `sub` is Send and is exclusively borrowed by the master for the whole time the worker uses it.
unsafe impl Sync for Slot {}
unsafe impl Send for Slot {}

struct Worker {
    slot: Arc<Slot>,
    thread: Option<JoinHandle<()>>,
}

pub struct StepPool {
    workers: Vec<Worker>,
}

/// Spins (then parks, for a worker, or yields, for the master) until `state` is one of `wanted`.
fn wait_for(state: &AtomicU8, wanted: &[u8], park: bool) -> u8 {
    let start = Instant::now();
    let mut spins = 0u32;
    loop {
        let s = state.load(Ordering::Acquire);
        if wanted.contains(&s) {
            return s;
        }
        spins = spins.wrapping_add(1);
        if !spins.is_multiple_of(1024) || start.elapsed() < SPIN {
            std::hint::spin_loop();
        } else if park {
            std::thread::park_timeout(Duration::from_millis(5));
        } else {
            std::thread::yield_now();
        }
    }
}

impl StepPool {
    /// A pool for groups of up to `max_group` members (`max_group - 1` workers; the caller's thread
    /// steps the first member itself).
    pub fn new(max_group: usize) -> StepPool {
        let workers = (1..max_group.max(1))
            .map(|k| {
                let slot = Arc::new(Slot {
                    state: AtomicU8::new(IDLE),
                    job: UnsafeCell::new(Job {
                        sub: std::ptr::null_mut(),
                        t: 0.0,
                        h: 0.0,
                        result: None,
                    }),
                });
                let s = slot.clone();
                let thread = std::thread::Builder::new()
                    .name(format!("airring-step-{k}"))
                    .spawn(move || loop {
                        if wait_for(&s.state, &[READY, QUIT], true) == QUIT {
                            return;
                        }
                        // SAFETY: READY: the master wrote the job and waits for DONE (see Slot).
                        let job = unsafe { &mut *s.job.get() };
                        let sub = unsafe { &mut *job.sub };
                        job.result = Some(sub.do_step(job.t, job.h));
                        s.state.store(DONE, Ordering::Release);
                    })
                    .expect("spawning a worker thread");
                Worker {
                    slot,
                    thread: Some(thread),
                }
            })
            .collect();
        StepPool { workers }
    }

    /// Steps every member over [t, t+h], the first on this thread, the others on the workers.
    pub fn step(
        &self,
        members: &mut [&mut Subsystem],
        t: f64,
        h: f64,
    ) -> Vec<Result<(), CallError>> {
        assert!(
            members.len() <= self.workers.len() + 1,
            "group larger than the pool"
        );
        let (first, rest) = members.split_first_mut().expect("a group has members");
        for (w, m) in self.workers.iter().zip(rest.iter_mut()) {
            // SAFETY: the slot is IDLE (the worker does not touch the job), see Slot.
            unsafe {
                *w.slot.job.get() = Job {
                    sub: &mut **m,
                    t,
                    h,
                    result: None,
                }
            };
            w.slot.state.store(READY, Ordering::Release);
            if let Some(th) = &w.thread {
                th.thread().unpark();
            }
        }
        let mut results = vec![first.do_step(t, h)];
        for w in self.workers.iter().take(rest.len()) {
            wait_for(&w.slot.state, &[DONE], false);
            // SAFETY: DONE: the worker finished with the job.
            let r =
                unsafe { (*w.slot.job.get()).result.take() }.expect("the worker stored a result");
            w.slot.state.store(IDLE, Ordering::Release);
            results.push(r);
        }
        results
    }
}

impl Drop for StepPool {
    fn drop(&mut self) {
        for w in &mut self.workers {
            w.slot.state.store(QUIT, Ordering::Release);
            if let Some(th) = w.thread.take() {
                th.thread().unpark();
                let _ = th.join();
            }
        }
    }
}

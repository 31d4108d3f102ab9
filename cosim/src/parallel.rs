//! A small pool of persistent worker threads that step the members of one group (the two air
//! films) in parallel.
//!
//! Why not rayon or scoped threads: a macro step lasts ~0.2 ms, and waking a parked thread costs
//! tens of microseconds, which alone would break the master's 2 % overhead budget. The workers spin
//! for a short while after each job (the next one comes within microseconds: only the rotor steps in
//! between) and park only when the master is idle for longer.
//!
//! Panics: a member that panics on a worker is reported as that member's failed step (the worker
//! lives on); a member that panics on the caller's thread unwinds only after every worker has
//! finished its job, so no worker is left holding a pointer into a member.

use fmi_core::CallError;
use fmi_core::Status;
use std::cell::UnsafeCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// What the pool steps: one member of a group over [t, t+h].
pub trait Step: Send {
    fn step(&mut self, t: f64, h: f64) -> Result<(), CallError>;
}

/// Work that threads waiting on the pool may do, one small piece at a time: an observer's
/// per-sample work (a time-series row's text and write) taken off the master's thread. A worker
/// waits for its next step while the master steps the rotor and records the macro point, and
/// the master waits for the slower film; in a path-1 run-up that is ~1.6 s of the worker's
/// 3.5 s. A piece must take microseconds: a step handed over meanwhile waits for it.
pub trait IdleWork: Send + Sync {
    /// Does one piece if one is waiting and returns true; false when there is none (or another
    /// thread is doing one).
    fn run_one(&self) -> bool;
}

/// The idle work of one pool, offered by observers (cheap to clone).
#[derive(Clone, Default)]
pub struct IdleWorkers {
    list: Arc<IdleList>,
}

#[derive(Default)]
struct IdleList {
    /// Something was offered (read at every spin: cheaper than the lock).
    any: AtomicBool,
    work: Mutex<Vec<Arc<dyn IdleWork>>>,
}

impl IdleWorkers {
    /// Lets the pool's waiting threads run `work`'s pieces until the pool ends.
    pub fn offer(&self, work: Arc<dyn IdleWork>) {
        let mut list = self.list.work.lock().unwrap_or_else(|p| p.into_inner());
        list.push(work);
        self.list.any.store(true, Ordering::Release);
    }

    /// Takes `work` back (the same allocation as offered): once this returns no waiting thread
    /// runs a piece of it (a piece under way holds the list's lock until it ends), and the list
    /// holds it no more. Observers withdraw their work when their run ends: a `CoSim` (and its
    /// pool) that steps another run would otherwise keep the finished run's work alive and
    /// offer it to its threads.
    pub fn withdraw(&self, work: &Arc<dyn IdleWork>) {
        let mut list = self.list.work.lock().unwrap_or_else(|p| p.into_inner());
        list.retain(|w| !std::ptr::addr_eq(Arc::as_ptr(w), Arc::as_ptr(work)));
        self.list.any.store(!list.is_empty(), Ordering::Release);
    }

    /// One piece of any offered work; false when none was done. A piece that panics is
    /// contained here (the thread goes on waiting for its step) and its work is offered no
    /// more; the work itself sees the panic (a poisoned lock) on its owner's side.
    fn run_one(&self) -> bool {
        if !self.list.any.load(Ordering::Acquire) {
            return false;
        }
        let Ok(mut list) = self.list.work.try_lock() else {
            return false;
        };
        for k in 0..list.len() {
            match catch_unwind(AssertUnwindSafe(|| list[k].run_one())) {
                Ok(true) => return true,
                Ok(false) => {}
                Err(_) => {
                    list.remove(k);
                    self.list.any.store(!list.is_empty(), Ordering::Release);
                    return true;
                }
            }
        }
        false
    }
}

const IDLE: u8 = 0;
const READY: u8 = 1;
const DONE: u8 = 2;
const QUIT: u8 = 3;

/// How long a worker spins for the next job before it parks. Longer than the gap between two
/// jobs in a whirl (the other film's ~1 ms step plus the rotor's): a parked worker costs a futex
/// wake-up of 50-100 us on the next job, which was 5 % of a path-1 run-up with 100 us here.
const SPIN: Duration = Duration::from_millis(2);

/// The error a panicking member's step is reported as.
const PANICKED: CallError = CallError {
    function: "fmi2DoStep (the step panicked in the master's step thread)",
    status: Status::Error,
};

struct Job {
    sub: *mut dyn Step,
    t: f64,
    h: f64,
    result: Option<Result<(), CallError>>,
}

struct Slot {
    state: AtomicU8,
    job: UnsafeCell<Option<Job>>,
}

// SAFETY: `job` is written only by the master while `state` is IDLE/DONE and only by the worker while
// it is READY; the Release/Acquire pairs on `state` order those accesses. The member behind
// `sub` is Send and is exclusively borrowed by the master for the whole time the worker uses it
// (`StepPool::step` does not return, or unwind, before every started job is DONE).
unsafe impl Sync for Slot {}
unsafe impl Send for Slot {}

struct Worker {
    slot: Arc<Slot>,
    thread: Option<JoinHandle<()>>,
}

pub struct StepPool {
    workers: Vec<Worker>,
    idle: IdleWorkers,
}

/// Spins for [`SPIN`] (then parks, for a worker, or yields, for the master) until `state` is one
/// of `wanted`, doing pieces of `idle` work while it spins. Once past the spin, every wake-up
/// parks or yields again at once: a parked worker that spun again after each of its 5 ms
/// time-outs (~1 000 spins) would take CPU from whatever else runs on a busy machine while the
/// films are stepped one after the other.
fn wait_for(state: &AtomicU8, wanted: &[u8], park: bool, idle: &IdleWorkers) -> u8 {
    let start = Instant::now();
    let mut spins = 0u32;
    let mut spinning = true;
    loop {
        let s = state.load(Ordering::Acquire);
        if wanted.contains(&s) {
            return s;
        }
        if spinning {
            if idle.run_one() {
                // A piece took microseconds: the clock is read at the next spin.
                spins |= 1023;
            }
            spins = spins.wrapping_add(1);
            // The clock is read every 1 024 spins only.
            spinning = !spins.is_multiple_of(1024) || start.elapsed() < SPIN;
            std::hint::spin_loop();
        } else if park {
            // The master unparks a worker when it hands over a job (a wake-up before the park
            // makes it return at once); the time-out only bounds a missed one.
            std::thread::park_timeout(PARK_TIMEOUT);
        } else {
            std::thread::yield_now();
        }
    }
}

/// Longest park of an idle worker between checks of its slot.
const PARK_TIMEOUT: Duration = Duration::from_millis(50);

/// Waits, also while unwinding, until the first `n` workers are DONE with their jobs.
struct JoinJobs<'a> {
    workers: &'a [Worker],
    n: usize,
    idle: &'a IdleWorkers,
}

impl Drop for JoinJobs<'_> {
    fn drop(&mut self) {
        for w in &self.workers[..self.n] {
            wait_for(&w.slot.state, &[DONE], false, self.idle);
        }
    }
}

impl StepPool {
    /// A pool for groups of up to `max_group` members (`max_group - 1` workers; the caller's thread
    /// steps the first member itself).
    pub fn new(max_group: usize) -> StepPool {
        let idle = IdleWorkers::default();
        let workers = (1..max_group.max(1))
            .map(|k| {
                let slot = Arc::new(Slot {
                    state: AtomicU8::new(IDLE),
                    job: UnsafeCell::new(None),
                });
                let s = slot.clone();
                let idle = idle.clone();
                let thread = std::thread::Builder::new()
                    .name(format!("cosim-step-{k}"))
                    .spawn(move || loop {
                        if wait_for(&s.state, &[READY, QUIT], true, &idle) == QUIT {
                            return;
                        }
                        // SAFETY: READY: the master wrote the job and waits for DONE (see Slot).
                        if let Some(job) = unsafe { &mut *s.job.get() } {
                            let sub = unsafe { &mut *job.sub };
                            let r = catch_unwind(AssertUnwindSafe(|| sub.step(job.t, job.h)));
                            job.result = Some(r.unwrap_or(Err(PANICKED)));
                        }
                        s.state.store(DONE, Ordering::Release);
                    })
                    .expect("spawning a worker thread");
                Worker {
                    slot,
                    thread: Some(thread),
                }
            })
            .collect();
        StepPool { workers, idle }
    }

    /// Where observers offer work for the threads that wait on this pool.
    pub fn idle_workers(&self) -> IdleWorkers {
        self.idle.clone()
    }

    /// Steps every member over [t, t+h], the first on this thread, the others on the workers.
    /// Returns one result per member, in order.
    pub fn step<S: Step>(
        &self,
        members: &mut [&mut S],
        t: f64,
        h: f64,
    ) -> Vec<Result<(), CallError>> {
        assert!(
            members.len() <= self.workers.len() + 1,
            "group larger than the pool"
        );
        let Some((first, rest)) = members.split_first_mut() else {
            return vec![];
        };
        let mut join = JoinJobs {
            workers: &self.workers,
            n: 0,
            idle: &self.idle,
        };
        for (w, m) in self.workers.iter().zip(rest.iter_mut()) {
            let sub: &mut dyn Step = &mut **m;
            // SAFETY: the slot is IDLE (the worker does not touch the job), see Slot. The
            // lifetime is erased: `join` waits for DONE before `members` can go out of scope.
            unsafe {
                *w.slot.job.get() = Some(Job {
                    sub: std::mem::transmute::<*mut (dyn Step + '_), *mut (dyn Step + 'static)>(
                        sub,
                    ),
                    t,
                    h,
                    result: None,
                })
            };
            w.slot.state.store(READY, Ordering::Release);
            join.n += 1;
            if let Some(th) = &w.thread {
                th.thread().unpark();
            }
        }
        let mut results = vec![first.step(t, h)];
        drop(join);
        for w in self.workers.iter().take(rest.len()) {
            // SAFETY: DONE (waited for by `join`): the worker finished with the job.
            let r = unsafe { (*w.slot.job.get()).take() }
                .and_then(|j| j.result)
                .unwrap_or(Err(PANICKED));
            w.slot.state.store(IDLE, Ordering::Release);
            results.push(r);
        }
        results
    }
}

impl Drop for StepPool {
    fn drop(&mut self) {
        for w in &mut self.workers {
            // A worker is IDLE here (every job was collected), so QUIT reaches it at its next wait.
            w.slot.state.store(QUIT, Ordering::Release);
            if let Some(th) = w.thread.take() {
                th.thread().unpark();
                let _ = th.join();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// A member that counts its steps, panics on demand, and fails on demand.
    struct Member {
        steps: usize,
        panic_at: Option<usize>,
        fail: bool,
        live: Arc<AtomicUsize>,
    }

    impl Drop for Member {
        fn drop(&mut self) {
            self.live.fetch_sub(1, Ordering::SeqCst);
        }
    }

    impl Step for Member {
        fn step(&mut self, _t: f64, _h: f64) -> Result<(), CallError> {
            self.steps += 1;
            std::thread::sleep(Duration::from_millis(2));
            if self.panic_at == Some(self.steps) {
                panic!("member panics in step {}", self.steps);
            }
            if self.fail {
                Err(CallError {
                    function: "fmi2DoStep",
                    status: Status::Discard,
                })
            } else {
                Ok(())
            }
        }
    }

    fn members(n: usize, live: &Arc<AtomicUsize>) -> Vec<Member> {
        live.fetch_add(n, Ordering::SeqCst);
        (0..n)
            .map(|_| Member {
                steps: 0,
                panic_at: None,
                fail: false,
                live: live.clone(),
            })
            .collect()
    }

    #[test]
    fn steps_every_member_and_reports_each_result_in_order() {
        let live = Arc::new(AtomicUsize::new(0));
        let pool = StepPool::new(3);
        let mut m = members(3, &live);
        m[2].fail = true;
        for _ in 0..50 {
            let mut refs: Vec<&mut Member> = m.iter_mut().collect();
            let r = pool.step(&mut refs, 0.0, 1.0);
            assert!(r[0].is_ok() && r[1].is_ok());
            assert_eq!(r[2].as_ref().unwrap_err().status, Status::Discard);
        }
        assert!(m.iter().all(|x| x.steps == 50));
    }

    #[test]
    fn a_member_panicking_on_a_worker_is_a_failed_step_and_the_pool_lives_on() {
        let live = Arc::new(AtomicUsize::new(0));
        let pool = StepPool::new(2);
        let mut m = members(2, &live);
        m[1].panic_at = Some(3);
        for k in 1..=6 {
            let mut refs: Vec<&mut Member> = m.iter_mut().collect();
            let r = pool.step(&mut refs, 0.0, 1.0);
            assert!(r[0].is_ok());
            if k == 3 {
                assert_eq!(r[1].as_ref().unwrap_err(), &PANICKED);
            } else {
                assert!(r[1].is_ok(), "step {k}: {:?}", r[1]);
            }
        }
        assert_eq!(m[1].steps, 6, "the worker survived the panic");
    }

    #[test]
    fn a_member_panicking_on_the_callers_thread_unwinds_after_the_workers_finished() {
        let live = Arc::new(AtomicUsize::new(0));
        let pool = StepPool::new(3);
        let mut m = members(3, &live);
        m[0].panic_at = Some(1);
        let r = catch_unwind(AssertUnwindSafe(|| {
            let mut refs: Vec<&mut Member> = m.iter_mut().collect();
            pool.step(&mut refs, 0.0, 1.0)
        }));
        assert!(r.is_err(), "the caller's panic propagates");
        // Both workers finished their 2 ms jobs before the unwind left `step`.
        assert_eq!(m[1].steps, 1);
        assert_eq!(m[2].steps, 1);
        // The pool is usable again (every slot went back to a collectable state).
        m[0].panic_at = None;
        let mut refs: Vec<&mut Member> = m.iter_mut().collect();
        let r = pool.step(&mut refs, 0.0, 1.0);
        assert!(r.iter().all(|x| x.is_ok()));
        drop(refs);
        drop(pool);
        drop(m);
        assert_eq!(live.load(Ordering::SeqCst), 0);
    }
    /// Work with `n` pieces that counts the pieces done and panics at piece `panic_at`.
    struct Pieces {
        left: AtomicUsize,
        done: AtomicUsize,
        panic_at: Option<usize>,
    }

    impl IdleWork for Pieces {
        fn run_one(&self) -> bool {
            if self
                .left
                .fetch_update(Ordering::AcqRel, Ordering::Acquire, |l| l.checked_sub(1))
                .is_err()
            {
                return false;
            }
            let k = self.done.fetch_add(1, Ordering::AcqRel) + 1;
            if self.panic_at == Some(k) {
                panic!("idle piece {k} panics");
            }
            true
        }
    }

    fn pieces(n: usize, panic_at: Option<usize>) -> Arc<Pieces> {
        Arc::new(Pieces {
            left: AtomicUsize::new(n),
            done: AtomicUsize::new(0),
            panic_at,
        })
    }

    /// Offered work is done by the threads that wait on the pool (the worker between its jobs,
    /// the caller while it waits for the worker), without its owner doing any of it.
    #[test]
    fn threads_waiting_on_the_pool_do_the_offered_work() {
        let live = Arc::new(AtomicUsize::new(0));
        let pool = StepPool::new(2);
        let work = pieces(200, None);
        pool.idle_workers().offer(work.clone());
        let mut m = members(2, &live);
        let mut steps = 0;
        while work.done.load(Ordering::Acquire) < 200 && steps < 2_000 {
            let mut refs: Vec<&mut Member> = m.iter_mut().collect();
            assert!(pool.step(&mut refs, 0.0, 1.0).iter().all(|r| r.is_ok()));
            steps += 1;
        }
        assert_eq!(
            work.done.load(Ordering::Acquire),
            200,
            "after {steps} steps"
        );
        assert!(m.iter().all(|x| x.steps == steps));
    }

    /// Withdrawn work is run no more and the pool holds it no more; other offered work goes on.
    #[test]
    fn withdrawn_work_is_run_no_more_and_released() {
        let live = Arc::new(AtomicUsize::new(0));
        let pool = StepPool::new(2);
        let (first, second) = (pieces(100_000, None), pieces(50, None));
        let offered: Arc<dyn IdleWork> = first.clone();
        pool.idle_workers().offer(offered.clone());
        pool.idle_workers().offer(second.clone());
        let mut m = members(2, &live);
        let mut step = |n: usize| {
            for _ in 0..n {
                let mut refs: Vec<&mut Member> = m.iter_mut().collect();
                assert!(pool.step(&mut refs, 0.0, 1.0).iter().all(|r| r.is_ok()));
            }
        };
        step(20);
        assert!(first.done.load(Ordering::Acquire) > 0, "no piece before");
        pool.idle_workers().withdraw(&offered);
        let done = first.done.load(Ordering::Acquire);
        drop(offered);
        assert_eq!(Arc::strong_count(&first), 1, "the pool still holds it");
        for _ in 0..2_000 {
            if second.done.load(Ordering::Acquire) == 50 {
                break;
            }
            step(1);
        }
        assert_eq!(first.done.load(Ordering::Acquire), done);
        assert_eq!(second.done.load(Ordering::Acquire), 50);
    }

    /// A piece that panics is contained: its work is offered no more, and the pool's steps go on.
    #[test]
    fn a_panicking_piece_of_idle_work_is_dropped_and_the_pool_lives_on() {
        let live = Arc::new(AtomicUsize::new(0));
        let pool = StepPool::new(2);
        let bad = pieces(1_000, Some(3));
        pool.idle_workers().offer(bad.clone());
        let mut m = members(2, &live);
        for _ in 0..20 {
            let mut refs: Vec<&mut Member> = m.iter_mut().collect();
            assert!(pool.step(&mut refs, 0.0, 1.0).iter().all(|r| r.is_ok()));
        }
        assert_eq!(
            bad.done.load(Ordering::Acquire),
            3,
            "no piece after the panic"
        );
        let good = pieces(10, None);
        pool.idle_workers().offer(good.clone());
        for _ in 0..2_000 {
            if good.done.load(Ordering::Acquire) == 10 {
                break;
            }
            let mut refs: Vec<&mut Member> = m.iter_mut().collect();
            assert!(pool.step(&mut refs, 0.0, 1.0).iter().all(|r| r.is_ok()));
        }
        assert_eq!(good.done.load(Ordering::Acquire), 10);
    }
}

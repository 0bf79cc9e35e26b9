//! [`Workers`]: persistent worker threads that share each run with the
//! calling thread, and allocate nothing per run.

use super::Executor;
use std::any::Any;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, TryLockError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// `threads` threads for coif's tasks: the thread that calls
/// [`Executor::run`] and `threads - 1` workers started once, by
/// [`Workers::new`] (the engine asked for them), and joined on drop.
///
/// In `run` the caller works on the tasks beside the workers. Each thread
/// owns a share of the run's indices, the same share of every run of the
/// same count (thread `k` of `T`: indices `count k / T .. count (k + 1) /
/// T`, the caller being thread 0): it takes its own share from the front,
/// then takes what is left of the others' from their backs, one index at
/// a time, until none is left; the caller returns when every task has.
/// So a stage that runs the same tasks every step (the guides' blocks)
/// finds each task's data where that thread left it the step before, in
/// its core's own caches, and a thread that is late (a worker still
/// waking) loses its work to the others, not the run's time. (Measured on
/// Sintel's simulation, `docs/threads.md`: with every task from one
/// shared counter, so that tasks moved between cores from step to step,
/// and workers that yielded while they spun, its tasks took 1.6 ms a
/// frame summed over two threads against 0.94 ms on one; with shares and
/// no yielding, 1.4-1.5 ms, and 1.24 ms where the worker never slept
/// between frames.)
///
/// `Workers::new(2)` keeps two threads busy on two cores, never three:
/// while the caller runs a serial part of a frame between stages (the
/// hair grid's fields, a sort), one worker waits on the other core,
/// spinning about [`Workers::SPIN`] for the next run and then sleeping.
/// [`Executor::wake`] wakes a sleeping worker ahead of a run. A run
/// allocates nothing, on any thread (a rayon pool's caller sleeps while
/// its workers work, and injecting a job from outside it allocates now
/// and then).
///
/// Which thread runs which index can change from run to run; no coif
/// result depends on it. Two threads calling `run` at once, or a task
/// calling `run` again, get a correct result: the second run goes through
/// the calling thread alone. A panicking task does not strand the others:
/// the run finishes every index, then raises the first panic on the
/// caller.
pub struct Workers {
    shared: Arc<Shared>,
    handles: Vec<JoinHandle<()>>,
    threads: usize,
    /// Held for the length of a run: one run at a time uses the workers.
    running: Mutex<()>,
}

/// The most tasks one published run holds; `run` publishes more in turns.
const MAX_RUN: usize = u32::MAX as usize;

/// One thread's share of the current run: the next index to take from
/// the front (bits 32..64) and one past the last (0..32), in one word, so
/// that the owner taking from the front and another thread taking from
/// the back never take the same index (each claim is one compare-exchange
/// of the whole word). On a cache line of its own: its owner claims from
/// it at every task.
#[repr(align(128))]
struct Share(AtomicU64);

impl Share {
    fn pack(next: usize, end: usize) -> u64 {
        (next as u64) << 32 | end as u64
    }
}

struct Shared {
    /// The number of the last run published: the workers wait for it to
    /// change.
    run: AtomicU64,
    /// Per thread (0 the caller, `k` worker `k`): its share of the current
    /// run. Every share is empty between runs (a run returns only once
    /// every index has been claimed and has returned).
    shares: Box<[Share]>,
    /// Tasks of the current run that have returned (or panicked).
    done: AtomicUsize,
    /// The address of the current run's `&(dyn Fn(usize) + Sync)`, on the
    /// caller's stack.
    task: AtomicUsize,
    /// First task offset of the current run (runs of more than
    /// [`MAX_RUN`] tasks are published in turns).
    offset: AtomicUsize,
    /// The first panic of the current run.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
    /// Workers asleep on `wake` (counted under `sleep`).
    sleepers: AtomicUsize,
    sleep: Mutex<()>,
    wake: Condvar,
    stop: AtomicBool,
    /// Workers that have started (`Workers::new` waits for all of them).
    started: AtomicUsize,
}

impl Shared {
    /// Claims and runs indices of the current run until none is left:
    /// thread `me`'s own share from the front, then the others' from the
    /// back, in thread order after `me`.
    fn drain(&self, me: usize) {
        let threads = self.shares.len();
        for j in (0..threads).map(|d| (me + d) % threads) {
            let share = &self.shares[j].0;
            let own = j == me;
            loop {
                let word = share.load(Ordering::Acquire);
                let (next, end) = ((word >> 32) as usize, (word & u32::MAX as u64) as usize);
                if next >= end {
                    break;
                }
                let (claimed, index) = if own {
                    (Share::pack(next + 1, end), next)
                } else {
                    (Share::pack(next, end - 1), end - 1)
                };
                if share
                    .compare_exchange_weak(word, claimed, Ordering::AcqRel, Ordering::Acquire)
                    .is_err()
                {
                    continue;
                }
                // SAFETY: index `index` of the current run is claimed by
                // this thread and not done, so that run's `run` has not
                // returned: the task it published (read after the claim,
                // which saw the share written after the task) is alive.
                // (A share is non-empty only while its run is open: a
                // claim can only be of the run whose task this reads.)
                let task = unsafe {
                    *(self.task.load(Ordering::Acquire) as *const &(dyn Fn(usize) + Sync))
                };
                let index = self.offset.load(Ordering::Acquire) + index;
                if let Err(payload) = catch_unwind(AssertUnwindSafe(|| task(index))) {
                    let mut first = self.panic.lock().unwrap_or_else(|e| e.into_inner());
                    first.get_or_insert(payload);
                }
                self.done.fetch_add(1, Ordering::AcqRel);
            }
        }
    }

    /// Worker `me`'s life: drain every run, spin a while after each, sleep
    /// until the next.
    fn work(&self, me: usize) {
        let mut seen = self.run.load(Ordering::Acquire);
        self.started.fetch_add(1, Ordering::Release);
        while !self.stop.load(Ordering::Acquire) {
            self.drain(me);
            let idle = Instant::now();
            let mut spins = 0u32;
            loop {
                let run = self.run.load(Ordering::Acquire);
                if run != seen {
                    seen = run;
                    break;
                }
                if self.stop.load(Ordering::Acquire) {
                    return;
                }
                // Spinning, not yielding: on this project's machine a
                // `yield_now` every 64 spins (a system call each) made the
                // tasks on both threads a fifth to a third slower
                // (docs/threads.md).
                spins += 1;
                if spins.is_multiple_of(64) && idle.elapsed() > Workers::SPIN {
                    seen = self.sleep_until_next(seen);
                    break;
                }
                std::hint::spin_loop();
            }
        }
    }

    /// Sleeps until a run after `seen` is published (or the stop, or a
    /// wake with no run: [`Executor::wake`]); returns the last run's
    /// number.
    fn sleep_until_next(&self, seen: u64) -> u64 {
        let mut guard = self.sleep.lock().unwrap_or_else(|e| e.into_inner());
        self.sleepers.fetch_add(1, Ordering::SeqCst);
        if self.run.load(Ordering::SeqCst) == seen && !self.stop.load(Ordering::SeqCst) {
            // One wait: a wake without a run (`Workers::wake`) returns too,
            // and the worker spins again for `SPIN`. (A spurious wake-up
            // does the same.)
            guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
        }
        drop(guard);
        self.sleepers.fetch_sub(1, Ordering::SeqCst);
        self.run.load(Ordering::SeqCst)
    }

    /// Wakes the sleeping workers (after a run or the stop was published,
    /// or ahead of a run).
    fn wake_sleepers(&self) {
        if self.sleepers.load(Ordering::SeqCst) > 0 {
            let _guard = self.sleep.lock().unwrap_or_else(|e| e.into_inner());
            self.wake.notify_all();
        }
    }
}

impl Workers {
    /// How long a worker keeps looking for the next run before it sleeps.
    pub const SPIN: Duration = Duration::from_micros(100);

    /// `threads` threads in all, the caller's included (0 = one per core,
    /// as `std::thread::available_parallelism` says): starts `threads - 1`
    /// workers and waits until each has started. Fails if the system
    /// cannot start a thread.
    pub fn new(threads: usize) -> std::io::Result<Workers> {
        let threads = match threads {
            0 => std::thread::available_parallelism().map_or(1, usize::from),
            n => n,
        };
        let shared = Arc::new(Shared {
            run: AtomicU64::new(0),
            shares: (0..threads).map(|_| Share(AtomicU64::new(0))).collect(),
            done: AtomicUsize::new(0),
            task: AtomicUsize::new(0),
            offset: AtomicUsize::new(0),
            panic: Mutex::new(None),
            sleepers: AtomicUsize::new(0),
            sleep: Mutex::new(()),
            wake: Condvar::new(),
            stop: AtomicBool::new(false),
            started: AtomicUsize::new(0),
        });
        let mut workers = Workers {
            shared,
            handles: Vec::with_capacity(threads - 1),
            threads,
            running: Mutex::new(()),
        };
        for k in 1..threads {
            let shared = Arc::clone(&workers.shared);
            let handle = std::thread::Builder::new()
                .name(format!("coif-worker-{k}"))
                .spawn(move || shared.work(k))?;
            workers.handles.push(handle);
        }
        // Started before `new` returns, so that what a thread's start
        // allocates (the standard library's own, such as its name for the
        // stack overflow handler) falls here, not in a later run.
        while workers.shared.started.load(Ordering::Acquire) < threads - 1 {
            std::thread::yield_now();
        }
        Ok(workers)
    }

    /// Publishes `count` (at most [`MAX_RUN`]) tasks from `offset`, one
    /// share per thread, drains them beside the workers and waits for
    /// every one.
    fn run_published(&self, offset: usize, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let sh = &*self.shared;
        sh.task.store(
            &task as *const &(dyn Fn(usize) + Sync) as usize,
            Ordering::Release,
        );
        sh.offset.store(offset, Ordering::Release);
        sh.done.store(0, Ordering::Release);
        let threads = sh.shares.len();
        for (k, share) in sh.shares.iter().enumerate() {
            let (from, to) = (count * k / threads, count * (k + 1) / threads);
            share.0.store(Share::pack(from, to), Ordering::SeqCst);
        }
        sh.run.fetch_add(1, Ordering::SeqCst);
        sh.wake_sleepers();
        sh.drain(0);
        // The last tasks are the workers': spin for them, and yield now and
        // then only once the wait is long (a worker preempted, threads
        // beyond the cores).
        let waiting = Instant::now();
        let mut spins = 0u32;
        while sh.done.load(Ordering::Acquire) < count {
            spins += 1;
            if spins.is_multiple_of(64) && waiting.elapsed() > Workers::SPIN {
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
    }
}

impl std::fmt::Debug for Workers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workers")
            .field("threads", &self.threads)
            .finish()
    }
}

impl Drop for Workers {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.shared.wake_sleepers();
        for handle in self.handles.drain(..) {
            let _ = handle.join();
        }
    }
}

// SAFETY: an index is run only by the thread whose compare-exchange took
// it off its share's front or back (each value once), and `run` returns
// only when `done` has counted every index of every turn; a second run at
// the same time (another caller, or a task) goes through `Serial`'s loop.
unsafe impl Executor for Workers {
    fn threads(&self) -> usize {
        self.threads
    }

    /// Wakes the sleeping workers, which then spin for [`Workers::SPIN`]
    /// waiting for the run.
    fn wake(&self) {
        self.shared.wake_sleepers();
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let guard = match self.running.try_lock() {
            Ok(guard) => Some(guard),
            Err(TryLockError::Poisoned(e)) => Some(e.into_inner()),
            Err(TryLockError::WouldBlock) => None,
        };
        if guard.is_none() || self.threads == 1 || count <= 1 {
            drop(guard);
            return (0..count).for_each(task);
        }
        let mut offset = 0;
        while offset < count {
            let turn = (count - offset).min(MAX_RUN);
            self.run_published(offset, turn, task);
            offset += turn;
        }
        let panic = self
            .shared
            .panic
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take();
        if let Some(payload) = panic {
            resume_unwind(payload);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::run_all;
    use super::*;
    use std::sync::atomic::AtomicU32;

    #[test]
    fn every_index_runs_once_at_any_thread_count() {
        for threads in [1, 2, 3, 8] {
            let workers = Workers::new(threads).unwrap();
            assert_eq!(workers.threads(), threads);
            for _ in 0..50 {
                run_all(&workers);
            }
            // Runs of every size, back to back: each index exactly once.
            for count in [0, 1, 2, 7, 64, 1000] {
                let hits: Vec<AtomicU32> = (0..count).map(|_| AtomicU32::new(0)).collect();
                workers.run(count, &|i| {
                    hits[i].fetch_add(1, Ordering::Relaxed);
                });
                assert!(hits.iter().all(|h| h.load(Ordering::Relaxed) == 1));
            }
        }
        assert!(Workers::new(0).unwrap().threads() >= 1, "0 = one per core");
    }

    #[test]
    fn a_run_after_the_workers_slept_still_uses_them() {
        let workers = Workers::new(2).unwrap();
        run_all(&workers);
        std::thread::sleep(Workers::SPIN * 20);
        // A task that waits for another thread to start a second task can
        // only finish if a worker woke up and took one.
        let started = AtomicUsize::new(0);
        workers.run(2, &|_| {
            started.fetch_add(1, Ordering::SeqCst);
            let t = Instant::now();
            while started.load(Ordering::SeqCst) < 2 {
                assert!(
                    t.elapsed() < Duration::from_secs(20),
                    "no worker took a task"
                );
                std::hint::spin_loop();
            }
        });
    }

    #[test]
    fn each_thread_takes_its_own_share_first_then_the_others_from_the_back() {
        let workers = Workers::new(2).unwrap();
        for _ in 0..20 {
            // Four tasks on two threads: the caller's share is 0..2, the
            // worker's 2..4. Task 0 (the caller's first) waits until task
            // 2 has started on another thread, so the worker must take its
            // own share front to back and then the caller's last index.
            let order = Mutex::new(Vec::new());
            let started_two = AtomicBool::new(false);
            let caller = std::thread::current().id();
            workers.run(4, &|i| {
                if i == 0 {
                    let t = Instant::now();
                    while !started_two.load(Ordering::SeqCst) {
                        assert!(t.elapsed() < Duration::from_secs(20), "no worker took 2");
                        std::hint::spin_loop();
                    }
                    // And until the worker has taken the rest.
                    while order.lock().unwrap().len() < 3 {
                        assert!(t.elapsed() < Duration::from_secs(20), "the worker stopped");
                        std::hint::spin_loop();
                    }
                    return;
                }
                assert_ne!(
                    std::thread::current().id(),
                    caller,
                    "task {i} ran on the caller"
                );
                if i == 2 {
                    started_two.store(true, Ordering::SeqCst);
                }
                order.lock().unwrap().push(i);
            });
            assert_eq!(*order.lock().unwrap(), vec![2, 3, 1]);
        }
    }

    #[test]
    fn wake_wakes_a_sleeping_worker_which_sleeps_again_with_no_run() {
        let workers = Workers::new(2).unwrap();
        let sleepers = || workers.shared.sleepers.load(Ordering::SeqCst);
        let until = |what: &str, f: &dyn Fn() -> bool| {
            let t = Instant::now();
            while !f() {
                assert!(t.elapsed() < Duration::from_secs(20), "{what}");
                std::thread::sleep(Duration::from_micros(50));
            }
        };
        until("the worker never slept", &|| sleepers() == 1);
        // Awake it spins for `SPIN` and sleeps again: watched by spinning
        // here, a few tries (this thread may be descheduled through one).
        let woke = (0..50).any(|_| {
            until("the worker did not sleep again", &|| sleepers() == 1);
            workers.wake();
            let t = Instant::now();
            while t.elapsed() < Duration::from_millis(5) {
                if sleepers() == 0 {
                    return true;
                }
                std::hint::spin_loop();
            }
            false
        });
        assert!(woke, "wake did not wake the sleeping worker");
        until("it did not sleep again", &|| sleepers() == 1);
        // And a run after it still uses it.
        run_all(&workers);
    }

    #[test]
    fn a_panic_is_raised_on_the_caller_after_every_other_task() {
        let workers = Workers::new(3).unwrap();
        for bad in [0, 5, 9] {
            let done = AtomicUsize::new(0);
            let caught = catch_unwind(AssertUnwindSafe(|| {
                workers.run(10, &|i| {
                    if i == bad {
                        panic!("task {bad}");
                    }
                    done.fetch_add(1, Ordering::Relaxed);
                })
            }));
            let payload = caught.expect_err("the panic reaches the caller");
            assert_eq!(
                payload.downcast_ref::<String>().map(String::as_str),
                Some(format!("task {bad}").as_str())
            );
            assert_eq!(done.load(Ordering::Relaxed), 9, "the other tasks ran");
        }
        // And the pool still works.
        run_all(&workers);
    }

    #[test]
    fn nested_and_concurrent_runs_finish() {
        let workers = Workers::new(2).unwrap();
        // A task that runs the executor again: that run is the caller's.
        let inner = AtomicUsize::new(0);
        workers.run(4, &|_| {
            workers.run(3, &|_| {
                inner.fetch_add(1, Ordering::Relaxed);
            });
        });
        assert_eq!(inner.load(Ordering::Relaxed), 12);
        // Two threads running it at once.
        let total = AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..2 {
                s.spawn(|| {
                    for _ in 0..200 {
                        workers.run(5, &|_| {
                            total.fetch_add(1, Ordering::Relaxed);
                        });
                    }
                });
            }
        });
        assert_eq!(total.load(Ordering::Relaxed), 2 * 200 * 5);
    }
}

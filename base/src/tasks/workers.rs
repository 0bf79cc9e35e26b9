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
/// In `run` the caller works on the tasks beside the workers: every thread
/// takes the next undone index from one shared counter until none is
/// left, and the caller returns when every task has. So `Workers::new(2)`
/// keeps two threads busy on two cores, never three: while the caller
/// runs a serial part of a frame between stages (the hair grid, a sort),
/// one worker waits on the other core, spinning about
/// [`Workers::SPIN`] for the next run and then sleeping. A run allocates
/// nothing, on any thread (a rayon pool's caller sleeps while its
/// workers work, and injecting a job from outside it allocates now and
/// then).
///
/// Which thread runs which index changes from run to run; no coif result
/// depends on it. Two threads calling `run` at once, or a task calling
/// `run` again, get a correct result: the second run goes through the
/// calling thread alone. A panicking task does not strand the others: the
/// run finishes every index, then raises the first panic on the caller.
pub struct Workers {
    shared: Arc<Shared>,
    handles: Vec<JoinHandle<()>>,
    threads: usize,
    /// Held for the length of a run: one run at a time uses the workers.
    running: Mutex<()>,
}

/// Bits of the run word given to the task count and to the next index.
const INDEX_BITS: u32 = 24;
const INDEX_MASK: u64 = (1 << INDEX_BITS) - 1;
/// The most tasks one published run holds; `run` publishes more in turns.
const MAX_RUN: usize = INDEX_MASK as usize;

struct Shared {
    /// The current run in one word, so that a claim sees all of it at
    /// once: a run number (bits 48..64), the task count (24..48) and the
    /// next index to hand out (0..24). An index below the count is
    /// claimed by the one compare-exchange that moves the next index past
    /// it.
    word: AtomicU64,
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
}

impl Shared {
    /// Whether `word` has an index left to claim.
    fn open(word: u64) -> bool {
        (word & INDEX_MASK) < ((word >> INDEX_BITS) & INDEX_MASK)
    }

    /// Claims and runs indices of the current run until none is left.
    fn drain(&self) {
        loop {
            let word = self.word.load(Ordering::Acquire);
            if !Self::open(word) {
                return;
            }
            if self
                .word
                .compare_exchange_weak(word, word + 1, Ordering::AcqRel, Ordering::Acquire)
                .is_err()
            {
                continue;
            }
            // SAFETY: index `word & INDEX_MASK` of the current run is claimed
            // by this thread and not done, so that run's `run` has not
            // returned: the task it published (read after the word, which
            // was published after it) is alive.
            let task =
                unsafe { *(self.task.load(Ordering::Acquire) as *const &(dyn Fn(usize) + Sync)) };
            let index = self.offset.load(Ordering::Acquire) + (word & INDEX_MASK) as usize;
            if let Err(payload) = catch_unwind(AssertUnwindSafe(|| task(index))) {
                let mut first = self.panic.lock().unwrap_or_else(|e| e.into_inner());
                first.get_or_insert(payload);
            }
            self.done.fetch_add(1, Ordering::AcqRel);
        }
    }

    /// A worker's life: drain every run, spin a while after each, sleep
    /// until the next.
    fn work(&self) {
        while !self.stop.load(Ordering::Acquire) {
            self.drain();
            let idle = Instant::now();
            let mut spins = 0u32;
            while !Self::open(self.word.load(Ordering::Acquire)) {
                if self.stop.load(Ordering::Acquire) {
                    return;
                }
                spins += 1;
                if spins.is_multiple_of(64) {
                    if idle.elapsed() > Workers::SPIN {
                        self.sleep_until_open();
                        break;
                    }
                    std::thread::yield_now();
                } else {
                    std::hint::spin_loop();
                }
            }
        }
    }

    fn sleep_until_open(&self) {
        let mut guard = self.sleep.lock().unwrap_or_else(|e| e.into_inner());
        self.sleepers.fetch_add(1, Ordering::SeqCst);
        while !Self::open(self.word.load(Ordering::SeqCst)) && !self.stop.load(Ordering::SeqCst) {
            guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
        }
        self.sleepers.fetch_sub(1, Ordering::SeqCst);
    }

    /// Wakes the sleeping workers (after a run or the stop was published).
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
    /// workers. Fails if the system cannot start a thread.
    pub fn new(threads: usize) -> std::io::Result<Workers> {
        let threads = match threads {
            0 => std::thread::available_parallelism().map_or(1, usize::from),
            n => n,
        };
        let shared = Arc::new(Shared {
            word: AtomicU64::new(0),
            done: AtomicUsize::new(0),
            task: AtomicUsize::new(0),
            offset: AtomicUsize::new(0),
            panic: Mutex::new(None),
            sleepers: AtomicUsize::new(0),
            sleep: Mutex::new(()),
            wake: Condvar::new(),
            stop: AtomicBool::new(false),
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
                .spawn(move || shared.work())?;
            workers.handles.push(handle);
        }
        Ok(workers)
    }

    /// Publishes `count` (at most [`MAX_RUN`]) tasks from `offset`, drains
    /// them beside the workers and waits for every one.
    fn run_published(&self, offset: usize, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let sh = &*self.shared;
        sh.task.store(
            &task as *const &(dyn Fn(usize) + Sync) as usize,
            Ordering::Release,
        );
        sh.offset.store(offset, Ordering::Release);
        sh.done.store(0, Ordering::Release);
        let number = ((sh.word.load(Ordering::Acquire) >> 48) + 1) & 0xffff;
        sh.word.store(
            number << 48 | (count as u64) << INDEX_BITS,
            Ordering::SeqCst,
        );
        sh.wake_sleepers();
        sh.drain();
        let mut spins = 0u32;
        while sh.done.load(Ordering::Acquire) < count {
            spins += 1;
            if spins.is_multiple_of(64) {
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

// SAFETY: an index is run only by the thread whose compare-exchange moved
// the run word's next index past it (each value once), and `run` returns
// only when `done` has counted every index of every turn; a second run at
// the same time (another caller, or a task) goes through `Serial`'s loop.
unsafe impl Executor for Workers {
    fn threads(&self) -> usize {
        self.threads
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

//! Engine-style executors for the thread tests: what an engine's job system
//! might do with coif's tasks (any order, its own threads, a C callback),
//! none of it rayon.

use coif_kernels::tasks::{CTask, Callback, Executor};
use std::ffi::c_void;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// Runs the tasks last first, on the calling thread (testkit's).
pub use coif_testkit::executors::Backwards;

/// Starts `n` scoped threads per run; each takes the next index from a
/// shared counter (the order changes from run to run).
pub struct Scoped(pub usize);

// SAFETY: each index is claimed once by `fetch_add`; the scope joins every
// thread before `run` returns.
unsafe impl Executor for Scoped {
    fn threads(&self) -> usize {
        self.0
    }
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let next = AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..self.0 {
                s.spawn(|| loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= count {
                        break;
                    }
                    task(i);
                });
            }
        });
    }
}

/// A C parallel-for: three scoped threads, each taking every third index
/// from the last one down.
unsafe extern "C" fn three_threads_backwards(
    _ctx: *mut c_void,
    count: usize,
    task: CTask,
    task_ctx: *mut c_void,
) {
    let task_ctx = task_ctx as usize;
    std::thread::scope(|s| {
        for part in 0..3 {
            s.spawn(move || {
                for i in (0..count).rev().filter(|i| i % 3 == part) {
                    // SAFETY: each index once, before this function returns.
                    unsafe { task(task_ctx as *mut c_void, i) };
                }
            });
        }
    });
}

/// [`three_threads_backwards`] behind coif's C-callable executor.
pub fn c_callback() -> Callback {
    // SAFETY: the callback runs each index once and returns after the last.
    unsafe { Callback::new(three_threads_backwards, std::ptr::null_mut(), 3) }
}

/// A pool of persistent worker threads that spin for work, as a game
/// engine's workers do: `run` allocates nothing, so a count of every
/// thread's allocations sees only coif's.
pub struct SpinPool {
    shared: Arc<Shared>,
    workers: Vec<JoinHandle<()>>,
}

const MASK: u64 = (1 << 24) - 1;

struct Shared {
    /// The run in one word, so a claim sees them together: generation
    /// (bits 48..64), task count (24..48), next index (0..24).
    next: AtomicU64,
    done: AtomicUsize,
    /// The current run's `&&(dyn Fn(usize) + Sync)`, as an address.
    task: AtomicUsize,
    stop: AtomicBool,
}

impl Shared {
    /// Claims and runs indices of the current generation `generation`
    /// until none is left.
    fn work(&self, generation: u64) {
        loop {
            let v = self.next.load(Ordering::Acquire);
            let (g, count, i) = (v >> 48, (v >> 24) & MASK, v & MASK);
            if g != generation || i >= count {
                return;
            }
            if self
                .next
                .compare_exchange(v, v + 1, Ordering::AcqRel, Ordering::Acquire)
                .is_err()
            {
                continue;
            }
            // SAFETY: index i of this generation is claimed, so its run has
            // not returned and the task it published is alive.
            let task =
                unsafe { *(self.task.load(Ordering::Acquire) as *const &(dyn Fn(usize) + Sync)) };
            task(i as usize);
            self.done.fetch_add(1, Ordering::AcqRel);
        }
    }
}

impl SpinPool {
    /// `workers` threads besides the caller, which works too.
    pub fn new(workers: usize) -> SpinPool {
        let shared = Arc::new(Shared {
            next: AtomicU64::new(0),
            done: AtomicUsize::new(0),
            task: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
        });
        let workers = (0..workers)
            .map(|_| {
                let sh = Arc::clone(&shared);
                std::thread::spawn(move || {
                    while !sh.stop.load(Ordering::Acquire) {
                        let generation = sh.next.load(Ordering::Acquire) >> 48;
                        sh.work(generation);
                        std::thread::yield_now();
                    }
                })
            })
            .collect();
        SpinPool { shared, workers }
    }
}

impl Drop for SpinPool {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
    }
}

// SAFETY: an index is run only by the thread whose compare-exchange claimed
// it in the run's generation, and `run` returns once `done == count`.
unsafe impl Executor for SpinPool {
    fn threads(&self) -> usize {
        self.workers.len() + 1
    }
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let sh = &self.shared;
        sh.task.store(
            &task as *const &(dyn Fn(usize) + Sync) as usize,
            Ordering::Release,
        );
        sh.done.store(0, Ordering::Release);
        let generation = ((sh.next.load(Ordering::Acquire) >> 48) + 1) & 0xffff;
        assert!(count as u64 <= MASK, "SpinPool runs at most 2^24 tasks");
        sh.next
            .store(generation << 48 | (count as u64) << 24, Ordering::Release);
        sh.work(generation);
        while sh.done.load(Ordering::Acquire) < count {
            std::thread::yield_now();
        }
    }
}

/// Serial, the reverse order, two and three scoped threads, a rayon pool
/// of two and coif's workers of three: the executors the "same bytes on any thread count" tests
/// run a step on.
pub fn all() -> Vec<Box<dyn Executor>> {
    vec![
        Box::new(coif_kernels::tasks::Serial),
        Box::new(Backwards(1)),
        Box::new(Scoped(2)),
        Box::new(Scoped(3)),
        Box::new(coif_kernels::tasks::Rayon::new(2).expect("a rayon pool")),
        Box::new(coif_kernels::tasks::Workers::new(3).expect("three threads")),
    ]
}

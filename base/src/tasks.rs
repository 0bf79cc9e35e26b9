//! Tasks: how coif's per-frame stages run on more than one thread without
//! owning any.
//!
//! Every parallel stage is a set of `count` independent tasks, numbered
//! `0..count`; task `i` reads shared input and writes only its own part of
//! the output, and any reduction happens afterwards, in index order, on the
//! calling thread. So the result is the same bytes whatever thread runs
//! which task, and with any number of threads.
//!
//! Who runs the tasks is the caller's choice, through [`Executor`]:
//!
//! - [`Serial`]: on the calling thread, in index order (no threads at all);
//! - `Rayon` (Cargo feature `rayon`, on by default): a rayon thread pool;
//! - the engine's own job system: implement [`Executor`] with a
//!   parallel-for that hands the indices to its workers and waits for them
//!   (the shape of PhysX's `CpuDispatcher` and Jolt's `JobSystem`, reduced to
//!   what a stage of independent tasks needs: no task here waits on another).
//!
//! Stages that need an order (build, then read) are run one after another
//! by the caller; an executor never sees a dependency.

/// Runs a stage's tasks.
///
/// # Safety
///
/// Implementors promise that [`Executor::run`] calls `task(i)` exactly once
/// for every `i` in `0..count` (never twice, never concurrently with itself
/// for the same `i`) and returns only after every call has returned. coif's
/// stages hand each task a disjoint `&mut` part of their output on that
/// promise ([`for_each_chunk_mut`]), so breaking it is undefined behaviour.
pub unsafe trait Executor: Sync {
    /// How many tasks may run at once (1 for a serial executor). Stages use
    /// it only to choose how finely to split work, never for the result.
    fn threads(&self) -> usize;

    /// Runs `task(0)`, ..., `task(count - 1)`, in any order and on any
    /// threads, and returns when all of them have returned.
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync));
}

/// Runs every task on the calling thread, in index order.
#[derive(Clone, Copy, Debug, Default)]
pub struct Serial;

// SAFETY: each index runs once, in order, before `run` returns.
unsafe impl Executor for Serial {
    fn threads(&self) -> usize {
        1
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        for i in 0..count {
            task(i);
        }
    }
}

/// A raw pointer that may cross threads; only [`for_each_chunk_mut`] builds
/// one, for slices whose chunks it hands out disjointly.
struct SendPtr<T>(*mut T);
// SAFETY: the pointee is `T: Send`, and each chunk is reached by one task only.
unsafe impl<T: Send> Send for SendPtr<T> {}
// SAFETY: as above: tasks share the pointer but never the same chunk.
unsafe impl<T: Send> Sync for SendPtr<T> {}

impl<T> SendPtr<T> {
    fn get(&self) -> *mut T {
        self.0
    }
}

/// Splits `data` into chunks of `chunk_len` items (the last may be shorter)
/// and runs `f(i, chunk_i)` for each, one task per chunk, on `executor`.
/// With `chunk_len == 0` or empty `data` nothing runs.
pub fn for_each_chunk_mut<T: Send>(
    executor: &dyn Executor,
    data: &mut [T],
    chunk_len: usize,
    f: &(dyn Fn(usize, &mut [T]) + Sync),
) {
    if chunk_len == 0 || data.is_empty() {
        return;
    }
    let len = data.len();
    let count = len.div_ceil(chunk_len);
    let base = SendPtr(data.as_mut_ptr());
    executor.run(count, &|i| {
        if i >= count {
            return;
        }
        let start = i * chunk_len;
        let n = chunk_len.min(len - start);
        // SAFETY: chunk i is [start, start + n) within `data`, disjoint from
        // every other chunk, and the executor runs each i once while `data`
        // stays mutably borrowed by this call.
        let chunk = unsafe { std::slice::from_raw_parts_mut(base.get().add(start), n) };
        f(i, chunk);
    });
}

#[cfg(feature = "rayon")]
mod rayon_executor {
    use super::Executor;

    /// A rayon thread pool of a fixed size, built once (Cargo feature
    /// `rayon`). Tasks are handed out by rayon's work stealing; the result
    /// does not depend on which thread runs which.
    pub struct Rayon {
        pool: rayon::ThreadPool,
        threads: usize,
    }

    impl Rayon {
        /// A pool of `threads` workers (0 = one per core).
        pub fn new(threads: usize) -> Result<Rayon, rayon::ThreadPoolBuildError> {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?;
            let threads = pool.current_num_threads();
            Ok(Rayon { pool, threads })
        }
    }

    impl std::fmt::Debug for Rayon {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.debug_struct("Rayon")
                .field("threads", &self.threads)
                .finish()
        }
    }

    // SAFETY: rayon's parallel range runs each index once and `install`
    // returns after every one has finished.
    unsafe impl Executor for Rayon {
        fn threads(&self) -> usize {
            self.threads
        }

        fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
            use rayon::prelude::*;
            if count == 0 {
                return;
            }
            if self.threads == 1 || count == 1 {
                (0..count).for_each(task);
                return;
            }
            self.pool
                .install(|| (0..count).into_par_iter().for_each(task));
        }
    }
}

#[cfg(feature = "rayon")]
pub use rayon_executor::Rayon;

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn run_all(executor: &dyn Executor) {
        let mut data: Vec<u32> = (0..1001).collect();
        for_each_chunk_mut(executor, &mut data, 64, &|i, chunk| {
            for (j, x) in chunk.iter_mut().enumerate() {
                *x = *x * 3 + (i * 64 + j) as u32;
            }
        });
        for (k, x) in data.iter().enumerate() {
            assert_eq!(*x, 4 * k as u32);
        }
        let calls = AtomicUsize::new(0);
        executor.run(37, &|_| {
            calls.fetch_add(1, Ordering::Relaxed);
        });
        assert_eq!(calls.load(Ordering::Relaxed), 37);
    }

    #[test]
    fn serial_runs_every_chunk_once() {
        run_all(&Serial);
    }

    #[cfg(feature = "rayon")]
    #[test]
    fn rayon_runs_every_chunk_once() {
        for threads in [1, 2, 3, 8] {
            run_all(&Rayon::new(threads).unwrap());
        }
    }
}

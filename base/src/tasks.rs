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
//! - [`Workers`]: the calling thread and `threads - 1` worker threads that
//!   [`Workers::new`] starts (the caller asked for them) and its drop
//!   joins; the caller works on each run beside them, and a run allocates
//!   nothing (what the demo's `--threads` uses);
//! - `Rayon` (Cargo feature `rayon`, on by default): a rayon thread pool,
//!   for a host already on rayon (its caller sleeps while the pool works);
//! - the engine's own job system: implement [`Executor`] with a
//!   parallel-for that hands the indices to its workers and waits for them,
//!   or wrap a C callback of that shape in [`Callback`].
//!
//! # Mapping onto an engine's job system
//!
//! PhysX asks the engine for a `PxCpuDispatcher` (`submitTask(task)`, which
//! queues one task and returns, and `getWorkerCount()`); its tasks signal
//! completion through continuation tasks. Jolt asks for a `JobSystem`
//! (`GetMaxConcurrency()`, `CreateJob(name, colour, function,
//! dependencies)` from a fixed-size job pool, and `WaitForJobs(barrier)`, on
//! whose calling thread queued jobs may run while it waits). coif's stages
//! need less than either: no task waits on another and no task creates
//! tasks, so one blocking parallel-for per stage is the whole interface:
//!
//! - [`Executor::threads`] is `getWorkerCount` / `GetMaxConcurrency` (a
//!   hint for how finely to split; never part of any result);
//! - [`Executor::wake`] (optional, a no-op by default) says a run comes
//!   soon: a job system whose workers sleep may wake them ahead of it;
//! - [`Executor::run`] is "create `count` jobs (or fewer jobs that each take
//!   a range of indices), add them to a barrier, wait for it". The calling
//!   thread may run tasks itself while it waits, as Jolt's does;
//! - coif never calls `run` from inside one of its own tasks (no nesting),
//!   so an engine whose wait may only happen outside its jobs (Jolt's one
//!   waiter per barrier) is fine as long as it calls coif from outside them;
//! - stages keep `count` small (the strand step makes at most 64 tasks
//!   however many strands there are), so a
//!   fixed-size job pool never runs dry;
//! - a task never panics on bad data (coif's rule); [`Callback`] still
//!   catches a panic at the C boundary and re-raises it after the wait.
//!
//! Stages that need an order (build, then read) are run one after another
//! by the caller; an executor never sees a dependency.

use std::ffi::c_void;
use std::marker::PhantomData;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::Mutex;

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

    /// A hint that a run comes soon: an executor whose threads sleep
    /// between runs may start waking them now, so that they are awake when
    /// the run is published rather than some tens of microseconds into it.
    /// Never needed for a correct result; the default does nothing.
    /// coif calls it where a step or a frame begins, ahead of the serial
    /// work before its first run ([`Workers`] wakes its sleeping workers);
    /// an engine can call it earlier still, when its own frame begins (a
    /// sleeping core can take longer to wake than coif's set-up lasts).
    fn wake(&self) {}
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

/// A mutable slice that a stage's tasks write in disjoint parts: how one
/// task gets parts of several output arrays (for one array,
/// [`for_each_chunk_mut`] does it safely), or writes scattered elements
/// whose disjointness the stage guarantees (a prefix sum of counts, as in
/// a binning pass).
pub struct DisjointMut<'a, T> {
    base: SendPtr<T>,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

impl<'a, T: Send> DisjointMut<'a, T> {
    /// Borrows `data` mutably for as long as the view lives.
    pub fn new(data: &'a mut [T]) -> DisjointMut<'a, T> {
        DisjointMut {
            base: SendPtr(data.as_mut_ptr()),
            len: data.len(),
            _borrow: PhantomData,
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the slice is empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Elements `start..start + len`; panics when they are out of bounds.
    ///
    /// # Safety
    ///
    /// While the returned slice lives, no other call of [`DisjointMut::range`]
    /// or [`DisjointMut::set`] on this view may touch any of its elements,
    /// on any thread.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn range(&self, start: usize, len: usize) -> &mut [T] {
        assert!(start <= self.len && len <= self.len - start);
        // SAFETY: in bounds (asserted); exclusive by the caller's promise.
        unsafe { std::slice::from_raw_parts_mut(self.base.get().add(start), len) }
    }

    /// Writes `value` at `i` (the old value is dropped); panics when `i` is
    /// out of bounds.
    ///
    /// # Safety
    ///
    /// No other thread reads or writes element `i` at the same time, and no
    /// slice from [`DisjointMut::range`] that holds it is alive.
    pub unsafe fn set(&self, i: usize, value: T) {
        assert!(i < self.len);
        // SAFETY: in bounds (asserted); exclusive by the caller's promise.
        unsafe { *self.base.get().add(i) = value };
    }
}

/// A C task: runs task `index` of the stage whose context is `task_ctx`.
pub type CTask = unsafe extern "C" fn(task_ctx: *mut c_void, index: usize);

/// A C parallel-for: must call `task(task_ctx, i)` once for every `i` in
/// `0..count`, on any threads, and return after the last call returned.
/// `ctx` is the engine's own pointer given to [`Callback::new`].
pub type CRun =
    unsafe extern "C" fn(ctx: *mut c_void, count: usize, task: CTask, task_ctx: *mut c_void);

/// An engine's job system seen through one C function,
/// `void (*run)(void *ctx, size_t count, void (*task)(void *, size_t), void *task_ctx)`
/// (the form the C interface takes). Each [`Executor::run`] becomes one call
/// of `run` with a task function that calls the stage's task `i`; a panic
/// inside a task (coif's tasks do not panic, by rule) is caught before it
/// reaches C and raised again once `run` has returned.
#[derive(Debug)]
pub struct Callback {
    run: CRun,
    ctx: *mut c_void,
    threads: usize,
}

// SAFETY: `Callback::new`'s caller promises that `run` may be called with
// `ctx` from any thread, concurrently.
unsafe impl Send for Callback {}
// SAFETY: as above.
unsafe impl Sync for Callback {}

impl Callback {
    /// Wraps `run` and its context; `threads` is the job system's worker
    /// count (a splitting hint; 0 counts as 1).
    ///
    /// # Safety
    ///
    /// `run` must keep [`CRun`]'s promise (each index exactly once, none
    /// after it returns, no unwinding out of it), and `run` with `ctx` must
    /// be callable from any thread for as long as the `Callback` lives.
    pub unsafe fn new(run: CRun, ctx: *mut c_void, threads: usize) -> Callback {
        Callback { run, ctx, threads }
    }
}

/// What [`Callback::run`] hands C as `task_ctx`.
struct Trampoline<'a> {
    task: &'a (dyn Fn(usize) + Sync),
    count: usize,
    panic: Mutex<Option<Box<dyn std::any::Any + Send>>>,
}

/// The [`CTask`] behind every [`Callback`]: task `index` of the
/// [`Trampoline`] at `task_ctx`, with any panic kept for the caller.
unsafe extern "C" fn trampoline(task_ctx: *mut c_void, index: usize) {
    // SAFETY: `Callback::run` passes a pointer to a live `Trampoline` and
    // `run` calls this only before it returns.
    let t = unsafe { &*(task_ctx as *const Trampoline<'_>) };
    if index >= t.count {
        return;
    }
    if let Err(payload) = catch_unwind(AssertUnwindSafe(|| (t.task)(index))) {
        if let Ok(mut slot) = t.panic.lock() {
            slot.get_or_insert(payload);
        }
    }
}

// SAFETY: `Callback::new`'s caller promised that `run` calls each index
// once and returns after the last call; the trampoline forwards each call
// to `task` once.
unsafe impl Executor for Callback {
    fn threads(&self) -> usize {
        self.threads.max(1)
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        if count == 0 {
            return;
        }
        let t = Trampoline {
            task,
            count,
            panic: Mutex::new(None),
        };
        let task_ctx = &t as *const Trampoline<'_> as *mut c_void;
        // SAFETY: the engine's `run` as promised to `Callback::new`; `t`
        // outlives the call.
        unsafe { (self.run)(self.ctx, count, trampoline, task_ctx) };
        if let Ok(Some(payload)) = t.panic.into_inner() {
            resume_unwind(payload);
        }
    }
}

mod workers;
pub use workers::Workers;

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

    pub(super) fn run_all(executor: &dyn Executor) {
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
        // Two arrays written in the same disjoint ranges, and one scattered
        // write per element (a permutation: disjoint by construction).
        let (mut a, mut b, mut c) = (vec![0u32; 1001], vec![0u16; 1001], vec![0usize; 1001]);
        let (da, db, dc) = (
            DisjointMut::new(&mut a),
            DisjointMut::new(&mut b),
            DisjointMut::new(&mut c),
        );
        assert_eq!((da.len(), dc.is_empty()), (1001, false));
        executor.run(1001usize.div_ceil(64), &|i| {
            let (start, len) = (i * 64, 64.min(1001 - i * 64));
            // SAFETY: task i alone touches [start, start + len) of a and b,
            // and element 10 k mod 1001 of c for k in that range (10 is
            // prime to 1001 = 7 x 11 x 13, so those elements are distinct).
            let (ra, rb) = unsafe { (da.range(start, len), db.range(start, len)) };
            for j in 0..len {
                let k = start + j;
                ra[j] = 2 * k as u32;
                rb[j] = k as u16;
                // SAFETY: as above.
                unsafe { dc.set(k * 10 % 1001, k) };
            }
        });
        for k in 0..1001 {
            assert_eq!(
                (a[k], b[k] as usize, c[k * 10 % 1001]),
                (2 * k as u32, k, k)
            );
        }
    }

    #[test]
    fn serial_runs_every_chunk_once() {
        run_all(&Serial);
    }

    /// A C-style parallel-for: runs the indices backwards on two scoped
    /// threads (odd and even), as an engine's workers might.
    unsafe extern "C" fn two_threads_backwards(
        ctx: *mut c_void,
        count: usize,
        task: CTask,
        task_ctx: *mut c_void,
    ) {
        // SAFETY (test): ctx points at the test's call counter.
        let calls = unsafe { &*(ctx as *const AtomicUsize) };
        calls.fetch_add(1, Ordering::Relaxed);
        let task_ctx = task_ctx as usize;
        std::thread::scope(|s| {
            for parity in 0..2 {
                s.spawn(move || {
                    for i in (0..count).rev().filter(|i| i % 2 == parity) {
                        // SAFETY: each index once, before this returns.
                        unsafe { task(task_ctx as *mut c_void, i) };
                    }
                });
            }
        });
    }

    #[test]
    fn a_c_callback_runs_every_chunk_once() {
        let runs = AtomicUsize::new(0);
        let ctx = &runs as *const AtomicUsize as *mut c_void;
        // SAFETY: the callback keeps the promise; `runs` outlives `exec`.
        let exec = unsafe { Callback::new(two_threads_backwards, ctx, 2) };
        run_all(&exec);
        assert_eq!(runs.load(Ordering::Relaxed), 3, "one C call per run");
        assert_eq!(exec.threads(), 2);
    }

    #[test]
    fn a_panicking_task_reaches_the_caller_not_c() {
        let runs = AtomicUsize::new(0);
        let ctx = &runs as *const AtomicUsize as *mut c_void;
        // SAFETY: as above.
        let exec = unsafe { Callback::new(two_threads_backwards, ctx, 0) };
        assert_eq!(exec.threads(), 1, "0 workers counts as 1");
        let done = AtomicUsize::new(0);
        let caught = catch_unwind(AssertUnwindSafe(|| {
            exec.run(10, &|i| {
                if i == 3 {
                    panic!("task 3");
                }
                done.fetch_add(1, Ordering::Relaxed);
            })
        }));
        let msg = caught.expect_err("the panic is raised again after the wait");
        assert_eq!(msg.downcast_ref::<&str>(), Some(&"task 3"));
        assert_eq!(done.load(Ordering::Relaxed), 9, "the other tasks still ran");
    }

    #[cfg(feature = "rayon")]
    #[test]
    fn rayon_runs_every_chunk_once() {
        for threads in [1, 2, 3, 8] {
            run_all(&Rayon::new(threads).unwrap());
        }
    }
}

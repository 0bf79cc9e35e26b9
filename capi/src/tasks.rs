//! The engine's job system as coif's executor: a C parallel-for
//! ([`CoifExecutor`]) that the `_with` calls hand their tasks to
//! (`coif_base::tasks::Callback` behind it).

use crate::CoifStatus;
use coif_base::tasks::{Callback, Executor, Serial};
use std::ffi::c_void;

/// One task of a coif stage: the engine calls it as `task(task_ctx, i)` for
/// every `i` in `0..count` of a `run` call, passing `task_ctx` unchanged.
pub type CoifTaskFn = unsafe extern "C" fn(task_ctx: *mut c_void, index: usize);

/// The engine's parallel-for: calls `task(task_ctx, i)` exactly once for
/// every `i` in `0..count`, in any order, on any of its threads (the calling
/// thread included), and returns only after every call has returned. `ctx`
/// is `CoifExecutor::ctx`.
pub type CoifRunFn =
    unsafe extern "C" fn(ctx: *mut c_void, count: usize, task: CoifTaskFn, task_ctx: *mut c_void);

/// An engine's job system as coif sees it: one blocking parallel-for.
///
/// The contract of `run` (breaking it is undefined behaviour, as each task
/// writes its own part of the output): call `task(task_ctx, i)` exactly
/// once for every `i` in `0..count`, in any order, on any threads, and
/// return after the last call has returned. `run` may be called from any
/// thread that calls coif, and must return normally (no `longjmp`, no C++
/// exception). coif never calls `run` from inside one of its tasks (no
/// nesting), a task never waits for another, and a stage makes at most 64
/// tasks however large the set, so a fixed pool of jobs does not run dry.
/// `threads` is the number of workers (0 counts as 1); coif uses it only to
/// choose how finely to split, never for a result: the same input gives the
/// same bytes with any executor, any `threads` and any order.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct CoifExecutor {
    /// The engine's own pointer, passed to `run` unchanged.
    pub ctx: *mut c_void,
    /// Worker count, a splitting hint (0 counts as 1).
    pub threads: usize,
    /// The parallel-for, a `CoifRunFn` (must not be NULL).
    pub run: Option<
        unsafe extern "C" fn(
            ctx: *mut c_void,
            count: usize,
            task: CoifTaskFn,
            task_ctx: *mut c_void,
        ),
    >,
}

/// The executor behind a `*const CoifExecutor`: NULL runs the tasks on the
/// calling thread in index order.
pub(crate) enum Exec {
    /// No executor given.
    Serial(Serial),
    /// The engine's parallel-for.
    C(Callback),
}

impl Exec {
    /// The executor to hand a stage.
    pub(crate) fn get(&self) -> &dyn Executor {
        match self {
            Exec::Serial(s) => s,
            Exec::C(c) => c,
        }
    }
}

/// Reads `*e`: NULL is [`Serial`]; a non-NULL executor whose `run` is NULL
/// is `COIF_ERROR_NULL`, a misaligned pointer `COIF_ERROR_INVALID_ARGUMENT`.
/// Allocates nothing.
///
/// # Safety
/// `e` is NULL or points to a readable `CoifExecutor` whose `run` keeps the
/// contract above for the length of the call that reads it.
pub(crate) unsafe fn executor(e: *const CoifExecutor) -> Result<Exec, CoifStatus> {
    if e.is_null() {
        return Ok(Exec::Serial(Serial));
    }
    if !e.is_aligned() {
        return Err(CoifStatus::COIF_ERROR_INVALID_ARGUMENT);
    }
    // SAFETY: non-NULL, aligned (checked) and readable (the caller's contract).
    let e = unsafe { *e };
    let run = e.run.ok_or(CoifStatus::COIF_ERROR_NULL)?;
    // SAFETY: the caller promises `run` keeps the parallel-for contract and
    // may be called with `ctx` from this call's thread; the `Callback`
    // lives only inside the coif call that made it.
    Ok(Exec::C(unsafe { Callback::new(run, e.ctx, e.threads) }))
}

/// Most tasks a stage of the C interface makes (the strand step's own
/// limit, `coif_kernels::MAX_STEP_TASKS`, is the same).
pub(crate) const MAX_TASKS: usize = 64;

/// Items per task when `count` items are split for `exec`: about four tasks
/// per thread, at most [`MAX_TASKS`], rounded up to a multiple of `align`
/// (at least `align`). Only the split depends on the executor, never a result.
pub(crate) fn per_task(count: usize, exec: &dyn Executor, align: usize) -> usize {
    let tasks = (4 * exec.threads().max(1)).min(MAX_TASKS);
    count.div_ceil(tasks).div_ceil(align).max(1) * align
}

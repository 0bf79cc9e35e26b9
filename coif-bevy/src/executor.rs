//! coif's [`Executor`] on Bevy's [`ComputeTaskPool`].

use bevy::tasks::ComputeTaskPool;
use coif::base::tasks::Executor;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Runs coif's tasks on Bevy's compute pool: one scope per stage with at
/// most one Bevy task per pool thread, each taking indices from a shared
/// counter until none is left (the calling thread works too, as Bevy's
/// scopes do). coif's stages give the same bytes whatever thread runs which
/// index, so this matches [`coif::base::tasks::Serial`] bit for bit.
///
/// Each stage's scope costs Bevy a few allocations (the task futures and
/// the scope's result list): a handful per fixed step, independent of the
/// hair size. [`crate::HairExecutor::Serial`] allocates nothing.
#[derive(Clone, Copy)]
pub struct TaskPoolExecutor<'a> {
    pool: &'a bevy::tasks::TaskPool,
}

impl<'a> TaskPoolExecutor<'a> {
    /// The global compute pool (initialised by Bevy's `TaskPoolPlugin`, or
    /// here with default threads if no app did).
    pub fn compute() -> TaskPoolExecutor<'static> {
        TaskPoolExecutor {
            pool: ComputeTaskPool::get_or_init(bevy::tasks::TaskPool::default),
        }
    }

    /// An executor on any Bevy task pool.
    pub fn new(pool: &'a bevy::tasks::TaskPool) -> Self {
        TaskPoolExecutor { pool }
    }
}

// SAFETY: every index in 0..count is taken exactly once from the atomic
// counter (fetch_add hands out each value once), and `scope` returns only
// after every spawned future has completed; with one thread or one task
// the loop runs on the calling thread before `run` returns.
unsafe impl Executor for TaskPoolExecutor<'_> {
    fn threads(&self) -> usize {
        self.pool.thread_num().max(1)
    }

    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        let workers = self.threads().min(count);
        if workers <= 1 {
            for i in 0..count {
                task(i);
            }
            return;
        }
        let next = AtomicUsize::new(0);
        let work = || loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= count {
                break;
            }
            task(i);
        };
        let work = &work;
        self.pool.scope(|s| {
            for _ in 0..workers {
                s.spawn(async move { work() });
            }
        });
    }
}

//! Executors for the "same bytes on any executor" tests.

use coif_base::tasks::Executor;

/// Runs every task on the calling thread, last index first, while saying
/// it has `.0` threads: a stage that splits its work by
/// [`Executor::threads`] cuts as many parts, and any order dependence
/// between tasks shows.
pub struct Backwards(pub usize);

// SAFETY: `run` runs every index once, on the calling thread, and returns
// after the last.
unsafe impl Executor for Backwards {
    fn threads(&self) -> usize {
        self.0
    }
    fn run(&self, count: usize, task: &(dyn Fn(usize) + Sync)) {
        (0..count).rev().for_each(task);
    }
}

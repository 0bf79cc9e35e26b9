//! A counting global allocator for the "allocates nothing per frame" tests.
//! Each test crate that uses it declares it as its allocator:
//!
//! ```ignore
//! #[global_allocator]
//! static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;
//! ```
//!
//! The count is per thread (tests run on parallel threads) and includes
//! reallocations; [`allocations_all_threads`] counts every thread (for a
//! test binary that holds that one test, so that stages run on worker
//! threads are counted too).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The counting allocator: forwards to the system allocator and counts
/// allocations and reallocations per thread.
pub struct Counting;

/// Allocations on every thread of the process.
static ALL_THREADS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: every call forwards to the system allocator unchanged; the
// counter is a thread-local `Cell` with a const initialiser, which does not
// allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        ALL_THREADS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: forwards the caller's layout to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc`/`realloc` above with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        ALL_THREADS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as for `System.realloc`, with the caller's arguments.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Allocations (and reallocations) made on this thread so far.
pub fn allocations() -> usize {
    ALLOCATIONS.with(|a| a.get())
}

/// Allocations (and reallocations) made on every thread so far. Only
/// meaningful in a test binary whose other tests cannot run meanwhile.
pub fn allocations_all_threads() -> usize {
    ALL_THREADS.load(Ordering::Relaxed)
}

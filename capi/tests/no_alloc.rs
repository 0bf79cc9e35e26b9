//! `coif_step`, `coif_strands_set_roots` and `coif_strands_positions` do not
//! allocate once the set and its rig are sized: counted by a global
//! allocator (this test binary holds one test, so nothing else allocates
//! meanwhile).

use coif_capi::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::ptr;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: the caller's contract is System's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        // SAFETY: `p` came from `alloc` above, i.e. from System.
        unsafe { System.dealloc(p, layout) }
    }
    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as above.
        unsafe { System.realloc(p, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn per_frame_calls_do_not_allocate() {
    const STRANDS: usize = 40;
    const VERTS: usize = 10;
    let mut xyz = Vec::new();
    let mut roots = Vec::new();
    for i in 0..STRANDS {
        let (x, z) = ((i % 8) as f32 * 0.01, (i / 8) as f32 * 0.01);
        roots.extend([x, 1.6, z]);
        for v in 0..VERTS {
            xyz.extend([x + 0.002 * v as f32, 1.6 - 0.01 * v as f32, z]);
        }
    }
    let rig = [
        CoifSphere {
            center: [0.03, 1.5, 0.02],
            radius: 0.06,
        },
        CoifSphere {
            center: [0.0, 1.45, 0.0],
            radius: 0.04,
        },
    ];
    let params = coif_sim_params_default();
    let mut out = vec![0.0f32; xyz.len()];
    let mut c: *mut CoifStrands = ptr::null_mut();
    // SAFETY: every buffer holds what its count says; `c` is live until freed.
    unsafe {
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), STRANDS * VERTS, VERTS, &mut c),
            CoifStatus::COIF_OK
        );
        // Warm up: the first step with this rig sizes the scratch.
        assert_eq!(
            coif_step(c, &params, rig.as_ptr(), rig.len()),
            CoifStatus::COIF_OK
        );
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        for frame in 0..120 {
            roots[0] = 0.001 * frame as f32;
            assert_eq!(
                coif_strands_set_roots(c, roots.as_ptr(), STRANDS),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_step(c, &params, rig.as_ptr(), rig.len()),
                CoifStatus::COIF_OK
            );
            assert_eq!(coif_step(c, &params, rig.as_ptr(), 1), CoifStatus::COIF_OK);
            assert_eq!(
                coif_strands_positions(c, out.as_mut_ptr(), STRANDS * VERTS),
                CoifStatus::COIF_OK
            );
        }
        let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
        coif_strands_free(c);
        assert_eq!(allocations, 0, "per-frame C calls allocated");
    }
}

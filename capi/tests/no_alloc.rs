//! The per-frame calls do not allocate once the set, its rig and the
//! refinement level are sized: `coif_step` (and `coif_step_with` on a C
//! parallel-for that runs the tasks in order on the calling thread, split
//! for four workers), `coif_strands_set_roots`, `coif_strands_positions`,
//! `coif_refine`, `coif_hairs_distance_lod`, `coif_hairs_write_vertices`,
//! `coif_gpu_pack_guides`, `coif_gpu_render_hair_count`,
//! `coif_shade_kajiya_kay`, `coif_shade_marschner_lut`,
//! `coif_shade_pbrt_table` and their `_with` forms, the dual scattering
//! calls `coif_shade_*_dual` and their `_with` forms (counts behind given
//! and NULL), and for cloth
//! `coif_patch_set_skinned`, `coif_patch_step`, `coif_patch_step_all` and
//! `coif_patch_blended`, and for the world around the hair
//! `coif_step_colliders` and `coif_step_colliders_with` (spheres, capsules,
//! a field set, wind, drag and gusts) with `coif_sdf_set_transform_at` and
//! `coif_sdf_set_distance_at` (the set holds one field, a closed
//! octahedron, which must build). Counted by a global allocator (this test
//! binary holds one test, so nothing else allocates meanwhile).

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

/// A C parallel-for in the style of a serial job system: every index in
/// order on the calling thread (so the count sees every allocation).
unsafe extern "C" fn in_order(
    _ctx: *mut std::ffi::c_void,
    count: usize,
    task: CoifTaskFn,
    task_ctx: *mut std::ffi::c_void,
) {
    for i in 0..count {
        // SAFETY: each index once, before returning.
        unsafe { task(task_ctx, i) };
    }
}

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
    let mut hairs: *mut CoifHairs = ptr::null_mut();
    let mut lut: *mut CoifMarschnerLut = ptr::null_mut();
    let mut table: *mut CoifPbrtTable = ptr::null_mut();
    // Scalp triangles over the 8 x 5 grid of roots.
    let mut tris = Vec::new();
    for j in 0..4u32 {
        for i in 0..7u32 {
            let k = j * 8 + i;
            tris.extend([k, k + 1, k + 8, k + 1, k + 9, k + 8]);
        }
    }
    let settings = CoifHairSettings {
        hairs_per_cm2: 20.0,
        max_segments_per_span: 8,
        ..coif_hair_settings_default()
    };
    let kk = coif_kajiya_kay_default();
    let (patch_rows, patch_cols) = (5usize, 9usize);
    let patch_n = patch_rows * patch_cols;
    let mut patch_grid: Vec<f32> = (0..patch_n)
        .flat_map(|k| {
            [
                0.02 * (k % patch_cols) as f32,
                1.5,
                0.02 * (k / patch_cols) as f32,
            ]
        })
        .collect();
    let patch_pinned: Vec<u8> = (0..patch_n).map(|k| u8::from(k < patch_cols)).collect();
    let mut patch_out = vec![0.0f32; 3 * patch_n];
    let mut patch: *mut CoifPatch = ptr::null_mut();
    let (light, eye) = ([0.3f32, 1.0, 0.5], [0.0f32, 0.2, 1.0]);
    // Four workers as far as the split goes: several tasks per stage.
    let exec = CoifExecutor {
        ctx: ptr::null_mut(),
        threads: 4,
        run: Some(in_order),
    };
    let capsules = [
        CoifCapsule {
            a: [0.0, 1.52, -0.05],
            b: [0.08, 1.52, 0.05],
            radius: 0.02,
        },
        CoifCapsule {
            a: [0.04, 1.45, 0.0],
            b: [0.04, 1.45, 0.0],
            radius: 0.03,
        },
    ];
    let windy = CoifSimParams {
        wind: [1.5, 0.0, 0.5],
        drag: 3.0,
        turbulence: 0.3,
        ..params
    };
    // An octahedron of half-diagonal 4 cm, counter-clockwise from outside.
    let r = 0.04f32;
    let mesh = [
        r, 0.0, 0.0, -r, 0.0, 0.0, 0.0, r, 0.0, 0.0, -r, 0.0, 0.0, 0.0, r, 0.0, 0.0, -r,
    ];
    let mesh_tris: [u32; 24] = [
        0, 2, 4, 1, 4, 2, 0, 4, 3, 1, 3, 4, 0, 5, 2, 1, 2, 5, 0, 3, 5, 1, 5, 3,
    ];
    let mut world: *mut CoifStrands = ptr::null_mut();
    let mut fields: *mut CoifSdfSet = ptr::null_mut();
    // SAFETY: every buffer holds what its count says; `c` is live until freed.
    unsafe {
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), STRANDS * VERTS, VERTS, &mut world),
            CoifStatus::COIF_OK
        );
        assert_eq!(coif_sdf_set_new(&mut fields), CoifStatus::COIF_OK);
        let mut field: *mut CoifSdf = ptr::null_mut();
        assert_eq!(
            coif_sdf_new(mesh.as_ptr(), 6, mesh_tris.as_ptr(), 8, 0.01, &mut field),
            CoifStatus::COIF_OK,
            "the closed octahedron's field must build"
        );
        assert_eq!(
            coif_sdf_set_add(fields, &mut field, ptr::null_mut()),
            CoifStatus::COIF_OK
        );
        assert_eq!(coif_sdf_set_count(fields), 1);
        // Warm up: the first step against these colliders sizes their lists.
        assert_eq!(
            coif_step_colliders(
                world,
                &windy,
                rig.as_ptr(),
                rig.len(),
                capsules.as_ptr(),
                2,
                fields
            ),
            CoifStatus::COIF_OK
        );
    }
    // SAFETY: every buffer holds what its count says; `c` is live until freed.
    unsafe {
        assert_eq!(
            coif_strands_new(xyz.as_ptr(), STRANDS * VERTS, VERTS, &mut c),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_hairs_new(c, tris.as_ptr(), tris.len() / 3, &settings, &mut hairs),
            CoifStatus::COIF_OK
        );
        let lut_params = coif_marschner_params_default();
        assert_eq!(
            coif_marschner_lut_new(&lut_params, 16, &mut lut),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_patch_new(
                patch_grid.as_ptr(),
                patch_rows,
                patch_cols,
                patch_pinned.as_ptr(),
                &mut patch
            ),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_patch_step(patch, &params, rig.as_ptr(), rig.len()),
            CoifStatus::COIF_OK
        );
        let pbrt_params = coif_pbrt_params_default();
        assert_eq!(
            coif_pbrt_table_new(&pbrt_params, 8, &mut table),
            CoifStatus::COIF_OK
        );
        let ds_settings = CoifDualScatteringSettings {
            resolution: 8,
            ..coif_dual_scattering_settings_default()
        };
        let (mut ds_m, mut ds_p) = (ptr::null_mut(), ptr::null_mut());
        assert_eq!(
            coif_dual_scattering_from_marschner_lut(lut, &ds_settings, &mut ds_m),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_dual_scattering_from_pbrt_table(table, &ds_settings, &mut ds_p),
            CoifStatus::COIF_OK
        );
        let refined_len = coif_refine_bound(c, 4);
        let mut refined = vec![0.0f32; 3 * refined_len];
        let mut tangents = vec![0.0f32; 3 * refined_len];
        let vertex_len = coif_hairs_vertex_bound(hairs, 8, usize::MAX);
        assert!(vertex_len > 0);
        let mut vertices = vec![CoifRenderVertex::default(); vertex_len];
        let mut gpu_guides = vec![CoifGpuGuideVertex::default(); STRANDS * VERTS];
        let mut rgb = vec![0.0f32; 3 * vertex_len];
        // Per-vertex shadowing for dual scattering (an opacity map's counts).
        let fibres: Vec<f32> = (0..vertex_len).map(|k| (k % 11) as f32).collect();
        let direct: Vec<f32> = fibres.iter().map(|n| (-0.3 * n).exp()).collect();
        let behind: Vec<f32> = fibres.iter().map(|n| 10.0 - n).collect();
        // Warm up: the first step with this rig sizes the sphere scratch,
        // the first refinement at the finest level the refinement scratch.
        assert_eq!(
            coif_step(c, &params, rig.as_ptr(), rig.len()),
            CoifStatus::COIF_OK
        );
        assert_eq!(
            coif_refine(
                c,
                4,
                refined.as_mut_ptr(),
                tangents.as_mut_ptr(),
                refined_len
            ),
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
                coif_step_with(c, &params, rig.as_ptr(), rig.len(), &exec),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_strands_positions(c, out.as_mut_ptr(), STRANDS * VERTS),
                CoifStatus::COIF_OK
            );
            // The GPU path's per-frame calls: the guides buffer and the
            // view's hair count.
            let mut packed = 0usize;
            assert_eq!(
                coif_gpu_pack_guides(c, gpu_guides.as_mut_ptr(), gpu_guides.len(), &mut packed),
                CoifStatus::COIF_OK
            );
            assert_eq!(packed, STRANDS * VERTS);
            assert!(coif_gpu_render_hair_count(hairs, frame) > 0 || frame == 0);
            patch_grid[0] = 0.001 * frame as f32;
            assert_eq!(
                coif_patch_set_skinned(patch, patch_grid.as_ptr(), patch_n),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_patch_step(patch, &params, rig.as_ptr(), rig.len()),
                CoifStatus::COIF_OK
            );
            let patches = [patch];
            assert_eq!(
                coif_patch_step_all(patches.as_ptr(), 1, &params, rig.as_ptr(), 2, &exec),
                CoifStatus::COIF_OK
            );
            assert_eq!(
                coif_patch_blended(patch, patch_out.as_mut_ptr(), patch_n),
                CoifStatus::COIF_OK
            );
            // Coarser levels reuse the refinement scratch.
            let level = 1 + frame % 4;
            assert_eq!(
                coif_refine(
                    c,
                    level,
                    refined.as_mut_ptr(),
                    tangents.as_mut_ptr(),
                    refined_len
                ),
                CoifStatus::COIF_OK
            );
            let (mut groups, mut factor) = (0usize, 0.0f32);
            assert_eq!(
                coif_hairs_distance_lod(
                    hairs,
                    0.5 + 0.01 * frame as f32,
                    0.2,
                    &mut groups,
                    &mut factor
                ),
                CoifStatus::COIF_OK
            );
            let mut written = 0usize;
            assert_eq!(
                coif_hairs_write_vertices(
                    hairs,
                    c,
                    1 + frame % 8,
                    groups,
                    factor,
                    vertices.as_mut_ptr(),
                    vertex_len,
                    &mut written
                ),
                CoifStatus::COIF_OK
            );
            assert!(written > 0);
            let (v, l, e, out) = (
                vertices.as_ptr(),
                light.as_ptr(),
                eye.as_ptr(),
                rgb.as_mut_ptr(),
            );
            let statuses = [
                coif_shade_kajiya_kay(&kk, v, written, l, e, out, vertex_len),
                coif_shade_marschner_lut(lut, v, written, l, e, out, vertex_len),
                coif_shade_pbrt_table(table, v, written, l, e, out, vertex_len),
                coif_shade_kajiya_kay_with(&kk, v, written, l, e, out, vertex_len, &exec),
                coif_shade_marschner_lut_with(lut, v, written, l, e, out, vertex_len, &exec),
                coif_shade_pbrt_table_with(table, v, written, l, e, out, vertex_len, &exec),
            ];
            assert_eq!(statuses, [CoifStatus::COIF_OK; 6]);
            let (f, d) = (fibres.as_ptr(), direct.as_ptr());
            // Counts behind given, and NULL (infinitely deep hair).
            let (b, deep) = (behind.as_ptr(), ptr::null());
            let statuses = [
                coif_shade_marschner_lut_dual(
                    lut, ds_m, v, written, l, e, f, b, d, out, vertex_len,
                ),
                coif_shade_pbrt_table_dual(table, ds_p, v, written, l, e, f, b, d, out, vertex_len),
                coif_shade_marschner_lut_dual_with(
                    lut, ds_m, v, written, l, e, f, b, d, out, vertex_len, &exec,
                ),
                coif_shade_pbrt_table_dual_with(
                    table, ds_p, v, written, l, e, f, b, d, out, vertex_len, &exec,
                ),
                coif_shade_marschner_lut_dual(
                    lut, ds_m, v, written, l, e, f, deep, d, out, vertex_len,
                ),
                coif_shade_pbrt_table_dual_with(
                    table, ds_p, v, written, l, e, f, deep, d, out, vertex_len, &exec,
                ),
            ];
            assert_eq!(statuses, [CoifStatus::COIF_OK; 6]);

            let (ca, sa) = (capsules.as_ptr(), rig.as_ptr());
            let turn = 0.01 * frame as f32;
            let pose = [
                turn.cos(),
                0.0,
                turn.sin(),
                0.05,
                0.0,
                1.0,
                0.0,
                1.45,
                -turn.sin(),
                0.0,
                turn.cos(),
                0.0,
            ];
            let mut d = 0.0f32;
            let statuses = [
                coif_strands_set_roots(world, roots.as_ptr(), STRANDS),
                coif_sdf_set_transform_at(fields, 0, pose.as_ptr()),
                coif_step_colliders(world, &windy, sa, 2, ca, 2, fields),
                coif_step_colliders_with(world, &windy, sa, 2, ca, 2, fields, &exec),
                coif_step_colliders(world, &windy, ptr::null(), 0, ca, 1, ptr::null()),
                coif_sdf_set_distance_at(fields, 0, light.as_ptr(), &mut d),
            ];
            assert_eq!(statuses, [CoifStatus::COIF_OK; 6]);
        }
        let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
        coif_dual_scattering_free(ds_m);
        coif_dual_scattering_free(ds_p);
        coif_pbrt_table_free(table);
        assert!(rgb.iter().all(|c| c.is_finite()) && rgb.iter().any(|&c| c > 0.0));
        coif_marschner_lut_free(lut);
        coif_patch_free(patch);
        coif_hairs_free(hairs);
        coif_strands_free(c);
        coif_strands_free(world);
        coif_sdf_set_free(fields);
        assert_eq!(allocations, 0, "per-frame C calls allocated");
    }
}

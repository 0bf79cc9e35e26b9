//! The scalar reference of the strand step: the generic body of `step.rs`
//! ([`crate::step`]'s `step_chain`) instantiated at `f32`, one strand (lane)
//! at a time, so the algorithm and its operation order are the SIMD path's
//! by construction. Tests compare the two; benchmarks run them side by side.
//!
//! The numbered steps are those of `step.rs`'s header:
//!
//! 1. Broad phase: the swept boxes of a group of four blocks (the scalar
//!    twin of `block_sweep_aabb`) and their reach against the rig, once
//!    per step.
//! 2. Prediction: root path, Verlet per substep, fixed direction part.
//! 3. Shape: the local shape springs (`shape.rs`) and the global shape pull.
//! 4. Projection of the length constraints (tridiagonal, blended directions),
//!    `iterations` times per substep, with bending if on.
//! 5. Pearls.
//! 6. Strain limit (two-sided, Follow-The-Leader order) with push-out.
//! 7. Velocity over the step, and the guard (a lane that went non-finite or
//!    beyond 10^6 m is restored).

use super::broad_phase::block_sweep_aabb;
use crate::drive::{drive, PAIR};
use crate::hair_grid::apply_block;
use crate::lanes::{Vec3Lanes, V3};
use crate::step::{step_chain, Chain, ChainScratch};
use crate::{Colliders, SimParams, Sphere, Strands};
use coif_base::lanes::F32Lanes;
use coif_base::tasks::{Executor, Serial};

/// One lane's copy of a block's per-vertex data, sized when the strands are
/// built.
#[derive(Clone, Debug, Default)]
pub(crate) struct LaneBuffers {
    pos: Vec<V3<f32>>,
    prev: Vec<V3<f32>>,
    w: Vec<f32>,
    rest_len: Vec<f32>,
    rest_vec: Vec<V3<f32>>,
    rest_offset: Vec<V3<f32>>,
    bend_len: Vec<f32>,
    bend_share: Vec<[f32; 2]>,
    shape_weight: Vec<f32>,
    arc: Vec<f32>,
    pub(crate) chain: ChainScratch<f32>,
}

impl LaneBuffers {
    /// Room for the candidates of `counts` colliders.
    pub(crate) fn reserve(&mut self, counts: [usize; 3]) {
        self.chain.reserve(counts);
    }

    pub(crate) fn new(verts: usize) -> Self {
        LaneBuffers {
            pos: vec![V3::zero(); verts],
            prev: vec![V3::zero(); verts],
            w: vec![0.0; verts],
            rest_len: vec![0.0; verts],
            rest_vec: vec![V3::zero(); verts],
            rest_offset: vec![V3::zero(); verts],
            bend_len: vec![0.0; verts],
            bend_share: vec![[0.0; 2]; verts],
            shape_weight: vec![0.0; verts],
            arc: vec![0.0; verts],
            chain: ChainScratch::new(verts),
        }
    }
}

fn lane3(a: &Vec3Lanes, l: usize) -> V3<f32> {
    V3::from_vec3(a.lane(l))
}

fn lane1(a: &F32Lanes, l: usize) -> f32 {
    a.as_array()[l]
}

/// Advances every strand by one fixed step of `params.dt` against rig
/// spheres, one lane at a time, on the calling thread (the twin of
/// [`crate::step`]).
pub fn step(strands: &mut Strands, params: &SimParams, spheres: &[Sphere]) {
    step_colliders_with(strands, params, &Colliders::spheres(spheres), &Serial);
}

/// [`step`] with its blocks handed out as tasks to `executor`, as
/// [`crate::step_with`] does: the same bytes with any executor.
pub fn step_with(
    strands: &mut Strands,
    params: &SimParams,
    spheres: &[Sphere],
    executor: &dyn Executor,
) {
    step_colliders_with(strands, params, &Colliders::spheres(spheres), executor);
}

/// The twin of [`crate::step_colliders`]: every collider, one lane at a
/// time, on the calling thread.
pub fn step_colliders(strands: &mut Strands, params: &SimParams, colliders: &Colliders<'_>) {
    step_colliders_with(strands, params, colliders, &Serial);
}

/// The twin of [`crate::step_colliders_with`].
pub fn step_colliders_with(
    strands: &mut Strands,
    params: &SimParams,
    colliders: &Colliders<'_>,
    executor: &dyn Executor,
) {
    drive(
        strands,
        params,
        colliders,
        executor,
        |s, st, b, lanes, k| {
            let real = lanes.start..lanes.end.min(s.lanes_in_block(b));
            block_sweep_aabb(st.pos, st.prev, k.gravity_dt2, real)
        },
        |strands, states, scratch, world, k, ids| {
            // The blocks one after the other, each lane on its own.
            let mut bads = [0u32; PAIR];
            for ((st, &(b, g)), bad) in states.iter_mut().zip(ids).zip(&mut bads) {
                let (verts, base) = (strands.verts, b * strands.verts);
                for l in 0..strands.lanes_in_block(b) {
                    let lb = &mut scratch.lane;
                    for v in 0..verts {
                        let i = base + v;
                        lb.pos[v] = lane3(&st.pos[v], l);
                        lb.prev[v] = lane3(&st.prev[v], l);
                        lb.w[v] = lane1(&strands.inv_mass[i], l);
                        lb.rest_len[v] = lane1(&strands.rest_len[i], l);
                        lb.rest_vec[v] = lane3(&strands.rest_vec[i], l);
                        lb.rest_offset[v] = lane3(&strands.rest_offset[i], l);
                        lb.bend_len[v] = lane1(&strands.bend_len[i], l);
                        let sh = strands.bend_share[i];
                        lb.bend_share[v] = [lane1(&sh[0], l), lane1(&sh[1], l)];
                        lb.shape_weight[v] = lane1(&strands.shape_weight[i], l);
                        lb.arc[v] = lane1(&strands.rest_arc[i], l);
                    }
                    // 2.-7.
                    let mut c = Chain {
                        pos: &mut lb.pos,
                        prev: &mut lb.prev,
                        w: &lb.w,
                        rest_len: &lb.rest_len,
                        rest_vec: &lb.rest_vec,
                        rest_offset: &lb.rest_offset,
                        bend_len: &lb.bend_len,
                        bend_share: &lb.bend_share,
                        shape_weight: &lb.shape_weight,
                        arc: &lb.arc,
                    };
                    let ok: bool =
                        step_chain(&mut c, &mut lb.chain, k, world, &scratch.candidates, g);
                    for v in 0..verts {
                        st.pos[v].set_lane(l, lb.pos[v].to_vec3());
                        st.prev[v].set_lane(l, lb.prev[v].to_vec3());
                    }
                    if !ok {
                        *bad |= 1 << l;
                    }
                }
            }
            bads
        },
        |s, st, grid, gk, b| {
            // One lane, one vertex at a time: the same body as the SIMD
            // path's, each vertex on its own.
            let mut moved = 0u32;
            for l in 0..s.lanes_in_block(b) {
                for v in 0..s.verts {
                    let i = b * s.verts + v;
                    let mut x = lane3(&st.pos[v], l);
                    let mut xp = lane3(&st.prev[v], l);
                    let (w, arc) = (lane1(&s.inv_mass[i], l), lane1(&s.rest_arc[i], l));
                    if apply_block::<f32>(
                        grid,
                        std::slice::from_mut(&mut x),
                        std::slice::from_mut(&mut xp),
                        &[w],
                        &[arc],
                        gk,
                    ) {
                        moved |= 1 << l;
                    }
                    st.pos[v].set_lane(l, x.to_vec3());
                    st.prev[v].set_lane(l, xp.to_vec3());
                }
            }
            moved
        },
    );
}

//! The SIMD batch driver shared by Kajiya-Kay and the Marschner tables:
//! full blocks of eight samples are loaded straight from the SoA arrays
//! (one unaligned 32-byte load per component), the tail goes through
//! [`ShadingSamples::load_block`]'s padding.

use crate::{RgbBuffer, ShadingSamples};
use coif_base::{Vec3x8, LANES};
use wide::f32x8;

#[inline(always)]
fn load_x8(a: &[f32], start: usize) -> f32x8 {
    let chunk: &[f32; LANES] = a[start..start + LANES]
        .try_into()
        .expect("slice of LANES values");
    f32x8::new(*chunk)
}

#[inline(always)]
fn load_vec3_x8(a: [&[f32]; 3], start: usize) -> Vec3x8 {
    Vec3x8::new(
        load_x8(a[0], start),
        load_x8(a[1], start),
        load_x8(a[2], start),
    )
}

#[inline(always)]
fn store_x8(dst: &mut [f32], start: usize, v: f32x8) {
    dst[start..start + LANES].copy_from_slice(v.as_array());
}

/// Resizes `out` to `samples.len()` and writes `shade_x8(t, wi, wo)` for every
/// block of eight samples.
#[inline(always)]
pub(crate) fn shade_blocks(
    samples: &ShadingSamples,
    out: &mut RgbBuffer,
    shade_x8: impl Fn(Vec3x8, Vec3x8, Vec3x8) -> Vec3x8,
) {
    let n = samples.len();
    out.resize(n);
    let full = n - n % LANES;
    let mut start = 0;
    while start < full {
        let v = shade_x8(
            load_vec3_x8(samples.t(), start),
            load_vec3_x8(samples.wi(), start),
            load_vec3_x8(samples.wo(), start),
        );
        store_x8(&mut out.r, start, v.x);
        store_x8(&mut out.g, start, v.y);
        store_x8(&mut out.b, start, v.z);
        start += LANES;
    }
    if start < n {
        let (t, wi, wo) = samples.load_block(start);
        out.store_block(start, shade_x8(t, wi, wo));
    }
}

//! The SIMD batch driver shared by Kajiya-Kay and the Marschner tables:
//! full blocks of eight samples are loaded straight from the SoA arrays
//! (one unaligned 32-byte load per component), the tail goes through
//! [`ShadingSamples::load_block`]'s padding.

use crate::{RgbBuffer, ShadingSamples};
use coif_base::lanes::F32Lanes;
use coif_base::{Vec3Lanes, LANES};

#[inline(always)]
fn load_simd(a: &[f32], start: usize) -> F32Lanes {
    let chunk: &[f32; LANES] = a[start..start + LANES]
        .try_into()
        .expect("slice of LANES values");
    F32Lanes::new(*chunk)
}

#[inline(always)]
fn load_vec3_simd(a: [&[f32]; 3], start: usize) -> Vec3Lanes {
    Vec3Lanes::new(
        load_simd(a[0], start),
        load_simd(a[1], start),
        load_simd(a[2], start),
    )
}

#[inline(always)]
fn store_simd(dst: &mut [f32], start: usize, v: F32Lanes) {
    dst[start..start + LANES].copy_from_slice(v.as_array());
}

/// Resizes `out` to `samples.len()` and writes `shade_simd(t, wi, wo)` for every
/// block of eight samples.
#[inline(always)]
pub(crate) fn shade_blocks(
    samples: &ShadingSamples,
    out: &mut RgbBuffer,
    shade_simd: impl Fn(Vec3Lanes, Vec3Lanes, Vec3Lanes) -> Vec3Lanes,
) {
    let n = samples.len();
    out.resize(n);
    let full = n - n % LANES;
    let mut start = 0;
    while start < full {
        let v = shade_simd(
            load_vec3_simd(samples.t(), start),
            load_vec3_simd(samples.wi(), start),
            load_vec3_simd(samples.wo(), start),
        );
        store_simd(&mut out.r, start, v.x);
        store_simd(&mut out.g, start, v.y);
        store_simd(&mut out.b, start, v.z);
        start += LANES;
    }
    if start < n {
        let (t, wi, wo) = samples.load_block(start);
        out.store_block(start, shade_simd(t, wi, wo));
    }
}

//! Scalar twin of the SIMD batch lookup in `marschner/lut.rs`.

use super::Lut;
use crate::{RgbBuffer, ShadingSamples};

/// Scalar batch: [`Lut::scattering`] for every sample, the reference of the
/// SIMD [`Lut::scattering_batch`]. `out` is resized to `samples.len()`.
pub fn scattering_batch(lut: &Lut, samples: &ShadingSamples, out: &mut RgbBuffer) {
    out.resize(samples.len());
    for i in 0..samples.len() {
        let (t, wi, wo) = samples.get(i);
        out.set(i, lut.scattering(t, wi, wo));
    }
}

//! Scalar twin of the SIMD batch in `kajiya_kay.rs`.

use super::KajiyaKay;
use crate::{RgbBuffer, ShadingSamples};

/// Scalar batch: [`KajiyaKay::shade`] per sample, the reference of the SIMD
/// [`KajiyaKay::shade_batch`]. `out` is resized to `samples.len()`.
pub fn shade_batch(model: &KajiyaKay, samples: &ShadingSamples, out: &mut RgbBuffer) {
    out.resize(samples.len());
    for i in 0..samples.len() {
        let (t, wi, wo) = samples.get(i);
        out.set(i, model.shade(t, wi, wo));
    }
}

//! Scalar twin of the SIMD batch lookup in `pbrt/table.rs`.

use super::Table;
use crate::{RgbBuffer, ShadingSamples};

/// Scalar batch: `out[k] = table.scattering(samples[k])`, the reference of
/// the SIMD [`Table::scattering_batch`]. `out` is resized to the batch (no
/// allocation once it has the capacity).
pub fn scattering_batch(table: &Table, samples: &ShadingSamples, out: &mut RgbBuffer) {
    out.resize(samples.len());
    for k in 0..samples.len() {
        let (t, wi, wo) = samples.get(k);
        out.set(k, table.scattering(t, wi, wo));
    }
}

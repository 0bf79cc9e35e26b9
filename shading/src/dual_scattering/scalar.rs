//! Scalar twin of the SIMD batch in `dual_scattering/mod.rs`.

use super::{check_lengths, DualScattering};
use crate::{Error, RgbBuffer, ShadingSamples};

/// Scalar batch: `out[k] = ds.shade(single[k], samples[k], fibres[k],
/// direct[k])`, the reference of [`DualScattering::shade_batch`]. `out` is
/// resized to the batch (no allocation once it has the capacity).
///
/// # Errors
///
/// As [`DualScattering::shade_batch`].
pub fn shade_batch(
    ds: &DualScattering,
    samples: &ShadingSamples,
    single: &RgbBuffer,
    fibres: &[f32],
    direct: &[f32],
    out: &mut RgbBuffer,
) -> Result<(), Error> {
    check_lengths(samples, single, fibres, direct)?;
    out.resize(samples.len());
    for k in 0..samples.len() {
        let (t, wi, wo) = samples.get(k);
        out.set(k, ds.shade(single.get(k), t, wi, wo, fibres[k], direct[k]));
    }
    Ok(())
}

//! Error measurements for reports and benches: the lookup tables, the
//! far-field quadrature and the Monte Carlo estimate from the exact per-`h`
//! model against a high-order far-field reference.
//!
//! Relative RMS error over `samples` random configurations (tangent, `wi`,
//! `wo` independent and uniform on the sphere, from `seed`):
//! `sqrt(sum |approx - reference|^2 / sum |reference|^2)`, summed over the
//! three colour channels.

use super::far_field::{recommended_order, FarField};
use super::monte_carlo::scattering_monte_carlo;
use super::params::{Lobes, Params};
use super::table::{Parameterisation, Table};
use crate::Error;
use coif_base::rng::SplitMix64;
use glam::Vec3;

/// Quadrature order of the reference far field in this module: four
/// times [`recommended_order`], at least 256.
pub fn reference_order(params: &Params) -> usize {
    (4 * recommended_order(params)).max(256)
}

/// `samples` random (t, wi, wo) triples from `seed`.
pub fn random_configurations(samples: usize, seed: u64) -> Vec<(Vec3, Vec3, Vec3)> {
    let mut rng = SplitMix64::new(seed);
    (0..samples)
        .map(|_| (rng.unit_vector(), rng.unit_vector(), rng.unit_vector()))
        .collect()
}

/// Relative RMS of `approx` against `reference` over the configurations.
pub fn relative_rms(
    configs: &[(Vec3, Vec3, Vec3)],
    reference: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
    approx: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
) -> f32 {
    let (mut err, mut norm) = (0.0f64, 0.0f64);
    for &(t, wi, wo) in configs {
        let r = reference(t, wi, wo).as_dvec3();
        let a = approx(t, wi, wo).as_dvec3();
        err += (a - r).length_squared();
        norm += r.length_squared();
    }
    (err / norm).sqrt() as f32
}

/// Relative RMS error of a `resolution` table with the given axes against
/// the far field at [`reference_order`].
///
/// # Errors
///
/// As [`Table::with_axes`].
pub fn table_error_with_axes(
    params: &Params,
    resolution: usize,
    axes: Parameterisation,
    samples: usize,
    seed: u64,
) -> Result<f32, Error> {
    let table = Table::with_axes(params, resolution, axes)?;
    let reference = FarField::new(params, reference_order(params))?;
    let configs = random_configurations(samples, seed);
    Ok(relative_rms(
        &configs,
        |t, wi, wo| reference.eval(t, wi, wo),
        |t, wi, wo| table.scattering(t, wi, wo),
    ))
}

/// Relative RMS error of a `resolution` table ([`Parameterisation::Angles`])
/// against the far field at [`reference_order`].
///
/// # Errors
///
/// As [`Table::new`].
pub fn table_error(
    params: &Params,
    resolution: usize,
    samples: usize,
    seed: u64,
) -> Result<f32, Error> {
    table_error_with_axes(params, resolution, Parameterisation::Angles, samples, seed)
}

/// Relative RMS error of the far field with `order` quadrature nodes
/// against the far field at [`reference_order`].
///
/// # Errors
///
/// As [`FarField::new`].
pub fn far_field_error(
    params: &Params,
    order: usize,
    samples: usize,
    seed: u64,
) -> Result<f32, Error> {
    let approx = FarField::new(params, order)?;
    let reference = FarField::new(params, reference_order(params))?;
    let configs = random_configurations(samples, seed);
    Ok(relative_rms(
        &configs,
        |t, wi, wo| reference.eval(t, wi, wo),
        |t, wi, wo| approx.eval(t, wi, wo),
    ))
}

/// Relative RMS error of [`scattering_monte_carlo`] with `h_samples`
/// stratified offsets per configuration (offsets from one generator seeded
/// with `seed + 1`) against the far field at [`reference_order`].
///
/// # Errors
///
/// As [`Params::validate`].
pub fn monte_carlo_error(
    params: &Params,
    h_samples: usize,
    samples: usize,
    seed: u64,
) -> Result<f32, Error> {
    let reference = FarField::new(params, reference_order(params))?;
    let lobes = Lobes::new(params);
    let configs = random_configurations(samples, seed);
    let rng = std::cell::RefCell::new(SplitMix64::new(seed.wrapping_add(1)));
    Ok(relative_rms(
        &configs,
        |t, wi, wo| reference.eval(t, wi, wo),
        |t, wi, wo| {
            scattering_monte_carlo(&lobes, params, t, wi, wo, h_samples, &mut rng.borrow_mut())
        },
    ))
}

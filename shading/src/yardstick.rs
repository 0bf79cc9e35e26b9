//! Every shading model measured against the yardstick, pbrt-v3's far field
//! (Pharr, Jakob & Humphreys 2016; Chiang et al. 2016): relative RMS error over random directions, raw and
//! after the best single gain (the error of the *shape* of the lobes, for
//! models like Kajiya-Kay that are not energy-normalised).
//!
//! Conventions differ between the models, so the comparison maps pbrt's
//! material onto each: pbrt's `scattering` includes the `cos theta_i` of the
//! rendering equation and Marschner's does not (see [`crate::marschner::scattering`]), so Marschner is
//! multiplied by `cos theta_i = sqrt(1 - (t.wi)^2)`; Marschner's R shift is
//! pbrt's cuticle tilt, `alpha_R = -2 alpha`; its R width is pbrt's
//! longitudinal standard deviation `beta_R = sqrt(v0)`; absorption per unit
//! radius is pbrt's `sigma_a`.

use crate::kajiya_kay::KajiyaKay;
use crate::pbrt::{self, quality::random_configurations, FarField, Lobes};
use crate::{marschner, Error};
use glam::Vec3;

/// One model's distance from pbrt's far field.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelError {
    /// The model's name.
    pub model: String,
    /// `sqrt(sum |a - r|^2 / sum |r|^2)` over RGB and samples.
    pub relative_rms: f64,
    /// The same after scaling `a` by the least-squares gain `g`.
    pub relative_rms_after_gain: f64,
    /// `g = sum a.r / sum a.a`.
    pub gain: f64,
}

/// Marschner parameters matching a pbrt material (see the module doc).
pub fn marschner_matching(p: &pbrt::Params) -> marschner::Params {
    let lobes = Lobes::new(p);
    marschner::Params {
        eta: p.eta,
        alpha_r: -2.0 * p.alpha,
        beta_r: lobes.v[0].sqrt(),
        absorption: p.sigma_a,
        ..Default::default()
    }
}

fn cos_theta_i(t: Vec3, wi: Vec3) -> f32 {
    (1.0 - t.dot(wi).powi(2)).max(0.0).sqrt()
}

/// Errors of `approx` against `reference` values over `configs`.
fn compare(
    model: &str,
    configs: &[(Vec3, Vec3, Vec3)],
    reference: &[Vec3],
    approx: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
) -> ModelError {
    let values: Vec<Vec3> = configs
        .iter()
        .map(|&(t, wi, wo)| approx(t, wi, wo))
        .collect();
    let (mut ar, mut aa, mut rr) = (0.0f64, 0.0f64, 0.0f64);
    for (a, r) in values.iter().zip(reference) {
        let (a, r) = (a.as_dvec3(), r.as_dvec3());
        ar += a.dot(r);
        aa += a.dot(a);
        rr += r.dot(r);
    }
    let gain = if aa > 0.0 { ar / aa } else { 0.0 };
    let err = |g: f64| {
        let e: f64 = values
            .iter()
            .zip(reference)
            .map(|(a, r)| (a.as_dvec3() * g - r.as_dvec3()).length_squared())
            .sum();
        (e / rr).sqrt()
    };
    ModelError {
        model: model.to_string(),
        relative_rms: err(1.0),
        relative_rms_after_gain: err(gain),
        gain,
    }
}

/// Kajiya-Kay, Marschner (direct and a table of `resolution`) and pbrt's own
/// table of `resolution`, against pbrt's far field at its recommended
/// quadrature order, over `samples` random (t, wi, wo) from `seed`.
///
/// # Errors
///
/// As [`pbrt::FarField::new`] and [`pbrt::Table::new`] for invalid
/// parameters or a resolution below 2.
pub fn versus_pbrt(
    params: &pbrt::Params,
    resolution: usize,
    samples: usize,
    seed: u64,
) -> Result<Vec<ModelError>, Error> {
    let configs = random_configurations(samples, seed);
    let far = FarField::new(params, pbrt::recommended_order(params))?;
    let reference: Vec<Vec3> = configs
        .iter()
        .map(|&(t, wi, wo)| far.eval(t, wi, wo))
        .collect();
    let m = marschner_matching(params);
    let lut = marschner::Lut::new(&m, resolution);
    let table = pbrt::Table::new(params, resolution)?;
    let kk = KajiyaKay::default();
    Ok(vec![
        compare("kajiya-kay", &configs, &reference, |t, wi, wo| {
            kk.shade(t, wi, wo) * cos_theta_i(t, wi)
        }),
        compare("marschner direct", &configs, &reference, |t, wi, wo| {
            marschner::scattering(&m, t, wi, wo) * cos_theta_i(t, wi)
        }),
        compare(
            &format!("marschner table {resolution}"),
            &configs,
            &reference,
            |t, wi, wo| lut.scattering(t, wi, wo) * cos_theta_i(t, wi),
        ),
        compare(
            &format!("pbrt table {resolution}"),
            &configs,
            &reference,
            |t, wi, wo| table.scattering(t, wi, wo),
        ),
    ])
}

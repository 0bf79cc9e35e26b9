//! Absorption coefficients from pigment concentrations and from a desired
//! hair colour (pbrt-v3 `HairBSDF::SigmaAFromConcentration` and
//! `SigmaAFromReflectance`, after d'Eon 2011 and Chiang 2016 section 4.2).

use super::params::pow_n;
use glam::Vec3;

/// Absorption of eumelanin per unit concentration, RGB (d'Eon 2011).
pub const EUMELANIN_SIGMA_A: Vec3 = Vec3::new(0.419, 0.697, 1.37);
/// Absorption of pheomelanin per unit concentration, RGB (d'Eon 2011).
pub const PHEOMELANIN_SIGMA_A: Vec3 = Vec3::new(0.187, 0.4, 1.05);

/// `sigma_a = c_eu (0.419, 0.697, 1.37) + c_ph (0.187, 0.4, 1.05)`.
/// Eumelanin 1.3 (pbrt-v3's default) gives (0.5447, 0.9061, 1.781).
pub fn sigma_a_from_concentration(eumelanin: f32, pheomelanin: f32) -> Vec3 {
    let one = |eu: f32, ph: f32| eumelanin * eu + pheomelanin * ph;
    Vec3::new(
        one(EUMELANIN_SIGMA_A.x, PHEOMELANIN_SIGMA_A.x),
        one(EUMELANIN_SIGMA_A.y, PHEOMELANIN_SIGMA_A.y),
        one(EUMELANIN_SIGMA_A.z, PHEOMELANIN_SIGMA_A.z),
    )
}

/// The absorption that makes a hair volume look like `color` (each channel
/// in (0, 1]) under multiple scattering, for azimuthal roughness `beta_n`
/// (the inversion is fitted, so it depends on roughness):
/// Chiang 2016 eq. 9,
/// `sigma_a = (ln c / (5.969 - 0.215 b + 2.532 b^2 - 10.73 b^3 + 5.574 b^4 + 0.245 b^5))^2`
/// with `b = beta_n`. A channel of 0 gives +infinity (black), a negative one
/// NaN; a
/// channel of 1 gives 0.
pub fn sigma_a_from_reflectance(color: Vec3, beta_n: f32) -> Vec3 {
    let b = beta_n;
    let d = 5.969 - 0.215 * b + 2.532 * (b * b) - 10.73 * pow_n(b, 3)
        + 5.574 * pow_n(b, 4)
        + 0.245 * pow_n(b, 5);
    let one = |c: f32| {
        let x = c.ln() / d;
        x * x
    };
    Vec3::new(one(color.x), one(color.y), one(color.z))
}

//! pbrt-v3's hair BSDF (Chiang et al. 2016 with d'Eon et al. 2011's
//! longitudinal term), the physically based yardstick of coif's shading.
//!
//! * [`scattering_local`]: pbrt-v3's `HairBSDF::f(wo, wi) * |wi.z|` at one
//!   offset `h`, reproduced to float precision (same `f32` operations in
//!   the same order, same approximations of I0 and ln 2).
//! * [`scattering`] and [`FarField`]: the far-field form, averaged over `h`
//!   in [-1, 1], in world space (what a rasteriser shading a thin fibre needs).
//! * [`Table`]: the far-field form baked into two 2D tables, with scalar and
//!   `wide` SIMD batch lookups.
//! * [`scattering_monte_carlo`]: the far field estimated from `n`
//!   stratified offsets of [`scattering_local`], as pbrt's one random `h`
//!   per camera ray estimates it (scalar only).
//! * [`sample()`] and [`pdf()`]: pbrt-v3's importance sampling of the exact
//!   model at one `h` (`Sample_f`, `Pdf`), for path tracing.
//! * [`melanin`]: absorption from pigment concentrations or from a colour.
//! * [`quality`]: error measurements for reports and benches.
//!
//! See `shading/PBRT.md` for conventions, derivations and measured figures.

pub mod attenuation;
pub mod azimuthal;
pub mod bessel;
mod far_field;
pub(crate) mod fast_acos;
pub mod longitudinal;
pub mod melanin;
mod monte_carlo;
mod params;
pub mod quality;
pub mod sample;
pub mod table;

pub use far_field::{
    gauss_legendre, recommended_order, scattering, world_angles, FarField,
    DEFAULT_QUADRATURE_ORDER, MAX_FAR_FIELD_ORDER, MAX_QUADRATURE_ORDER,
};
pub use melanin::{sigma_a_from_concentration, sigma_a_from_reflectance};
pub use monte_carlo::{local_directions, scattering_batch_monte_carlo, scattering_monte_carlo};
pub use params::{Lobes, Params};
pub use sample::{ap_pdf, luminance, pdf, sample, HairSample};
pub use table::{Parameterisation, Table, MAX_TABLE_RESOLUTION};

use attenuation::{ap, P_MAX};
use azimuthal::np;
use glam::Vec3;
use longitudinal::mp;
use std::f32::consts::PI;

/// pbrt-v3's sum over p = 0..3 of `M_p A_p N_p`, in pbrt-v3's local frame
/// (x = tangent, z = shading normal, y = z cross x; `sin theta = w.x`,
/// `phi = atan2(w.z, w.y)`; both directions point away from the fibre), at
/// offset `h` in [-1, 1] across the fibre (`gamma_o = asin h`): that is,
/// pbrt's `f(wo, wi)` times `|wi.z|` (exactly the sum, also where `wi.z = 0`).
///
/// Follows pbrt-v3's `HairBSDF::f` (current version: the 2018 alpha fix and
/// the 2019 tilt of theta_o): `eta' = sqrt(eta^2 - sin^2 theta_o) / cos theta_o`,
/// `sin gamma_t = h / eta'`, `T = exp(-sigma_a 2 cos gamma_t / cos theta_t)`,
/// `phi = phi_i - phi_o` (wrapped only inside `N_p`), `A_p` with the untilted
/// `cos theta_o`, `M_p` with theta_o tilted per lobe, and the residual
/// `M_3 A_3 / (2 pi)` untilted.
///
/// Never panics. Directions need not be exactly unit (`sin theta` is taken
/// as the x component, as in pbrt); NaN input gives NaN output.
pub fn scattering_local(params: &Params, h: f32, wo: Vec3, wi: Vec3) -> Vec3 {
    let lobes = Lobes::new(params);
    scattering_local_with(&lobes, params, h, wo, wi)
}

/// [`scattering_local`] with the per-material constants already derived.
pub fn scattering_local_with(lobes: &Lobes, params: &Params, h: f32, wo: Vec3, wi: Vec3) -> Vec3 {
    let gamma_o = h.clamp(-1.0, 1.0).asin();
    let eta = params.eta;

    let sin_theta_o = wo.x;
    let cos_theta_o = (1.0 - sin_theta_o * sin_theta_o).max(0.0).sqrt();
    let phi_o = wo.z.atan2(wo.y);

    let sin_theta_i = wi.x;
    let cos_theta_i = (1.0 - sin_theta_i * sin_theta_i).max(0.0).sqrt();
    let phi_i = wi.z.atan2(wi.y);

    let sin_theta_t = sin_theta_o / eta;
    let cos_theta_t = (1.0 - sin_theta_t * sin_theta_t).max(0.0).sqrt();

    let etap = (eta * eta - sin_theta_o * sin_theta_o).sqrt() / cos_theta_o;
    let sin_gamma_t = h / etap;
    let cos_gamma_t = (1.0 - sin_gamma_t * sin_gamma_t).max(0.0).sqrt();
    let gamma_t = sin_gamma_t.clamp(-1.0, 1.0).asin();

    let transmittance = exp3(-params.sigma_a * (2.0 * cos_gamma_t / cos_theta_t));

    let phi = phi_i - phi_o;
    let a = ap(cos_theta_o, eta, h, transmittance);
    let mut sum = Vec3::ZERO;
    for (p, a_p) in a.iter().enumerate().take(P_MAX) {
        let (sin_op, cos_op) = lobes.tilt(p, sin_theta_o, cos_theta_o);
        let m = mp(cos_theta_i, cos_op, sin_theta_i, sin_op, lobes.v[p]);
        sum += *a_p * m * np(phi, p as i32, lobes.s, gamma_o, gamma_t);
    }
    let m3 = mp(
        cos_theta_i,
        cos_theta_o,
        sin_theta_i,
        sin_theta_o,
        lobes.v[P_MAX],
    );
    sum += a[P_MAX] * m3 / (2.0 * PI);
    sum
}

/// Per-channel `exp`.
#[inline]
pub(crate) fn exp3(v: Vec3) -> Vec3 {
    Vec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}

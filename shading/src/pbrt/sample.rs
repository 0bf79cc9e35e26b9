//! Importance sampling of pbrt-v3's hair BSDF at one offset `h`: pbrt-v3's
//! `HairBSDF::Sample_f`, `HairBSDF::Pdf` and `ComputeApPdf` (Chiang et al.
//! 2016, "A practical and controllable hair and fur model for production
//! path tracing", section 4.3; pbrt-v3 `src/materials/hair.cpp`), written
//! from the published formulas, in pbrt's local frame (see
//! [`super::scattering_local`]).
//!
//! Sampling a direction `wi` for a given `wo` and `h`:
//!
//! 1. choose the lobe `p` in 0..=3 with probability
//!    `apPdf[p] = y(A_p) / sum_q y(A_q)` ([`ap_pdf`]), `y` the luminance
//!    `0.212671 r + 0.715160 g + 0.072169 b` ([`luminance`], pbrt's RGB `y()`);
//! 2. sample `M_p` by d'Eon's inversion around the tilted `theta_o'`:
//!    `cos theta = 1 + v ln(u + (1 - u) e^(-2/v))` with `u >= 1e-5`,
//!    `sin theta_i = -cos theta sin theta_o' + sin theta cos(2 pi u') cos theta_o'`;
//! 3. sample `N_p`: `dphi = Phi(p, gamma_o, gamma_t) + x` with `x` from the
//!    logistic of scale `s` trimmed to `[-pi, pi]` by inverting its CDF,
//!    `x = -s ln(1 / (u k + F(-pi)) - 1)`, `k = F(pi) - F(-pi)`, clamped to
//!    `[-pi, pi]`; for the residual `p = 3`, `dphi = 2 pi u`;
//! 4. `wi = (sin theta_i, cos theta_i cos(phi_o + dphi), cos theta_i sin(phi_o + dphi))`.
//!
//! The density of `wi` (per unit solid angle) is the mixture
//! `sum_{p<3} apPdf[p] M_p(tilted) N_p + apPdf[3] M_3 / (2 pi)` ([`pdf`]),
//! and the Monte Carlo weight is `scattering_local(h, wo, wi) / pdf`
//! (pbrt's `f |cos theta_i| / pdf`). For a white fibre (`sigma_a = 0`)
//! `A_p` are grey and sum to 1, so `apPdf = A_p` and the weight is 1 up to
//! rounding, whatever the direction.
//!
//! pbrt-v3 derives its four uniforms from two by `DemuxFloat` (splitting the
//! bits of each); here the caller passes four independent uniforms
//! `[u_lobe, u_np, u_mp, u_mp_phi]` (pbrt's `u[0][0]`, `u[0][1]`,
//! `u[1][0]`, `u[1][1]`), so no demultiplexing is needed. As in pbrt, the
//! lobe's uniform is rescaled by subtracting the skipped probabilities but
//! not reused.

use super::attenuation::{ap, P_MAX};
use super::azimuthal::{logistic_cdf, np, phi};
use super::longitudinal::mp;
use super::params::{Lobes, Params};
use super::{exp3, scattering_local_with};
use glam::Vec3;
use std::f32::consts::PI;

/// pbrt-v3's RGB luminance weights (`YWeight`, CIE Y of linear sRGB
/// primaries): `y = 0.212671 r + 0.715160 g + 0.072169 b`.
pub const LUMINANCE: [f32; 3] = [0.212_671, 0.715_160, 0.072_169];

/// pbrt's `RGBSpectrum::y()`: `0.212671 r + 0.715160 g + 0.072169 b`
/// (summed in that order).
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    LUMINANCE[0] * c.x + LUMINANCE[1] * c.y + LUMINANCE[2] * c.z
}

/// pbrt-v3's `ComputeApPdf(cos theta_o)`: the probability of choosing each
/// lobe p = 0..=3, `y(A_p) / sum_q y(A_q)`, with `A_p` as in
/// [`super::scattering_local`] (`sin theta_o = sqrt(1 - cos^2 theta_o)`,
/// `eta'`, `gamma_t`, `T = exp(-sigma_a 2 cos gamma_t / cos theta_t)`).
/// If the luminances sum to zero or NaN, every entry is NaN.
pub fn ap_pdf(params: &Params, cos_theta_o: f32, h: f32) -> [f32; P_MAX + 1] {
    let eta = params.eta;
    let sin_theta_o = (1.0 - cos_theta_o * cos_theta_o).max(0.0).sqrt();
    let sin_theta_t = sin_theta_o / eta;
    let cos_theta_t = (1.0 - sin_theta_t * sin_theta_t).max(0.0).sqrt();
    let etap = (eta * eta - sin_theta_o * sin_theta_o).sqrt() / cos_theta_o;
    let sin_gamma_t = h / etap;
    let cos_gamma_t = (1.0 - sin_gamma_t * sin_gamma_t).max(0.0).sqrt();
    let transmittance = exp3(-params.sigma_a * (2.0 * cos_gamma_t / cos_theta_t));
    let a = ap(cos_theta_o, eta, h, transmittance);
    let sum_y = a.iter().fold(0.0f32, |s, a_p| s + luminance(*a_p));
    if sum_y.is_nan() || sum_y <= 0.0 {
        return [f32::NAN; P_MAX + 1];
    }
    let mut out = [0.0f32; P_MAX + 1];
    for (o, a_p) in out.iter_mut().zip(a.iter()) {
        *o = luminance(*a_p) / sum_y;
    }
    out
}

/// The tilt of [`Lobes::tilt`] without its `abs` on the cosine: pbrt-v3's
/// `Sample_f` rotates `theta_o` this way before sampling `M_p` (its `Pdf`
/// and `f` take the absolute value).
#[inline]
fn tilt_signed(lobes: &Lobes, p: usize, sin_theta_o: f32, cos_theta_o: f32) -> (f32, f32) {
    let (s, c) = (lobes.sin_2k_alpha, lobes.cos_2k_alpha);
    match p {
        0 => (
            sin_theta_o * c[1] - cos_theta_o * s[1],
            cos_theta_o * c[1] + sin_theta_o * s[1],
        ),
        1 => (
            sin_theta_o * c[0] + cos_theta_o * s[0],
            cos_theta_o * c[0] - sin_theta_o * s[0],
        ),
        2 => (
            sin_theta_o * c[2] + cos_theta_o * s[2],
            cos_theta_o * c[2] - sin_theta_o * s[2],
        ),
        _ => (sin_theta_o, cos_theta_o),
    }
}

/// pbrt-v3's `SampleTrimmedLogistic(u, s, a, b)`: the inverse CDF of the
/// logistic of scale `s` renormalised to `[a, b]`,
/// `x = -s ln(1 / (u k + F(a)) - 1)` with `k = F(b) - F(a)`, clamped to
/// `[a, b]` (a NaN `x` gives `a`; never panics).
#[inline]
pub fn sample_trimmed_logistic(u: f32, s: f32, a: f32, b: f32) -> f32 {
    let k = logistic_cdf(b, s) - logistic_cdf(a, s);
    let x = -s * (1.0 / (u * k + logistic_cdf(a, s)) - 1.0).ln();
    // `max`/`min` rather than `clamp` (which panics on NaN or crossed
    // bounds): a NaN `x` becomes `a`.
    x.max(a).min(b)
}

/// One sampled direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairSample {
    /// The sampled incident direction (pbrt's local frame, pointing away
    /// from the fibre, unit up to rounding).
    pub wi: Vec3,
    /// Its density per unit solid angle, [`pdf`]`(wo, wi)` as pbrt computes
    /// it inside `Sample_f`.
    pub pdf: f32,
    /// `scattering_local(h, wo, wi) / pdf` (pbrt's `f |cos theta_i| / pdf`),
    /// zero where `pdf` is not positive and finite.
    pub weight: Vec3,
    /// The lobe chosen (0 = R, 1 = TT, 2 = TRT, 3 = residual).
    pub lobe: usize,
}

/// pbrt-v3's `HairBSDF::Sample_f` at offset `h` (in [-1, 1]; clamped for
/// `gamma_o`) for `wo` in pbrt's local frame, from four independent
/// uniforms in [0, 1): `u = [u_lobe, u_np, u_mp, u_mp_phi]`. See the
/// module documentation for the steps.
///
/// Never panics; NaN input gives a NaN direction and a zero weight.
pub fn sample(lobes: &Lobes, params: &Params, h: f32, wo: Vec3, u: [f32; 4]) -> HairSample {
    let eta = params.eta;
    let gamma_o = h.clamp(-1.0, 1.0).asin();
    let sin_theta_o = wo.x;
    let cos_theta_o = (1.0 - sin_theta_o * sin_theta_o).max(0.0).sqrt();
    let phi_o = wo.z.atan2(wo.y);

    let ap_pdf = ap_pdf(params, cos_theta_o, h);
    let mut u_lobe = u[0];
    let mut p = 0;
    while p < P_MAX {
        if u_lobe < ap_pdf[p] {
            break;
        }
        u_lobe -= ap_pdf[p];
        p += 1;
    }

    let (sin_op, cos_op) = tilt_signed(lobes, p, sin_theta_o, cos_theta_o);

    // M_p: d'Eon's inversion of the longitudinal lobe.
    let v = lobes.v[p];
    let u_mp = u[2].max(1e-5);
    let cos_theta = 1.0 + v * (u_mp + (1.0 - u_mp) * (-2.0 / v).exp()).ln();
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let cos_phi = (2.0 * PI * u[3]).cos();
    let sin_theta_i = -cos_theta * sin_op + sin_theta * cos_phi * cos_op;
    let cos_theta_i = (1.0 - sin_theta_i * sin_theta_i).max(0.0).sqrt();

    // N_p around Phi(p, gamma_o, gamma_t).
    let etap = (eta * eta - sin_theta_o * sin_theta_o).sqrt() / cos_theta_o;
    let sin_gamma_t = h / etap;
    let gamma_t = sin_gamma_t.clamp(-1.0, 1.0).asin();
    let dphi = if p < P_MAX {
        phi(p as i32, gamma_o, gamma_t) + sample_trimmed_logistic(u[1], lobes.s, -PI, PI)
    } else {
        2.0 * PI * u[1]
    };

    let phi_i = phi_o + dphi;
    let wi = Vec3::new(
        sin_theta_i,
        cos_theta_i * phi_i.cos(),
        cos_theta_i * phi_i.sin(),
    );

    let pdf = mixture_pdf(
        lobes,
        &ap_pdf,
        (sin_theta_o, cos_theta_o),
        (sin_theta_i, cos_theta_i),
        dphi,
        gamma_o,
        gamma_t,
    );
    let weight = if pdf > 0.0 && pdf.is_finite() {
        scattering_local_with(lobes, params, h, wo, wi) / pdf
    } else {
        Vec3::ZERO
    };
    HairSample {
        wi,
        pdf,
        weight,
        lobe: p,
    }
}

/// `sum_{p<3} apPdf[p] M_p(theta_i, theta_o'_p) N_p(dphi) + apPdf[3] M_3 / (2 pi)`.
fn mixture_pdf(
    lobes: &Lobes,
    ap_pdf: &[f32; P_MAX + 1],
    (sin_theta_o, cos_theta_o): (f32, f32),
    (sin_theta_i, cos_theta_i): (f32, f32),
    dphi: f32,
    gamma_o: f32,
    gamma_t: f32,
) -> f32 {
    let mut pdf = 0.0f32;
    for (p, a_p) in ap_pdf.iter().enumerate().take(P_MAX) {
        let (sin_op, cos_op) = lobes.tilt(p, sin_theta_o, cos_theta_o);
        pdf += mp(cos_theta_i, cos_op, sin_theta_i, sin_op, lobes.v[p])
            * a_p
            * np(dphi, p as i32, lobes.s, gamma_o, gamma_t);
    }
    pdf += mp(
        cos_theta_i,
        cos_theta_o,
        sin_theta_i,
        sin_theta_o,
        lobes.v[P_MAX],
    ) * ap_pdf[P_MAX]
        * (1.0 / (2.0 * PI));
    pdf
}

/// pbrt-v3's `HairBSDF::Pdf(wo, wi)` at offset `h`: the density per unit
/// solid angle with which [`sample`] produces `wi` (pbrt's local frame,
/// `phi = phi_i - phi_o` from `atan2`). Never panics; NaN in, NaN out.
pub fn pdf(lobes: &Lobes, params: &Params, h: f32, wo: Vec3, wi: Vec3) -> f32 {
    let eta = params.eta;
    let gamma_o = h.clamp(-1.0, 1.0).asin();
    let sin_theta_o = wo.x;
    let cos_theta_o = (1.0 - sin_theta_o * sin_theta_o).max(0.0).sqrt();
    let phi_o = wo.z.atan2(wo.y);
    let sin_theta_i = wi.x;
    let cos_theta_i = (1.0 - sin_theta_i * sin_theta_i).max(0.0).sqrt();
    let phi_i = wi.z.atan2(wi.y);
    let etap = (eta * eta - sin_theta_o * sin_theta_o).sqrt() / cos_theta_o;
    let sin_gamma_t = h / etap;
    let gamma_t = sin_gamma_t.clamp(-1.0, 1.0).asin();
    let ap_pdf = ap_pdf(params, cos_theta_o, h);
    mixture_pdf(
        lobes,
        &ap_pdf,
        (sin_theta_o, cos_theta_o),
        (sin_theta_i, cos_theta_i),
        phi_i - phi_o,
        gamma_o,
        gamma_t,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trimmed_logistic_sampling_inverts_its_cdf() {
        let s = 0.3f32;
        let k = logistic_cdf(PI, s) - logistic_cdf(-PI, s);
        for u in [0.0f32, 0.1, 0.5, 0.9, 0.999] {
            let x = sample_trimmed_logistic(u, s, -PI, PI);
            let back = (logistic_cdf(x, s) - logistic_cdf(-PI, s)) / k;
            assert!((back - u).abs() < 1e-5, "u {u} -> x {x} -> {back}");
        }
        assert_eq!(sample_trimmed_logistic(f32::NAN, s, -PI, PI), -PI);
        let _ = sample_trimmed_logistic(0.5, s, f32::NAN, 1.0);
    }

    #[test]
    fn lobe_probabilities_sum_to_one_and_follow_luminance() {
        let params = Params::default();
        for h in [-0.9f32, 0.0, 0.5] {
            for cos_o in [0.2f32, 0.7, 1.0] {
                let a = ap_pdf(&params, cos_o, h);
                let sum: f32 = a.iter().sum();
                assert!((sum - 1.0).abs() < 1e-5, "{a:?}");
                assert!(a.iter().all(|&x| (0.0..=1.0).contains(&x)));
            }
        }
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
    }
}

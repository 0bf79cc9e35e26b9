//! The attenuation A_p of each scattering path: Fresnel reflectance with the
//! real index of refraction and the transmittance of one pass through the
//! fibre (Chiang 2016 section 4; pbrt-v3 `Ap` and `FrDielectric`).

use glam::Vec3;

/// Number of explicit lobes; the term `p = P_MAX` is the residual.
pub const P_MAX: usize = 3;

/// Unpolarised Fresnel reflectance of a dielectric interface for the
/// cosine `cos_theta_i` of the incident angle, from index `eta_i` into
/// `eta_t` (pbrt-v3 `FrDielectric`; negative cosines swap the media).
#[inline]
pub fn fr_dielectric(cos_theta_i: f32, eta_i: f32, eta_t: f32) -> f32 {
    let mut cos_i = cos_theta_i.clamp(-1.0, 1.0);
    let (mut ei, mut et) = (eta_i, eta_t);
    if cos_i <= 0.0 {
        std::mem::swap(&mut ei, &mut et);
        cos_i = cos_i.abs();
    }
    let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
    let sin_t = ei / et * sin_i;
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
    let r_parl = ((et * cos_i) - (ei * cos_t)) / ((et * cos_i) + (ei * cos_t));
    let r_perp = ((ei * cos_i) - (et * cos_t)) / ((ei * cos_i) + (et * cos_t));
    (r_parl * r_parl + r_perp * r_perp) / 2.0
}

/// `A_0 = f`, `A_1 = (1 - f)^2 T`, `A_2 = A_1 T f`, and the residual
/// `A_3 = A_2 f T / (1 - T f)` (the geometric series of all higher orders),
/// with `f = F(cos theta_o cos gamma_o)` at the entry point, `eta`, and `T`
/// the per-channel transmittance of one internal segment.
///
/// `cos_theta_o` is the *untilted* value, as in pbrt-v3. The one deviation
/// from pbrt-v3: where it computes `A_3 = 0/0` (see the body) this gives 0.
#[inline]
pub fn ap(cos_theta_o: f32, eta: f32, h: f32, t: Vec3) -> [Vec3; P_MAX + 1] {
    let cos_gamma_o = (1.0 - h * h).max(0.0).sqrt();
    let cos_theta = cos_theta_o * cos_gamma_o;
    let f = fr_dielectric(cos_theta, 1.0, eta);
    let a0 = Vec3::splat(f);
    let a1 = t * ((1.0 - f) * (1.0 - f));
    let a2 = a1 * t * f;
    let num = a2 * f * t;
    let den = Vec3::ONE - t * f;
    // pbrt-v3 divides unguarded; at f = T = 1 (grazing entry, channel without
    // absorption) that is 0/0. The limit of (1-f)^2 f^2 T^3 / (1 - T f) there
    // is 0, which is what this returns; elsewhere the value is pbrt's.
    let residual = |n: f32, d: f32| if d == 0.0 { 0.0 } else { n / d };
    let a3 = Vec3::new(
        residual(num.x, den.x),
        residual(num.y, den.y),
        residual(num.z, den.z),
    );
    [a0, a1, a2, a3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_fresnel_is_the_textbook_value() {
        // ((eta - 1) / (eta + 1))^2 for eta = 1.55.
        let r = ((1.55f32 - 1.0) / (1.55 + 1.0)).powi(2);
        assert!((fr_dielectric(1.0, 1.0, 1.55) - r).abs() < 1e-6);
        assert_eq!(fr_dielectric(0.0, 1.0, 1.55), 1.0, "grazing");
        // From inside, beyond the critical angle: total internal reflection.
        assert_eq!(fr_dielectric(-0.1, 1.0, 1.55), 1.0);
    }

    #[test]
    fn without_absorption_the_attenuations_sum_to_one() {
        for h in [-1.0f32, -0.7, 0.0, 0.3, 0.99, 1.0] {
            for cos_o in [0.0f32, 0.4, 1.0] {
                let a = ap(cos_o, 1.55, h, Vec3::ONE);
                let total = a[0] + a[1] + a[2] + a[3];
                assert!(
                    (total - Vec3::ONE).abs().max_element() < 1e-5,
                    "h {h} cos {cos_o}: {total}"
                );
            }
        }
    }
}

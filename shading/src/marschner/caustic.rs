//! The TRT caustic treatment (Marschner 2003, section 4.3).
//!
//! For eta' < 2, phi(2, h) turns at h_c = sqrt((4 - eta'^2) / 3), where
//! dphi/dh = 0 and N_P is infinite (a caustic at azimuth +-phi_c,
//! phi_c = phi(2, h_c)). The paper removes the singular part near +-phi_c
//! and adds a glint of finite width w_c in its place:
//!
//!   N_TRT(phi) = N_P(2, phi) (1 - t G(phi - phi_c)) (1 - t G(phi + phi_c))
//!              + t k_G A(2, h_c) Delta_h (g(w_c; phi - phi_c) + g(w_c; phi + phi_c))
//!
//! with G(x) = g(w_c; x) / g(w_c; 0), the glint's h-interval
//! Delta_h = min(Delta_h_M, 2 sqrt(2 w_c / |d^2 phi / dh^2 (h_c)|)), and t = 1.
//! For eta' >= 2 the two caustics have merged at phi = 0 and vanished:
//! phi_c = 0, h_c = 0, Delta_h = Delta_h_M, and the glint fades out as eta'
//! goes from 2 to 2 + Delta_eta' (t = 1 - smoothstep(2, 2 + Delta_eta', eta'),
//! continuous with t = 1 below 2).
//!
//! Note: h_c is computed exactly. A public port writes it so that operator
//! precedence gives (6 * 2 c) / (pi - 2) = 0.5105 for every eta'; the true
//! value is 0.7297 at eta' = 1.55 (see the tests).

use super::azimuthal::{
    attenuation, caustic_offset, exit_azimuth, exit_azimuth_second_derivative, n_plain, wrap_angle,
    Interface,
};
use super::longitudinal::gaussian;
use super::params::Sanitised;

/// Where and how strong the TRT glints are, for one eta'.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Caustic {
    /// Azimuth of the caustic, phi_c in [0, pi] (glints at +-phi_c).
    pub phi_c: f64,
    /// Offset of the turning point h_c (0 when eta' >= 2).
    pub h_c: f64,
    /// The h-interval Delta_h the glint gathers.
    pub delta_h: f64,
    /// Blend t in [0, 1] between the plain N_P and the glint treatment.
    pub t: f64,
}

/// smoothstep(a, b, x) = 3 s^2 - 2 s^3, s = clamp((x - a) / (b - a), 0, 1).
fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let s = ((x - a) / (b - a)).clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// The caustic of the TRT lobe at Bravais index `eta_perp`, for caustic
/// width `w_c`, caustic limit `delta_h_max` and fade range `fade`.
pub fn caustic(eta_perp: f64, w_c: f64, delta_h_max: f64, fade: f64) -> Caustic {
    match caustic_offset(eta_perp) {
        Some(h_c) => {
            let curvature = exit_azimuth_second_derivative(2, h_c, eta_perp).abs();
            let width = if curvature > 0.0 {
                2.0 * (2.0 * w_c / curvature).sqrt()
            } else {
                f64::INFINITY
            };
            Caustic {
                phi_c: wrap_angle(exit_azimuth(2, h_c, eta_perp)).abs(),
                h_c,
                delta_h: width.min(delta_h_max),
                t: 1.0,
            }
        }
        None => Caustic {
            phi_c: 0.0,
            h_c: 0.0,
            delta_h: delta_h_max,
            t: 1.0 - smoothstep(2.0, 2.0 + fade, eta_perp),
        },
    }
}

/// N_TRT(phi) per RGB channel with the caustic treatment above.
pub(crate) fn n_trt(params: &Sanitised, phi: f64, iface: &Interface) -> [f64; 3] {
    let c = caustic(
        iface.eta_perp,
        params.caustic_width,
        params.caustic_limit,
        params.caustic_fade_range,
    );
    let plain = n_plain(2, phi, iface, &params.absorption, params.roots);
    let w = params.caustic_width;
    let d_minus = wrap_angle(phi - c.phi_c);
    let d_plus = wrap_angle(phi + c.phi_c);
    let fade_shape = |d: f64| (-0.5 * (d / w) * (d / w)).exp();
    let keep = (1.0 - c.t * fade_shape(d_minus)) * (1.0 - c.t * fade_shape(d_plus));
    let glint_a = attenuation(2, c.h_c, iface, &params.absorption);
    let glint = c.t * params.glint_scale * c.delta_h * (gaussian(w, d_minus) + gaussian(w, d_plus));
    let mut n = [0.0; 3];
    for k in 0..3 {
        n[k] = plain[k] * keep + glint_a[k] * glint;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caustic_offset_is_exact_not_the_precedence_bug() {
        let c = caustic(1.55, 15f64.to_radians(), 0.5, 0.3);
        assert!((c.h_c - 0.7297).abs() < 1e-4, "{}", c.h_c);
        // The precedence bug's (6 * 2 c) / (pi - 2) with c = 0.5 * ... is a
        // constant 0.5105 whatever eta' is; the exact value is far from it.
        assert!((c.h_c - 0.5105).abs() > 0.2);
        // At h_c the derivative of phi(2, h) vanishes.
        let d = super::super::azimuthal::exit_azimuth_derivative(2, c.h_c, 1.55);
        assert!(d.abs() < 1e-9);
        // h_c moves with eta'.
        assert!(caustic(1.3, 0.2, 0.5, 0.3).h_c > c.h_c);
    }

    #[test]
    fn glint_fades_out_above_eta_prime_two() {
        assert_eq!(caustic(1.99, 0.2, 0.5, 0.3).t, 1.0);
        assert!((caustic(2.0, 0.2, 0.5, 0.3).t - 1.0).abs() < 1e-12);
        let mid = caustic(2.15, 0.2, 0.5, 0.3).t;
        assert!(mid > 0.0 && mid < 1.0);
        assert_eq!(caustic(2.31, 0.2, 0.5, 0.3).t, 0.0);
    }
}

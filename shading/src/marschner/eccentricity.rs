//! Elliptical cross sections (Marschner 2003, section 4.3, "eccentricity"):
//! the TRT term of a fibre whose minor/major axis ratio is `a` is computed
//! with an effective index
//!
//!   eta*_1 = 2 (eta - 1) a^2 - eta + 2,  eta*_2 = 2 (eta - 1) a^-2 - eta + 2,
//!   eta*(phi_h) = ((eta*_1 + eta*_2) + cos(2 phi_h) (eta*_1 - eta*_2)) / 2,
//!
//! where phi_h is the half azimuth measured from the major axis.
//!
//! Orientation: `scattering` receives only the tangent, not the orientation
//! of the cross section, so coif places the major axis along the light's
//! projection into the normal plane (phi_i = 0, phi_h = phi / 2, so
//! cos 2 phi_h = cos phi). That keeps S a function of (theta_i, theta_o, phi),
//! as the factored tables need, and symmetric in phi. A round fibre (a = 1)
//! is unaffected by this choice: eta* = eta.

/// eta*(phi_h) for index `eta`, eccentricity `a`, given cos(2 phi_h).
pub fn effective_eta(eta: f64, a: f64, cos_two_phi_h: f64) -> f64 {
    let e1 = 2.0 * (eta - 1.0) * a * a - eta + 2.0;
    let e2 = 2.0 * (eta - 1.0) / (a * a) - eta + 2.0;
    (0.5 * ((e1 + e2) + cos_two_phi_h * (e1 - e2))).max(1.0001)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_fibre_keeps_eta_and_ellipse_spans_the_two_indices() {
        for c in [-1.0, -0.3, 0.0, 0.7, 1.0] {
            assert!((effective_eta(1.55, 1.0, c) - 1.55).abs() < 1e-12);
        }
        let a: f64 = 0.85;
        let e1 = 2.0 * 0.55 * a * a - 1.55 + 2.0;
        let e2 = 2.0 * 0.55 / (a * a) - 1.55 + 2.0;
        assert!((effective_eta(1.55, a, 1.0) - e1).abs() < 1e-12);
        assert!((effective_eta(1.55, a, -1.0) - e2).abs() < 1e-12);
        assert!(e1 < 1.55 && e2 > 1.55);
    }
}

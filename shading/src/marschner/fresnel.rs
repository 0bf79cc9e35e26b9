//! Fresnel reflectance with Bravais' virtual indices (Marschner 2003,
//! appendix B): light arriving at longitudinal difference angle theta_d
//! refracts in the normal plane as through a 2D interface of index eta' for
//! the perpendicular polarisation and eta'' for the parallel one.

/// Bravais' virtual indices (eta', eta'') of a fibre of index `eta` at
/// difference angle theta_d (given by its sine and cosine):
/// eta' = sqrt(eta^2 - sin^2 theta_d) / cos theta_d,
/// eta'' = eta^2 cos theta_d / sqrt(eta^2 - sin^2 theta_d).
pub fn bravais(eta: f64, sin_theta_d: f64, cos_theta_d: f64) -> (f64, f64) {
    let root = (eta * eta - sin_theta_d * sin_theta_d).max(1e-12).sqrt();
    (root / cos_theta_d, eta * eta * cos_theta_d / root)
}

/// Reflectance of one polarisation at incidence angle `gamma` (radians) onto
/// a medium of relative index `eta` (< 1 from inside). `parallel` picks the
/// p polarisation, else s. Total internal reflection gives 1.
fn polarised(eta: f64, gamma: f64, parallel: bool) -> f64 {
    let (sin_i, cos_i) = gamma.sin_cos();
    let cos_i = cos_i.abs();
    let sin_t = sin_i / eta;
    if sin_t.abs() >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).sqrt();
    let (num, den) = if parallel {
        (eta * cos_i - cos_t, eta * cos_i + cos_t)
    } else {
        (cos_i - eta * cos_t, cos_i + eta * cos_t)
    };
    if den <= 0.0 {
        return 1.0;
    }
    let r = num / den;
    (r * r).min(1.0)
}

/// Unpolarised Fresnel reflectance F(eta', eta'', gamma) =
/// (F_s(eta', gamma) + F_p(eta'', gamma)) / 2 (Marschner 2003, appendix B).
/// For light leaving the fibre, call it with (1/eta', 1/eta'', gamma_t).
pub fn fresnel(eta_perp: f64, eta_par: f64, gamma: f64) -> f64 {
    0.5 * (polarised(eta_perp, gamma, false) + polarised(eta_par, gamma, true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_and_total_internal_reflection() {
        // ((eta - 1) / (eta + 1))^2 at normal incidence for both polarisations.
        let f0 = fresnel(1.55, 1.55, 0.0);
        assert!((f0 - (0.55f64 / 2.55).powi(2)).abs() < 1e-12);
        // From inside at 60 deg with eta = 1.55: sin 60 * 1.55 > 1, so TIR.
        assert_eq!(fresnel(1.0 / 1.55, 1.0 / 1.55, 60f64.to_radians()), 1.0);
        // Bravais indices at theta_d = 0 are eta itself.
        let (a, b) = bravais(1.55, 0.0, 1.0);
        assert!((a - 1.55).abs() < 1e-12 && (b - 1.55).abs() < 1e-12);
    }
}

//! Longitudinal scattering M_p (Marschner 2003, section 4.1): a unit-area
//! Gaussian in the half angle theta_h, shifted by alpha_p and of standard
//! deviation beta_p, with the paper's relations
//! alpha_TT = -alpha_R / 2, alpha_TRT = -3 alpha_R / 2,
//! beta_TT = beta_R / 2, beta_TRT = 2 beta_R.

use super::params::Sanitised;

/// Unit-area Gaussian g(beta; x) = exp(-x^2 / (2 beta^2)) / (beta sqrt(2 pi)).
#[inline]
pub fn gaussian(beta: f64, x: f64) -> f64 {
    let inv = 1.0 / beta;
    let z = x * inv;
    (-0.5 * z * z).exp() * inv * (1.0 / (2.0 * std::f64::consts::PI).sqrt())
}

/// Shift alpha_p of lobe p (0 = R, 1 = TT, 2 = TRT), radians.
pub fn shift(alpha_r: f64, p: usize) -> f64 {
    match p {
        0 => alpha_r,
        1 => -0.5 * alpha_r,
        _ => -1.5 * alpha_r,
    }
}

/// Width beta_p of lobe p (0 = R, 1 = TT, 2 = TRT), radians.
pub fn width(beta_r: f64, p: usize) -> f64 {
    match p {
        0 => beta_r,
        1 => 0.5 * beta_r,
        _ => 2.0 * beta_r,
    }
}

/// (M_R, M_TT, M_TRT) at half angle `theta_h`: M_p = g(beta_p; theta_h - alpha_p).
pub(crate) fn m_terms(p: &Sanitised, theta_h: f64) -> [f64; 3] {
    let m = |k: usize| gaussian(width(p.beta_r, k), theta_h - shift(p.alpha_r, k));
    [m(0), m(1), m(2)]
}

//! The longitudinal scattering function M_p of d'Eon et al. 2011
//! ("An energy-conserving hair reflectance model", EGSR), as pbrt-v3 writes it
//! (`Mp` in `src/materials/hair.cpp`).

use super::bessel::{i0, log_i0};

/// `M_p(theta_i, theta_o; v) = csch(1/v) / (2v) exp(-sin theta_i sin theta_o / v)
/// I0(cos theta_i cos theta_o / v)` (d'Eon 2011, eq. 7).
///
/// For `v <= 0.1` pbrt-v3 evaluates it in log form to avoid overflow:
/// `exp(ln I0(a) - b - 1/v + 0.6931 + ln(1/(2v)))` with `a = cos cos / v`,
/// `b = sin sin / v`, and the constant 0.6931 standing for ln 2 (pbrt's
/// constant, kept). Operation order follows pbrt-v3 exactly.
/// (pbrt's 0.6931 is kept on purpose instead of `LN_2`.)
#[inline]
#[allow(clippy::approx_constant)]
pub fn mp(cos_theta_i: f32, cos_theta_o: f32, sin_theta_i: f32, sin_theta_o: f32, v: f32) -> f32 {
    let a = cos_theta_i * cos_theta_o / v;
    let b = sin_theta_i * sin_theta_o / v;
    if v <= 0.1 {
        (log_i0(a) - b - 1.0 / v + 0.6931 + (1.0 / (2.0 * v)).ln()).exp()
    } else {
        ((-b).exp() * i0(a)) / ((1.0 / v).sinh() * 2.0 * v)
    }
}

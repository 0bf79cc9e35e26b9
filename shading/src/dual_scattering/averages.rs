//! The per-fibre averages of dual scattering (Zinke, Yuksel, Weber and
//! Keyser 2008, "Dual scattering approximation for fast multiple scattering
//! in hair", section 4.1 and eqs. 6-14), computed by quadrature from any
//! single-fibre model given as a scattering function.
//!
//! For light arriving at longitude `theta_i` (relative to the fibre), the
//! fibre sends the fraction
//!
//! `a(theta_i) = integral over a half sphere of f(theta_i, theta_o, phi) cos theta_o d omega_o`
//!
//! of the power it intercepts into that half (`d omega = cos theta d theta
//! d phi`), `f` being the fibre's scattering function without the
//! `cos theta_i` of the lighting integral (Marschner's `S`; pbrt-v3's far
//! field divided by `cos theta_i`). The forward half (`a_f`) holds the
//! directions with `|phi| > pi/2` (the light goes on past the fibre), the
//! backward half (`a_b`) the rest. In each half, `alpha` and `beta^2` are
//! the mean and variance of the half angle `theta_h = (theta_i +
//! theta_o) / 2` under the same weight: the longitudinal shift and width
//! of the light leaving into that half.
//!
//! For the global term (eq. 13 of the paper) the fibre is also averaged
//! over the forward azimuths, as light that has crossed many fibres arrives
//! from all of them: `G(theta_i, theta_o) = 2/pi integral from pi/2 to pi of
//! f d phi`, kept as a Gaussian in `theta_h` over `cos^2 theta_d`
//! (`G ~ g_amp g(theta_h - mu_g, v_g) / cos^2 theta_d`, the form of
//! Marschner's lobes), its amplitude, mean and variance the moments of
//! `G cos^2 theta_d` over `theta_h`. The paper keeps one such Gaussian per
//! lobe (R, TT, TRT); one per fibre works for any model, pbrt-v3's
//! included, whose lobes are not Gaussians in `theta_h`.
//!
//! The quadrature is Gauss-Legendre in `theta_o` and the midpoint rule in
//! `phi` over `[0, pi]` (every model here is even in `phi`), in `f64`.

use glam::{DVec3, Vec3};
use std::f64::consts::{FRAC_PI_2, PI};

/// The averages of one fibre for light at one longitude, per RGB channel
/// where the absorption makes them differ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FibreAverages {
    /// Longitude of the light, `theta_i`, radians.
    pub theta: f32,
    /// Forward-scattering attenuation `a_f` (fraction of the intercepted
    /// power sent forward), RGB.
    pub a_f: Vec3,
    /// Backward-scattering attenuation `a_b`, RGB.
    pub a_b: Vec3,
    /// Forward longitudinal shift `alpha_f` (mean of `theta_h`), RGB.
    pub alpha_f: Vec3,
    /// Backward longitudinal shift `alpha_b`, RGB.
    pub alpha_b: Vec3,
    /// Forward longitudinal width `beta_f` (standard deviation of `theta_h`), RGB.
    pub beta_f: Vec3,
    /// Backward longitudinal width `beta_b`, RGB.
    pub beta_b: Vec3,
    /// Amplitude of the forward-azimuth average `G` (see the module docs), RGB.
    pub g_amplitude: Vec3,
    /// Mean of `theta_h` under `G cos^2 theta_d` (luminance-weighted).
    pub g_mean: f32,
    /// Variance of `theta_h` under `G cos^2 theta_d` (luminance-weighted).
    pub g_variance: f32,
}

/// Quadrature nodes: `theta_o` (Gauss-Legendre) and `phi` (midpoint) counts.
pub(crate) const THETA_NODES: usize = 96;
pub(crate) const PHI_NODES: usize = 96;

/// Rec. 709 luminance weights (the weighting of the one-channel widths).
pub(crate) const LUMINANCE: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);

/// The averages at `theta_i` of the fibre whose scattering function (no
/// `cos theta_i`) for unit directions along tangent `+X` is `f(t, wi, wo)`,
/// with the Gauss-Legendre `nodes` on [-1, 1] (`THETA_NODES` of them).
/// Non-finite or negative values of `f` count as 0.
pub(crate) fn fibre_averages(
    f: &impl Fn(Vec3, Vec3, Vec3) -> Vec3,
    nodes: &[(f64, f64)],
    theta_i: f64,
) -> FibreAverages {
    let t = Vec3::X;
    let wi = Vec3::new(theta_i.sin() as f32, theta_i.cos() as f32, 0.0);
    let dphi = PI / PHI_NODES as f64;

    // Sums per half: [weight, weight * theta_h, weight * theta_h^2].
    let mut fwd = [DVec3::ZERO; 3];
    let mut back = [DVec3::ZERO; 3];
    // Moments of G cos^2 theta_d over theta_h.
    let mut glob = [DVec3::ZERO; 3];
    for &(x, w) in nodes {
        let theta_o = FRAC_PI_2 * x;
        let d_theta = FRAC_PI_2 * w;
        let (sin_o, cos_o) = theta_o.sin_cos();
        let theta_h = 0.5 * (theta_i + theta_o);
        let cos_d = (0.5 * (theta_o - theta_i)).cos();
        let mut g_sum = DVec3::ZERO;
        for k in 0..PHI_NODES {
            let phi = (k as f64 + 0.5) * dphi;
            let wo = Vec3::new(
                sin_o as f32,
                (cos_o * phi.cos()) as f32,
                (cos_o * phi.sin()) as f32,
            );
            let v = f(t, wi, wo).as_dvec3();
            let v = DVec3::new(clean(v.x), clean(v.y), clean(v.z));
            // Both signs of phi: 2 * integral over [0, pi].
            let weight = v * (2.0 * cos_o * cos_o * d_theta * dphi);
            let half = if phi > FRAC_PI_2 {
                g_sum += v * dphi;
                &mut fwd
            } else {
                &mut back
            };
            half[0] += weight;
            half[1] += weight * theta_h;
            half[2] += weight * theta_h * theta_h;
        }
        // G = 2/pi * integral over the forward half of phi; times
        // cos^2 theta_d, over d theta_h = d theta_o / 2.
        let g = g_sum * (2.0 / PI) * (cos_d * cos_d) * (0.5 * d_theta);
        glob[0] += g;
        glob[1] += g * theta_h;
        glob[2] += g * theta_h * theta_h;
    }
    let (alpha_f, beta_f) = moments(&fwd);
    let (alpha_b, beta_b) = moments(&back);
    let g_lum = glob.map(|m| m.dot(LUMINANCE));
    let (g_mean, g_var) = if g_lum[0] > 1e-12 {
        let mean = g_lum[1] / g_lum[0];
        (mean, (g_lum[2] / g_lum[0] - mean * mean).max(0.0))
    } else {
        (0.0, 0.0)
    };
    FibreAverages {
        theta: theta_i as f32,
        a_f: fwd[0].as_vec3(),
        a_b: back[0].as_vec3(),
        alpha_f: alpha_f.as_vec3(),
        alpha_b: alpha_b.as_vec3(),
        beta_f: beta_f.as_vec3(),
        beta_b: beta_b.as_vec3(),
        g_amplitude: glob[0].as_vec3(),
        g_mean: g_mean as f32,
        g_variance: g_var as f32,
    }
}

fn clean(x: f64) -> f64 {
    if x.is_finite() && x > 0.0 {
        x
    } else {
        0.0
    }
}

/// Mean and standard deviation per channel from `[sum w, sum w x, sum w x^2]`
/// (0 where the weight is 0).
fn moments(m: &[DVec3; 3]) -> (DVec3, DVec3) {
    let per = |w: f64, wx: f64, wx2: f64| {
        if w > 1e-12 {
            let mean = wx / w;
            (mean, (wx2 / w - mean * mean).max(0.0).sqrt())
        } else {
            (0.0, 0.0)
        }
    };
    let (a0, b0) = per(m[0].x, m[1].x, m[2].x);
    let (a1, b1) = per(m[0].y, m[1].y, m[2].y);
    let (a2, b2) = per(m[0].z, m[1].z, m[2].z);
    (DVec3::new(a0, a1, a2), DVec3::new(b0, b1, b2))
}

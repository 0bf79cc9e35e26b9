//! Azimuthal scattering N_p (Marschner 2003, section 4.2).
//!
//! A ray entering a smooth round fibre at offset h in [-1, 1] (gamma_i =
//! asin h) leaves after p internal segments in the azimuth
//!
//!   phi(p, h) = 2 p gamma_t - 2 gamma_i + p pi,   gamma_t = asin(h / eta')
//!
//! and N_p(phi) sums, over every root h of phi(p, h) = phi (mod 2 pi),
//! A(p, h) / |2 dphi/dh|. The attenuation is A(0, h) = F(eta', eta'', gamma_i)
//! and A(p, h) = (1 - F(eta', eta'', gamma_i))^2 F(1/eta', 1/eta'', gamma_t)^(p-1) T^p,
//! T = exp(-2 sigma_a' (1 + cos 2 gamma_t)), sigma_a' = sigma_a / cos theta_t.

use super::fresnel::fresnel;
use super::params::RootSolver;
use std::f64::consts::{PI, TAU};

/// phi(p, h) = 2 p asin(h / eta') - 2 asin(h) + p pi.
#[inline]
pub fn exit_azimuth(p: u32, h: f64, eta_perp: f64) -> f64 {
    let p = p as f64;
    2.0 * p * (h / eta_perp).clamp(-1.0, 1.0).asin() - 2.0 * h.clamp(-1.0, 1.0).asin() + p * PI
}

/// dphi/dh = 2 p / sqrt(eta'^2 - h^2) - 2 / sqrt(1 - h^2).
#[inline]
pub fn exit_azimuth_derivative(p: u32, h: f64, eta_perp: f64) -> f64 {
    let p = p as f64;
    2.0 * p / (eta_perp * eta_perp - h * h).max(1e-300).sqrt()
        - 2.0 / (1.0 - h * h).max(1e-300).sqrt()
}

/// d^2 phi / dh^2 = 2 p h / (eta'^2 - h^2)^(3/2) - 2 h / (1 - h^2)^(3/2).
pub fn exit_azimuth_second_derivative(p: u32, h: f64, eta_perp: f64) -> f64 {
    let p = p as f64;
    let a = (eta_perp * eta_perp - h * h).max(1e-300);
    let b = (1.0 - h * h).max(1e-300);
    2.0 * p * h / (a * a.sqrt()) - 2.0 * h / (b * b.sqrt())
}

/// Up to three roots h of phi(p, h) = phi (mod 2 pi).
#[derive(Clone, Copy, Debug, Default)]
pub struct Roots {
    h: [f64; 3],
    len: usize,
}

impl Roots {
    /// The roots found, as a slice.
    pub fn as_slice(&self) -> &[f64] {
        &self.h[..self.len]
    }

    fn push(&mut self, h: f64) {
        if self.len < 3 {
            self.h[self.len] = h;
            self.len += 1;
        }
    }
}

/// Offset of the TRT turning point, where dphi(2, h)/dh = 0:
/// h_c = sqrt((4 - eta'^2) / 3) for eta' < 2 (Marschner 2003, section 4.3;
/// 0.7297 at eta' = 1.55). `None` for eta' >= 2, where phi(2, h) is monotone.
pub fn caustic_offset(eta_perp: f64) -> Option<f64> {
    if eta_perp < 2.0 {
        Some(((4.0 - eta_perp * eta_perp) / 3.0).sqrt())
    } else {
        None
    }
}

/// Roots of phi(p, h) = phi (mod 2 pi) for p in {0, 1, 2}, by safeguarded
/// Newton iteration on each interval where phi(p, h) is monotone: [-1, 1]
/// for p = 0 and p = 1 (and p = 2 when eta' >= 2), else split at +-h_c.
pub fn roots_exact(p: u32, phi: f64, eta_perp: f64) -> Roots {
    let mut roots = Roots::default();
    let mut bounds = [-1.0, 1.0, 0.0, 0.0];
    let mut n = 2;
    if p == 2 {
        if let Some(hc) = caustic_offset(eta_perp) {
            bounds = [-1.0, -hc, hc, 1.0];
            n = 4;
        }
    }
    for w in bounds[..n].windows(2) {
        let (a, b) = (w[0], w[1]);
        let (fa, fb) = (exit_azimuth(p, a, eta_perp), exit_azimuth(p, b, eta_perp));
        let (lo, hi) = if fa < fb { (fa, fb) } else { (fb, fa) };
        for k in -1..=3 {
            let y = phi + TAU * k as f64;
            if y >= lo && y <= hi {
                roots.push(solve_monotone(p, eta_perp, y, a, b, fa));
            }
        }
    }
    roots
}

/// Root of phi(p, h) = y on [a, b] where phi is monotone and brackets y:
/// Newton steps, falling back to bisection whenever a step leaves the bracket.
fn solve_monotone(p: u32, eta_perp: f64, y: f64, a: f64, b: f64, fa: f64) -> f64 {
    let (mut lo, mut hi) = (a, b);
    // Sign of g = phi - y at the low end decides which side a point is on.
    let low_negative = fa - y < 0.0;
    let mut h = 0.5 * (a + b);
    for _ in 0..60 {
        let g = exit_azimuth(p, h, eta_perp) - y;
        if g == 0.0 {
            return h;
        }
        if (g < 0.0) == low_negative {
            lo = h;
        } else {
            hi = h;
        }
        let d = exit_azimuth_derivative(p, h, eta_perp);
        let mut next = h - g / d;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - h).abs() < 1e-15 || hi - lo < 1e-15 {
            return next;
        }
        h = next;
    }
    h
}

/// Roots from the paper's cubic approximation (Marschner 2003, eq. 10):
/// phi(p, gamma_i) ~ (6 p c / pi - 2) gamma_i - 8 p c / pi^3 gamma_i^3 + p pi,
/// c = asin(1 / eta'), solved in closed form for gamma_i in [-pi/2, pi/2];
/// h = sin gamma_i.
pub fn roots_cubic(p: u32, phi: f64, eta_perp: f64) -> Roots {
    let mut roots = Roots::default();
    let pf = p as f64;
    let c = (1.0 / eta_perp).clamp(-1.0, 1.0).asin();
    let a3 = -8.0 * pf * c / (PI * PI * PI);
    let a1 = 6.0 * pf * c / PI - 2.0;
    for k in -1..=3 {
        let y = phi + TAU * k as f64;
        let a0 = pf * PI - y;
        let mut candidates = [f64::NAN; 3];
        if a3 == 0.0 {
            candidates[0] = -a0 / a1;
        } else {
            // Depressed cubic g^3 + P g + Q = 0.
            let pp = a1 / a3;
            let qq = a0 / a3;
            let disc = 0.25 * qq * qq + pp * pp * pp / 27.0;
            if disc > 0.0 {
                let s = disc.sqrt();
                candidates[0] = (-0.5 * qq + s).cbrt() + (-0.5 * qq - s).cbrt();
            } else {
                let r = 2.0 * (-pp / 3.0).max(0.0).sqrt();
                let arg = if r > 0.0 {
                    (1.5 * qq / pp * (-3.0 / pp).sqrt()).clamp(-1.0, 1.0)
                } else {
                    0.0
                };
                let base = arg.acos() / 3.0;
                for (j, cand) in candidates.iter_mut().enumerate() {
                    *cand = r * (base - TAU * j as f64 / 3.0).cos();
                }
            }
        }
        for g in candidates {
            if g.abs() <= 0.5 * PI {
                roots.push(g.sin());
            }
        }
    }
    roots
}

/// dphi/dh of the cubic approximation: (a1 + 3 a3 gamma^2) / cos gamma.
pub fn cubic_derivative(p: u32, h: f64, eta_perp: f64) -> f64 {
    let pf = p as f64;
    let c = (1.0 / eta_perp).clamp(-1.0, 1.0).asin();
    let g = h.clamp(-1.0, 1.0).asin();
    let d_gamma = 6.0 * pf * c / PI - 2.0 - 24.0 * pf * c / (PI * PI * PI) * g * g;
    d_gamma / (1.0 - h * h).max(1e-300).sqrt()
}

/// Everything A(p, h) needs about one lobe's refraction geometry.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interface {
    /// Bravais indices (eta', eta'').
    pub eta_perp: f64,
    pub eta_par: f64,
    /// cos theta_t, the longitudinal refraction angle (sin theta_t = sin theta_d / eta).
    pub cos_theta_t: f64,
}

/// A(p, h) per RGB channel for `absorption` sigma_a.
pub(crate) fn attenuation(p: u32, h: f64, iface: &Interface, absorption: &[f64; 3]) -> [f64; 3] {
    let gamma_i = h.clamp(-1.0, 1.0).asin();
    let f_in = fresnel(iface.eta_perp, iface.eta_par, gamma_i);
    if p == 0 {
        return [f_in; 3];
    }
    let gamma_t = (h / iface.eta_perp).clamp(-1.0, 1.0).asin();
    let f_out = fresnel(1.0 / iface.eta_perp, 1.0 / iface.eta_par, gamma_t);
    let base = (1.0 - f_in) * (1.0 - f_in) * f_out.powi(p as i32 - 1);
    let path = 2.0 * (1.0 + (2.0 * gamma_t).cos()) / iface.cos_theta_t;
    absorption.map(|s| base * (-(s * path) * p as f64).exp())
}

/// Smallest |2 dphi/dh| used: keeps N finite exactly at a caustic (where the
/// caustic treatment multiplies it by zero anyway).
pub(crate) const MIN_DERIVATIVE: f64 = 1e-6;

/// N_p(phi) per RGB channel without any caustic treatment (the paper's
/// N_P): the sum over roots of A(p, h) / |2 dphi/dh|.
pub(crate) fn n_plain(
    p: u32,
    phi: f64,
    iface: &Interface,
    absorption: &[f64; 3],
    solver: RootSolver,
) -> [f64; 3] {
    let roots = match solver {
        RootSolver::Exact => roots_exact(p, phi, iface.eta_perp),
        RootSolver::Cubic => roots_cubic(p, phi, iface.eta_perp),
    };
    let mut n = [0.0; 3];
    for &h in roots.as_slice() {
        let d = match solver {
            RootSolver::Exact => exit_azimuth_derivative(p, h, iface.eta_perp),
            RootSolver::Cubic => cubic_derivative(p, h, iface.eta_perp),
        };
        let inv = 1.0 / (2.0 * d.abs()).max(MIN_DERIVATIVE);
        let a = attenuation(p, h, iface, absorption);
        for c in 0..3 {
            n[c] += a[c] * inv;
        }
    }
    n
}

/// Wraps an angle into (-pi, pi].
#[inline]
pub fn wrap_angle(x: f64) -> f64 {
    let mut y = x % TAU;
    if y > PI {
        y -= TAU;
    } else if y <= -PI {
        y += TAU;
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_roots_satisfy_the_equation() {
        for &eta in &[1.2, 1.55, 1.9, 2.5] {
            for p in 0..3 {
                for i in 0..50 {
                    let phi = -PI + TAU * (i as f64 + 0.5) / 50.0;
                    for &h in roots_exact(p, phi, eta).as_slice() {
                        let r = wrap_angle(exit_azimuth(p, h, eta) - phi);
                        assert!(r.abs() < 1e-9, "p {p} eta {eta} phi {phi} h {h}: {r}");
                    }
                }
            }
        }
    }

    #[test]
    fn root_counts_match_the_shape_of_phi() {
        // R: exactly one root for every phi; TT: one root for phi near pi,
        // none for phi near 0 (below 2 asin(1/eta')); TRT for eta' < 2: three
        // roots just inside the caustic, one just outside.
        assert_eq!(roots_exact(0, 1.0, 1.55).as_slice().len(), 1);
        assert_eq!(roots_exact(1, PI, 1.55).as_slice().len(), 1);
        assert_eq!(roots_exact(1, 0.1, 1.55).as_slice().len(), 0);
        let hc = caustic_offset(1.55).unwrap();
        assert!((hc - 0.7297).abs() < 1e-4);
        let phi_c = wrap_angle(exit_azimuth(2, hc, 1.55));
        assert_eq!(roots_exact(2, phi_c - 0.01, 1.55).as_slice().len(), 3);
        assert_eq!(roots_exact(2, phi_c + 0.01, 1.55).as_slice().len(), 1);
    }
}

//! Error measurements for reports and benches: tables against the direct
//! model (or any reference), and the paper's cubic root approximation
//! against the exact root solver.

use super::azimuthal::{roots_cubic, roots_exact};
use super::{lobes_at, FibreAngles, Lut, LutLayout, Params, RootSolver};
use coif_base::rng::SplitMix64;
use glam::Vec3;

/// Relative RMS error of `approx` against `reference` over `samples` random
/// configurations (t, wi, wo each uniform on the unit sphere, from `seed`):
/// sqrt(sum |approx - reference|^2 / sum |reference|^2), summed over RGB.
/// Samples where the reference is not finite are skipped. Both closures take
/// (t, wi, wo), so any model (e.g. pbrt's far field) can be the reference.
pub fn relative_rms_error(
    reference: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
    approx: impl Fn(Vec3, Vec3, Vec3) -> Vec3,
    samples: usize,
    seed: u64,
) -> f64 {
    let mut rng = SplitMix64::new(seed);
    let (mut err, mut norm) = (0.0f64, 0.0f64);
    for _ in 0..samples {
        let (t, wi, wo) = (rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
        let r = reference(t, wi, wo);
        if !r.is_finite() {
            continue;
        }
        let a = approx(t, wi, wo);
        let d = (a - r).as_dvec3();
        err += d.length_squared();
        norm += r.as_dvec3().length_squared();
    }
    if norm > 0.0 {
        (err / norm).sqrt()
    } else {
        0.0
    }
}

/// Relative RMS error of a [`Lut`] of `resolution` and `layout` against the
/// direct [`super::scattering`] with the same parameters.
pub fn lut_relative_rms_error(
    params: &Params,
    resolution: usize,
    layout: LutLayout,
    samples: usize,
    seed: u64,
) -> f64 {
    let lut = Lut::with_layout(params, resolution, layout);
    relative_rms_error(
        |t, wi, wo| super::scattering(params, t, wi, wo),
        |t, wi, wo| lut.scattering(t, wi, wo),
        samples,
        seed,
    )
}

/// How far the paper's cubic approximation of phi(p, h) lands from the
/// exact roots.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CubicRootError {
    /// Largest |h_cubic - h_exact| over matched roots (p = 1, 2; p = 0 is
    /// exact in both).
    pub max_h_difference: f64,
    /// Configurations where the two solvers found different root counts
    /// (they disagree near the caustic and the TT cut-off).
    pub root_count_mismatches: usize,
    /// Configurations tried.
    pub configurations: usize,
    /// Relative RMS of S with `RootSolver::Cubic` against `RootSolver::Exact`.
    pub relative_rms: f64,
}

/// Compares the cubic root approximation with the exact solver over
/// `samples` random configurations.
pub fn cubic_root_error(params: &Params, samples: usize, seed: u64) -> CubicRootError {
    let exact = Params {
        roots: RootSolver::Exact,
        ..params.clone()
    };
    let cubic = Params {
        roots: RootSolver::Cubic,
        ..params.clone()
    };
    let mut out = CubicRootError {
        configurations: samples,
        ..Default::default()
    };
    let mut rng = SplitMix64::new(seed ^ 0x5eed);
    for _ in 0..samples {
        let phi = rng.range(-std::f32::consts::PI, std::f32::consts::PI) as f64;
        let cos_d = rng.range(0.3, 1.0) as f64;
        let eta = params.eta as f64;
        let eta_perp = (eta * eta - (1.0 - cos_d * cos_d)).sqrt() / cos_d;
        for p in 1..3 {
            let e = roots_exact(p, phi, eta_perp);
            let c = roots_cubic(p, phi, eta_perp);
            if e.as_slice().len() != c.as_slice().len() {
                out.root_count_mismatches += 1;
                continue;
            }
            let mut es: Vec<f64> = e.as_slice().to_vec();
            let mut cs: Vec<f64> = c.as_slice().to_vec();
            es.sort_by(f64::total_cmp);
            cs.sort_by(f64::total_cmp);
            for (a, b) in es.iter().zip(&cs) {
                out.max_h_difference = out.max_h_difference.max((a - b).abs());
            }
        }
    }
    out.relative_rms = relative_rms_error(
        |t, wi, wo| super::scattering(&exact, t, wi, wo),
        |t, wi, wo| super::scattering(&cubic, t, wi, wo),
        samples,
        seed,
    );
    out
}

/// The direct model's lobes at explicit angles (radians), for tests and plots.
pub fn lobes_at_angles(params: &Params, theta_i: f32, theta_o: f32, phi: f32) -> super::Lobes {
    let l = lobes_at(
        &super::params::Sanitised::new(params),
        &FibreAngles {
            theta_i: theta_i as f64,
            theta_o: theta_o as f64,
            phi: phi as f64,
        },
    );
    let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
    super::Lobes {
        r: v(l[0]),
        tt: v(l[1]),
        trt: v(l[2]),
    }
}

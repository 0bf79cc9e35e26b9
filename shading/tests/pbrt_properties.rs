//! Properties of pbrt-v3's hair model that hold exactly (up to rounding):
//! finiteness and non-negativity everywhere, the symmetries of the model,
//! and the far-field form as the quadrature of the exact one.

use coif_base::SplitMix64;
use coif_shading::pbrt::{self, longitudinal::mp, FarField, Params};
use glam::{Quat, Vec3};

fn materials() -> Vec<Params> {
    vec![
        Params::default(),
        Params {
            sigma_a: Vec3::ZERO,
            ..Params::default()
        },
        Params {
            eta: 1.9,
            beta_m: 0.05,
            beta_n: 0.05,
            alpha: 0.1,
            sigma_a: Vec3::new(0.0, 5.0, 40.0),
        },
        Params {
            eta: 1.01,
            beta_m: 1.0,
            beta_n: 1.0,
            alpha: -0.05,
            sigma_a: Vec3::ZERO,
        },
    ]
}

/// Hard directions: along and against the fibre, in the normal plane, on
/// the shading normal (wi.z = 0 and wi.y = 0), nearly grazing, and random.
fn directions() -> Vec<Vec3> {
    let mut v = vec![
        Vec3::X,
        -Vec3::X,
        Vec3::Y,
        -Vec3::Y,
        Vec3::Z,
        -Vec3::Z,
        Vec3::new(1.0, 1e-7, 0.0),
        Vec3::new(-1.0, 0.0, 1e-7),
        Vec3::new(0.999_999_9, 0.0, 0.000_447),
    ];
    let mut rng = SplitMix64::new(5);
    v.extend((0..40).map(|_| rng.unit_vector()));
    v
}

#[test]
fn finite_and_non_negative_everywhere_including_grazing_and_h_at_the_rim() {
    for params in materials() {
        let ff = FarField::new(&params, 16).unwrap();
        for &wo in &directions() {
            for &wi in &directions() {
                for h in [-1.0f32, -0.999_999, -0.5, 0.0, 0.3, 0.999_999, 1.0] {
                    let f = pbrt::scattering_local(&params, h, wo, wi);
                    assert!(
                        f.is_finite() && f.min_element() >= 0.0,
                        "{params:?} h {h} wo {wo} wi {wi}: {f}"
                    );
                }
                let f = ff.eval_local(wo, wi);
                assert!(
                    f.is_finite() && f.min_element() >= 0.0,
                    "far field {wo} {wi}: {f}"
                );
                let g = pbrt::scattering(&params, Vec3::X, wi, wo);
                assert!(
                    g.is_finite() && g.min_element() >= 0.0,
                    "world {wo} {wi}: {g}"
                );
            }
        }
    }
}

#[test]
fn nan_input_gives_nan_not_a_panic() {
    let p = Params::default();
    assert!(pbrt::scattering_local(&p, f32::NAN, Vec3::Y, Vec3::Z).is_nan());
    assert!(pbrt::scattering_local(&p, 0.2, Vec3::NAN, Vec3::Z).is_nan());
    assert!(pbrt::scattering(&p, Vec3::X, Vec3::NAN, Vec3::Y).is_nan());
}

/// Mirroring the normal plane (z -> -z) and the offset (h -> -h) is a
/// symmetry of the cylinder: gamma_o, gamma_t and phi all change sign.
#[test]
fn mirror_symmetry_in_h_and_azimuth() {
    let mut rng = SplitMix64::new(11);
    let mirror = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
    for params in materials() {
        for _ in 0..500 {
            let (wo, wi, h) = (rng.unit_vector(), rng.unit_vector(), rng.range(-1.0, 1.0));
            let a = pbrt::scattering_local(&params, h, wo, wi);
            let b = pbrt::scattering_local(&params, -h, mirror(wo), mirror(wi));
            // The mirrored phase differences are wrapped by different whole
            // turns of 2 pi: a few ulp of pi, times the logistic slope 1/s.
            assert!(
                (a - b).abs().max_element() <= 1e-4 * a.max_element().max(1e-3),
                "{a} {b}"
            );
        }
    }
}

/// Rotating both directions about the fibre axis only shifts phi_i and
/// phi_o together; the model depends on their difference.
#[test]
fn invariant_under_rotation_about_the_fibre() {
    let mut rng = SplitMix64::new(12);
    let p = Params::default();
    for _ in 0..500 {
        let (wo, wi, h) = (rng.unit_vector(), rng.unit_vector(), rng.range(-0.99, 0.99));
        let q = Quat::from_rotation_x(rng.range(-3.0, 3.0));
        let a = pbrt::scattering_local(&p, h, wo, wi);
        let b = pbrt::scattering_local(&p, h, q * wo, q * wi);
        // phi differences pass through atan2 and wrap: f32 rounding of a few
        // ulp of pi, amplified by the logistic's slope 1/s.
        assert!(
            (a - b).abs().max_element() <= 2e-4 * a.max_element().max(1e-2),
            "{a} {b}"
        );
    }
}

/// d'Eon's M_p is symmetric in (theta_i, theta_o); pbrt's full model is not
/// reciprocal (N_p and A_p use theta_o only, and the tilt acts on theta_o),
/// so only this factor is tested for reciprocity.
#[test]
fn longitudinal_term_is_reciprocal() {
    let mut rng = SplitMix64::new(13);
    for v in [0.005f32, 0.05, 0.1, 0.3, 2.0] {
        for _ in 0..200 {
            let (ti, to) = (rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
            let a = mp(ti.cos(), to.cos(), ti.sin(), to.sin(), v);
            let b = mp(to.cos(), ti.cos(), to.sin(), ti.sin(), v);
            assert!((a - b).abs() <= 1e-6 * a.max(1.0), "v {v}: {a} {b}");
        }
    }
}

/// The far field is the quadrature of `scattering_local` over h with the
/// published nodes and weights, and it is even in phi.
#[test]
fn far_field_is_the_h_quadrature_of_the_exact_model() {
    let mut rng = SplitMix64::new(14);
    for params in materials() {
        let ff = FarField::new(&params, 24).unwrap();
        let weights: f32 = ff.nodes().map(|(_, w)| w).sum();
        assert!(
            (weights - 1.0).abs() < 1e-5,
            "weights average over h: {weights}"
        );
        for _ in 0..200 {
            let (wo, wi) = (rng.unit_vector(), rng.unit_vector());
            let direct: Vec3 = ff
                .nodes()
                .map(|(h, w)| pbrt::scattering_local(&params, h, wo, wi) * w)
                .sum();
            let far = ff.eval_local(wo, wi);
            let tol = 1e-5 * direct.max_element().max(1e-2);
            assert!((far - direct).abs().max_element() <= tol, "{far} {direct}");
            let m = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
            let mirrored = ff.eval_local(m(wo), m(wi));
            let tol_mirror = 1e-4 * direct.max_element().max(1e-2);
            assert!(
                (far - mirrored).abs().max_element() <= tol_mirror,
                "even in phi"
            );
        }
    }
}

/// The world-space far field equals the local one in the frame x = t,
/// y = normal-plane part of wo: any tangent, any rotation.
#[test]
fn world_far_field_matches_the_local_frame() {
    let mut rng = SplitMix64::new(15);
    let p = Params::default();
    let ff = FarField::new(&p, pbrt::DEFAULT_QUADRATURE_ORDER).unwrap();
    for _ in 0..300 {
        let (wo, wi) = (rng.unit_vector(), rng.unit_vector());
        let local = ff.eval_local(wo, wi);
        let q = Quat::from_axis_angle(rng.unit_vector(), rng.range(0.0, 3.0));
        let world = pbrt::scattering(&p, q * Vec3::X, q * wi, q * wo);
        let tol = 1e-3 * local.max_element().max(1e-2);
        assert!(
            (world - local).abs().max_element() <= tol,
            "{world} {local}"
        );
    }
}

#[test]
fn far_field_batch_matches_single_evaluations() {
    let mut rng = SplitMix64::new(16);
    let p = Params::default();
    let ff = FarField::new(&p, 32).unwrap();
    let mut samples = coif_shading::ShadingSamples::default();
    for _ in 0..37 {
        samples.push(rng.unit_vector(), rng.unit_vector(), rng.unit_vector());
    }
    let mut out = coif_shading::RgbBuffer::default();
    ff.scattering_batch(&samples, &mut out);
    assert_eq!(out.len(), 37);
    for k in 0..37 {
        let (t, wi, wo) = samples.get(k);
        assert_eq!(out.get(k), ff.eval(t, wi, wo));
    }
}

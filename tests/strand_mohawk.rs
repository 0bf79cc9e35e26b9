//! The TressFX mohawk (`../shared/data/grooms/ratboy_mohawk.tfx`, 2,226
//! strands of 32 vertices, centimetres) under the strand step with local
//! shape constraints: it keeps its groom under gravity, lags when shaken and
//! returns; SIMD = scalar with local shape on. Skipped, with a message, when
//! the shared groom folder is absent.

use coif_testkit::groom_path;

use coif::geometry::scene::scalp_spheres;
use coif::groom;
use coif::kernels::{self, measure, scalar, SimParams, Sphere, Strands};
use glam::Vec3;

/// The mohawk in metres and two 8 cm head spheres tangent under its scalp.
fn mohawk() -> Option<(Vec<Vec3>, usize, Vec<Sphere>)> {
    let path = groom_path("ratboy_mohawk.tfx")?;
    let g = groom::load(&std::fs::read(path).ok()?).ok()?;
    let (pts, v) = g.uniform_points(0.01)?;
    let rig = scalp_spheres(&pts, v, 2, 0.08);
    Some((pts, v, rig))
}

/// Mean tip drift relative to the root (tip - root now against groomed), as
/// a share of the mean strand length.
fn tip_drift(s: &Strands, groom: &[Vec3], v: usize) -> f64 {
    let now = s.positions();
    let (mut drift, mut len) = (0.0f64, 0.0f64);
    for k in 0..s.strand_count() {
        let (g, p) = (&groom[k * v..(k + 1) * v], &now[k * v..(k + 1) * v]);
        drift += ((p[v - 1] - p[0]) - (g[v - 1] - g[0])).length() as f64;
        len += g
            .windows(2)
            .map(|w| (w[1] - w[0]).length() as f64)
            .sum::<f64>();
    }
    drift / len
}

#[test]
fn mohawk_keeps_its_groom_lags_when_shaken_and_returns() {
    let Some((pts, v, rig)) = mohawk() else {
        return;
    };
    let params = SimParams {
        local_shape_stiffness: 1.0,
        ..Default::default()
    };
    let mut s = Strands::from_polylines(&pts, v).unwrap();
    let dt = params.dt as f64;
    // 3 s under gravity on the head.
    for _ in 0..(3.0 / dt).round() as usize {
        kernels::step(&mut s, &params, &rig);
    }
    let rest = tip_drift(&s, &pts, v);
    // Shaken side to side: 8 cm, 2 Hz, 2 s, head spheres with the roots.
    let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
    let mut moved_roots = roots.clone();
    let mut peak: f64 = 0.0;
    for i in 1..=(2.0 / dt).round() as usize {
        let off =
            Vec3::X * (0.08 * (2.0 * std::f64::consts::PI * 2.0 * i as f64 * dt).sin()) as f32;
        for (m, r) in moved_roots.iter_mut().zip(&roots) {
            *m = *r + off;
        }
        s.set_roots(&moved_roots).unwrap();
        let moved: Vec<Sphere> = rig
            .iter()
            .map(|c| Sphere {
                center: c.center + off,
                radius: c.radius,
            })
            .collect();
        kernels::step(&mut s, &params, &moved);
        peak = peak.max(tip_drift(&s, &pts, v));
    }
    // 2 s after, back at the start.
    s.set_roots(&roots).unwrap();
    for _ in 0..(2.0 / dt).round() as usize {
        kernels::step(&mut s, &params, &rig);
    }
    let after = tip_drift(&s, &pts, v);
    println!(
        "mohawk, local shape 1: rest {:.2} %, peak shaken {:.2} %, 2 s after {:.2} %",
        rest * 100.0,
        peak * 100.0,
        after * 100.0
    );
    assert!(rest <= 0.05, "rest drift {rest}");
    assert!(peak >= 0.03, "the tips should lag when shaken: {peak}");
    assert!(after <= 0.05, "2 s after the shake: {after}");
    assert_eq!(s.restored_strands(), 0);
    // Not asserted: segment lengths. The two fitted spheres hold some roots
    // inside them (up to 2.7 cm deep); those strands' first free vertex is
    // pushed out to the surface, stretching the root segment, which no
    // solver can avoid with the root pinned inside the rig.
    let inside = roots
        .iter()
        .filter(|r| rig.iter().any(|c| (**r - c.center).length() < c.radius))
        .count();
    println!(
        "{inside} of {} roots lie inside the fitted spheres",
        roots.len()
    );
}

#[test]
fn mohawk_simd_matches_scalar_with_local_shape() {
    let Some((pts, v, rig)) = mohawk() else {
        return;
    };
    for k in [1.0, 0.5] {
        let params = SimParams {
            local_shape_stiffness: k,
            ..Default::default()
        };
        let mut a = Strands::from_polylines(&pts, v).unwrap();
        let mut b = a.clone();
        let roots: Vec<Vec3> = pts.iter().step_by(v).copied().collect();
        for i in 0..12 {
            let off = Vec3::X * 0.01 * (i as f32 * 0.7).sin();
            let moved: Vec<Vec3> = roots.iter().map(|r| *r + off).collect();
            a.set_roots(&moved).unwrap();
            b.set_roots(&moved).unwrap();
            kernels::step(&mut a, &params, &rig);
            scalar::step(&mut b, &params, &rig);
        }
        let worst = measure::max_distance(&a, &b);
        println!("mohawk, local shape {k}: SIMD - scalar {worst} m");
        assert!(worst <= 1e-6, "local shape {k}: {worst} m");
    }
}

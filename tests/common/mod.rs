//! Scenes shared by the cross-crate tests.
#![allow(dead_code)]

pub mod counting;

use coif::kernels::rng::SplitMix64;
use coif::kernels::Sphere;
use glam::Vec3;
use std::path::PathBuf;

/// The path of a shared groom (`../shared/data/grooms/NAME` beside the
/// repository), or None with a message when the folder is absent, so that
/// tests needing it skip rather than fail.
pub fn groom_path(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/data/grooms")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "skipping: {} is absent (the shared groom folder is not beside the repository)",
            p.display()
        );
        None
    }
}

/// `count` random curly strands of `verts` vertices hanging around a head
/// sphere of radius 0.1 at the origin; returns the points and a rig of
/// spheres that intersect them.
pub fn curly_strands(count: usize, verts: usize, seed: u64) -> (Vec<Vec3>, Vec<Sphere>) {
    let mut rng = SplitMix64::new(seed);
    let mut pts = Vec::with_capacity(count * verts);
    for _ in 0..count {
        let n = {
            let mut d = rng.unit_vector();
            d.y = d.y.abs();
            d.normalize()
        };
        let root = n * 0.1;
        let (u, w) = n.any_orthonormal_pair();
        let seg = rng.range(0.005, 0.012);
        let phase = rng.range(0.0, std::f32::consts::TAU);
        let mut p = root;
        for v in 0..verts {
            pts.push(p);
            let a = phase + v as f32 * 0.9;
            let dir = (n * 0.6 + (u * a.cos() + w * a.sin()) * 0.8).normalize();
            p += dir * seg;
        }
    }
    let rig = vec![
        Sphere {
            center: Vec3::ZERO,
            radius: 0.1,
        },
        Sphere {
            center: Vec3::new(0.0, -0.12, 0.0),
            radius: 0.06,
        },
        Sphere {
            center: Vec3::new(0.09, 0.05, 0.0),
            radius: 0.03,
        },
        Sphere {
            center: Vec3::new(-0.05, 0.08, 0.07),
            radius: 0.02,
        },
    ];
    (pts, rig)
}

/// Roots of a grown set moved by `offset`.
pub fn shifted_roots(points: &[Vec3], verts: usize, offset: Vec3) -> Vec<Vec3> {
    points.iter().step_by(verts).map(|p| *p + offset).collect()
}

/// The small procedural head of the pipeline tests: 384 guides of 16
/// vertices, light curl.
pub fn small_hair_scene() -> coif::frame::HairScene {
    coif::frame::HairScene::procedural(&coif::geometry::scene::GrowOptions {
        strand_count: 384,
        verts_per_strand: 16,
        curl: 0.15,
        ..Default::default()
    })
    .expect("the small procedural scene is valid")
}

/// The stability matrices' rig motion at `step` (of `dt` seconds): a circle
/// of `radius` metres at `hz` (a whipping head at about 4 m/s for 15 cm at
/// 4 Hz), plus a jump of `jump` metres every other 30 steps (teleports).
pub fn stress_offset(step: usize, dt: f32, radius: f32, hz: f32, jump: f32) -> Vec3 {
    let t = step as f32 * dt;
    let a = std::f32::consts::TAU * hz * t;
    let jumps = ((step / 30) % 2) as f32;
    Vec3::new(radius * a.cos() + jump * jumps, radius * a.sin(), 0.0)
}

/// A unit direction at longitudinal angle `theta` from the normal plane of
/// the fibre axis `X` (`sin theta = w . X`) and azimuth `phi` around `X`.
pub fn fibre_direction(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin(),
        theta.cos() * phi.cos(),
        theta.cos() * phi.sin(),
    )
}

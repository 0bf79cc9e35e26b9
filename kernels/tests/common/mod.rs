//! Fixtures shared by coif-kernels' integration tests: random curly strands
//! round a head with a rig of spheres, and root motions for the stress matrices (hair grown
//! on a sphere head comes from coif_geometry::scene).
#![allow(dead_code)]

pub mod executors;

use coif_kernels::rng::SplitMix64;
use coif_kernels::Sphere;
use glam::Vec3;

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

/// `side * side` strands of `verts` vertices, `segment` apart, hanging
/// straight down from a square grid of roots `spacing` apart in the x-z
/// plane (strand `row * side + col`: with 16 a block is half a row). Also
/// the crowd bench's hanging set (`benches/crowd.rs` includes this file).
pub fn hanging_grid(side: usize, spacing: f32, verts: usize, segment: f32) -> Vec<Vec3> {
    let mut pts = Vec::with_capacity(side * side * verts);
    for row in 0..side {
        for col in 0..side {
            let root = Vec3::new(spacing * col as f32, 0.0, spacing * row as f32);
            pts.extend((0..verts).map(|v| root - Vec3::Y * (segment * v as f32)));
        }
    }
    pts
}

/// Roots of a grown set moved by `offset`.
pub fn shifted_roots(points: &[Vec3], verts: usize, offset: Vec3) -> Vec<Vec3> {
    points.iter().step_by(verts).map(|p| *p + offset).collect()
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

//! Built-in scenes: hair grown on a sphere "head", for the default run,
//! tests and benchmarks, with no files needed.

use crate::kernels::rng::SplitMix64;
use crate::kernels::Sphere;
use glam::Vec3;

/// A sphere head with guide strands grown along its normals.
#[derive(Clone, Debug)]
pub struct SphereHead {
    /// The head (and the first sphere of the collision rig).
    pub head: Sphere,
    /// `strand_count * verts_per_strand` points, strand after strand, root first.
    pub points: Vec<Vec3>,
    pub verts_per_strand: usize,
}

/// Options for [`grow_on_sphere`].
#[derive(Clone, Debug)]
pub struct GrowOptions {
    pub strand_count: usize,
    pub verts_per_strand: usize,
    /// Strand length in metres.
    pub length: f32,
    /// Head centre and radius in metres.
    pub center: Vec3,
    pub radius: f32,
    /// Roots cover the cap of the sphere above this height, as a fraction of
    /// the radius from the centre (-1 = whole sphere, 0 = upper half).
    pub lowest_root: f32,
    /// Curl amplitude as a fraction of the segment length (0 = straight).
    pub curl: f32,
    pub seed: u64,
}

impl Default for GrowOptions {
    fn default() -> Self {
        GrowOptions {
            strand_count: 2048,
            verts_per_strand: 32,
            length: 0.25,
            center: Vec3::ZERO,
            radius: 0.1,
            lowest_root: -0.25,
            curl: 0.0,
            seed: 1,
        }
    }
}

/// Grows strands along the normals of a sphere: roots on a Fibonacci spiral
/// over the cap above `lowest_root`, each strand leaving straight along its
/// normal (with optional curl around it), so under gravity it falls and drapes.
pub fn grow_on_sphere(o: &GrowOptions) -> SphereHead {
    let mut rng = SplitMix64::new(o.seed);
    let verts = o.verts_per_strand.max(2);
    let seg = o.length / (verts - 1) as f32;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let mut points = Vec::with_capacity(o.strand_count * verts);
    for i in 0..o.strand_count {
        // Heights uniform in [lowest_root, 1] cover the cap with even area.
        let y = 1.0 - (1.0 - o.lowest_root) * (i as f32 + 0.5) / o.strand_count as f32;
        let r = (1.0 - y * y).max(0.0).sqrt();
        let a = golden * i as f32;
        let n = Vec3::new(r * a.cos(), y, r * a.sin()).normalize();
        let root = o.center + n * o.radius;
        let (u, w) = n.any_orthonormal_pair();
        let phase = rng.range(0.0, std::f32::consts::TAU);
        let turns = rng.range(2.0, 4.0);
        for v in 0..verts {
            let s = v as f32 / (verts - 1) as f32;
            let angle = phase + turns * std::f32::consts::TAU * s;
            let curl = (u * angle.cos() + w * angle.sin()) * (o.curl * seg * s.min(0.2) * 5.0);
            points.push(root + n * (seg * v as f32) + curl);
        }
    }
    SphereHead {
        head: Sphere {
            center: o.center,
            radius: o.radius,
        },
        points,
        verts_per_strand: verts,
    }
}

/// One strand sticking out horizontally (+x) from a pinned root at `root`.
pub fn horizontal_strand(root: Vec3, length: f32, verts: usize) -> Vec<Vec3> {
    let verts = verts.max(2);
    (0..verts)
        .map(|v| root + Vec3::X * (length * v as f32 / (verts - 1) as f32))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strands_start_on_the_sphere_and_have_the_asked_length() {
        let o = GrowOptions {
            strand_count: 100,
            curl: 0.0,
            ..Default::default()
        };
        let h = grow_on_sphere(&o);
        assert_eq!(h.points.len(), 100 * 32);
        for s in h.points.chunks(32) {
            assert!(((s[0] - o.center).length() - o.radius).abs() < 1e-5);
            let len: f32 = s.windows(2).map(|w| (w[1] - w[0]).length()).sum();
            assert!((len - o.length).abs() < 1e-4, "{len}");
            assert!(s[0].y >= o.lowest_root * o.radius - 1e-5);
        }
    }
}

//! Hair grown on a sphere head: a copy of `coif_geometry::scene`'s growth
//! (which depends on this crate, so the tests cannot use it), giving the
//! same points for the same options.

use coif_kernels::rng::SplitMix64;
use coif_kernels::Sphere;
use glam::Vec3;

/// A sphere head with guide strands grown along its normals.
#[derive(Clone, Debug)]
pub struct SphereHead {
    /// The head (and the first sphere of the collision rig).
    pub head: Sphere,
    /// `strand_count * verts_per_strand` points, strand after strand, root first.
    pub points: Vec<Vec3>,
    /// Vertices per strand.
    pub verts_per_strand: usize,
}

/// Options for [`grow_on_sphere`].
#[derive(Clone, Debug)]
pub struct GrowOptions {
    pub strand_count: usize,
    /// Vertices per strand.
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
        grow_strand(
            o.center + n * o.radius,
            n,
            seg,
            verts,
            o.curl,
            &mut rng,
            &mut points,
        );
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

/// Appends one strand of `verts` points `seg` apart growing from `root`
/// along the unit `normal`, curling around it: a helix of 2-4 random turns
/// with a random phase, of radius `curl * seg`, growing in over the first
/// fifth of the strand.
pub fn grow_strand(
    root: Vec3,
    normal: Vec3,
    seg: f32,
    verts: usize,
    curl: f32,
    rng: &mut SplitMix64,
    out: &mut Vec<Vec3>,
) {
    let (u, w) = normal.any_orthonormal_pair();
    let phase = rng.range(0.0, std::f32::consts::TAU);
    let turns = rng.range(2.0, 4.0);
    for v in 0..verts {
        let s = v as f32 / (verts.max(2) - 1) as f32;
        let angle = phase + turns * std::f32::consts::TAU * s;
        let around = (u * angle.cos() + w * angle.sin()) * (curl * seg * s.min(0.2) * 5.0);
        out.push(root + normal * (seg * v as f32) + around);
    }
}

/// One strand sticking out horizontally (+x) from a pinned root at `root`.
pub fn horizontal_strand(root: Vec3, length: f32, verts: usize) -> Vec<Vec3> {
    let verts = verts.max(2);
    (0..verts)
        .map(|v| root + Vec3::X * (length * v as f32 / (verts - 1) as f32))
        .collect()
}

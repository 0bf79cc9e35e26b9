//! Scalp meshes and guide strands grown from them (DESIGN.md section 2,
//! "grow guide strands from a scalp mesh along vertex normals").
//!
//! One guide grows from every mesh vertex along its (area-weighted) normal,
//! so the mesh's triangles are exactly the interpolation triangles
//! `coif::lod::Interpolation::new` needs (guide roots = mesh vertices).
//! A gravity-relaxed start runs a few simulation steps against the head so
//! the first frame does not begin with hair sticking straight out.

use coif_base::SplitMix64;
use coif_kernels::{self as kernels, SimParams, Sphere, Strands};
use glam::Vec3;
use std::fmt;

/// Why a scalp mesh or its guides could not be made.
#[derive(Clone, Debug, PartialEq)]
pub enum ScalpError {
    /// A triangle names a vertex past the end of the positions.
    IndexOutOfRange { triangle: usize },
    /// A position is not finite.
    NonFinite { index: usize },
    /// No vertices or no triangles.
    Empty,
    /// A growth option is out of range.
    InvalidOption(&'static str),
    /// The simulation refused the grown strands.
    Simulation(kernels::Error),
}

impl fmt::Display for ScalpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScalpError::IndexOutOfRange { triangle } => {
                write!(f, "triangle {triangle} names a missing vertex")
            }
            ScalpError::NonFinite { index } => write!(f, "scalp vertex {index} is not finite"),
            ScalpError::Empty => write!(f, "the scalp mesh has no vertices or no triangles"),
            ScalpError::InvalidOption(why) => write!(f, "invalid growth option: {why}"),
            ScalpError::Simulation(e) => write!(f, "relaxing the guides failed: {e}"),
        }
    }
}

impl std::error::Error for ScalpError {}

/// A triangle mesh of the scalp with area-weighted vertex normals.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalpMesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

impl ScalpMesh {
    /// Validates the mesh and computes vertex normals as the sum of the
    /// incident triangles' cross products (area-weighted), normalised;
    /// a vertex in no triangle gets +y.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<ScalpMesh, ScalpError> {
        if positions.is_empty() || triangles.is_empty() {
            return Err(ScalpError::Empty);
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(ScalpError::NonFinite { index });
        }
        if let Some(triangle) = triangles
            .iter()
            .position(|t| t.iter().any(|&i| i as usize >= positions.len()))
        {
            return Err(ScalpError::IndexOutOfRange { triangle });
        }
        let mut normals = vec![Vec3::ZERO; positions.len()];
        for t in &triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += n;
            }
        }
        for n in &mut normals {
            *n = n.try_normalize().unwrap_or(Vec3::Y);
        }
        Ok(ScalpMesh {
            positions,
            normals,
            triangles,
        })
    }

    /// A procedural scalp: the cap of a sphere above height `lowest` (a
    /// fraction of the radius from the centre, -1..1), as `rings` rings of
    /// `segments` vertices around a pole vertex, triangles wound outward.
    pub fn sphere_cap(
        center: Vec3,
        radius: f32,
        rings: usize,
        segments: usize,
        lowest: f32,
    ) -> ScalpMesh {
        let (rings, segments) = (rings.max(1), segments.max(3));
        let lowest = lowest.clamp(-0.99, 0.99);
        let max_polar = lowest.acos();
        let mut positions = vec![center + Vec3::Y * radius];
        for r in 1..=rings {
            let polar = max_polar * r as f32 / rings as f32;
            for s in 0..segments {
                let az =
                    std::f32::consts::TAU * (s as f32 + 0.5 * (r % 2) as f32) / segments as f32;
                let d = Vec3::new(polar.sin() * az.cos(), polar.cos(), polar.sin() * az.sin());
                positions.push(center + d * radius);
            }
        }
        let ring = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
        let mut triangles = Vec::new();
        for s in 0..segments {
            triangles.push([0, ring(1, s + 1), ring(1, s)]);
        }
        for r in 1..rings {
            for s in 0..segments {
                let (a, b, c, d) = (
                    ring(r, s),
                    ring(r, s + 1),
                    ring(r + 1, s),
                    ring(r + 1, s + 1),
                );
                if r % 2 == 1 {
                    triangles.push([a, b, d]);
                    triangles.push([a, d, c]);
                } else {
                    triangles.push([a, b, c]);
                    triangles.push([b, d, c]);
                }
            }
        }
        ScalpMesh::new(positions, triangles).expect("a sphere cap is a valid mesh")
    }

    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Total area in m^2.
    pub fn area(&self) -> f32 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }
}

/// How guides grow from a scalp.
#[derive(Clone, Debug, PartialEq)]
pub struct GuideOptions {
    /// Strand length in metres.
    pub length: f32,
    pub verts_per_strand: usize,
    /// Curl amplitude as a fraction of the segment length (0 = straight).
    pub curl: f32,
    /// Simulation steps of relaxation under gravity against `head` (0 = none).
    pub relax_steps: usize,
    pub seed: u64,
}

impl Default for GuideOptions {
    fn default() -> Self {
        GuideOptions {
            length: 0.25,
            verts_per_strand: 32,
            curl: 0.3,
            relax_steps: 90,
            seed: 1,
        }
    }
}

/// One guide per scalp vertex along its normal (with optional curl around
/// it), then `relax_steps` default simulation steps against `head` so the
/// hair starts draped. Returns the points, strand after strand, root first;
/// guide i grows from mesh vertex i.
pub fn grow_guides(
    mesh: &ScalpMesh,
    o: &GuideOptions,
    head: &[Sphere],
) -> Result<Vec<Vec3>, ScalpError> {
    if !(o.length > 0.0 && o.length.is_finite()) {
        return Err(ScalpError::InvalidOption("length must be finite and > 0"));
    }
    if o.verts_per_strand < 2 {
        return Err(ScalpError::InvalidOption("at least 2 vertices per strand"));
    }
    if !o.curl.is_finite() {
        return Err(ScalpError::InvalidOption("curl must be finite"));
    }
    let verts = o.verts_per_strand;
    let seg = o.length / (verts - 1) as f32;
    let mut rng = SplitMix64::new(o.seed);
    let mut points = Vec::with_capacity(mesh.positions.len() * verts);
    for (root, n) in mesh.positions.iter().zip(&mesh.normals) {
        crate::scene::grow_strand(*root, *n, seg, verts, o.curl, &mut rng, &mut points);
    }
    if o.relax_steps == 0 {
        return Ok(points);
    }
    let mut strands = Strands::from_polylines(&points, verts).map_err(ScalpError::Simulation)?;
    let params = SimParams::default();
    for _ in 0..o.relax_steps {
        kernels::step(&mut strands, &params, head);
    }
    Ok(strands.positions())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_cap_normals_point_outward_and_area_is_the_caps() {
        let c = Vec3::new(0.0, 1.6, 0.0);
        let mesh = ScalpMesh::sphere_cap(c, 0.1, 12, 24, 0.0);
        for (p, n) in mesh.positions().iter().zip(mesh.normals()) {
            assert!(((*p - c).normalize() - *n).length() < 0.05, "{p} {n}");
        }
        // Triangles wound outward: face normals agree with the vertex normals.
        for t in mesh.triangles() {
            let [a, b, d] = t.map(|i| mesh.positions()[i as usize]);
            assert!((b - a).cross(d - a).dot(a - c) > 0.0);
        }
        // A hemisphere of radius 0.1 has area 2 pi r^2; the mesh's is a bit less.
        let hemisphere = std::f32::consts::TAU * 0.01;
        assert!(
            mesh.area() < hemisphere && mesh.area() > 0.97 * hemisphere,
            "{}",
            mesh.area()
        );
    }

    #[test]
    fn guides_grow_along_normals_and_relax_onto_the_head() {
        let head = Sphere {
            center: Vec3::ZERO,
            radius: 0.1,
        };
        let mesh = ScalpMesh::sphere_cap(head.center, head.radius, 4, 12, 0.2);
        let straight = GuideOptions {
            curl: 0.0,
            relax_steps: 0,
            verts_per_strand: 8,
            ..Default::default()
        };
        let pts = grow_guides(&mesh, &straight, &[]).unwrap();
        assert_eq!(pts.len(), mesh.positions().len() * 8);
        for (i, s) in pts.chunks(8).enumerate() {
            assert_eq!(s[0], mesh.positions()[i]);
            let dir = (s[7] - s[0]).normalize();
            assert!(dir.dot(mesh.normals()[i]) > 0.999);
        }
        let relaxed = grow_guides(
            &mesh,
            &GuideOptions {
                verts_per_strand: 8,
                ..Default::default()
            },
            std::slice::from_ref(&head),
        )
        .unwrap();
        // Relaxed hair has fallen: tips lower on average, none inside the head.
        let tip_y = |p: &[Vec3]| p.chunks(8).map(|s| s[7].y).sum::<f32>();
        assert!(tip_y(&relaxed) < tip_y(&pts) - 0.05);
        assert!(relaxed.iter().all(|p| p.length() > head.radius - 1e-3));
    }

    #[test]
    fn bad_meshes_and_options_are_errors() {
        assert_eq!(
            ScalpMesh::new(vec![], vec![[0, 1, 2]]),
            Err(ScalpError::Empty)
        );
        assert_eq!(
            ScalpMesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]),
            Err(ScalpError::IndexOutOfRange { triangle: 0 })
        );
        assert_eq!(
            ScalpMesh::new(vec![Vec3::ZERO, Vec3::NAN, Vec3::ONE], vec![[0, 1, 2]]),
            Err(ScalpError::NonFinite { index: 1 })
        );
        let mesh = ScalpMesh::sphere_cap(Vec3::ZERO, 0.1, 2, 6, 0.0);
        for o in [
            GuideOptions {
                length: 0.0,
                ..Default::default()
            },
            GuideOptions {
                length: f32::NAN,
                ..Default::default()
            },
            GuideOptions {
                verts_per_strand: 1,
                ..Default::default()
            },
            GuideOptions {
                curl: f32::INFINITY,
                ..Default::default()
            },
        ] {
            assert!(matches!(
                grow_guides(&mesh, &o, &[]),
                Err(ScalpError::InvalidOption(_))
            ));
        }
    }
}

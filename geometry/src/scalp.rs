//! Scalp meshes and the guide strands grown from them.
//!
//! One guide grows from every mesh vertex along its area-weighted normal
//! ([`ScalpMesh::grow_guides`], by the one grower [`crate::grow::grow`]),
//! so the mesh's triangles are exactly the interpolation triangles
//! `coif_lod::Interpolation::new` needs (guide roots = mesh vertices).
//! The guides start sticking straight out; `coif_frame::drape` relaxes them
//! under gravity against the head.

use crate::grow::{grow, Growth, InvalidGrowth};
use crate::mesh::{MeshError, TriangleMesh};
use glam::Vec3;
use std::fmt;

/// Why a scalp mesh or its guides could not be made.
#[derive(Clone, Debug, PartialEq)]
pub enum ScalpError {
    /// A triangle names a vertex past the end of the positions.
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
    },
    /// A position is not finite.
    NonFinite {
        /// Index of the vertex.
        index: usize,
    },
    /// No vertices or no triangles.
    Empty,
    /// A growth option is out of range.
    InvalidOption(&'static str),
}

impl From<InvalidGrowth> for ScalpError {
    fn from(e: InvalidGrowth) -> Self {
        ScalpError::InvalidOption(e.0)
    }
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
        }
    }
}

impl std::error::Error for ScalpError {}

/// A triangle mesh of the scalp with area-weighted vertex normals.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalpMesh {
    mesh: TriangleMesh,
}

impl ScalpMesh {
    /// Validates the mesh and computes vertex normals as the sum of the
    /// incident triangles' cross products (area-weighted), normalised;
    /// a vertex in no triangle gets +y.
    ///
    /// # Errors
    ///
    /// [`ScalpError`] on no positions or triangles, an index out of range or a
    /// non-finite position.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<ScalpMesh, ScalpError> {
        let mesh = TriangleMesh::new(positions, triangles).map_err(|e| match e {
            MeshError::IndexOutOfRange { triangle, .. } => ScalpError::IndexOutOfRange { triangle },
            MeshError::NonFinite { index } => ScalpError::NonFinite { index },
            MeshError::TooLarge { .. } => {
                ScalpError::InvalidOption("more than 2^24 vertices or triangles")
            }
            _ => ScalpError::Empty,
        })?;
        Ok(ScalpMesh { mesh })
    }

    /// A procedural scalp: the cap of a sphere above height `lowest` (a
    /// fraction of the radius from the centre, -1..1), as `rings` rings of
    /// `segments` vertices around a pole vertex, triangles wound outward.
    /// `rings` is clamped to `1..=1024` and `segments` to `3..=4096` (at
    /// most about 4 million vertices: it allocated without bound).
    pub fn sphere_cap(
        center: Vec3,
        radius: f32,
        rings: usize,
        segments: usize,
        lowest: f32,
    ) -> ScalpMesh {
        let (rings, segments) = (rings.clamp(1, 1024), segments.clamp(3, 4096));
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
        // Valid by construction but for a non-finite centre or radius, which
        // the positions then carry (no check, no panic).
        ScalpMesh {
            mesh: TriangleMesh::unchecked(positions, triangles),
        }
    }

    /// The vertices (the guide roots).
    pub fn positions(&self) -> &[Vec3] {
        self.mesh.positions()
    }

    /// Unit area-weighted vertex normals (the guides' growth directions).
    pub fn normals(&self) -> &[Vec3] {
        self.mesh.normals()
    }

    /// Triangles as vertex indices, wound so their normals point outward.
    pub fn triangles(&self) -> &[[u32; 3]] {
        self.mesh.triangles()
    }

    /// Total area in m^2.
    pub fn area(&self) -> f32 {
        let p = self.positions();
        self.triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| p[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// One guide per vertex along its normal ([`grow`]): points strand
    /// after strand, root first; guide i grows from vertex i. Errors on
    /// options out of range ([`Growth::validate`]).
    ///
    /// # Errors
    ///
    /// [`ScalpError`] wrapping [`InvalidGrowth`] for options out of range.
    pub fn grow_guides(&self, growth: &Growth) -> Result<Vec<Vec3>, ScalpError> {
        growth.validate()?;
        Ok(grow(self.positions(), self.normals(), growth))
    }
}

//! Triangle meshes of bodies: read from Wavefront OBJ (with `tobj`, a
//! maintained loader), validated, with area-weighted vertex normals.
//!
//! A body mesh is what hair rests on and is drawn over: a character's
//! head and shoulders (the project ships Sintel's bust, `assets/sintel/`).
//! It may be open (a bust is cut at the chest) and may be a triangle soup:
//! the collision field built from it (`coif_kernels::Sdf::from_mesh`)
//! tolerates both.

use glam::Vec3;
use std::fmt;

/// The most vertices or triangles [`TriangleMesh::from_obj`] accepts
/// (16 million each: a body mesh for hair is thousands).
pub const MAX_MESH_ELEMENTS: usize = 1 << 24;

/// Why a mesh could not be read or made.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// The OBJ text could not be parsed (`tobj`'s reason).
    Obj(String),
    /// A triangle names a vertex past the end of the positions.
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The index it holds.
        index: u32,
        /// How many vertices there are.
        vertices: usize,
    },
    /// A position is not finite (after scaling).
    NonFinite {
        /// Index of the vertex.
        index: usize,
    },
    /// No vertices or no triangles.
    Empty,
    /// More than [`MAX_MESH_ELEMENTS`] vertices or triangles.
    TooLarge {
        /// The count found.
        count: usize,
    },
    /// The scale is not finite or not positive.
    BadScale,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::Obj(why) => write!(f, "not a readable Wavefront OBJ mesh: {why}"),
            MeshError::IndexOutOfRange {
                triangle,
                index,
                vertices,
            } => write!(
                f,
                "triangle {triangle} names vertex {index}, but the mesh has {vertices} vertices"
            ),
            MeshError::NonFinite { index } => write!(f, "mesh vertex {index} is not finite"),
            MeshError::Empty => write!(f, "the mesh has no vertices or no triangles"),
            MeshError::TooLarge { count } => write!(
                f,
                "the mesh has {count} vertices or triangles, more than {MAX_MESH_ELEMENTS}"
            ),
            MeshError::BadScale => write!(f, "the mesh scale must be finite and positive"),
        }
    }
}

impl std::error::Error for MeshError {}

/// A validated triangle mesh with area-weighted vertex normals.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Validates `positions` and `triangles` (non-empty, finite, indices in
    /// range, at most [`MAX_MESH_ELEMENTS`] of each) and computes the
    /// vertex normals ([`vertex_normals`]).
    ///
    /// # Errors
    /// [`MeshError::Empty`], [`MeshError::TooLarge`],
    /// [`MeshError::NonFinite`] or [`MeshError::IndexOutOfRange`].
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<TriangleMesh, MeshError> {
        if positions.is_empty() || triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        let count = positions.len().max(triangles.len());
        if count > MAX_MESH_ELEMENTS {
            return Err(MeshError::TooLarge { count });
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite { index });
        }
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    index,
                    vertices: positions.len(),
                });
            }
        }
        let normals = vertex_normals(&positions, &triangles);
        Ok(TriangleMesh {
            positions,
            normals,
            triangles,
        })
    }

    /// A mesh built by this crate, valid by construction (indices in
    /// range), without the checks: normals computed, nothing refused.
    pub(crate) fn unchecked(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> TriangleMesh {
        let normals = vertex_normals(&positions, &triangles);
        TriangleMesh {
            positions,
            normals,
            triangles,
        }
    }

    /// Reads a Wavefront OBJ mesh from its text with `tobj` (polygons
    /// triangulated, every object of the file in one mesh, positions only:
    /// normals and texture coordinates in the file are not used, the
    /// normals are recomputed) and multiplies the positions by `scale`
    /// (0.01 takes a mesh authored in centimetres to metres).
    ///
    /// # Errors
    /// [`MeshError::BadScale`], [`MeshError::Obj`] when `tobj` refuses the
    /// text, and [`TriangleMesh::new`]'s errors.
    ///
    /// ```
    /// use coif_geometry::mesh::TriangleMesh;
    /// let obj = "v 0 0 0\nv 100 0 0\nv 0 100 0\nf 1 2 3\n";
    /// let mesh = TriangleMesh::from_obj(obj.as_bytes(), 0.01).unwrap();
    /// assert_eq!(mesh.triangles(), &[[0, 1, 2]]);
    /// assert_eq!(mesh.positions()[1], glam::Vec3::X);
    /// assert!(TriangleMesh::from_obj(b"v 0 0 0\nf 1 2 9\n", 1.0).is_err());
    /// ```
    pub fn from_obj(text: &[u8], scale: f32) -> Result<TriangleMesh, MeshError> {
        if !(scale.is_finite() && scale > 0.0) {
            return Err(MeshError::BadScale);
        }
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ..Default::default()
        };
        let mut reader = std::io::BufReader::new(text);
        let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| MeshError::Obj(e.to_string()))?;
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for m in &models {
            let base = positions.len();
            let mesh = &m.mesh;
            if base + mesh.positions.len() / 3 > MAX_MESH_ELEMENTS
                || triangles.len() + mesh.indices.len() / 3 > MAX_MESH_ELEMENTS
            {
                return Err(MeshError::TooLarge {
                    count: (base + mesh.positions.len() / 3)
                        .max(triangles.len() + mesh.indices.len() / 3),
                });
            }
            positions.extend(
                mesh.positions
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2]) * scale),
            );
            let base = base as u32;
            triangles.extend(mesh.indices.chunks_exact(3).map(|t| {
                [
                    base.saturating_add(t[0]),
                    base.saturating_add(t[1]),
                    base.saturating_add(t[2]),
                ]
            }));
        }
        TriangleMesh::new(positions, triangles)
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Unit vertex normals (area-weighted; +y for a vertex in no triangle
    /// or only in degenerate ones).
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// Triangles, as indices of three vertices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The mesh's holes: the vertices of each connected set of boundary
    /// edges (edges in exactly one triangle), in increasing index order,
    /// the sets ordered by their smallest vertex. A closed mesh has none;
    /// a bust has its cuts (chest, arms) and openings (eyes, mouth).
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        let mut edges: Vec<(u32, u32)> = self
            .triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        edges.sort_unstable();
        // Boundary edges: those that appear once.
        let mut boundary = Vec::new();
        let mut i = 0;
        while i < edges.len() {
            let mut j = i + 1;
            while j < edges.len() && edges[j] == edges[i] {
                j += 1;
            }
            if j - i == 1 {
                boundary.push(edges[i]);
            }
            i = j;
        }
        // Connected sets by union-find over the boundary vertices.
        let mut parent: Vec<u32> = (0..self.positions.len() as u32).collect();
        fn root(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                parent[x as usize] = parent[parent[x as usize] as usize];
                x = parent[x as usize];
            }
            x
        }
        for &(a, b) in &boundary {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
        let mut on_boundary: Vec<u32> = boundary.iter().flat_map(|&(a, b)| [a, b]).collect();
        on_boundary.sort_unstable();
        on_boundary.dedup();
        // Each set's loop, found through its root in O(1) (a search of the
        // loops so far was quadratic: 3.3 s for 60,000 separate triangles).
        let mut slot = vec![u32::MAX; self.positions.len()];
        let mut loops: Vec<Vec<u32>> = Vec::new();
        for v in on_boundary {
            let r = root(&mut parent, v) as usize;
            match slot[r] {
                u32::MAX => {
                    slot[r] = loops.len() as u32;
                    loops.push(vec![v]);
                }
                at => loops[at as usize].push(v),
            }
        }
        loops.sort_by_key(|members| members[0]);
        loops
    }

    /// The axis-aligned box of the vertices, `(min, max)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }
}

/// Area-weighted vertex normals: per vertex, the sum of the cross products
/// `(b - a) x (c - a)` of the triangles it belongs to (twice their areas
/// along their normals), normalised; +y where that sum is zero. A triangle
/// with an index outside `positions` is skipped (the callers check them;
/// this never panics).
pub fn vertex_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for t in triangles {
        let corner = |i: u32| positions.get(i as usize).copied();
        let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
            continue;
        };
        let n = (b - a).cross(c - a);
        for &i in t {
            normals[i as usize] += n;
        }
    }
    for n in &mut normals {
        *n = n.try_normalize().unwrap_or(Vec3::Y);
    }
    normals
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's 8 corners and 12 outward triangles, as OBJ text.
    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";

    #[test]
    fn a_cube_reads_with_outward_normals() {
        let m = TriangleMesh::from_obj(CUBE.as_bytes(), 2.0).unwrap();
        assert_eq!(m.positions().len(), 8);
        assert_eq!(m.triangles().len(), 12);
        assert_eq!(m.bounds(), (Vec3::ZERO, Vec3::splat(2.0)));
        for (p, n) in m.positions().iter().zip(m.normals()) {
            let out = (*p - Vec3::ONE).normalize();
            assert!(n.dot(out) > 0.5, "{p}: {n}");
        }
    }

    #[test]
    fn holes_are_the_boundary_loops() {
        let closed = TriangleMesh::from_obj(CUBE.as_bytes(), 1.0).unwrap();
        assert!(closed.boundary_loops().is_empty());
        // Without its top (y = 1) face: one hole of the four top corners.
        let open = CUBE.replace("f 4 8 7 3\n", "");
        let m = TriangleMesh::from_obj(open.as_bytes(), 1.0).unwrap();
        let loops = m.boundary_loops();
        assert_eq!(loops.len(), 1, "{loops:?}");
        assert_eq!(loops[0].len(), 4);
        assert!(loops[0].iter().all(|&v| m.positions()[v as usize].y == 1.0));
        // Two separate triangles: two holes of three.
        let two = TriangleMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::Y,
                Vec3::Z,
                Vec3::ONE,
                Vec3::X * 2.0,
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        )
        .unwrap();
        assert_eq!(two.boundary_loops(), vec![vec![0, 1, 2], vec![3, 4, 5]]);
        // Many loops: one per separate triangle, in vertex order.
        let n = 20_000u32;
        let many = TriangleMesh::new(
            (0..3 * n)
                .map(|i| Vec3::new((i / 3) as f32, (i % 3) as f32, (i % 2) as f32))
                .collect(),
            (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
        )
        .unwrap();
        let loops = many.boundary_loops();
        assert_eq!(loops.len(), n as usize);
        assert!(loops
            .iter()
            .enumerate()
            .all(|(t, l)| *l == [3 * t as u32, 3 * t as u32 + 1, 3 * t as u32 + 2]));
    }

    #[test]
    fn bad_meshes_are_refused_with_a_reason() {
        let err = |text: &str| TriangleMesh::from_obj(text.as_bytes(), 1.0).unwrap_err();
        assert!(matches!(
            err("v 0 0 0\nv 1 0 0\nf 1 2 7\n"),
            MeshError::Obj(_)
        ));
        assert!(matches!(err("v 0 0 x\n"), MeshError::Obj(_)));
        assert_eq!(err(""), MeshError::Empty);
        assert_eq!(err("v 0 0 0\nv 1 0 0\nv 0 1 0\n"), MeshError::Empty);
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n"),
            MeshError::NonFinite { index: 2 }
        );
        assert_eq!(
            TriangleMesh::from_obj(CUBE.as_bytes(), 0.0).unwrap_err(),
            MeshError::BadScale
        );
        // Finite in the file, infinite once scaled.
        assert!(matches!(
            TriangleMesh::from_obj(b"v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n", 1e10).unwrap_err(),
            MeshError::NonFinite { .. }
        ));
        assert_eq!(
            TriangleMesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 3]]).unwrap_err(),
            MeshError::IndexOutOfRange {
                triangle: 0,
                index: 3,
                vertices: 3
            }
        );
        // Binary garbage: an error, never a panic.
        let noise: Vec<u8> = (0..4096u32)
            .map(|i| (i.wrapping_mul(2654435761) >> 24) as u8)
            .collect();
        assert!(TriangleMesh::from_obj(&noise, 1.0).is_err());
        for e in [
            MeshError::Empty,
            MeshError::BadScale,
            MeshError::TooLarge { count: 9 },
        ] {
            assert!(!e.to_string().is_empty());
        }
    }
}

//! The signed distance field of a triangle mesh, for hair against a body.
//!
//! [`Sdf::from_mesh`] samples the signed distance to a triangle mesh (a soup
//! is fine: holes, open boundaries and degenerate triangles are tolerated) on
//! a regular grid in the mesh's own frame; [`Sdf::distance`] and
//! [`Sdf::distance_and_normal`] read it back at world points through the
//! rigid transform set by [`Sdf::set_transform`] (the bone the mesh rides
//! on). The strand step reads it through the crate-internal
//! [`SdfLane::sample`], eight vertices at a time, in the mesh frame.
//!
//! Modules: `build.rs` (mesh to grid: exact band, closest-triangle
//! propagation, sign by the generalised winding number), `triangle.rs`
//! (Ericson's closest point on a triangle), `winding.rs` (Jacobson et al.'s
//! generalised winding number, Van Oosterom and Strackee's solid angle,
//! Barill et al.'s fast hierarchical sum), `lookup.rs` (trilinear value and
//! gradient, scalar and SIMD twins). `kernels/SDF.md` gives the algorithm,
//! the measurements and the memory.

mod build;
mod lookup;
mod slope;
mod triangle;
mod winding;

pub(crate) use lookup::SdfLane;

use crate::lanes::{Vec3Lanes, V3};
use crate::Error;
use coif_base::lanes::F32Lanes;
use glam::{Affine3A, UVec3, Vec3};

/// The most grid nodes (stored distances) [`Sdf::from_mesh`] accepts:
/// `2^23` = 8,388,608, i.e. 32 MiB of `f32` values kept, and about three
/// times that (squared distances, closest triangles then winding numbers,
/// the values) briefly while building, about 100 MiB at the cap. A 40 cm bust at 4 mm cells needs about 0.8
/// million; at 2 mm about 6 million. The cap also keeps every node index
/// exact in an `f32`, which the SIMD lookup relies on.
pub const MAX_SDF_CELLS: u64 = 1 << 23;

/// Empty cells added round the mesh's box on every side (before rounding the
/// counts up to whole coarse winding cells): the box boundary then lies at
/// least this far outside the surface, so values outside the box stay
/// positive and the whole narrow band lies inside the grid.
pub const MARGIN_CELLS: u32 = 2;

/// The sampled grid and the constants the lookup needs.
#[derive(Clone, Debug)]
pub(crate) struct Grid {
    /// Signed distance per node, x fastest, then y, then z.
    pub values: Vec<f32>,
    /// Nodes per axis (each at least 2).
    pub dims: UVec3,
    /// Mesh-frame position of node (0, 0, 0).
    pub origin: Vec3,
    pub cell: f32,
    pub inv_cell: f32,
    /// `dims - 1` and `dims - 2`, as floats: the clamps of the lookup.
    pub max_u: Vec3,
    pub max_i: Vec3,
    /// Node strides of y and z, as floats (exact: below 2^24).
    pub stride_y: f32,
    pub stride_z: f32,
    /// The largest lowest-corner index whose cell lies in the grid.
    pub max_base: i32,
    /// Offsets of a cell's eight corners from its lowest node, x fastest.
    pub corners: [i32; 8],
    /// The far map with the slope bounds (`build::far_map`): per block of
    /// `FAR_BLOCK^3` cells, `+1 / L` where every point of the block is
    /// outside and more than `far_clearance` from the surface, `-1 / L`
    /// where not, `L` the field's slope bound over the block grown by one
    /// block (`slope.rs`); its size in blocks, strides and clamps as floats,
    /// and `1 / (FAR_BLOCK cell)`.
    pub far: Vec<f32>,
    pub far_max: Vec3,
    pub far_stride_y: f32,
    pub far_stride_z: f32,
    pub far_inv: f32,
    pub far_clearance: f32,
    /// The largest radius of a clear ball (`SdfLane::clear_radius2`): just
    /// under a block width, `FAR_BLOCK cell (1 - 1e-3)`.
    pub ball_cap: f32,
    /// A lower bound of the field at every point outside the box: the
    /// least node value on the box's six faces, less a slack for the
    /// interpolant's rounding (`1e-5` of the largest face value, `1e-6` m;
    /// the value outside is a face's interpolant plus the distance to the
    /// box). A skin thinner than this never reaches outside the box
    /// (`SdfLane::sample_for_skin`).
    pub outside_floor: f32,
}

impl Grid {
    fn new(dims: UVec3, origin: Vec3, cell: f32) -> Grid {
        let max_base = ((dims.z - 2) * dims.y + (dims.y - 2)) * dims.x + (dims.x - 2);
        Grid {
            values: Vec::new(),
            dims,
            origin,
            cell,
            inv_cell: 1.0 / cell,
            max_u: (dims - UVec3::ONE).as_vec3(),
            max_i: (dims - UVec3::splat(2)).as_vec3(),
            stride_y: dims.x as f32,
            stride_z: (dims.x * dims.y) as f32,
            max_base: max_base as i32,
            corners: {
                let (sx, sy) = (dims.x as i32, (dims.x * dims.y) as i32);
                [0, 1, sx, sx + 1, sy, sy + 1, sy + sx, sy + sx + 1]
            },
            far: Vec::new(),
            far_max: Vec3::ZERO,
            far_stride_y: 0.0,
            far_stride_z: 0.0,
            far_inv: 1.0 / (cell * build::FAR_BLOCK as f32),
            far_clearance: (build::FAR_RING as f32 - 0.8661) * cell,
            ball_cap: build::FAR_BLOCK as f32 * cell * (1.0 - 1.0e-3),
            outside_floor: f32::NEG_INFINITY,
        }
    }

    pub fn node_count(&self) -> usize {
        (self.dims.x * self.dims.y * self.dims.z) as usize
    }

    /// [`Grid::outside_floor`] of `values`: the least value on the box's
    /// faces less its slack (`-inf` if a value there is not finite).
    fn outside_floor(&self, values: &[f32]) -> f32 {
        let [nx, ny, nz] = self.dims.to_array().map(|n| n as usize);
        let (mut least, mut largest) = (f32::INFINITY, 0.0f32);
        for z in 0..nz {
            for y in 0..ny {
                let row = &values[(z * ny + y) * nx..][..nx];
                // A whole row on the z or y faces; its two ends otherwise.
                let whole = z == 0 || z + 1 == nz || y == 0 || y + 1 == ny;
                let step = if whole { 1 } else { nx - 1 };
                for &v in row.iter().step_by(step) {
                    if !v.is_finite() {
                        return f32::NEG_INFINITY;
                    }
                    least = least.min(v);
                    largest = largest.max(v.abs());
                }
            }
        }
        least - 1.0e-5 * largest - 1.0e-6
    }
}

impl Sdf {
    /// How far outside the surface every point of a far-map block is: a
    /// skin thinner than this never reaches such a point, and the step
    /// skips its lookup there.
    pub(crate) fn far_clearance(&self) -> f32 {
        self.grid.far_clearance
    }

    /// The same field with no clear balls (every radius -1): the step then
    /// looks up every vertex every round, the reference the skipping is
    /// tested against.
    #[cfg(test)]
    pub(crate) fn without_clear_balls(mut self) -> Sdf {
        self.grid.ball_cap = -1.0;
        self
    }
}

/// The signed distance field of a triangle mesh on a regular grid, negative
/// inside, with the rigid transform that places the mesh in the world.
///
/// Distances within one cell of the surface are exact at the grid nodes;
/// farther ones are distances to a real triangle found by closest-triangle
/// propagation (never below the exact value, equal to it in practice near
/// the surface). The sign is the generalised winding number's
/// (inside where `w >= 1/2`), which tolerates holes. Between nodes the field
/// is trilinear. See `kernels/SDF.md` for the construction and its measured
/// accuracy.
#[derive(Clone)]
pub struct Sdf {
    grid: Grid,
    world_from_mesh: Affine3A,
    mesh_from_world: Affine3A,
}

impl std::fmt::Debug for Sdf {
    /// The grid's shape and the transform, not the values.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (lo, hi) = self.bounds();
        f.debug_struct("Sdf")
            .field("dims", &self.grid.dims)
            .field("cell", &self.grid.cell)
            .field("bounds", &(lo, hi))
            .field("world_from_mesh", &self.world_from_mesh)
            .finish_non_exhaustive()
    }
}

impl Sdf {
    /// `positions` in the mesh's own frame, metres; `triangles` index them
    /// (counter-clockwise seen from outside, so that the inside is negative).
    /// `cell` is the grid spacing in metres.
    ///
    /// Errors (never panics, never allocates a huge grid) on: no triangles
    /// ([`Error::NoTriangles`]), an index out of range
    /// ([`Error::IndexOutOfRange`]), a non-finite position
    /// ([`Error::NonFinite`]), `cell` not finite or `<= 0`
    /// ([`Error::InvalidParameter`]), a grid of more than [`MAX_SDF_CELLS`]
    /// nodes ([`Error::GridTooLarge`], counted in `f64` before allocating).
    /// Zero-area triangles are accepted (they count as their edges).
    ///
    /// The grid covers the box of the referenced vertices plus
    /// [`MARGIN_CELLS`] cells (and up to 7 more, rounding) on every side.
    /// The transform starts as the identity.
    ///
    /// # Errors
    ///
    /// As listed above: [`Error::NoTriangles`], [`Error::IndexOutOfRange`],
    /// [`Error::NonFinite`], [`Error::InvalidParameter`], [`Error::GridTooLarge`].
    pub fn from_mesh(positions: &[Vec3], triangles: &[[u32; 3]], cell: f32) -> Result<Sdf, Error> {
        if triangles.is_empty() {
            return Err(Error::NoTriangles);
        }
        if !(cell.is_finite() && cell > 0.0) {
            return Err(Error::InvalidParameter {
                name: "cell",
                value: cell,
                expected: "finite and > 0 (metres)",
            });
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFinite { index });
        }
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for (t, tri) in triangles.iter().enumerate() {
            for &i in tri {
                let Some(&p) = positions.get(i as usize) else {
                    return Err(Error::IndexOutOfRange {
                        triangle: t,
                        index: i,
                        vertices: positions.len(),
                    });
                };
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        let (dims, origin) = build::layout(lo, hi, cell)?;
        let mut grid = Grid::new(dims, origin, cell);
        let (values, band) = build::build(&grid, positions, triangles);
        let (far, blocks) = build::far_map(&grid, &values, &band);
        grid.outside_floor = grid.outside_floor(&values);
        grid.values = values;
        grid.far = far;
        grid.far_max = (blocks - UVec3::ONE).as_vec3();
        grid.far_stride_y = blocks.x as f32;
        grid.far_stride_z = (blocks.x * blocks.y) as f32;
        Ok(Sdf {
            grid,
            world_from_mesh: Affine3A::IDENTITY,
            mesh_from_world: Affine3A::IDENTITY,
        })
    }

    /// Signed distance (metres) at a world point, through the transform
    /// (negative inside). Inside the grid box: the trilinear interpolant of
    /// the node values. Outside: the value at the point clamped to the box
    /// plus the distance to the box, positive and no less than half the true
    /// distance (an upper bound of it, by the triangle inequality). A NaN
    /// point gives NaN or a finite value, never a panic. Allocates nothing.
    pub fn distance(&self, p: Vec3) -> f32 {
        let q = self.mesh_from_world.transform_point3(p);
        <f32 as SdfLane>::sample(self, V3::from_vec3(q)).0
    }

    /// The gradient of [`Sdf::distance`] at a world point, in the world frame
    /// (the trilinear interpolant's derivative, not normalised; outside the
    /// box the derivative of the outside value: the clamped point's
    /// gradient along the unclamped axes plus the unit direction away from
    /// the box).
    pub fn gradient(&self, p: Vec3) -> Vec3 {
        self.distance_and_gradient(p).1
    }

    /// [`Sdf::distance`] and [`Sdf::gradient`] in one lookup.
    pub fn distance_and_gradient(&self, p: Vec3) -> (f32, Vec3) {
        let q = self.mesh_from_world.transform_point3(p);
        let (d, g) = <f32 as SdfLane>::sample(self, V3::from_vec3(q));
        (d, self.world_from_mesh.transform_vector3(g.to_vec3()))
    }

    /// [`Sdf::distance`] and the unit outward normal (the normalised world
    /// gradient; zero where the gradient vanishes): the push-out direction.
    pub fn distance_and_normal(&self, p: Vec3) -> (f32, Vec3) {
        let (d, g) = self.distance_and_gradient(p);
        (d, g.normalize_or_zero())
    }

    /// Where the mesh stands in the world from now on (a rigid bone
    /// transform: rotation and translation). Errors with
    /// [`Error::InvalidTransform`] on a non-finite transform or a non-rigid
    /// one (columns not orthonormal within `1e-4`, or a reflection,
    /// `det <= 0`), and then changes nothing.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidTransform`] as described above.
    pub fn set_transform(&mut self, world_from_mesh: Affine3A) -> Result<(), Error> {
        if !world_from_mesh.is_finite() {
            return Err(Error::InvalidTransform {
                reason: "not finite",
            });
        }
        let m = world_from_mesh.matrix3;
        let cols = [m.x_axis, m.y_axis, m.z_axis];
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { 1.0 } else { 0.0 };
                if (Vec3::from(cols[i]).dot(Vec3::from(cols[j])) - want).abs() > 1e-4 {
                    return Err(Error::InvalidTransform {
                        reason: "not rigid: the columns are not orthonormal (scale or shear)",
                    });
                }
            }
        }
        if m.determinant() <= 0.0 {
            return Err(Error::InvalidTransform {
                reason: "not rigid: a reflection (determinant <= 0)",
            });
        }
        self.world_from_mesh = world_from_mesh;
        // Rigid: the inverse rotation is the transpose.
        let r = m.transpose();
        self.mesh_from_world = Affine3A {
            matrix3: r,
            translation: -(r * world_from_mesh.translation),
        };
        Ok(())
    }

    /// Signed distance and gradient (per metre, not normalised) at a point
    /// in the MESH frame, no transform: the scalar lane lookup the strand
    /// step runs (the crate-internal `SdfLane` at `f32`), for callers that
    /// keep their points in the mesh frame. Allocates nothing.
    pub fn sample_mesh(&self, p_mesh: Vec3) -> (f32, Vec3) {
        let (d, g) = <f32 as SdfLane>::sample(self, V3::from_vec3(p_mesh));
        (d, g.to_vec3())
    }

    /// [`Sdf::sample_mesh`] for eight points at once (one per lane), the
    /// SIMD lookup: the same bits per lane as the scalar one. Allocates
    /// nothing.
    pub fn sample_mesh_simd(&self, p_mesh: Vec3Lanes) -> (F32Lanes, Vec3Lanes) {
        <F32Lanes as SdfLane>::sample(self, p_mesh)
    }

    /// The transform set last (world from mesh; the identity at first).
    pub fn transform(&self) -> Affine3A {
        self.world_from_mesh
    }

    /// The grid spacing (metres).
    pub fn cell(&self) -> f32 {
        self.grid.cell
    }

    /// The grid's box in the mesh frame, `(min, max)`: the first and last
    /// nodes' positions.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let g = &self.grid;
        (g.origin, g.origin + g.max_u * g.cell)
    }

    /// Nodes per axis.
    pub fn dims(&self) -> UVec3 {
        self.grid.dims
    }

    /// Stored nodes (values), at most [`MAX_SDF_CELLS`]: `dims.x * dims.y * dims.z`.
    pub fn node_count(&self) -> usize {
        self.grid.node_count()
    }

    /// The stored value at node `(x, y, z)` (mesh frame position
    /// `min + (x, y, z) * cell`), None outside the grid.
    pub fn node_value(&self, x: u32, y: u32, z: u32) -> Option<f32> {
        let d = self.grid.dims;
        (x < d.x && y < d.y && z < d.z)
            .then(|| self.grid.values[((z * d.y + y) * d.x + x) as usize])
    }
}

//! Hair draped under gravity: grown strands (which leave the scalp
//! straight out, `coif_geometry::grow`) run a number of fixed steps of the
//! default strand simulation (`coif_kernels::step`) against a collision
//! rig, so that a scene does not start with hair sticking out.
//!
//! This is where the built-in scenes that need simulation live, so that
//! `coif-geometry` stays pure geometry.

use super::Error;
use coif_geometry::grow::Growth;
use coif_geometry::scalp::ScalpMesh;
use coif_geometry::scene::{grow_on_sphere, GrowOptions};
use coif_kernels::{self as kernels, SimParams, Sphere, Strands};
use glam::Vec3;

/// `steps` default simulation steps ([`SimParams::default`]) of the strands
/// `points` (`verts_per_strand` points each, root first, roots pinned)
/// against `rig`. Returns the draped points in the same order. Errors where
/// [`Strands::from_polylines`] does.
pub fn drape(
    points: &[Vec3],
    verts_per_strand: usize,
    rig: &[Sphere],
    steps: usize,
) -> Result<Vec<Vec3>, kernels::Error> {
    let mut strands = Strands::from_polylines(points, verts_per_strand)?;
    let params = SimParams::default();
    for _ in 0..steps {
        kernels::step(&mut strands, &params, rig);
    }
    Ok(strands.positions())
}

/// Hair grown on the default sphere head (`grow_on_sphere`, curl 0.3) and
/// draped under gravity for `steps` steps against the head: the draped
/// head the shadow-map tests, bench, report and profiling harness measure
/// on. Returns the world positions and the vertices per strand.
pub fn draped_on_sphere(strands: usize, verts: usize, steps: usize) -> (Vec<Vec3>, usize) {
    let scene = grow_on_sphere(&GrowOptions {
        strand_count: strands,
        verts_per_strand: verts,
        curl: 0.3,
        ..Default::default()
    });
    let draped = drape(
        &scene.points,
        scene.verts_per_strand,
        std::slice::from_ref(&scene.head),
        steps,
    )
    .expect("grown hair is valid");
    (draped, scene.verts_per_strand)
}

/// Guides grown from every vertex of a scalp mesh
/// ([`ScalpMesh::grow_guides`]) and draped for `steps` steps against
/// `head`. Guide i grows from mesh vertex i, so the mesh's triangles are
/// the guides' interpolation triangles.
pub fn draped_on_scalp(
    mesh: &ScalpMesh,
    growth: &Growth,
    head: &[Sphere],
    steps: usize,
) -> Result<Vec<Vec3>, Error> {
    let grown = mesh.grow_guides(growth)?;
    Ok(drape(&grown, growth.verts_per_strand, head, steps)?)
}

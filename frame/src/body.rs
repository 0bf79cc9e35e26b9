//! A character's body under the hair: its triangle mesh, drawn as shaded
//! opaque triangles, and the mesh's signed distance field, which the
//! guides collide with (`coif_kernels::step_colliders`).
//!
//! The body moves rigidly with the head pose (a bust on the head's bone):
//! per fixed step the field gets the pose as its transform
//! (`Sdf::set_transform`); per rendered frame the vertices and normals are
//! posed, shaded and rasterised.
//!
//! **Shading** (per vertex, Gouraud-interpolated by the triangle filler),
//! the head spheres' model plus a weak highlight, so skin and hair are lit
//! by the same light and ambient:
//!
//! ```text
//! L = albedo (ambient + E max(n.l, 0) V) + k_s E max(n.h, 0)^s V,
//! h = normalize(l + v),   V = T_shadow(p) [the ray to the light misses the occluders]
//! ```
//!
//! with `T_shadow` the hair's deep opacity map (skin under hair is darker)
//! and the occluders the spheres inscribed in the body (the head's,
//! [`Body::inscribed_sphere`]): the head shades the far shoulder. The mesh
//! does not shadow itself otherwise (no shadow map of the body).
//!
//! **Order**: drawn after the background (`Stage::Head`) with the depth
//! test, writing its depth (`coif_render::triangle`), so the hair blended
//! next is hidden behind the body and blends over it in front.

use super::shadow::ShadowStage;
use super::{Error, Light, SKIN_ALBEDO};
use coif_base::tasks::{for_each_chunk_mut, Executor};
use coif_geometry::mesh::TriangleMesh;
use coif_kernels::{Sdf, Sphere};
use coif_render::hair::NEAR;
use coif_render::head::occluded;
use coif_render::triangle::TriangleVertex;
use coif_render::triangle_bins::TriangleBins;
use coif_render::{Camera, Framebuffer};
use glam::{Affine3A, Vec3};
use std::fmt;

/// Cell of a body's distance field (metres): 4 mm, where the bust's field
/// meets its accuracy goals (median error 0.5 mm within 2 cm of the
/// surface; `kernels/SDF.md`) and builds in about 0.1 s.
pub const BODY_FIELD_CELL: f32 = 0.004;
/// Strength `k_s` and exponent `s` of the skin's highlight.
pub const SKIN_SPECULAR: (f32, f32) = (0.06, 24.0);
/// Albedo of the eyeballs (linear RGB): the whites of the eyes.
pub const SCLERA_ALBEDO: Vec3 = Vec3::new(0.62, 0.6, 0.58);
/// Albedo of the irises (linear RGB): dark green, pupil and iris as one
/// disc at a portrait's distance (Sintel's eyes are green).
pub const IRIS_ALBEDO: Vec3 = Vec3::new(0.03, 0.06, 0.04);

/// A character's body: its mesh (drawn) and the mesh's signed distance
/// field (collided with), at rest, in world metres.
#[derive(Clone)]
pub struct Body {
    mesh: TriangleMesh,
    field: Sdf,
    eyes: Vec<Sphere>,
    irises: Vec<Sphere>,
}

impl fmt::Debug for Body {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Body")
            .field("vertices", &self.mesh.positions().len())
            .field("triangles", &self.mesh.triangles().len())
            .field("field", &self.field)
            .finish()
    }
}

impl Body {
    /// The body of `mesh` (world metres, at rest), with its field at
    /// `cell` metres ([`BODY_FIELD_CELL`] for a bust).
    ///
    /// # Errors
    /// [`Error::Simulation`] when the field cannot be built (a bad cell,
    /// a grid over `coif_kernels::MAX_SDF_CELLS`).
    pub fn new(mesh: TriangleMesh, cell: f32) -> Result<Body, Error> {
        let field = Sdf::from_mesh(mesh.positions(), mesh.triangles(), cell)?;
        Ok(Body {
            mesh,
            field,
            eyes: Vec::new(),
            irises: Vec::new(),
        })
    }

    /// The body with eyeballs in the eye openings of its mesh, for a head
    /// about `head` (a sphere inside it) that faces +z. An eye opening is
    /// a hole of the mesh ([`TriangleMesh::boundary_loops`]) of mean radius
    /// `r` between 5 mm and 3 cm whose centre `c` lies in front of the head
    /// (`n = normalize(c - head.center)`, `n.z > 0.5`) and not low on the
    /// face (`n.y > -0.6`: not the mouth); its eyeball is the sphere of
    /// radius `1.3 r` centred `r` behind the opening along `n`, which
    /// fills 83 % of the opening's radius and bulges `0.3 r` out of it,
    /// and its iris the sphere of radius `0.45 r` whose front lies `0.08 r`
    /// before the eyeball's, looking straight ahead (+z). They are drawn
    /// (ray-cast, [`SCLERA_ALBEDO`], then [`IRIS_ALBEDO`] over it) and pose
    /// with the body; they do not collide. Meshes without such holes get
    /// none.
    pub fn with_eyes(mut self, head: &Sphere) -> Body {
        let positions = self.mesh.positions();
        let (mut eyes, mut irises) = (Vec::new(), Vec::new());
        for members in self.mesh.boundary_loops() {
            let points = members.iter().map(|&v| positions[v as usize]);
            let c = points.clone().sum::<Vec3>() / members.len() as f32;
            let r = points.map(|p| p.distance(c)).sum::<f32>() / members.len() as f32;
            let Some(n) = (c - head.center).try_normalize() else {
                continue;
            };
            if (0.005..0.03).contains(&r) && n.z > 0.5 && n.y > -0.6 {
                let eye = Sphere {
                    center: c - n * r,
                    radius: 1.3 * r,
                };
                let front = eye.center + Vec3::Z * eye.radius;
                irises.push(Sphere {
                    center: front + Vec3::Z * (0.08 * r - 0.45 * r),
                    radius: 0.45 * r,
                });
                eyes.push(eye);
            }
        }
        self.eyes = eyes;
        self.irises = irises;
        self
    }

    /// The eyeballs of [`Body::with_eyes`] at rest (none by default).
    pub fn eyes(&self) -> &[Sphere] {
        &self.eyes
    }

    /// The irises of [`Body::with_eyes`] at rest, one per eyeball.
    pub fn irises(&self) -> &[Sphere] {
        &self.irises
    }

    /// The mesh at rest.
    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    /// The mesh's signed distance field at rest (identity transform).
    pub fn field(&self) -> &Sdf {
        &self.field
    }

    /// The largest sphere about `center` inside the body: radius the
    /// field's depth there (`-distance`), None when `center` is not inside
    /// by more than a millimetre. Spheres inside the mesh stand for it
    /// where spheres are cheap: the hair's light occlusion and the
    /// rasteriser's occlusion culling (both stay conservative: a sphere
    /// inside the body hides only what the body hides).
    pub fn inscribed_sphere(&self, center: Vec3) -> Option<Sphere> {
        let depth = -self.field.distance(center);
        (depth > 1e-3).then_some(Sphere {
            center,
            radius: depth,
        })
    }
}

/// Colour of a skin point `p` with unit normal `n` (toward the eye), seen from
/// `eye`, lit by `light` with visibility `visible` in [0, 1]: the module
/// doc's Lambert plus a weak Blinn-Phong highlight. A point whose normal
/// faces away from the light gets the ambient term only. Non-finite input
/// or output gives the ambient colour.
pub fn shade_skin(p: Vec3, n: Vec3, eye: Vec3, light: &Light, visible: f32) -> Vec3 {
    let ambient = SKIN_ALBEDO * light.ambient;
    if !(p.is_finite() && n.is_finite() && eye.is_finite()) {
        return ambient;
    }
    let l = light.to_light;
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return ambient;
    }
    let direct = light.irradiance * visible.clamp(0.0, 1.0);
    let v = (eye - p).normalize_or_zero();
    let h = (l + v).normalize_or_zero();
    let (k_s, exponent) = SKIN_SPECULAR;
    let c = ambient
        + SKIN_ALBEDO * direct * n_dot_l
        + direct * (k_s * n.dot(h).max(0.0).powf(exponent));
    if c.is_finite() {
        c
    } else {
        ambient
    }
}

/// The body in a frame pipeline: the posed field the guides collide
/// with, and the per-frame buffers of its drawing (sized once).
pub(crate) struct BodyStage {
    rest: Vec<Vec3>,
    rest_normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    field: Sdf,
    rest_eyes: Vec<Sphere>,
    /// The eyeballs then the irises posed in render space, and the
    /// vertices' projections (with their colours) of the last frame.
    eyes: Vec<Sphere>,
    projected: Vec<Option<TriangleVertex>>,
    /// The triangles' tile lists, for the pipeline's frame size.
    bins: TriangleBins,
}

impl BodyStage {
    /// The stage of `body` drawn into `width x height` frames.
    pub(crate) fn new(body: &Body, width: usize, height: usize) -> BodyStage {
        let n = body.mesh.positions().len();
        BodyStage {
            rest: body.mesh.positions().to_vec(),
            rest_normals: body.mesh.normals().to_vec(),
            triangles: body.mesh.triangles().to_vec(),
            field: body.field.clone(),
            rest_eyes: [body.eyes.clone(), body.irises.clone()].concat(),
            eyes: [body.eyes.clone(), body.irises.clone()].concat(),
            projected: vec![None; n],
            bins: TriangleBins::new(width, height, body.mesh.triangles().len()),
        }
    }

    /// Places the field at the rigid head pose `pose` (checked finite by
    /// the caller; a refused pose keeps the previous transform).
    pub(crate) fn place(&mut self, pose: &Affine3A) {
        let _ = self.field.set_transform(*pose);
    }

    /// The field as placed by the last [`BodyStage::place`].
    pub(crate) fn field(&self) -> &Sdf {
        &self.field
    }

    /// Poses, shades and projects every vertex: positions relative to
    /// `origin` (render space), seen from `camera` (render space), lit by
    /// `light`, shadowed by the hair's `shadow` map and the `occluders`
    /// (render space). Runs of [`SHADE_CHUNK`] vertices are tasks on
    /// `executor` (each vertex depends on itself alone: the same bytes
    /// with any executor).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn shade(
        &mut self,
        pose: &Affine3A,
        origin: Vec3,
        camera: &Camera,
        light: &Light,
        occluders: &[Sphere],
        shadow: &ShadowStage,
        executor: &dyn Executor,
    ) {
        let eye = camera.eye();
        let l = light.to_light;
        for (dst, s) in self.eyes.iter_mut().zip(&self.rest_eyes) {
            dst.center = pose.transform_point3(s.center) - origin;
        }
        let (rest, rest_normals) = (&self.rest, &self.rest_normals);
        for_each_chunk_mut(executor, &mut self.projected, SHADE_CHUNK, &|c, out| {
            for (j, dst) in out.iter_mut().enumerate() {
                let k = c * SHADE_CHUNK + j;
                let p = pose.transform_point3(rest[k]) - origin;
                // Two-sided: where the mesh is open (a bust's cut arms), its
                // inside shows, lit as the side facing the eye.
                let n = pose.transform_vector3(rest_normals[k]);
                let n = if n.dot(eye - p) < 0.0 { -n } else { n };
                let visible = if n.dot(l) > 0.0 && !occluded(p, l, occluders, 1e-3) {
                    shadow.transmittance_at(p)
                } else {
                    0.0
                };
                let color = shade_skin(p, n, eye, light, visible);
                *dst = camera.project(p, NEAR).map(|s| TriangleVertex {
                    x: s.x,
                    y: s.y,
                    depth: s.z,
                    color,
                });
            }
        });
    }

    /// The eyeballs and the irises posed by the last [`BodyStage::shade`]
    /// (render space).
    pub(crate) fn eyes(&self) -> (&[Sphere], &[Sphere]) {
        self.eyes.split_at(self.eyes.len() / 2)
    }

    /// Draws the triangles of the last [`BodyStage::shade`], opaque and
    /// depth-tested (a triangle with a corner behind the near plane is
    /// skipped), binned into the hair raster's tiles and filled as tasks
    /// on `executor` ([`TriangleBins`]: the same bytes as one pass in mesh
    /// order); returns the pixels written.
    pub(crate) fn draw(&mut self, frame: &mut Framebuffer, executor: &dyn Executor) -> usize {
        (self.bins).draw(frame, &self.projected, &self.triangles, executor)
    }
}

/// Vertices per task of [`BodyStage::shade`]: Sintel's bust (3,046
/// vertices) is six tasks, each about 0.1 ms.
const SHADE_CHUNK: usize = 512;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skin_is_lit_facing_the_light_and_ambient_away_or_in_shadow() {
        let light = Light {
            to_light: Vec3::Z,
            irradiance: Vec3::ONE,
            ambient: Vec3::splat(0.1),
        };
        let ambient = SKIN_ALBEDO * light.ambient;
        let eye = Vec3::Z * 2.0;
        let lit = shade_skin(Vec3::ZERO, Vec3::Z, eye, &light, 1.0);
        // Head-on: Lambert 1 plus the whole highlight.
        let expected = SKIN_ALBEDO * 1.1 + Vec3::splat(SKIN_SPECULAR.0);
        assert!((lit - expected).length() < 1e-5, "{lit} vs {expected}");
        assert_eq!(shade_skin(Vec3::ZERO, -Vec3::Z, eye, &light, 1.0), ambient);
        assert_eq!(shade_skin(Vec3::ZERO, Vec3::Z, eye, &light, 0.0), ambient);
        let half = shade_skin(Vec3::ZERO, Vec3::Z, eye, &light, 0.5);
        assert!(half.x > ambient.x && half.x < lit.x);
        // Grazing light is dimmer than head-on.
        let side = shade_skin(Vec3::ZERO, Vec3::new(0.8, 0.0, 0.6), eye, &light, 1.0);
        assert!(side.x < lit.x && side.x > ambient.x);
        assert_eq!(shade_skin(Vec3::NAN, Vec3::Z, eye, &light, 1.0), ambient);
        assert_eq!(
            shade_skin(Vec3::ZERO, Vec3::Z, Vec3::NAN, &light, 1.0),
            ambient
        );
    }

    #[test]
    fn the_inscribed_sphere_is_inside_the_body() {
        // A closed box 20 cm on a side.
        let c = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.2, 0.0, 0.0),
            Vec3::new(0.2, 0.2, 0.0),
            Vec3::new(0.0, 0.2, 0.0),
            Vec3::new(0.0, 0.0, 0.2),
            Vec3::new(0.2, 0.0, 0.2),
            Vec3::new(0.2, 0.2, 0.2),
            Vec3::new(0.0, 0.2, 0.2),
        ];
        let quads = [
            [0, 3, 2, 1],
            [4, 5, 6, 7],
            [0, 1, 5, 4],
            [3, 7, 6, 2],
            [0, 4, 7, 3],
            [1, 2, 6, 5],
        ];
        let tris: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let mesh = TriangleMesh::new(c.to_vec(), tris).unwrap();
        let body = Body::new(mesh, 0.01).unwrap();
        let s = body.inscribed_sphere(Vec3::splat(0.1)).unwrap();
        assert!((s.radius - 0.1).abs() < 2e-3, "{}", s.radius);
        let off = body.inscribed_sphere(Vec3::new(0.05, 0.1, 0.1)).unwrap();
        assert!((off.radius - 0.05).abs() < 2e-3, "{}", off.radius);
        assert!(body.inscribed_sphere(Vec3::splat(0.5)).is_none());
        assert!(body.inscribed_sphere(Vec3::NAN).is_none());
        assert!(Body::new(body.mesh().clone(), 0.0).is_err());
    }
}

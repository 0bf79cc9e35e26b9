//! What a frame pipeline draws: guide strands at rest, their scalp
//! triangles, the collision rig, the head or body drawn under the hair and
//! the ribbons tied to it.

use super::body::{Body, BODY_FIELD_CELL};
use super::ribbon::bow_tails;
use super::Error;
use coif_geometry::groom::{self, Groom};
use coif_geometry::mesh::TriangleMesh;
use coif_geometry::scene::{self, GrowOptions};
use coif_geometry::triangulate::scalp_triangles;
use coif_kernels::patch::Ribbon;
use coif_kernels::Sphere;
use glam::Vec3;

/// Guides, triangles and rig of one groom, in metres, world space, at rest
/// (head pose = identity).
#[derive(Clone, Debug)]
pub struct HairScene {
    /// `guide_count * verts_per_strand` points, strand after strand, root first.
    pub guides: Vec<Vec3>,
    /// Points per guide.
    pub verts_per_strand: usize,
    /// Scalp triangles (indices of guides) that render hairs are
    /// interpolated over.
    pub triangles: Vec<[u32; 3]>,
    /// Collision spheres at rest; they follow the head.
    pub rig: Vec<Sphere>,
    /// The spheres drawn as the head (also shadow casters for the hair);
    /// with a [`HairScene::body`], spheres inscribed in it instead, not
    /// drawn: they cast the head's shadow on the hair and cull the hair
    /// hidden behind it.
    pub head: Vec<Sphere>,
    /// A character's body (mesh drawn under the hair, its field collided
    /// with), posed with the head; None for the sphere heads.
    pub body: Option<Body>,
    /// The point the head turns about (the top of the neck).
    pub pivot: Vec3,
    /// Centre of a sphere around the hair at rest, for framing.
    pub focus: Vec3,
    /// Radius of that sphere.
    pub extent: f32,
    /// Where a camera looks from (direction from the hair toward the eye).
    pub view_direction: Vec3,
    /// Ribbons tied to the head (rest grids, world space at rest, row 0
    /// attached), simulated as cloth patches rigidly skinned to the head;
    /// empty for none ([`HairScene::without_ribbons`]).
    pub ribbons: Vec<Ribbon>,
}

/// Where the built-in head's ribbons are tied (direction from its centre):
/// the upper left of the back, seen by the default camera.
pub const PROCEDURAL_RIBBON_ATTACH: Vec3 = Vec3::new(-0.85, 0.4, 0.1);
/// Where a loaded groom's ribbons are tied: the back of the head (grooms
/// face +z), toward the side camera.
pub const GROOM_RIBBON_ATTACH: Vec3 = Vec3::new(-0.6, 0.5, -0.6);

/// Sintel's groom and bust (`assets/sintel`, CC BY 3.0, Blender
/// Foundation), compiled in: the default scene needs no file beside the
/// program.
const SINTEL_GROOM: &[u8] = include_bytes!("../../assets/sintel/sintel_lite.tfx");
const SINTEL_BUST: &[u8] = include_bytes!("../../assets/sintel/sintel_bust.obj");

impl HairScene {
    /// The built-in head: `options` grows guides on a sphere
    /// ([`scene::grow_on_sphere`]); the rig is the head and a neck
    /// ([`scene::body_rig`]); triangles come from the roots' directions.
    /// Strands rooted on the face (the front of the sphere below a
    /// hairline, facing +z) are left out, so the head shows a face, and
    /// every strand is combed back (`comb_back`: turned about its root toward the back of the head) before the simulation
    /// drapes it. A bow's two silk tails ([`bow_tails`]) hang from the
    /// upper left of the back of the head, the side the default camera sees.
    pub fn procedural(options: &GrowOptions) -> Result<HairScene, Error> {
        options
            .validate()
            .map_err(coif_geometry::scalp::ScalpError::from)?;
        let grown = scene::grow_on_sphere(options);
        let rig = scene::body_rig(&grown.head, 2);
        let head = grown.head.clone();
        let verts = grown.verts_per_strand;
        let points: Vec<Vec3> = grown
            .points
            .chunks_exact(verts)
            .filter(|s| !on_face((s[0] - head.center) / head.radius))
            .flat_map(|s| comb_back(s, head.center))
            .collect();
        let mut scene = HairScene::assemble(
            points,
            verts,
            rig.clone(),
            rig,
            head.center - Vec3::Y * (1.1 * head.radius),
            head.center,
        )?;
        scene.ribbons = bow_tails(&head, PROCEDURAL_RIBBON_ATTACH);
        Ok(scene)
    }

    /// Sintel: her groom's 228 guides (32 points each) on her bust, the
    /// project's default character (`assets/sintel`, "Sintel (c) Blender
    /// Foundation | durian.blender.org, CC BY 3.0"), from the copies
    /// compiled into this crate ([`HairScene::on_mesh`]).
    ///
    /// # Errors
    /// None in practice (the files are the shipped ones); the scene's
    /// checks as [`HairScene::on_mesh`].
    pub fn sintel() -> Result<HairScene, Error> {
        HairScene::from_files(SINTEL_GROOM, SINTEL_BUST, 0.01, usize::MAX, 32)
    }

    /// Sintel's bust alone (the compiled-in copy, metres): for another
    /// groom on it ([`HairScene::on_mesh`]).
    ///
    /// # Errors
    /// None in practice (the shipped file); [`Error::Mesh`] otherwise.
    pub fn sintel_bust() -> Result<TriangleMesh, Error> {
        Ok(TriangleMesh::from_obj(SINTEL_BUST, 0.01)?)
    }

    /// A groom file's bytes (`.tfx` or `.hair`, centimetres) on the body
    /// mesh of an OBJ file's text, read at `mesh_scale` (0.01 for a mesh
    /// in centimetres): [`HairScene::on_mesh`] of the parsed pair.
    ///
    /// # Errors
    /// [`Error::Groom`] and [`Error::Mesh`] for files that cannot be read,
    /// then [`HairScene::on_mesh`]'s.
    pub fn from_files(
        groom_bytes: &[u8],
        obj_text: &[u8],
        mesh_scale: f32,
        max_guides: usize,
        verts_per_strand: usize,
    ) -> Result<HairScene, Error> {
        let groom = groom::load(groom_bytes)?;
        let mesh = TriangleMesh::from_obj(obj_text, mesh_scale)?;
        HairScene::on_mesh(&groom, mesh, max_guides, verts_per_strand)
    }

    /// A loaded groom (centimetres, as [`HairScene::from_groom`]) on the
    /// body `mesh` it was made for (metres, the same frame): the guides
    /// collide with the mesh's field ([`Body`], 4 mm cells) and no sphere;
    /// the body is drawn instead of a head sphere. Scalp triangles are the
    /// root directions from the centre of the sphere fitted to the roots;
    /// the sphere inscribed in the body about that centre stands for the
    /// head in the hair's light occlusion and occlusion culling; the head
    /// turns about a point below it (the top of the neck). Seen from the
    /// front left. No ribbons.
    ///
    /// # Errors
    /// [`Error::Scene`] when no sphere fits the roots, the fitted centre is
    /// not inside the body, or the roots make no scalp triangle;
    /// [`Error::Simulation`] when the field cannot be built.
    pub fn on_mesh(
        groom: &Groom,
        mesh: TriangleMesh,
        max_guides: usize,
        verts_per_strand: usize,
    ) -> Result<HairScene, Error> {
        let verts = verts_per_strand.max(2);
        let guides = groom_guides(groom, max_guides, verts)?;
        let roots: Vec<Vec3> = guides.iter().step_by(verts).copied().collect();
        let fitted =
            scene::fit_sphere(&roots).ok_or(Error::Scene("cannot fit a sphere to the roots"))?;
        let body = Body::new(mesh, BODY_FIELD_CELL)?;
        let head = body.inscribed_sphere(fitted.center).ok_or(Error::Scene(
            "the centre of the sphere fitted to the roots is not inside the body mesh",
        ))?;
        let pivot = head.center - Vec3::Y * (1.1 * head.radius);
        let mut scene = HairScene::assemble(
            guides,
            verts,
            Vec::new(),
            vec![head.clone()],
            pivot,
            fitted.center,
        )?;
        // Frame the body with the hair.
        let (mut lo, mut hi) = body.mesh().bounds();
        for p in &scene.guides {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        scene.focus = 0.5 * (lo + hi);
        scene.extent = 0.5 * (hi - lo).length();
        scene.body = Some(body.with_eyes(&head));
        Ok(scene)
    }

    /// The same scene without ribbons (`--no-ribbon`).
    pub fn without_ribbons(mut self) -> HairScene {
        self.ribbons.clear();
        self
    }

    /// A loaded groom in centimetres (TressFX's and cyHair's usual unit):
    /// scaled by 0.01 to metres; at most `max_guides` strands are kept as
    /// guides (every k-th strand); each is resampled to `verts_per_strand`
    /// points evenly spaced in arc length (authored strands may differ in
    /// vertex count). The rig is [`scene::scalp_spheres`] under the roots;
    /// the drawn head is the sphere fitted to the roots
    /// ([`scene::fit_sphere`]), shrunk so no root is inside it; triangles
    /// are the root directions from its centre, without long edges. A bow's
    /// two tails hang from the back of the drawn head (or of the sphere
    /// around the scalp spheres), on the side the camera sees.
    pub fn from_groom(
        groom: &Groom,
        max_guides: usize,
        verts_per_strand: usize,
    ) -> Result<HairScene, Error> {
        let verts = verts_per_strand.max(2);
        let guides = groom_guides(groom, max_guides, verts)?;
        let roots: Vec<Vec3> = guides.iter().step_by(verts).copied().collect();
        let rig = GroomRig::new(&guides, &roots, verts)?;
        let mut scene = HairScene::assemble(
            guides,
            verts,
            rig.rig,
            rig.head,
            rig.anchor.center - Vec3::Y * (1.1 * rig.anchor.radius),
            rig.fitted_center,
        )?;
        // From the side, a little above and behind: authored grooms face +z
        // and their hair falls back and down, behind the head from the front.
        scene.view_direction = Vec3::new(-1.0, 0.3, -0.35).normalize();
        scene.ribbons = bow_tails(&rig.anchor, GROOM_RIBBON_ATTACH);
        Ok(scene)
    }

    /// The scene of `guides` over `rig`, drawing `head`: scalp triangles
    /// from the roots' directions seen from `center` (without edges longer
    /// than `MAX_EDGE_IN_MEDIANS` median edges), framing from the bounds.
    fn assemble(
        guides: Vec<Vec3>,
        verts: usize,
        rig: Vec<Sphere>,
        head: Vec<Sphere>,
        pivot: Vec3,
        center: Vec3,
    ) -> Result<HairScene, Error> {
        let roots: Vec<Vec3> = guides.iter().step_by(verts).copied().collect();
        let triangles = scalp_triangles(&roots, center);
        if triangles.is_empty() {
            return Err(Error::Scene("the guide roots make no scalp triangle"));
        }
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in guides.iter().chain(head.iter().map(|s| &s.center)) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let focus = 0.5 * (lo + hi);
        let extent = 0.5 * (hi - lo).length();
        Ok(HairScene {
            guides,
            verts_per_strand: verts,
            triangles,
            rig,
            head,
            pivot,
            focus,
            extent,
            view_direction: Vec3::new(-0.45, 0.15, 1.0).normalize(),
            ribbons: Vec::new(),
            body: None,
        })
    }

    /// Number of guide strands.
    pub fn guide_count(&self) -> usize {
        self.guides.len() / self.verts_per_strand
    }

    /// The guides' roots.
    pub fn roots(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.guides.iter().step_by(self.verts_per_strand).copied()
    }
}

/// Whether unit direction `n` from the head's centre is on the face: in
/// front (+z) and below a hairline that rises toward the temples.
pub fn on_face(n: Vec3) -> bool {
    n.z > 0.25 && n.y < 0.3 - 0.3 * n.x.abs()
}

/// Turns a strand rigidly about its root so that it leaves the scalp
/// toward the back of the head, `normalize(n + (0, -0.3, -1.2))` for root
/// normal `n` instead of along `n`: hair combed back off the face.
pub fn comb_back(strand: &[Vec3], center: Vec3) -> impl Iterator<Item = Vec3> + '_ {
    let root = strand[0];
    let n = (root - center).normalize_or(Vec3::Y);
    let d = (n + Vec3::new(0.0, -0.3, -1.2)).normalize_or(n);
    let turn = glam::Quat::from_rotation_arc(n, d);
    strand.iter().map(move |p| root + turn * (*p - root))
}

/// Every k-th strand of `groom` (at most `max_guides`), scaled from
/// centimetres to metres and resampled to `verts` points evenly spaced in
/// arc length; strands of fewer than two points are skipped.
fn groom_guides(groom: &Groom, max_guides: usize, verts: usize) -> Result<Vec<Vec3>, Error> {
    let stride = groom.strand_count().div_ceil(max_guides.max(1)).max(1);
    groom.guides(stride, verts, 0.01).map_err(|e| match e {
        groom::Error::BadResample(_) => {
            Error::Scene("the groom has no strand with two or more points")
        }
        e => Error::Groom(e),
    })
}

/// The head and collision rig of a loaded groom, made from its roots.
struct GroomRig {
    /// The drawn head: one sphere for a scalp, the scalp spheres otherwise.
    head: Vec<Sphere>,
    /// Collision spheres: the head, plus the scalp spheres under a one-sphere head.
    rig: Vec<Sphere>,
    /// The sphere the pivot hangs below and the ribbons are tied to.
    anchor: Sphere,
    /// Centre of the sphere fitted to the roots (the triangulation's eye).
    fitted_center: Vec3,
}

impl GroomRig {
    /// The sphere fitted to the roots ([`scene::fit_sphere`]) is the head
    /// when the roots lie on it (RMS distance under a tenth of its radius,
    /// radius under 3/4 of the roots' bounding diagonal), shrunk so that no
    /// root is inside it; otherwise (a mohawk's strip of roots) the twelve
    /// [`scene::scalp_spheres`] under the roots are.
    fn new(guides: &[Vec3], roots: &[Vec3], verts: usize) -> Result<GroomRig, Error> {
        let fitted =
            scene::fit_sphere(roots).ok_or(Error::Scene("cannot fit a sphere to the roots"))?;
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for r in roots {
            lo = lo.min(*r);
            hi = hi.max(*r);
        }
        let diagonal = (hi - lo).length();
        // RMS distance of the roots from the fitted sphere's surface.
        let residual = (roots
            .iter()
            .map(|r| (r.distance(fitted.center) - fitted.radius).powi(2))
            .sum::<f32>()
            / roots.len() as f32)
            .sqrt();
        let scalp_radius = 0.15 * diagonal;
        let scalp = scene::scalp_spheres(guides, verts, 12, scalp_radius);
        let head = if residual < 0.1 * fitted.radius && fitted.radius < 0.75 * diagonal {
            // A scalp: the fitted sphere, shrunk so that no root is inside it.
            let nearest = roots
                .iter()
                .map(|r| r.distance(fitted.center))
                .fold(f32::INFINITY, f32::min);
            vec![Sphere {
                center: fitted.center,
                radius: (0.97 * nearest).min(fitted.radius),
            }]
        } else {
            // Not a sphere (a mohawk's strip of roots): the scalp spheres.
            scalp.clone()
        };
        let mut rig = head.clone();
        if head.len() == 1 {
            rig.extend(scalp);
        }
        let anchor = if head.len() == 1 {
            head[0].clone()
        } else {
            Sphere {
                center: head.iter().map(|s| s.center).sum::<Vec3>() / head.len() as f32,
                radius: scalp_radius,
            }
        };
        Ok(GroomRig {
            head,
            rig,
            anchor,
            fitted_center: fitted.center,
        })
    }
}

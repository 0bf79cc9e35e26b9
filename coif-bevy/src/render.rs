//! Render hairs into a dynamic mesh each frame: refinement, interpolation,
//! camera-facing ribbons or line strips with tangents; the render hair
//! count from the hair's size on screen.

use crate::components::{Hair, HairPrimitive};
use crate::sim::{vec3_of, HairState};
use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
use bevy::prelude::*;
use coif::geometry::{scene::fit_sphere, triangulate::scalp_triangles};
use coif::glam as cg;
use coif::kernels::Strands;
use coif::lod::{self, level, HairWidth, Interpolation, RefinedGuides, RenderHairs, RenderVertex};
use std::time::Instant;

/// On the entity holding a hair's mesh (a root entity at the identity: the
/// mesh is in world space): the hair entity it draws.
#[derive(Component, Clone, Copy, Debug)]
pub struct HairMeshOf(pub Entity);

/// The active camera as the LOD sees it.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Eye position, world.
    pub eye: cg::Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Viewport height, logical pixels (720 without a render target).
    pub height: f32,
}

impl View {
    /// Pixels per metre at `p`.
    pub fn pixels_per_metre(&self, p: cg::Vec3) -> f32 {
        level::pixels_per_metre(self.eye.distance(p).max(1e-3), self.fov_y, self.height)
    }

    /// Height on screen in pixels of something `extent` metres across at `p`.
    pub fn height_px(&self, p: cg::Vec3, extent: f32) -> f32 {
        self.pixels_per_metre(p) * extent
    }
}

/// The first active camera (lowest `order`), if any.
pub fn active_view(
    cameras: &Query<(&Camera, &GlobalTransform, Option<&Projection>)>,
) -> Option<View> {
    let (camera, global, projection) = cameras
        .iter()
        .filter(|(c, _, _)| c.is_active)
        .min_by_key(|(c, _, _)| c.order)?;
    let fov_y = match projection {
        Some(Projection::Perspective(p)) => p.fov,
        _ => std::f32::consts::FRAC_PI_4,
    };
    let height = camera
        .logical_viewport_size()
        .map(|s| s.y)
        .filter(|h| *h > 0.0)
        .unwrap_or(720.0);
    Some(View {
        eye: vec3_of(global.translation()),
        fov_y,
        height,
    })
}

/// The render hairs of `hair` over the scalp of its guides' roots (the
/// guides' points, `verts` per guide): a sphere fitted to the roots, their
/// triangulation seen from its centre, `density_per_cm2` hairs placed with
/// `seed`. Both draw paths place the same hairs.
pub fn interpolation_of(
    hair: &Hair,
    guides: &[cg::Vec3],
    verts: usize,
) -> Result<Interpolation, String> {
    let roots: Vec<cg::Vec3> = guides.iter().step_by(verts.max(1)).copied().collect();
    let head = fit_sphere(&roots).ok_or("no sphere fits the roots")?;
    let scalp = scalp_triangles(&roots, head.center);
    Interpolation::new(
        &roots,
        &scalp,
        hair.render.density_per_cm2,
        hair.render.seed,
    )
    .map_err(|e| e.to_string())
}

/// Segments per span and render-hair groups for `hair` seen from `view`
/// (2,000 pixels per metre without one): the refinement level from the
/// guides' curvature and `error_px`, the groups from its size on screen.
/// Both draw paths choose alike.
pub fn choose_level(
    hair: &Hair,
    strands: &Strands,
    interp: &Interpolation,
    center: cg::Vec3,
    extent: f32,
    view: Option<View>,
) -> (usize, usize) {
    let r = &hair.render;
    let px_per_m = view.map(|v| v.pixels_per_metre(center)).unwrap_or(2000.0);
    let segments = level::segments_per_span(
        level::max_second_difference_strands(strands.blocks()),
        px_per_m,
        r.error_px,
        r.max_segments.max(1),
    )
    .clamp(1, r.max_segments.max(1));
    let share =
        (px_per_m * extent / r.full_detail_px.max(1.0)).clamp(r.min_share.clamp(0.0, 1.0), 1.0);
    let groups_all = interp.group_count();
    let groups = ((groups_all as f32 * share).ceil() as usize).clamp(1.min(groups_all), groups_all);
    (segments, groups)
}

/// Per-hair LOD buffers, sized once.
pub struct RenderState {
    interp: Interpolation,
    refined: RefinedGuides,
    hairs: RenderHairs,
    vertices: Vec<RenderVertex>,
    /// (primitive, vertices drawn, vertices per hair) the indices are for.
    indexed: (HairPrimitive, usize, usize),
    pub(crate) mesh: Option<(Handle<Mesh>, Entity)>,
}

impl RenderState {
    /// Interpolation over the rest roots' scalp, refinement buffers.
    pub fn new(
        hair: &Hair,
        guides: &[cg::Vec3],
        verts: usize,
        strands: &Strands,
    ) -> Result<RenderState, String> {
        let interp = interpolation_of(hair, guides, verts)?;
        let refined = RefinedGuides::new(strands.blocks(), hair.render.max_segments.max(1))
            .map_err(|e| e.to_string())?;
        let hairs = RenderHairs::new(&interp, &refined);
        let capacity =
            interp.hair_count() * lod::refined_len(verts, hair.render.max_segments.max(1));
        Ok(RenderState {
            interp,
            refined,
            hairs,
            vertices: vec![RenderVertex::default(); capacity],
            indexed: (HairPrimitive::Lines, usize::MAX, 0),
            mesh: None,
        })
    }

    /// Render hairs at full detail.
    pub fn hair_count(&self) -> usize {
        self.interp.hair_count()
    }

    /// An empty mesh of the primitive's topology, kept in the main world
    /// (it is rewritten every frame).
    pub fn empty_mesh(&self, primitive: HairPrimitive) -> Mesh {
        let topology = match primitive {
            HairPrimitive::Ribbons => PrimitiveTopology::TriangleList,
            HairPrimitive::Lines => PrimitiveTopology::LineList,
        };
        Mesh::new(
            topology,
            RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD,
        )
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, Vec::<[f32; 3]>::new())
        .with_inserted_attribute(Mesh::ATTRIBUTE_TANGENT, Vec::<[f32; 4]>::new())
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, Vec::<[f32; 2]>::new())
        .with_inserted_indices(Indices::U32(Vec::new()))
    }

    /// Refines, interpolates and writes the render vertices for `view`;
    /// returns (vertices written, vertices per hair, hairs drawn).
    fn build_vertices(
        &mut self,
        hair: &Hair,
        strands: &Strands,
        center: cg::Vec3,
        extent: f32,
        view: Option<View>,
    ) -> Result<(usize, usize, usize), String> {
        let r = &hair.render;
        let (segments, groups) = choose_level(hair, strands, &self.interp, center, extent, view);
        self.refined.set_segments_per_span_clamped(segments);
        lod::refine_strands(strands.blocks(), None, &mut self.refined)
            .map_err(|e| e.to_string())?;
        lod::interpolate(&self.interp, &self.refined, None, groups, &mut self.hairs)
            .map_err(|e| e.to_string())?;
        let width = HairWidth {
            root: r.root_width,
            tip: r.tip_width,
        };
        let n = lod::write_render_vertices(
            &self.interp,
            &self.hairs,
            groups,
            width,
            r.width_scale,
            &mut self.vertices,
        )
        .map_err(|e| e.to_string())?;
        let per_hair = self.hairs.verts_per_hair().max(1);
        Ok((n, per_hair, n / per_hair))
    }
}

/// Writes each hair's mesh (`PostUpdate`): its LOD from the active camera,
/// world-space vertices (moved with the head while the simulation follows
/// it rigidly), camera-facing ribbons or lines, with the unit tangent in
/// `ATTRIBUTE_TANGENT.xyz` (w = position along the hair, 0 at the root) and
/// `ATTRIBUTE_UV_0 = (position along the hair, side -1 / +1)`.
pub fn build_hair_meshes(
    cameras: Query<(&Camera, &GlobalTransform, Option<&Projection>)>,
    mut hairs: Query<(Entity, &Hair, &mut HairState)>,
    mut meshes: ResMut<Assets<Mesh>>,
) {
    let view = active_view(&cameras);
    for (entity, hair, mut state) in &mut hairs {
        let start = Instant::now();
        let state = &mut *state;
        let extent = state.extent;
        let center = state.pose.translation.into();
        // While following, the strands stay where they were last stepped
        // and the head has carried them on by `carry`.
        let carry = state.pose * state.stepped_pose.inverse();
        let origin = state.strands.origin().as_vec3();
        let Some(render) = state.render.as_mut() else {
            continue;
        };
        let (n, per_hair, drawn) =
            match render.build_vertices(hair, &state.strands, center, extent, view) {
                Ok(v) => v,
                Err(e) => {
                    crate::warn_once!("coif-bevy: hair {entity}: {e}");
                    continue;
                }
            };
        let lod_done = Instant::now();
        let Some((handle, _)) = render.mesh.as_ref() else {
            continue;
        };
        let Some(mut mesh) = meshes.get_mut(handle) else {
            continue;
        };
        let eye = view.map(|v| v.eye);
        let primitive = hair.render.primitive;
        write_mesh(
            &mut mesh,
            &render.vertices[..n],
            origin,
            carry,
            eye,
            primitive,
        );
        let key = (primitive, n, per_hair);
        if render.indexed != key {
            if let Ok(Some(Indices::U32(indices))) = mesh.try_indices_mut_option() {
                write_indices(indices, primitive, n, per_hair);
            }
            render.indexed = key;
        }
        state.stats.render_hairs = drawn;
        state.stats.mesh_vertices = match primitive {
            HairPrimitive::Ribbons => 2 * n,
            HairPrimitive::Lines => n,
        };
        state.stats.lod_ms = (lod_done - start).as_secs_f32() * 1e3;
        state.stats.mesh_ms = start.elapsed().as_secs_f32() * 1e3;
        state.stats.plugin_ms = state.stats.mesh_ms;
        // Bevy uploads a changed mesh whole: 36 bytes per vertex
        // (position, tangent, uv) and the indices.
        let indices = mesh.indices().map_or(0, |i| i.len());
        state.stats.upload_bytes = state.stats.mesh_vertices * 36 + indices * 4;
    }
}

/// The vertex attributes of `vertices` (origin-relative) into `mesh`, in
/// place (the attribute vectors keep their capacity).
fn write_mesh(
    mesh: &mut Mesh,
    vertices: &[RenderVertex],
    origin: cg::Vec3,
    carry: cg::Affine3A,
    eye: Option<cg::Vec3>,
    primitive: HairPrimitive,
) {
    let moved = carry != cg::Affine3A::IDENTITY;
    let world = |v: &RenderVertex| {
        let p = origin + cg::Vec3::from_array(v.position);
        let t = cg::Vec3::from_array(v.tangent);
        if moved {
            (carry.transform_point3(p), carry.transform_vector3(t))
        } else {
            (p, t)
        }
    };
    let ribbons = primitive == HairPrimitive::Ribbons;
    if let Ok(Some(VertexAttributeValues::Float32x3(pos))) =
        mesh.try_attribute_mut_option(Mesh::ATTRIBUTE_POSITION)
    {
        pos.clear();
        for v in vertices {
            let (p, t) = world(v);
            if ribbons {
                // Across the hair, facing the eye (or +Y without one).
                let to_eye = eye.map_or(cg::Vec3::Y, |e| e - p);
                let side = t.cross(to_eye).normalize_or_zero() * (0.5 * v.width);
                pos.push((p - side).to_array());
                pos.push((p + side).to_array());
            } else {
                pos.push(p.to_array());
            }
        }
    }
    if let Ok(Some(VertexAttributeValues::Float32x4(tan))) =
        mesh.try_attribute_mut_option(Mesh::ATTRIBUTE_TANGENT)
    {
        tan.clear();
        for v in vertices {
            let (_, t) = world(v);
            let a = [t.x, t.y, t.z, v.strand_parameter];
            tan.push(a);
            if ribbons {
                tan.push(a);
            }
        }
    }
    if let Ok(Some(VertexAttributeValues::Float32x2(uv))) =
        mesh.try_attribute_mut_option(Mesh::ATTRIBUTE_UV_0)
    {
        uv.clear();
        for v in vertices {
            if ribbons {
                uv.push([v.strand_parameter, -1.0]);
                uv.push([v.strand_parameter, 1.0]);
            } else {
                uv.push([v.strand_parameter, 0.0]);
            }
        }
    }
}

/// Indices of `n` render vertices, `per_hair` per hair: two triangles per
/// ribbon segment, or a line per segment.
pub fn write_indices(indices: &mut Vec<u32>, primitive: HairPrimitive, n: usize, per_hair: usize) {
    indices.clear();
    let per_hair = per_hair.max(1);
    for h in 0..n / per_hair {
        let first = h * per_hair;
        for s in first..first + per_hair - 1 {
            let s = s as u32;
            match primitive {
                HairPrimitive::Lines => indices.extend_from_slice(&[s, s + 1]),
                HairPrimitive::Ribbons => {
                    let (a, b, c, d) = (2 * s, 2 * s + 1, 2 * s + 2, 2 * s + 3);
                    indices.extend_from_slice(&[a, b, c, b, d, c]);
                }
            }
        }
    }
}

/// Despawns the mesh entity of a hair that is gone (its entity despawned or
/// its `Hair` removed), and drops the mesh asset with it.
pub fn remove_orphan_meshes(
    mut commands: Commands,
    meshes: Query<(Entity, &HairMeshOf)>,
    hairs: Query<(), With<Hair>>,
) {
    for (entity, of) in &meshes {
        if hairs.get(of.0).is_err() {
            commands.entity(entity).despawn();
        }
    }
}

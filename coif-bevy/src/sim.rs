//! The hair's simulation state and the systems that build and step it.

use crate::assets::{BodyMeshAsset, GroomAsset};
use crate::components::{CapsuleCollider, Hair, HairDrawPath, MeshCollider, SphereCollider};
use crate::executor::TaskPoolExecutor;
use crate::render::RenderState;
use bevy::prelude::*;
use coif::base::tasks::{Executor, Serial};
use coif::glam as cg;
use coif::kernels::{step_colliders_with, Capsule, Colliders, Sdf, Sphere, Strands};
use std::time::Instant;

/// Who runs the step's tasks (a resource; default: Bevy's compute pool).
/// Both give the same bytes.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HairExecutor {
    /// Bevy's `ComputeTaskPool`, through [`TaskPoolExecutor`].
    #[default]
    TaskPool,
    /// coif's `Serial`: the calling thread, no allocation at all.
    Serial,
}

/// coif's glam from Bevy's (the two may be different versions).
pub fn affine_of(g: &GlobalTransform) -> cg::Affine3A {
    cg::Affine3A::from_cols_array(&g.affine().to_cols_array())
}

/// A point in coif's glam.
pub fn vec3_of(v: Vec3) -> cg::Vec3 {
    cg::Vec3::from_array(v.to_array())
}

/// The fields of every [`MeshCollider`], in one slice as coif's step wants
/// them, each built once and moved by its entity's transform every step.
#[derive(Resource, Default)]
pub struct HairFields {
    pub(crate) sdfs: Vec<Sdf>,
    pub(crate) owners: Vec<Entity>,
}

impl HairFields {
    /// The fields built so far.
    pub fn fields(&self) -> &[Sdf] {
        &self.sdfs
    }
}

/// Marks a [`MeshCollider`] whose field is built (or failed to build).
#[derive(Component)]
pub struct MeshColliderBuilt;

/// Timings and counts of a hair's last step and mesh build.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HairStats {
    /// Wall time of the last fixed step (posing, colliders, coif's step,
    /// positions written), milliseconds.
    pub step_ms: f32,
    /// Wall time of the last mesh build (refine, interpolate, render
    /// vertices, then the mesh's attributes), milliseconds.
    pub mesh_ms: f32,
    /// The part of `mesh_ms` in coif's LOD (refine, interpolate, render
    /// vertices), milliseconds.
    pub lod_ms: f32,
    /// Steps taken so far.
    pub steps: u64,
    /// Strands the last step advanced (coif's sleeping blocks skipped).
    pub awake_strands: usize,
    /// True while the hair follows the head rigidly (too small on screen).
    pub following: bool,
    /// Render hairs drawn in the last mesh.
    pub render_hairs: usize,
    /// Vertices in the last mesh.
    pub mesh_vertices: usize,
    /// Height of the hair on screen (pixels) from the active camera, or
    /// infinity without one.
    pub height_px: f32,
    /// The plugin's CPU time for this hair in the last frame outside the
    /// step (LOD choice, packing and upload on the GPU path; refinement,
    /// interpolation and the mesh's attributes on the CPU mesh path),
    /// milliseconds.
    pub plugin_ms: f32,
    /// Bytes handed to the GPU for this hair in the last frame: the
    /// guides and the view on the GPU path; the whole mesh (vertex
    /// attributes and indices, which Bevy uploads again when the mesh
    /// changes) on the CPU mesh path.
    pub upload_bytes: usize,
}

/// The simulation of one [`Hair`], added by the plugin once its groom is
/// loaded (and its transform propagated).
#[derive(Component)]
pub struct HairState {
    pub(crate) strands: Strands,
    pub(crate) positions: Vec<cg::Vec3>,
    pub(crate) accumulated: f32,
    pub(crate) pose: cg::Affine3A,
    /// The pose the strands are at (behind `pose` while following).
    pub(crate) stepped_pose: cg::Affine3A,
    pub(crate) following: bool,
    /// The sag-free rest state was solved (or is not wanted).
    pub(crate) rest_solved: bool,
    pub(crate) extent: f32,
    pub(crate) render: Option<RenderState>,
    /// The render hairs' placement, for the GPU path (which keeps no CPU
    /// render buffers).
    pub(crate) interpolation: Option<coif::lod::Interpolation>,
    pub(crate) stats: HairStats,
}

impl HairState {
    /// Builds the strands of `hair` from `groom` at the pose `pose` (the
    /// groom's file frame scaled to metres is the rest frame; the strands
    /// start teleported to `pose`, without velocity).
    pub fn new(hair: &Hair, groom: &GroomAsset, pose: cg::Affine3A) -> Result<HairState, String> {
        HairState::for_draw_path(hair, groom, pose, HairDrawPath::CpuMesh)
    }

    /// As [`HairState::new`], with the render data `path` draws from: the
    /// CPU mesh path's refinement and vertex buffers, or the GPU path's
    /// render-hair placement alone.
    pub fn for_draw_path(
        hair: &Hair,
        groom: &GroomAsset,
        pose: cg::Affine3A,
        path: HairDrawPath,
    ) -> Result<HairState, String> {
        let verts = hair.verts_per_strand.max(2);
        let guides = groom
            .0
            .guides(hair.guide_stride.max(1), verts, hair.scale)
            .map_err(|e| e.to_string())?;
        let mut strands = Strands::from_polylines(&guides, verts).map_err(|e| e.to_string())?;
        strands.teleport(pose).map_err(|e| e.to_string())?;
        let (mut lo, mut hi) = (cg::Vec3::splat(f32::MAX), cg::Vec3::splat(f32::MIN));
        for p in &guides {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let mut positions = vec![cg::Vec3::ZERO; strands.strand_count() * verts];
        strands
            .write_positions(&mut positions)
            .map_err(|e| e.to_string())?;
        // A groom without a scalp to interpolate over is simulated, not drawn.
        let warn =
            |e: String| log::warn!("coif-bevy: the groom's render hairs cannot be built: {e}");
        let (render, interpolation) = match path {
            HairDrawPath::CpuMesh => (
                RenderState::new(hair, &guides, verts, &strands)
                    .map_err(warn)
                    .ok(),
                None,
            ),
            HairDrawPath::Gpu => (
                None,
                crate::render::interpolation_of(hair, &guides, verts)
                    .map_err(warn)
                    .ok(),
            ),
        };
        Ok(HairState {
            strands,
            positions,
            accumulated: 0.0,
            pose,
            stepped_pose: pose,
            following: false,
            rest_solved: !hair.sag_free,
            extent: (hi - lo).length(),
            render,
            interpolation,
            stats: HairStats::default(),
        })
    }

    /// The simulated strands.
    pub fn strands(&self) -> &Strands {
        &self.strands
    }

    /// Every guide's points in world space, strand after strand, as of the
    /// last step (moved rigidly with the head while following).
    pub fn positions(&self) -> &[cg::Vec3] {
        &self.positions
    }

    /// Points per guide.
    pub fn verts_per_strand(&self) -> usize {
        self.strands.verts_per_strand()
    }

    /// Timings and counts.
    pub fn stats(&self) -> HairStats {
        self.stats
    }
}

/// The draw path the plugin runs (the one asked for, or the CPU mesh path
/// where the app has no renderer for the GPU path).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActiveDrawPath(pub HairDrawPath);

/// Builds [`HairState`] for hairs whose groom has loaded, at their
/// propagated pose (`PostUpdate`, after transform propagation).
pub fn init_hairs(
    mut commands: Commands,
    grooms: Res<Assets<GroomAsset>>,
    mut meshes: ResMut<Assets<Mesh>>,
    hairs: Query<(Entity, &Hair, &GlobalTransform), Without<HairState>>,
    path: Option<Res<ActiveDrawPath>>,
    mut failed: Local<Vec<Entity>>,
) {
    let path = path.map_or(HairDrawPath::CpuMesh, |p| p.0);
    for (entity, hair, global) in &hairs {
        if failed.contains(&entity) {
            continue;
        }
        let Some(groom) = grooms.get(&hair.groom) else {
            continue;
        };
        match HairState::for_draw_path(hair, groom, affine_of(global), path) {
            Ok(mut state) => {
                if let Some(render) = state.render.as_mut() {
                    let mesh = meshes.add(render.empty_mesh(hair.render.primitive));
                    let mesh_entity = commands
                        .spawn((
                            Mesh3d(mesh.clone()),
                            Transform::IDENTITY,
                            crate::render::HairMeshOf(entity),
                            // Rewritten every frame: bounds computed once
                            // would cull the hair once it moves out of them.
                            bevy::camera::visibility::NoFrustumCulling,
                        ))
                        .id();
                    render.mesh = Some((mesh, mesh_entity));
                }
                commands.entity(entity).insert(state);
            }
            Err(e) => {
                log::warn!("coif-bevy: hair {entity} cannot be built: {e}");
                failed.push(entity);
            }
        }
    }
}

/// Builds each new [`MeshCollider`]'s field once its mesh has loaded.
pub fn build_mesh_colliders(
    mut commands: Commands,
    bodies: Res<Assets<BodyMeshAsset>>,
    colliders: Query<(Entity, &MeshCollider, &GlobalTransform), Without<MeshColliderBuilt>>,
    mut fields: ResMut<HairFields>,
) {
    for (entity, collider, global) in &colliders {
        let Some(body) = bodies.get(&collider.mesh) else {
            continue;
        };
        let mesh = &body.0;
        match Sdf::from_mesh(mesh.positions(), mesh.triangles(), collider.cell) {
            Ok(mut sdf) => {
                let _ = sdf.set_transform(affine_of(global));
                fields.sdfs.push(sdf);
                fields.owners.push(entity);
            }
            Err(e) => log::warn!("coif-bevy: mesh collider {entity}: {e}"),
        }
        commands.entity(entity).insert(MeshColliderBuilt);
    }
}

/// Reused lists of the rig, so that a step allocates nothing.
#[derive(Default)]
pub struct RigScratch {
    spheres: Vec<(Entity, Sphere)>,
    capsules: Vec<(Entity, Capsule)>,
    sphere_list: Vec<Sphere>,
    capsule_list: Vec<Capsule>,
}

/// The fixed step (`FixedUpdate`): each hair takes as many steps of its
/// `params.dt` as the fixed time covers, posed by its entity's global
/// transform, against every collider, on the chosen executor.
#[allow(clippy::too_many_arguments)]
pub fn step_hairs(
    time: Res<Time>,
    executor: Res<HairExecutor>,
    mut hairs: Query<(Entity, &Hair, &mut HairState, &GlobalTransform)>,
    spheres: Query<(Entity, &SphereCollider, &GlobalTransform)>,
    capsules: Query<(Entity, &CapsuleCollider, &GlobalTransform)>,
    transforms: Query<&GlobalTransform>,
    mut fields: ResMut<HairFields>,
    mut rig: Local<RigScratch>,
) {
    // The rig, in a stable order (by entity) so each collider keeps its
    // index from step to step (coif sweeps colliders by index).
    let rig = &mut *rig;
    rig.spheres.clear();
    rig.spheres.extend(spheres.iter().map(|(e, s, g)| {
        let center = vec3_of(g.translation());
        (
            e,
            Sphere {
                center,
                radius: s.radius,
            },
        )
    }));
    rig.spheres.sort_unstable_by_key(|(e, _)| *e);
    rig.sphere_list.clear();
    rig.sphere_list
        .extend(rig.spheres.iter().map(|(_, s)| s.clone()));
    rig.capsules.clear();
    rig.capsules.extend(capsules.iter().map(|(e, c, g)| {
        let a = g.transform_point(Vec3::new(0.0, -c.half_length, 0.0));
        let b = g.transform_point(Vec3::new(0.0, c.half_length, 0.0));
        let capsule = Capsule {
            a: vec3_of(a),
            b: vec3_of(b),
            radius: c.radius,
        };
        (e, capsule)
    }));
    rig.capsules.sort_unstable_by_key(|(e, _)| *e);
    rig.capsule_list.clear();
    rig.capsule_list
        .extend(rig.capsules.iter().map(|(_, c)| *c));
    // The fields follow their entities; a despawned owner drops its field.
    let fields = &mut *fields;
    let mut i = 0;
    while i < fields.owners.len() {
        match transforms.get(fields.owners[i]) {
            Ok(g) => {
                let _ = fields.sdfs[i].set_transform(affine_of(g));
                i += 1;
            }
            Err(_) => {
                fields.owners.remove(i);
                fields.sdfs.remove(i);
            }
        }
    }
    let colliders = Colliders {
        spheres: &rig.sphere_list,
        capsules: &rig.capsule_list,
        sdfs: &fields.sdfs,
    };
    let pool;
    let exec: &dyn Executor = match *executor {
        HairExecutor::TaskPool => {
            pool = TaskPoolExecutor::compute();
            &pool
        }
        HairExecutor::Serial => &Serial,
    };
    let elapsed = time.delta_secs();
    for (entity, hair, mut state, global) in &mut hairs {
        let state = &mut *state;
        let dt = hair.params.dt;
        if !(dt.is_finite() && dt > 0.0) {
            continue;
        }
        state.accumulated += elapsed;
        let start = Instant::now();
        let pose = affine_of(global);
        // Steps within a millionth of a second of due count as due (the
        // fixed time and dt are both rounded).
        while state.accumulated >= dt - 1e-6 {
            state.accumulated -= dt;
            if state.following {
                // Rigidly with the head: the output moves, nothing is stepped.
                let delta = pose * state.pose.inverse();
                for p in &mut state.positions {
                    *p = delta.transform_point3(*p);
                }
                state.pose = pose;
                continue;
            }
            if let Err(e) = state.strands.set_head_pose(pose) {
                crate::warn_once!(
                    "coif-bevy: hair {entity}: the head pose is not rigid ({e}); not stepped"
                );
                break;
            }
            if !state.rest_solved {
                state.rest_solved = true;
                if let Err(e) = state.strands.solve_sag_free(&hair.params, &colliders) {
                    crate::warn_once!(
                        "coif-bevy: hair {entity}: no sag-free rest state ({e}); the groom as built"
                    );
                }
            }
            step_colliders_with(&mut state.strands, &hair.params, &colliders, exec);
            state.pose = pose;
            state.stepped_pose = pose;
            state.stats.steps += 1;
            state.stats.awake_strands = state.strands.awake_strands();
            let _ = state.strands.write_positions(&mut state.positions);
        }
        state.stats.step_ms = start.elapsed().as_secs_f32() * 1e3;
    }
}

/// The view of a hair from the active camera: chooses between simulating
/// and following rigidly (`Update`).
pub fn choose_sim_lod(
    cameras: Query<(&Camera, &GlobalTransform, Option<&Projection>)>,
    mut hairs: Query<(&Hair, &mut HairState, &GlobalTransform)>,
) {
    let view = crate::render::active_view(&cameras);
    for (hair, mut state, global) in &mut hairs {
        let height = view
            .map(|v| v.height_px(vec3_of(global.translation()), state.extent))
            .unwrap_or(f32::INFINITY);
        let follow = height < hair.lod.follow_below_px;
        if state.following && !follow {
            // Resume where the head carried the hair (positions already
            // moved): the strands jump there without velocity.
            let delta = state.pose * state.stepped_pose.inverse();
            let _ = state.strands.teleport(delta);
            state.stepped_pose = state.pose;
        }
        state.following = follow;
        state.stats.following = follow;
        state.stats.height_px = height;
    }
}

//! coif's hair in Bevy: `app.add_plugins(HairPlugin::default())`.
//!
//! What an app needs (the root README's "In Bevy"; the asset paths are
//! under the app's `assets/`):
//!
//! ```no_run
//! use bevy::prelude::*;
//! use coif_bevy::{Hair, HairPlugin, MeshCollider};
//!
//! fn main() {
//!     App::new().add_plugins((DefaultPlugins, HairPlugin::default())).add_systems(Startup, setup).run();
//! }
//! fn setup(mut commands: Commands, assets: Res<AssetServer>) {
//!     let head = commands.spawn(Transform::default()).id(); // the head bone (animate it)
//!     commands.spawn((Hair::new(assets.load("sintel/sintel_lite.tfx")), Transform::default(), ChildOf(head)));
//!     commands.spawn((MeshCollider { mesh: assets.load("sintel/sintel_bust.obj"), cell: 0.004 }, Transform::default(), ChildOf(head)));
//!     commands.spawn((Camera3d::default(), Transform::from_xyz(0.0, 0.35, 0.8).looking_at(Vec3::new(0.0, 0.33, 0.0), Vec3::Y)));
//! }
//! ```
//!
//! - Assets: [`GroomAsset`] (`.tfx`, cyHair `.hair`) and [`BodyMeshAsset`]
//!   (`.obj`, for mesh colliders), with their loaders.
//! - Components: [`Hair`] (a groom, every [`coif::kernels::SimParams`]
//!   field, wind included, and its render settings), spawned under the
//!   head bone; [`SphereCollider`], [`CapsuleCollider`] and
//!   [`MeshCollider`].
//! - Systems, in order (README.md of this crate):
//!   `PostUpdate`, after transform propagation: [`sim::init_hairs`] (the
//!   strands at the propagated pose) and [`sim::build_mesh_colliders`] (each
//!   field once);
//!   `FixedUpdate`: [`sim::step_hairs`] (pose from the bone's
//!   `GlobalTransform`, coif's step on Bevy's `ComputeTaskPool`);
//!   `Update`: [`sim::choose_sim_lod`] (simulate or follow rigidly, from
//!   the active camera);
//!   `PostUpdate`: [`render::remove_orphan_meshes`] (meshes of hairs gone),
//!   [`render::build_hair_meshes`] (refine, interpolate,
//!   ribbons or lines into the hair's mesh), then with the `render`
//!   feature `material::attach_hair_material` (the default
//!   `HairMaterial` on each hair mesh, where the app has `PbrPlugin`).
//! - Feature `render` (default): `material` (the bevy_pbr material over
//!   the hair WGSL, coif's tables as textures) and `headless` (rendering
//!   into an image and reading it back, without a window).

/// `log::warn!` once per call site (Bevy's `LogPlugin`, where an app has
/// it, shows `log` records).
#[macro_export]
#[doc(hidden)]
macro_rules! warn_once {
    ($($arg:tt)*) => {{
        static DONE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
        if !DONE.swap(true, std::sync::atomic::Ordering::Relaxed) {
            log::warn!($($arg)*);
        }
    }};
}

pub mod assets;
pub mod components;
pub mod executor;
#[cfg(feature = "render")]
pub mod gpu;
#[cfg(feature = "render")]
pub mod headless;
#[cfg(feature = "render")]
pub mod material;
pub mod render;
pub mod shading;
pub mod sim;

pub use assets::{BodyMeshAsset, BodyMeshLoader, BodyMeshSettings, GroomAsset, GroomLoader};
pub use components::{
    CapsuleCollider, Hair, HairDrawPath, HairLod, HairPrimitive, HairRender, MeshCollider,
    SphereCollider,
};
pub use executor::TaskPoolExecutor;
#[cfg(feature = "render")]
pub use material::{DefaultHairMaterial, HairLook, HairMaterial};
pub use render::HairMeshOf;
pub use sim::{ActiveDrawPath, HairExecutor, HairFields, HairState, HairStats};

use bevy::prelude::*;
use bevy::transform::TransformSystems;

/// System sets of the plugin, for ordering an app's own systems.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HairSystems {
    /// `PostUpdate`: new hairs and mesh colliders are built.
    Init,
    /// `FixedUpdate`: the step.
    Step,
    /// `Update`: simulate or follow, from the camera.
    Lod,
    /// `PostUpdate`: the meshes are written.
    Mesh,
}

/// The plugin: assets, loaders, the step in `FixedUpdate` and the mesh
/// building in `PostUpdate`.
#[derive(Clone, Debug)]
pub struct HairPlugin {
    /// Sets `Time<Fixed>` to this period in seconds (None leaves the app's
    /// own). Each hair steps at its `params.dt`, accumulated from the fixed
    /// time: with the same period, one step per fixed update.
    pub fixed_timestep: Option<f64>,
    /// Who runs the step's tasks.
    pub executor: HairExecutor,
    /// Build render meshes (off for a simulation-only app).
    pub meshes: bool,
    /// With the `render` feature: draw each hair mesh with
    /// `HairMaterial` where the app has Bevy's renderer (`PbrPlugin`
    /// added before this plugin, as `DefaultPlugins` does); an app
    /// without it (e.g. `MinimalPlugins`) runs as without the feature.
    pub material: bool,
    /// How hair is drawn: on the GPU (the default, with the `render`
    /// feature, where the app has Bevy's renderer) or through a CPU-built
    /// mesh. Without the feature or a renderer the CPU meshes are built
    /// whatever this says ([`ActiveDrawPath`] tells which runs).
    pub draw_path: HairDrawPath,
}

impl Default for HairPlugin {
    fn default() -> Self {
        HairPlugin {
            fixed_timestep: Some(1.0 / 60.0),
            executor: HairExecutor::TaskPool,
            meshes: true,
            material: true,
            draw_path: HairDrawPath::Gpu,
        }
    }
}

impl Plugin for HairPlugin {
    fn build(&self, app: &mut App) {
        app.init_asset::<GroomAsset>()
            .init_asset::<BodyMeshAsset>()
            .register_asset_loader(GroomLoader)
            .register_asset_loader(BodyMeshLoader);
        if !app.world().contains_resource::<Assets<Mesh>>() {
            app.init_asset::<Mesh>();
        }
        if let Some(dt) = self.fixed_timestep {
            app.insert_resource(Time::<Fixed>::from_seconds(dt));
        }
        app.insert_resource(self.executor)
            .init_resource::<sim::HairFields>()
            .configure_sets(
                PostUpdate,
                HairSystems::Init.after(TransformSystems::Propagate),
            )
            .configure_sets(PostUpdate, HairSystems::Mesh.after(HairSystems::Init))
            .add_systems(
                PostUpdate,
                (sim::build_mesh_colliders, sim::init_hairs).in_set(HairSystems::Init),
            )
            .add_systems(FixedUpdate, sim::step_hairs.in_set(HairSystems::Step))
            .add_systems(Update, sim::choose_sim_lod.in_set(HairSystems::Lod));
        if !self.meshes {
            return;
        }
        #[cfg(feature = "render")]
        let renderer = self.material && app.is_plugin_added::<bevy::pbr::PbrPlugin>();
        #[cfg(not(feature = "render"))]
        let renderer = false;
        let path = if renderer {
            self.draw_path
        } else {
            HairDrawPath::CpuMesh
        };
        app.insert_resource(ActiveDrawPath(path)).add_systems(
            PostUpdate,
            render::remove_orphan_meshes.in_set(HairSystems::Mesh),
        );
        #[cfg(feature = "render")]
        if renderer && path == HairDrawPath::Gpu {
            gpu::register_shaders(app);
            gpu::compute::add_compute_pass(app);
            app.add_plugins(bevy::pbr::MaterialPlugin::<gpu::GpuHairMaterial>::default())
                .init_resource::<HairLook>()
                .add_systems(
                    PostUpdate,
                    (gpu::init_gpu_hairs, gpu::update_gpu_hairs)
                        .chain()
                        .in_set(HairSystems::Mesh),
                );
            return;
        }
        app.add_systems(
            PostUpdate,
            render::build_hair_meshes.in_set(HairSystems::Mesh),
        );
        #[cfg(feature = "render")]
        if renderer {
            material::register_shader(app);
            app.add_plugins(bevy::pbr::MaterialPlugin::<HairMaterial>::default())
                .init_resource::<HairLook>()
                .add_systems(
                    PostUpdate,
                    material::attach_hair_material
                        .after(render::build_hair_meshes)
                        .in_set(HairSystems::Mesh),
                );
        }
    }
}

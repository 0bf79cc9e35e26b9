//! Components an app puts on its entities.

use crate::assets::{BodyMeshAsset, GroomAsset};
use bevy::prelude::*;
use coif::kernels::SimParams;

/// Hair: a groom simulated by coif, posed by its entity's
/// [`GlobalTransform`] each fixed step. Spawn it as a child of the head
/// bone: the groom's file frame (scaled by `scale`) is the entity's local
/// frame, so the bone's motion turns the roots and the rest shape (coif's
/// one-call head pose, `Strands::set_head_pose`). The transform must be a
/// rotation and a translation (no scale).
#[derive(Component, Clone, Debug)]
pub struct Hair {
    /// The groom asset.
    pub groom: Handle<GroomAsset>,
    /// Every simulation parameter (wind, drag and gusts included); `dt` is
    /// the step the hair takes, accumulated from `FixedUpdate`'s time.
    /// Changed at any time; the next step reads it.
    pub params: SimParams,
    /// Metres per groom file unit (0.01 for TressFX and cyHair files in
    /// centimetres).
    pub scale: f32,
    /// Points per simulated guide (the groom is resampled to it).
    pub verts_per_strand: usize,
    /// Keep every `guide_stride`-th strand of the file as a guide (1 = all).
    pub guide_stride: usize,
    /// How the hair is drawn.
    pub render: HairRender,
    /// Simulation level of detail from the active camera.
    pub lod: HairLod,
    /// Before the first step, make the groom the springs' rest state
    /// against the colliders then in place (coif's
    /// `Strands::solve_sag_free`): the hair keeps its style at rest instead
    /// of sagging, and returns to it after the head moves. Default true.
    pub sag_free: bool,
}

impl Hair {
    /// A hair of `groom` with coif's styled defaults: the groom held by
    /// local shape springs at `coif::frame::style::SCENE_STIFFNESS` from its
    /// sag-free rest state (it swings when the head turns and comes back),
    /// hair against hair on, centimetre files, 24 points per guide.
    pub fn new(groom: Handle<GroomAsset>) -> Self {
        Hair {
            groom,
            params: SimParams {
                local_shape_stiffness: coif::frame::style::SCENE_STIFFNESS,
                volume_stiffness: 1.0,
                hair_friction: 1.0,
                ..SimParams::default()
            },
            scale: 0.01,
            verts_per_strand: 24,
            guide_stride: 1,
            render: HairRender::default(),
            lod: HairLod::default(),
            sag_free: true,
        }
    }
}

/// How render hairs are built into the hair's dynamic mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HairPrimitive {
    /// Camera-facing ribbons: two vertices per render vertex, triangles.
    Ribbons,
    /// Line strips (as a line list): one vertex per render vertex.
    Lines,
}

/// How the plugin draws hair ([`crate::HairPlugin::draw_path`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HairDrawPath {
    /// On the GPU (feature `render`): the guides uploaded once a frame
    /// (16 bytes per guide vertex) into a persistent storage buffer, the
    /// render hairs refined, interpolated and expanded into ribbons in the
    /// vertex shader (coif-gpu's `render_vertex`), lit by Bevy's
    /// directional lights with their shadows, and casting into Bevy's
    /// shadow maps. Needs storage buffers in the vertex stage.
    #[default]
    Gpu,
    /// On the CPU: refinement, interpolation and ribbons written into a
    /// Bevy `Mesh` every frame (uploaded whole), drawn by `HairMaterial`
    /// under its own light. For targets without storage buffers in the
    /// vertex stage (WebGL2), and apps without Bevy's renderer (the meshes
    /// are still built for them to use).
    CpuMesh,
}

/// Render settings of a [`Hair`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairRender {
    /// Ribbons or lines.
    pub primitive: HairPrimitive,
    /// Render hairs per square centimetre of scalp at full detail.
    pub density_per_cm2: f32,
    /// Most segments per guide span after refinement (B-spline).
    pub max_segments: usize,
    /// Refinement error budget in pixels.
    pub error_px: f32,
    /// Width at the root and tip in metres, before `width_scale`.
    pub root_width: f32,
    /// Width at the tip in metres.
    pub tip_width: f32,
    /// Multiplies the widths (real hair is sub-pixel; a ribbon mesh without
    /// coverage blending needs it wider).
    pub width_scale: f32,
    /// Height on screen in pixels at and above which every render hair is
    /// drawn; below it the count falls in proportion (at least
    /// `min_share` of them).
    pub full_detail_px: f32,
    /// Smallest share of render hairs drawn.
    pub min_share: f32,
    /// GPU path: the narrowest ribbon drawn, in pixels; a hair thinner on
    /// screen is drawn this wide with its coverage kept by a dithered
    /// fade, instead of aliasing.
    pub min_width_px: f32,
    /// Seed of the render hairs' placement on the scalp.
    pub seed: u64,
}

impl Default for HairRender {
    fn default() -> Self {
        HairRender {
            primitive: HairPrimitive::Ribbons,
            density_per_cm2: 20.0,
            max_segments: 3,
            error_px: 0.5,
            root_width: 80e-6,
            tip_width: 40e-6,
            width_scale: 1.0,
            full_detail_px: 400.0,
            min_share: 0.05,
            min_width_px: 1.0,
            seed: 7,
        }
    }
}

/// Simulation level of detail from the active camera's distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairLod {
    /// Below this height on screen (pixels) the hair is not simulated: it
    /// follows the head rigidly, at no cost per step, and resumes from
    /// there (with the velocity it had) when it grows again. 0 = always
    /// simulated.
    pub follow_below_px: f32,
}

impl Default for HairLod {
    fn default() -> Self {
        HairLod {
            follow_below_px: 16.0,
        }
    }
}

/// A sphere collider at its entity's global translation (its scale is
/// ignored): every hair collides with it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SphereCollider {
    /// Radius in metres.
    pub radius: f32,
}

/// A capsule collider along its entity's local Y axis, from
/// `-half_length` to `+half_length` (as Bevy's `Capsule3d`), placed by its
/// global transform.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct CapsuleCollider {
    /// Half the length of the axis, metres.
    pub half_length: f32,
    /// Radius around the axis, metres.
    pub radius: f32,
}

/// A mesh collider: the mesh's signed distance field is built once when the
/// asset is loaded, then follows the entity's global transform (rotation
/// and translation) each fixed step.
#[derive(Component, Clone, Debug)]
pub struct MeshCollider {
    /// The body mesh (metres, the entity's local frame).
    pub mesh: Handle<BodyMeshAsset>,
    /// Cell of the field in metres (4 mm fits a head).
    pub cell: f32,
}

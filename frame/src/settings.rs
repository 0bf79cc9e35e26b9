//! Settings of a frame pipeline.

use super::ShadingModel;
use coif_kernels::SimParams;
use coif_lod::HairWidth;
use glam::Vec3;

/// Default [`FrameSettings::shadow_thinning`]: 1, the shadow map from
/// every render hair. Thinning (every k-th drawn group, each hair k times
/// wider) raised the map's error against the exact reference on the
/// default scene (38,446 vertices of 400 hairs after 30 frames) from
/// 0.106 mean absolute (k = 1) to 0.115 (k = 2, paired change +0.0093 +-
/// 0.0014) and 0.127 (k = 4) (`frame/README.md`), so it is an option, not
/// the default.
pub const DEFAULT_SHADOW_THINNING: usize = 1;

/// A directional light plus ambient light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit direction toward the light.
    pub to_light: Vec3,
    /// Irradiance (linear RGB).
    pub irradiance: Vec3,
    /// Ambient irradiance (linear RGB), lighting hair albedo and skin alike.
    pub ambient: Vec3,
}

impl Default for Light {
    /// A warm key light from the upper left front.
    fn default() -> Self {
        Light {
            to_light: Vec3::new(-0.55, 0.65, 0.52).normalize(),
            irradiance: Vec3::new(1.15, 1.1, 1.0),
            ambient: Vec3::new(0.10, 0.11, 0.13),
        }
    }
}

/// How a frame gets from the simulated guides to shaded vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PrepareMode {
    /// One pass per interpolation group (interpolate, shade, shadow
    /// lookup, head shadow, colour) writing each `ShadedVertex` once, after
    /// a shadow map built from every `shadow_thinning`-th group of hairs
    /// (see `frame/README.md`).
    #[default]
    Fused,
    /// The stage-by-stage reference: every render vertex interpolated into
    /// `RenderHairs` and written as `RenderVertex`, the shadow map built
    /// from all of them, shading samples, a batch per model, batch lookups,
    /// colours, then the `ShadedVertex` buffer.
    Reference,
}

/// Everything a [`super::FramePipeline`] is built with.
#[derive(Clone, Debug)]
pub struct FrameSettings {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// The hair shading model.
    pub shading: ShadingModel,
    /// Absorption of the hair for the physically based models (pbrt-v3's
    /// `sigma_a` per unit radius; `HairColor::sigma_a` gives blond, brown
    /// and dark).
    pub hair_sigma_a: Vec3,
    /// Multiple scattering by dual scattering for the physically based
    /// models (`coif_shading::dual_scattering`), its hair counts from the
    /// shadow map; `false` draws single scattering times the shadow map's
    /// transmittance.
    pub multiple_scattering: bool,
    /// Hair density of a real scalp (hairs per cm^2).
    pub real_hairs_per_cm2: f32,
    /// Render hairs interpolated per cm^2 (fewer than real: each render
    /// hair is widened by `real / render` so the coverage is kept).
    pub render_hairs_per_cm2: f32,
    /// Width of one real hair, root to tip (metres).
    pub hair_width: HairWidth,
    /// Distance LOD never draws fewer than this fraction of the render hairs.
    pub min_lod_fraction: f32,
    /// Chord error budget of the refinement (pixels).
    pub pixel_error: f32,
    /// Most B-spline segments per span (sizes the buffers).
    pub max_segments_per_span: usize,
    /// Simulation parameters of the guides (and of the ribbons).
    pub simulation: SimParams,
    /// Most fixed simulation steps per frame.
    pub max_substeps: u32,
    /// The directional light and the ambient light.
    pub light: Light,
    /// Direction from the hair's centre toward the camera at rest; `None`:
    /// the scene's [`super::HairScene::view_direction`].
    pub view_direction: Option<Vec3>,
    /// Camera distance in multiples of the hair's bounding radius.
    pub view_distance: f32,
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// Opacity of one hair strand where it covers a whole pixel.
    pub hair_opacity: f32,
    /// Exposure of the tone map.
    pub exposure: f32,
    /// Seed of the hair placement.
    pub seed: u64,
    /// Hair self-shadowing with a deep opacity map (see `shadow.rs`).
    pub shadows: bool,
    /// The fused prepare pass or the stage-by-stage reference.
    pub prepare: PrepareMode,
    /// [`PrepareMode::Fused`] builds the shadow map from every
    /// `shadow_thinning`-th drawn interpolation group, each hair's shadow
    /// widened as many times (1 = every hair, the reference's map).
    pub shadow_thinning: usize,
    /// The hair rasteriser leaves out segments hidden behind the head's
    /// spheres (`coif_render::raster::HairRaster::set_occluders`): exact,
    /// the frame's bytes do not change; `false` draws every segment (to
    /// measure what culling saves).
    pub occlusion_culling: bool,
}

impl Default for FrameSettings {
    fn default() -> Self {
        FrameSettings {
            width: 512,
            height: 512,
            shading: ShadingModel::KajiyaKay,
            hair_sigma_a: super::demo_sigma_a(),
            multiple_scattering: true,
            real_hairs_per_cm2: 150.0,
            render_hairs_per_cm2: 40.0,
            hair_width: HairWidth::default(),
            min_lod_fraction: 0.5,
            pixel_error: 0.5,
            max_segments_per_span: 3,
            simulation: SimParams {
                // No global shape pull: the built-in head's rest shape is its
                // guides grown straight out, and with the substepped solver a
                // pull of 0.05 per step held them out stiffly instead of
                // letting them drape. Grooms keep their style with local
                // shape constraints (the demo turns them on for grooms).
                bend_stiffness: 0.3,
                ..SimParams::default()
            },
            max_substeps: 4,
            light: Light::default(),
            view_direction: None,
            view_distance: 2.6,
            fov_y: 0.7,
            hair_opacity: 0.9,
            exposure: 1.0,
            seed: 7,
            shadows: true,
            prepare: PrepareMode::Fused,
            shadow_thinning: DEFAULT_SHADOW_THINNING,
            occlusion_culling: true,
        }
    }
}

impl FrameSettings {
    /// Small, fast settings for tests: `size x size` pixels, few hairs.
    pub fn small(size: usize) -> FrameSettings {
        FrameSettings {
            width: size,
            height: size,
            render_hairs_per_cm2: 12.0,
            max_segments_per_span: 2,
            ..FrameSettings::default()
        }
    }

    /// These settings with the simulation the demo gives a character on a
    /// body (Sintel, the default scene): the groom's local shape at
    /// [`crate::style::SCENE_STIFFNESS`], the air's drag
    /// ([`crate::motion::GUST_DRAG`]) in calm air (no wind, no
    /// turbulence: the motion's gust sets both frame by frame,
    /// [`crate::motion::gust`] and [`crate::motion::gust_turbulence`]),
    /// hair-hair volume and friction at 1.
    pub fn with_body_simulation(self) -> FrameSettings {
        FrameSettings {
            simulation: SimParams {
                local_shape_stiffness: crate::style::SCENE_STIFFNESS,
                drag: crate::motion::GUST_DRAG,
                turbulence: 0.0,
                volume_stiffness: 1.0,
                hair_friction: 1.0,
                ..self.simulation
            },
            ..self
        }
    }
}

//! The hair material (feature `render`): a bevy_pbr [`Material`] drawing
//! the plugin's hair mesh with `hair.wgsl`'s Kajiya-Kay and Marschner
//! functions, coif's Marschner tables (built on the CPU by
//! [`coif::shading::marschner::Lut`]) uploaded as three `rgba32float`
//! [`Image`]s, the hair's tangent read from `ATTRIBUTE_TANGENT`.
//!
//! The plugin attaches [`DefaultHairMaterial`] (built from the
//! [`HairLook`] resource when the first hair mesh appears) to every hair
//! mesh entity without a `MeshMaterial3d<HairMaterial>`; an app may insert
//! its own on the [`crate::HairMeshOf`] entity instead, or edit the asset.

use crate::shading::{lut_textures, HairShadingUniform, HAIR_MATERIAL_WGSL};
use crate::HairMeshOf;
use bevy::asset::{uuid_handle, RenderAssetUsages};
use bevy::mesh::{MeshVertexBufferLayoutRef, VertexBufferLayout};
use bevy::pbr::{Material, MaterialPipeline, MaterialPipelineKey};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, Extent3d, RenderPipelineDescriptor, ShaderType, SpecializedMeshPipelineError,
    TextureDimension, TextureFormat,
};
use bevy::shader::ShaderRef;
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{Lut, LutLayout, Params};

/// The material's shader (`HAIR_MATERIAL_WGSL`), registered by the plugin.
pub const HAIR_MATERIAL_SHADER: Handle<Shader> =
    uuid_handle!("5c0f6c2e-2b9e-4c77-9d43-0b3f1a8f6a21");

/// The `HairShading` uniform block as the GPU reads it (the fields of
/// [`HairShadingUniform`] as `vec4<f32>`s).
#[derive(Clone, Copy, Debug, Default, PartialEq, ShaderType, Reflect)]
pub struct HairShadingGpu {
    /// K_d (w unused).
    pub diffuse: Vec4,
    /// Primary highlight colour, exponent in w.
    pub primary: Vec4,
    /// Secondary highlight colour, exponent in w.
    pub secondary: Vec4,
    /// Tangent shifts: x primary, y secondary.
    pub shifts: Vec4,
    /// x table resolution, y 1 = angular layout, z Marschner weight.
    pub lut: Vec4,
    /// Direction to the light (xyz), intensity (w).
    pub light: Vec4,
}

impl From<HairShadingUniform> for HairShadingGpu {
    fn from(u: HairShadingUniform) -> Self {
        HairShadingGpu {
            diffuse: Vec4::from_array(u.diffuse),
            primary: Vec4::from_array(u.primary),
            secondary: Vec4::from_array(u.secondary),
            shifts: Vec4::from_array(u.shifts),
            lut: Vec4::from_array(u.lut),
            light: Vec4::from_array(u.light),
        }
    }
}

/// How hair looks and is lit: the inputs of a [`HairMaterial`]. As a
/// resource, the look of [`DefaultHairMaterial`].
#[derive(Resource, Clone, Debug)]
pub struct HairLook {
    /// Kajiya-Kay's colours, exponents and shifts.
    pub kajiya_kay: KajiyaKay,
    /// Marschner's fibre (absorption gives the colour).
    pub marschner: Params,
    /// Texels per side of the tables (clamped by coif to 2..=1024).
    pub lut_resolution: usize,
    /// 0 = Kajiya-Kay only, 1 = Marschner only (clamped to [0, 1]).
    pub marschner_weight: f32,
    /// Direction to the light, world space (normalised by the shader).
    pub to_light: Vec3,
    /// The light's intensity.
    pub intensity: f32,
}

impl Default for HairLook {
    fn default() -> Self {
        HairLook {
            kajiya_kay: KajiyaKay::default(),
            marschner: Params::default(),
            lut_resolution: 64,
            marschner_weight: 1.0,
            to_light: Vec3::new(0.4, 0.8, 0.6),
            intensity: 3.0,
        }
    }
}

/// The hair material: the shading uniform and coif's three Marschner
/// tables (`lut_m`, `lut_n0`, `lut_n1`) as textures, read with
/// `textureLoad` (no sampler: `rgba32float` is not filterable everywhere).
#[derive(Asset, AsBindGroup, Clone, Debug, Reflect)]
pub struct HairMaterial {
    /// The `HairShading` uniform.
    #[uniform(0)]
    pub shading: HairShadingGpu,
    /// coif's M table (`Lut::table_m`).
    #[texture(1, sample_type = "float", filterable = false)]
    pub lut_m: Handle<Image>,
    /// coif's N table, first half.
    #[texture(2, sample_type = "float", filterable = false)]
    pub lut_n0: Handle<Image>,
    /// coif's N table, second half.
    #[texture(3, sample_type = "float", filterable = false)]
    pub lut_n1: Handle<Image>,
}

impl HairMaterial {
    /// Builds coif's tables for `look` (angular layout) and adds them to
    /// `images`.
    pub fn new(look: &HairLook, images: &mut Assets<Image>) -> HairMaterial {
        let lut = Lut::with_layout(&look.marschner, look.lut_resolution, LutLayout::Angular);
        let res = lut.resolution() as u32;
        let shading = HairShadingUniform::new(
            &look.kajiya_kay,
            &lut,
            look.marschner_weight,
            coif::glam::Vec3::from_array(look.to_light.to_array()),
            look.intensity,
        )
        .map(HairShadingGpu::from)
        // Unreachable (the layout is angular); a black material rather
        // than a panic all the same.
        .unwrap_or_default();
        let [m, n0, n1] = lut_textures(&lut).map(|texels| {
            let bytes: Vec<u8> = texels
                .iter()
                .flat_map(|t| t.iter().flat_map(|f| f.to_le_bytes()))
                .collect();
            images.add(Image::new(
                Extent3d {
                    width: res,
                    height: res,
                    depth_or_array_layers: 1,
                },
                TextureDimension::D2,
                bytes,
                TextureFormat::Rgba32Float,
                RenderAssetUsages::RENDER_WORLD,
            ))
        });
        HairMaterial {
            shading,
            lut_m: m,
            lut_n0: n0,
            lut_n1: n1,
        }
    }

    /// Sets the light (direction to it, world space; intensity).
    pub fn set_light(&mut self, to_light: Vec3, intensity: f32) {
        self.shading.light = to_light.extend(intensity);
    }
}

impl Material for HairMaterial {
    fn vertex_shader() -> ShaderRef {
        HAIR_MATERIAL_SHADER.into()
    }

    fn fragment_shader() -> ShaderRef {
        HAIR_MATERIAL_SHADER.into()
    }

    // The hair draws in the main pass only: no depth prepass and no shadow
    // pass would know its vertex layout.
    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        false
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        layout: &MeshVertexBufferLayoutRef,
        _key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        let vertex: VertexBufferLayout = layout.0.get_layout(&[
            Mesh::ATTRIBUTE_POSITION.at_shader_location(0),
            Mesh::ATTRIBUTE_TANGENT.at_shader_location(1),
            Mesh::ATTRIBUTE_UV_0.at_shader_location(2),
        ])?;
        descriptor.vertex.buffers = vec![vertex];
        // Ribbons face the eye, lines have no side: draw both faces.
        descriptor.primitive.cull_mode = None;
        Ok(())
    }
}

/// The material the plugin gives each hair mesh (built once, at the first
/// hair mesh, from [`HairLook`]).
#[derive(Resource, Clone, Debug)]
pub struct DefaultHairMaterial(pub Handle<HairMaterial>);

/// Registers the shader (at plugin build).
pub(crate) fn register_shader(app: &mut App) {
    let shader = Shader::from_wgsl(HAIR_MATERIAL_WGSL, "coif_bevy/hair_material.wgsl");
    if let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() {
        let _ = shaders.insert(&HAIR_MATERIAL_SHADER, shader);
    }
}

/// Gives every hair mesh entity without a hair material the default one
/// (`PostUpdate`, after the mesh is written).
pub fn attach_hair_material(
    mut commands: Commands,
    meshes: Query<Entity, (With<HairMeshOf>, Without<MeshMaterial3d<HairMaterial>>)>,
    look: Option<Res<HairLook>>,
    default: Option<Res<DefaultHairMaterial>>,
    mut materials: ResMut<Assets<HairMaterial>>,
    mut images: ResMut<Assets<Image>>,
) {
    if meshes.is_empty() {
        return;
    }
    let handle = match default {
        Some(d) => d.0.clone(),
        None => {
            let look = look.map(|l| l.clone()).unwrap_or_default();
            let handle = materials.add(HairMaterial::new(&look, &mut images));
            commands.insert_resource(DefaultHairMaterial(handle.clone()));
            handle
        }
    };
    for entity in &meshes {
        commands
            .entity(entity)
            .try_insert(MeshMaterial3d(handle.clone()));
    }
}

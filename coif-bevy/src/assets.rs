//! Assets: grooms (`.tfx`, cyHair `.hair`) and triangle meshes (`.obj`)
//! used as colliders, with their loaders.

use bevy::asset::{io::Reader, AssetLoader, LoadContext};
use bevy::prelude::*;
use coif::geometry::mesh::TriangleMesh;
use coif::groom::Groom;
use serde::{Deserialize, Serialize};

/// A groom as its file holds it (file units, usually centimetres): every
/// strand with its own vertex count. The [`crate::Hair`] component says at
/// what scale and vertex count it is simulated.
#[derive(Asset, TypePath, Debug, Clone)]
pub struct GroomAsset(pub Groom);

/// A triangle mesh in metres (read at the loader's scale): a body for a
/// [`crate::MeshCollider`], whose signed distance field is built once.
#[derive(Asset, TypePath, Debug, Clone)]
pub struct BodyMeshAsset(pub TriangleMesh);

impl BodyMeshAsset {
    /// The body as a Bevy triangle-list [`Mesh`] to draw (positions in
    /// metres, area-weighted smooth normals; a triangle whose index is out
    /// of range is left out).
    pub fn to_mesh(&self) -> Mesh {
        use bevy::asset::RenderAssetUsages;
        use bevy::mesh::{Indices, PrimitiveTopology};
        let positions: Vec<[f32; 3]> = self.0.positions().iter().map(|p| p.to_array()).collect();
        let n = positions.len();
        let mut normals = vec![coif::glam::Vec3::ZERO; n];
        let mut indices = Vec::with_capacity(3 * self.0.triangles().len());
        for t in self.0.triangles() {
            if t.iter().any(|&i| i as usize >= n) {
                continue;
            }
            let [a, b, c] = t.map(|i| self.0.positions()[i as usize]);
            let area_normal = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += area_normal;
            }
            indices.extend_from_slice(t);
        }
        let normals: Vec<[f32; 3]> = normals
            .iter()
            .map(|v| v.try_normalize().unwrap_or(coif::glam::Vec3::Y).to_array())
            .collect();
        Mesh::new(
            PrimitiveTopology::TriangleList,
            RenderAssetUsages::default(),
        )
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_indices(Indices::U32(indices))
    }
}

/// Loads `.tfx` (TressFX) and `.hair` (cyHair) files: the format is told
/// by the bytes, as [`coif::groom::load`] does.
#[derive(Default, TypePath)]
pub struct GroomLoader;

/// Loads Wavefront `.obj` meshes as [`BodyMeshAsset`] (triangulated; only
/// positions and faces are read).
#[derive(Default, TypePath)]
pub struct BodyMeshLoader;

/// Settings of [`BodyMeshLoader`]: metres per file unit (0.01 for a mesh
/// in centimetres, as Sintel's bust is).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct BodyMeshSettings {
    /// Metres per file unit.
    pub scale: f32,
}

impl Default for BodyMeshSettings {
    fn default() -> Self {
        BodyMeshSettings { scale: 0.01 }
    }
}

/// Why a groom or mesh file could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The file could not be read.
    Io(std::io::Error),
    /// coif rejected the groom.
    Groom(String),
    /// coif rejected the mesh.
    Mesh(String),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Io(e) => write!(f, "reading the file: {e}"),
            LoadError::Groom(e) => write!(f, "groom: {e}"),
            LoadError::Mesh(e) => write!(f, "mesh: {e}"),
        }
    }
}

impl std::error::Error for LoadError {}

impl AssetLoader for GroomLoader {
    type Asset = GroomAsset;
    type Settings = ();
    type Error = LoadError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        _load_context: &mut LoadContext<'_>,
    ) -> Result<GroomAsset, LoadError> {
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(LoadError::Io)?;
        coif::groom::load(&bytes)
            .map(GroomAsset)
            .map_err(|e| LoadError::Groom(e.to_string()))
    }

    fn extensions(&self) -> &[&str] {
        &["tfx", "hair"]
    }
}

impl AssetLoader for BodyMeshLoader {
    type Asset = BodyMeshAsset;
    type Settings = BodyMeshSettings;
    type Error = LoadError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        settings: &BodyMeshSettings,
        _load_context: &mut LoadContext<'_>,
    ) -> Result<BodyMeshAsset, LoadError> {
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(LoadError::Io)?;
        TriangleMesh::from_obj(&bytes, settings.scale)
            .map(BodyMeshAsset)
            .map_err(|e| LoadError::Mesh(e.to_string()))
    }

    fn extensions(&self) -> &[&str] {
        &["obj"]
    }
}

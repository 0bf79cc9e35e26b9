//! Why a frame pipeline could not be built.

use std::fmt;

/// Why a frame pipeline or a scene could not be built.
#[derive(Debug)]
pub enum Error {
    /// Guides could not be grown (a growth option out of range).
    Geometry(coif_geometry::scalp::ScalpError),
    /// A body mesh could not be read or is not a mesh.
    Mesh(coif_geometry::mesh::MeshError),
    /// A groom file could not be read.
    Groom(coif_geometry::groom::Error),
    /// The simulation refused the guides or parameters.
    Simulation(coif_kernels::Error),
    /// LOD (interpolation, refinement) refused its input.
    Lod(coif_lod::Error),
    /// A shading table could not be built.
    Shading(coif_shading::Error),
    /// The scene cannot be drawn (no triangles, no head...).
    Scene(&'static str),
    /// A setting is out of range.
    Setting {
        /// The setting's name.
        name: &'static str,
        /// The range it must be in.
        expected: &'static str,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Geometry(e) => write!(f, "geometry: {e}"),
            Error::Mesh(e) => write!(f, "body mesh: {e}"),
            Error::Groom(e) => write!(f, "groom: {e}"),
            Error::Simulation(e) => write!(f, "simulation: {e}"),
            Error::Lod(e) => write!(f, "level of detail: {e}"),
            Error::Shading(e) => write!(f, "shading: {e}"),
            Error::Scene(why) => write!(f, "scene: {why}"),
            Error::Setting { name, expected } => write!(f, "setting {name}: expected {expected}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Geometry(e) => Some(e),
            Error::Mesh(e) => Some(e),
            Error::Groom(e) => Some(e),
            Error::Simulation(e) => Some(e),
            Error::Lod(e) => Some(e),
            Error::Shading(e) => Some(e),
            _ => None,
        }
    }
}

impl From<coif_geometry::scalp::ScalpError> for Error {
    fn from(e: coif_geometry::scalp::ScalpError) -> Self {
        Error::Geometry(e)
    }
}

impl From<coif_kernels::Error> for Error {
    fn from(e: coif_kernels::Error) -> Self {
        Error::Simulation(e)
    }
}

impl From<coif_lod::Error> for Error {
    fn from(e: coif_lod::Error) -> Self {
        Error::Lod(e)
    }
}

impl From<coif_shading::Error> for Error {
    fn from(e: coif_shading::Error) -> Self {
        Error::Shading(e)
    }
}

impl From<coif_geometry::mesh::MeshError> for Error {
    fn from(e: coif_geometry::mesh::MeshError) -> Self {
        Error::Mesh(e)
    }
}

impl From<coif_geometry::groom::Error> for Error {
    fn from(e: coif_geometry::groom::Error) -> Self {
        Error::Groom(e)
    }
}

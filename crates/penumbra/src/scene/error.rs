//! Why a scene could not be built.

use crate::description::{Invalid, Origin, SceneError};
use crate::geometry::mesh_file::MeshError;

/// Why a description could not be built.
#[derive(Debug)]
pub enum BuildError {
    Invalid(Invalid),
    /// A mesh file that could not be read, named by the value at `origin`.
    Mesh {
        origin: Origin,
        error: MeshError,
    },
}

impl From<Invalid> for BuildError {
    fn from(i: Invalid) -> Self {
        BuildError::Invalid(i)
    }
}

impl From<BuildError> for SceneError {
    fn from(e: BuildError) -> SceneError {
        match e {
            BuildError::Invalid(i) => i.into(),
            BuildError::Mesh { origin, error } => {
                Invalid::at(&origin, format!("cannot load mesh: {error}")).into()
            }
        }
    }
}

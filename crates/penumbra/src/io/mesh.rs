//! TEMPORARY
use std::path::{Path, PathBuf};
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    pub normals: Option<Vec<[f32; 3]>>,
    pub triangles: Vec<[u32; 3]>,
}
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{path}: bad")]
    Parse { path: String },
}
pub fn read_mesh(path: &Path) -> Result<MeshData, MeshError> {
    let _ = PathBuf::from(path);
    Err(MeshError::Parse {
        path: path.display().to_string(),
    })
}

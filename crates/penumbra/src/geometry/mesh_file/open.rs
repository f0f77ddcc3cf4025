//! Opening a mesh file: through the bounded reader of [`crate::input`],
//! within the input size limit, its first bytes read apart.

use std::path::Path;

use super::error::MeshError;
use crate::input::{self, InputFile, DEFAULT_MAX_FILE_SIZE};

/// Bytes of a mesh file looked at before the rest is read: a file that is
/// plainly not of its format (a large file of zeros) is refused from them.
pub(crate) const HEAD: usize = 4096;

/// Opens a mesh file (a regular file within the size limit), not yet read.
pub(crate) fn open_mesh(path: &Path) -> Result<InputFile, MeshError> {
    let limit = input::size_limit(DEFAULT_MAX_FILE_SIZE).map_err(MeshError::input)?;
    InputFile::open(path, limit).map_err(MeshError::input)
}

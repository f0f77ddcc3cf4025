//! The mesh data the file readers produce and the errors they report.
//!
//! Readers return plain arrays rather than scene objects so that parsing stays
//! independent of how the renderer later transforms and accelerates geometry.

use std::fmt;
use std::path::{Path, PathBuf};

/// Plain mesh data as read from a file, before any transform.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    /// Per-vertex normals when the file has them for every vertex (PLY nx/ny/nz, OBJ vn referenced consistently); otherwise None.
    pub normals: Option<Vec<[f32; 3]>>,
    /// Per-vertex texture coordinates (u, v) when the file has them for every vertex
    /// (PLY u/v, s/t, texture_u/texture_v or texture_s/texture_t; OBJ vt named by
    /// every face corner); otherwise None.
    pub uvs: Option<Vec<[f32; 2]>>,
    pub triangles: Vec<[u32; 3]>,
    /// Values beside the geometry: a PLY file's vertex and face attributes
    /// (vertex colours and others), named and grouped as Mitsuba names and
    /// groups them.
    pub attributes: Vec<MeshAttribute>,
}

/// A mesh attribute (Mitsuba's): `dim` values per vertex, or per triangle
/// for a face's (each triangle of a polygon's fan with the polygon's).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttribute {
    /// `vertex_NAME` or `face_NAME`: `vertex_color` for a PLY file's
    /// `r, g, b` or `red, green, blue`.
    pub name: String,
    /// Per triangle, else per vertex.
    pub per_face: bool,
    /// Values per vertex or triangle: 1, 3, or 4 (a colour with alpha).
    pub dim: usize,
    pub values: Vec<f32>,
}

/// Where in a file a problem was found, so users can open the file at that spot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// 1-based, as editors count; the column counts bytes.
    LineColumn {
        line: usize,
        column: usize,
    },
    /// Binary bodies have no lines, so the offset from the start of the file is reported.
    ByteOffset(u64),
    Unknown,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::LineColumn { line, column } => write!(f, "{line}:{column}"),
            Location::ByteOffset(offset) => write!(f, "byte {offset}"),
            Location::Unknown => f.write_str("unknown location"),
        }
    }
}

/// Text after the path in an error message: `:12:5` for text, `: byte 10234` for binary,
/// matching the `file:line:column:` convention that editors and terminals make clickable.
fn location_suffix(location: &Location) -> String {
    match location {
        Location::LineColumn { .. } => format!(":{location}"),
        Location::ByteOffset(_) => format!(": {location}"),
        Location::Unknown => String::new(),
    }
}

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not a file that is read (a FIFO, device, directory) or one over the size limit.
    #[error(transparent)]
    File(crate::input::InputError),
    /// A problem at a known place. Text formats give line and column (1-based); binary PLY bodies give the byte offset.
    #[error("{path}{}: {message}", location_suffix(.location))]
    Parse {
        path: PathBuf,
        location: Location,
        message: String,
    },
}

impl MeshError {
    /// The error of the bounded reader: an I/O failure stays [`MeshError::Io`].
    pub(crate) fn input(e: crate::input::InputError) -> Self {
        match e {
            crate::input::InputError::Io { path, source } => MeshError::Io { path, source },
            other => MeshError::File(other),
        }
    }

    /// A problem at a place; the message is bounded (values from the file
    /// it quotes cut to a few dozen characters, a few lines at most).
    pub(crate) fn parse(path: &Path, location: Location, message: impl Into<String>) -> Self {
        let message = message.into();
        MeshError::Parse {
            path: path.to_path_buf(),
            location,
            message: crate::input::quote::bounded(&message).into_owned(),
        }
    }
}

//! Mesh files: PLY (ASCII and binary), Wavefront OBJ and Mitsuba's
//! `serialized` meshes, read into plain
//! arrays ([`MeshData`]) with errors that name the file, line and column.
//!
//! A shape reads its own file, as Mitsuba's `ply` and `obj` shape plugins do:
//! the readers depend on nothing but the standard library and the bounded
//! reader of [`crate::input`] (regular files only, size-capped), so the
//! scene's builder can call them without reaching up into the output layer.

mod error;
pub mod obj;
mod open;
pub mod ply;
pub mod serialized;
mod text;

use std::path::Path;

pub use error::{Location, MeshAttribute, MeshData, MeshError};

/// Reads a triangle mesh, choosing the format by extension because neither PLY nor
/// OBJ content is reliably recognisable from a few leading bytes (OBJ has no magic).
pub fn read_mesh(path: &Path) -> Result<MeshData, MeshError> {
    read_mesh_part(path, 0)
}

/// [`read_mesh`] of mesh `shape_index` of a file that holds several (a
/// `.serialized` file; any other holds one, index 0).
pub fn read_mesh_part(path: &Path, shape_index: u32) -> Result<MeshData, MeshError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let one = |read: fn(&Path) -> Result<MeshData, MeshError>| {
        if shape_index == 0 {
            read(path)
        } else {
            Err(MeshError::parse(
                path,
                Location::Unknown,
                format!("shape_index {shape_index}: only a .serialized file holds several meshes"),
            ))
        }
    };
    match extension.as_deref() {
        Some("ply") => one(ply::read_ply),
        Some("obj") => one(obj::read_obj),
        Some("serialized") => serialized::read_serialized(path, shape_index),
        Some(other) => Err(MeshError::parse(
            path,
            Location::Unknown,
            format!("unsupported mesh format `.{other}`; supported: .ply, .obj, .serialized"),
        )),
        None => Err(MeshError::parse(
            path,
            Location::Unknown,
            "mesh file has no extension; supported: .ply, .obj, .serialized",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::text::{parse_i64, quote, Lines, Tokens};
    use super::*;

    fn parse_error(location: Location) -> String {
        MeshError::parse(Path::new("bunny.ply"), location, "something is wrong").to_string()
    }

    #[test]
    fn messages_follow_the_file_line_column_convention() {
        let at_line = parse_error(Location::LineColumn {
            line: 12,
            column: 5,
        });
        assert_eq!(at_line, "bunny.ply:12:5: something is wrong");
        let at_byte = parse_error(Location::ByteOffset(10234));
        assert_eq!(at_byte, "bunny.ply: byte 10234: something is wrong");
        assert_eq!(
            parse_error(Location::Unknown),
            "bunny.ply: something is wrong"
        );
    }

    #[test]
    fn io_errors_name_the_file() {
        let missing = Path::new("definitely/not/here.ply");
        let error = read_mesh(missing).unwrap_err();
        assert!(matches!(error, MeshError::Io { .. }), "{error:?}");
        assert!(error.to_string().starts_with("definitely/not/here.ply: "));
    }

    #[test]
    fn extension_dispatch_is_case_insensitive() {
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("tri.OBJ");
        std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert_eq!(read_mesh(&obj).unwrap().triangles, vec![[0, 1, 2]]);
        let ply = dir.path().join("tri.Ply");
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                    property float y\nproperty float z\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n\
                    0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        std::fs::write(&ply, text).unwrap();
        assert_eq!(read_mesh(&ply).unwrap().triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn unknown_extensions_list_the_supported_ones() {
        for name in ["model.stl", "model"] {
            let error = read_mesh(Path::new(name)).unwrap_err();
            let MeshError::Parse {
                location, message, ..
            } = &error
            else {
                panic!("expected a parse error, got {error:?}");
            };
            assert_eq!(*location, Location::Unknown);
            assert!(
                message.contains(".ply") && message.contains(".obj"),
                "{message}"
            );
        }
    }

    #[test]
    fn names_from_the_file_are_cut_in_messages() {
        let name = "e".repeat(100_000);
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
             property float z\nelement {name} 1\nproperty float {name}\nend_header\n0 0 0\n"
        );
        let error = ply::parse_ply(text.as_bytes(), Path::new("long.ply")).unwrap_err();
        let message = error.to_string();
        assert!(message.starts_with("long.ply:"), "{message}");
        assert!(message.len() < 300 && message.contains("eee…"), "{message}");
    }

    #[test]
    fn special_files_are_refused_as_meshes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("folder.ply");
        std::fs::create_dir(&path).unwrap();
        let error = read_mesh(&path).unwrap_err();
        assert!(matches!(error, MeshError::File(_)), "{error:?}");
        assert!(error.to_string().contains("is a directory"), "{error}");
    }

    /// A large file that is plainly not a mesh (a sparse file of zeros) is
    /// refused from its first bytes, never read whole.
    #[test]
    fn a_large_file_of_zeros_is_refused_from_its_head() {
        let dir = tempfile::tempdir().unwrap();
        let start = std::time::Instant::now();
        for name in ["zeros.ply", "zeros.obj"] {
            let path = dir.path().join(name);
            let file = std::fs::File::create(&path).unwrap();
            if file.set_len(3 << 30).is_err() {
                eprintln!("skipped {name}: no sparse files here");
                continue;
            }
            let error = read_mesh(&path).unwrap_err();
            let MeshError::Parse { location, .. } = &error else {
                panic!("{error:?}");
            };
            assert_eq!(
                *location,
                Location::LineColumn { line: 1, column: 1 },
                "{error}"
            );
        }
        assert!(start.elapsed().as_secs_f64() < 1.0, "{:?}", start.elapsed());
    }

    #[test]
    fn nul_bytes_in_an_obj_are_binary_data_at_their_place() {
        let error = obj::parse_obj(b"v 0 0 0\nv 1\x000 0\n", Path::new("b.obj")).unwrap_err();
        assert_eq!(
            error.to_string(),
            "b.obj:2:4: a NUL byte: this is binary data, not OBJ text"
        );
    }

    #[test]
    fn tokens_carry_one_based_columns() {
        let tokens: Vec<_> = Tokens::new(b"  v 1.5\t-2 \r").collect();
        assert_eq!(
            tokens,
            vec![(3, &b"v"[..]), (5, &b"1.5"[..]), (9, &b"-2"[..])]
        );
        assert_eq!(Tokens::new(b"v 1 2\r").end_column(), 6);
    }

    #[test]
    fn lines_are_counted_from_one() {
        let mut lines = Lines::new(b"a\r\nb\n\nc", 0, 0);
        assert_eq!(lines.next(), Some(&b"a\r"[..]));
        assert_eq!((lines.next(), lines.number), (Some(&b"b"[..]), 2));
        assert_eq!(lines.next(), Some(&b""[..]));
        assert_eq!((lines.next(), lines.number), (Some(&b"c"[..]), 4));
        assert_eq!(lines.next(), None);
    }

    #[test]
    fn integers_parse_like_the_standard_library() {
        let cases = [
            "0",
            "-0",
            "+7",
            "-12",
            "9223372036854775807",
            "-9223372036854775808",
            "9223372036854775808",
            "",
            "-",
            "+",
            "1.0",
            "1e3",
            "12a",
            " 1",
            "--1",
            "0x10",
            "00012",
        ];
        for case in cases {
            assert_eq!(
                parse_i64(case.as_bytes()),
                case.parse::<i64>().ok(),
                "{case:?}"
            );
        }
    }

    #[test]
    fn quoting_limits_length_and_tolerates_bad_utf8() {
        assert_eq!(quote(b"abc"), "`abc`");
        assert_eq!(quote(&[0xff]), "`\u{fffd}`");
        assert!(quote(&[b'x'; 1000]).chars().count() < 50);
    }
}

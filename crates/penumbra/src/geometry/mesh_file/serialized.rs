//! Mitsuba's `serialized` meshes: a file of zlib-compressed triangle
//! meshes, the format Mitsuba 0.5/0.6 and Mitsuba 3 write (versions 3 and
//! 4), read as Mitsuba's `serialized` shape reads it.
//!
//! # The format
//!
//! Little-endian throughout. The file holds one or more meshes one after
//! the other; each starts with an uncompressed header and continues as a
//! zlib stream:
//!
//! | bytes | content |
//! |---|---|
//! | `u16` | `0x041C`, the format's mark |
//! | `u16` | the version, 3 or 4 |
//! | zlib: `u32` | flags: `0x1` normals, `0x2` texture coordinates, `0x8` vertex colours, `0x1000` single and `0x2000` double precision |
//! | zlib: bytes | version 4 only: the mesh's name, ending in a zero byte |
//! | zlib: `u64`, `u64` | the numbers of vertices V and triangles F |
//! | zlib: floats | V positions (3 each), then if flagged V normals (3), V texture coordinates (2), V colours (3): `f32`, or `f64` with `0x2000` |
//! | zlib: `u32` | 3 F vertex indices |
//!
//! The file ends with the offset of each mesh from the start (a `u64` each
//! in version 4, a `u32` in version 3) and the number of meshes (`u32`);
//! `shape_index` picks a mesh by that table (0, the first, needs none).
//!
//! # Limits
//!
//! The counts are checked against the bytes they promise before anything
//! is allocated: the decompressed data of a mesh may not exceed the input
//! size limit of [`crate::input`] (4 GiB unless `--max-file-size` says
//! otherwise) nor what DEFLATE can make of the compressed bytes (1032 times
//! them), and no more than the counts promise is ever inflated, so a stream
//! that inflates without end (a zip bomb) stops there; and a stream shorter than its counts promise is an error naming
//! both numbers. Indices must name vertices and positions must be finite.
//! Vertex colours are read and not used (Penumbra's meshes carry none).

use std::io::Read;
use std::path::Path;

use flate2::read::ZlibDecoder;

use super::error::{Location, MeshData, MeshError};
use crate::input::{self, DEFAULT_MAX_FILE_SIZE};

/// The format's mark, the first two bytes of every mesh.
pub const MAGIC: u16 = 0x041C;

const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;

/// The most a DEFLATE stream inflates: 258 bytes from 2 bits at best,
/// about 1032 to 1. Counts promising more than this many times the
/// compressed bytes are lies, refused before anything is inflated.
const MAX_RATIO: u64 = 1032;

/// Longest mesh name read (version 4), in bytes.
const MAX_NAME: usize = 4096;

/// Reads mesh `shape_index` of a `.serialized` file.
pub fn read_serialized(path: &Path, shape_index: u32) -> Result<MeshData, MeshError> {
    let file = super::open::open_mesh(path)?;
    let bytes = file.read_rest(Vec::new()).map_err(MeshError::input)?;
    let limit = input::size_limit(DEFAULT_MAX_FILE_SIZE).map_err(MeshError::input)?;
    parse_serialized(&bytes, shape_index, limit, path)
}

/// Parses the bytes of a `.serialized` file, inflating at most `limit`
/// bytes; `path` names it in errors.
pub fn parse_serialized(
    bytes: &[u8],
    shape_index: u32,
    limit: u64,
    path: &Path,
) -> Result<MeshData, MeshError> {
    let fail = |at: u64, message: String| MeshError::parse(path, Location::ByteOffset(at), message);
    let version = header(bytes, 0, path)?;
    let start = if shape_index == 0 {
        0
    } else {
        let n = bytes.len();
        let count = n
            .checked_sub(4)
            .map(|i| u32_at(bytes, i))
            .ok_or_else(|| fail(0, "too short for its table of meshes".into()))?;
        if shape_index >= count {
            return Err(fail(
                (n - 4) as u64,
                format!("shape_index {shape_index} is out of range: the file holds {count} meshes"),
            ));
        }
        let size = if version >= 4 { 8 } else { 4 };
        let back = (count - shape_index) as usize * size + 4;
        let at = n
            .checked_sub(back)
            .ok_or_else(|| fail(0, format!("too short for its table of {count} meshes")))?;
        let offset = if size == 8 {
            u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
        } else {
            u32_at(bytes, at) as u64
        };
        if offset >= (n - 4) as u64 {
            return Err(fail(
                at as u64,
                format!("mesh {shape_index} starts at byte {offset}, past the end of the meshes"),
            ));
        }
        let offset = offset as usize;
        let v = header(bytes, offset, path)?;
        if v != version {
            return Err(fail(
                offset as u64,
                format!("mesh {shape_index} is of version {v}, the file's first of {version}"),
            ));
        }
        offset
    };
    let mut z = Inflated {
        reader: ZlibDecoder::new(&bytes[start + 4..]),
        read: 0,
        limit,
        path,
        start: start as u64 + 4,
    };
    let flags = z.u32()?;
    if version == 4 {
        let mut name = 0;
        while z.bytes(1)?[0] != 0 {
            name += 1;
            if name > MAX_NAME {
                return Err(z.error(format!("a mesh name longer than {MAX_NAME} bytes")));
            }
        }
    }
    let vertices = z.u64()?;
    let faces = z.u64()?;
    let real = if flags & DOUBLE_PRECISION != 0 { 8 } else { 4 };
    let per_vertex = 3
        + if flags & HAS_NORMALS != 0 { 3 } else { 0 }
        + if flags & HAS_TEXCOORDS != 0 { 2 } else { 0 }
        + if flags & HAS_COLORS != 0 { 3 } else { 0 };
    let needed = vertices
        .checked_mul(per_vertex * real)
        .and_then(|v| faces.checked_mul(12).and_then(|f| v.checked_add(f)));
    let compressed = (bytes.len() - start - 4) as u64;
    match needed {
        Some(n) if n <= limit.saturating_sub(z.read) => {
            if n > MAX_RATIO.saturating_mul(compressed) {
                return Err(z.error(format!(
                    "{vertices} vertices and {faces} triangles are {n} bytes, more than \
                     {compressed} compressed bytes can hold"
                )));
            }
        }
        _ => {
            return Err(z.error(format!(
                "{vertices} vertices and {faces} triangles would inflate past the size limit of {limit} bytes"
            )))
        }
    }
    if vertices > u32::MAX as u64 {
        return Err(z.error(format!("{vertices} vertices: indices are 32-bit")));
    }
    let v = vertices as usize;
    let floats = |z: &mut Inflated, n: usize| -> Result<Vec<f32>, MeshError> {
        let raw = z.bytes(n * real as usize)?;
        Ok(if real == 8 {
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()) as f32)
                .collect()
        } else {
            raw.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        })
    };
    let positions: Vec<[f32; 3]> = floats(&mut z, 3 * v)?
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    if let Some(i) = positions
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(fail(
            0,
            format!("mesh {shape_index}: vertex {i} is not finite"),
        ));
    }
    let normals = if flags & HAS_NORMALS != 0 {
        Some(
            floats(&mut z, 3 * v)?
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect(),
        )
    } else {
        None
    };
    let uvs = if flags & HAS_TEXCOORDS != 0 {
        Some(
            floats(&mut z, 2 * v)?
                .chunks_exact(2)
                .map(|c| [c[0], c[1]])
                .collect(),
        )
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        floats(&mut z, 3 * v)?;
    }
    let raw = z.bytes(faces as usize * 12)?;
    let mut triangles = Vec::with_capacity(faces as usize);
    for (i, c) in raw.chunks_exact(12).enumerate() {
        let t = [u32_at(c, 0), u32_at(c, 4), u32_at(c, 8)];
        if let Some(&bad) = t.iter().find(|&&k| k as u64 >= vertices) {
            return Err(fail(
                0,
                format!("mesh {shape_index}: triangle {i} names vertex {bad} of {vertices}"),
            ));
        }
        triangles.push(t);
    }
    Ok(MeshData {
        positions,
        normals,
        uvs,
        triangles,
        attributes: Vec::new(),
    })
}

/// The version of the mesh whose header starts at `at`.
fn header(bytes: &[u8], at: usize, path: &Path) -> Result<u16, MeshError> {
    let fail = |m: String| MeshError::parse(path, Location::ByteOffset(at as u64), m);
    let Some(h) = bytes.get(at..at + 4) else {
        return Err(fail("too short for a serialized mesh header".into()));
    };
    let magic = u16::from_le_bytes([h[0], h[1]]);
    let version = u16::from_le_bytes([h[2], h[3]]);
    if magic != MAGIC {
        return Err(fail(format!(
            "not a serialized mesh (its first bytes are {magic:#06x}, not {MAGIC:#06x})"
        )));
    }
    if !(3..=4).contains(&version) {
        return Err(fail(format!(
            "serialized mesh version {version} is not supported; supported: 3, 4"
        )));
    }
    Ok(version)
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

/// A mesh's zlib stream, read in pieces as the counts ask for them, never
/// past `limit` bytes.
struct Inflated<'a, 'p> {
    reader: ZlibDecoder<&'a [u8]>,
    read: u64,
    limit: u64,
    path: &'p Path,
    /// Where the stream starts in the file.
    start: u64,
}

impl Inflated<'_, '_> {
    fn error(&self, message: String) -> MeshError {
        MeshError::parse(
            self.path,
            Location::ByteOffset(self.start),
            format!(
                "in the zlib stream starting here, after {} bytes: {message}",
                self.read
            ),
        )
    }

    /// The next `n` bytes; the vector grows as the stream gives them, so a
    /// stream shorter than its counts costs no more than it holds.
    fn bytes(&mut self, n: usize) -> Result<Vec<u8>, MeshError> {
        if self.read + n as u64 > self.limit {
            return Err(self.error(format!("more than the size limit of {} bytes", self.limit)));
        }
        let mut out = Vec::with_capacity(n.min(1 << 20));
        let got = (&mut self.reader)
            .take(n as u64)
            .read_to_end(&mut out)
            .map_err(|e| self.error(format!("corrupt stream: {e}")))?;
        self.read += got as u64;
        if got < n {
            return Err(self.error(format!(
                "the stream ends {} bytes short of what its counts promise",
                n - got
            )));
        }
        Ok(out)
    }

    fn u32(&mut self) -> Result<u32, MeshError> {
        Ok(u32_at(&self.bytes(4)?, 0))
    }

    fn u64(&mut self) -> Result<u64, MeshError> {
        Ok(u64::from_le_bytes(self.bytes(8)?.try_into().unwrap()))
    }
}

/// Writes a version 3 or 4 `.serialized` file of `meshes` (flags chosen
/// from what each has, `double` for double precision): what tests read.
pub fn write_serialized(meshes: &[MeshData], version: u16, double: bool) -> Vec<u8> {
    use flate2::write::ZlibEncoder;
    use std::io::Write;
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for (k, m) in meshes.iter().enumerate() {
        offsets.push(out.len() as u64);
        out.extend(MAGIC.to_le_bytes());
        out.extend(version.to_le_bytes());
        let mut data = Vec::new();
        let mut flags = if double { DOUBLE_PRECISION } else { 0x1000 };
        if m.normals.is_some() {
            flags |= HAS_NORMALS;
        }
        if m.uvs.is_some() {
            flags |= HAS_TEXCOORDS;
        }
        data.extend(flags.to_le_bytes());
        if version == 4 {
            data.extend(format!("mesh{k}").bytes());
            data.push(0);
        }
        data.extend((m.positions.len() as u64).to_le_bytes());
        data.extend((m.triangles.len() as u64).to_le_bytes());
        let mut put = |xs: &[f32]| {
            for &x in xs {
                if double {
                    data.extend((x as f64).to_le_bytes());
                } else {
                    data.extend(x.to_le_bytes());
                }
            }
        };
        put(m.positions.as_flattened());
        if let Some(n) = &m.normals {
            put(n.as_flattened());
        }
        if let Some(t) = &m.uvs {
            put(t.as_flattened());
        }
        for t in &m.triangles {
            for i in t {
                data.extend(i.to_le_bytes());
            }
        }
        let mut z = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&data).unwrap();
        out.extend(z.finish().unwrap());
    }
    for o in &offsets {
        if version == 4 {
            out.extend(o.to_le_bytes());
        } else {
            out.extend((*o as u32).to_le_bytes());
        }
    }
    out.extend((meshes.len() as u32).to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMIT: u64 = 1 << 30;

    fn tri(shift: f32, extra: bool) -> MeshData {
        MeshData {
            positions: vec![[shift, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.1]],
            normals: extra.then(|| vec![[0.0, 0.0, 1.0]; 3]),
            uvs: extra.then(|| vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            triangles: vec![[0, 1, 2]],
            attributes: Vec::new(),
        }
    }

    fn parse(bytes: &[u8], index: u32) -> Result<MeshData, MeshError> {
        parse_serialized(bytes, index, LIMIT, Path::new("m.serialized"))
    }

    #[test]
    fn every_version_precision_and_index_reads_back() {
        let meshes = [tri(0.25, true), tri(-0.5, false), tri(2.0, true)];
        for version in [3, 4] {
            for double in [false, true] {
                let bytes = write_serialized(&meshes, version, double);
                for (i, m) in meshes.iter().enumerate() {
                    assert_eq!(
                        &parse(&bytes, i as u32).unwrap(),
                        m,
                        "v{version} {double} {i}"
                    );
                }
                let e = parse(&bytes, 3).unwrap_err().to_string();
                assert!(
                    e.contains("shape_index 3 is out of range: the file holds 3"),
                    "{e}"
                );
            }
        }
    }

    #[test]
    fn a_corrupt_file_is_refused_with_its_place() {
        let good = write_serialized(&[tri(0.0, true)], 4, false);
        let err = |bytes: &[u8]| parse(bytes, 0).unwrap_err().to_string();
        assert!(err(&good[..3]).contains("too short"));
        let mut v5 = good.clone();
        v5[2] = 5;
        assert!(err(&v5).contains("version 5 is not supported; supported: 3, 4"));
        assert!(err(b"PK\x03\x04....").contains("not a serialized mesh"));
        // Truncated: the stream ends before its counts are met.
        let e = err(&good[..good.len() - 30]);
        assert!(
            e.starts_with("m.serialized: byte 4: in the zlib stream"),
            "{e}"
        );
        // Garbage inside the stream.
        let mut bad = good.clone();
        for b in &mut bad[8..20] {
            *b ^= 0x5a;
        }
        assert!(err(&bad).contains("zlib stream"));
        // An index past the vertices.
        let mut m = tri(0.0, false);
        m.triangles[0][2] = 3;
        let e = err(&write_serialized(&[m], 3, false));
        assert!(e.contains("triangle 0 names vertex 3 of 3"), "{e}");
        let mut m = tri(0.0, false);
        m.positions[1][0] = f32::NAN;
        assert!(err(&write_serialized(&[m], 4, true)).contains("vertex 1 is not finite"));
        // A table pointing past the end.
        let mut t = write_serialized(&[tri(0.0, false), tri(1.0, false)], 4, false);
        let n = t.len();
        t[n - 12..n - 4].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(parse(&t, 1)
            .unwrap_err()
            .to_string()
            .contains("past the end"));
    }

    /// Counts that promise more than the limit are refused before anything
    /// is inflated; a stream inflating past the limit stops at it.
    #[test]
    fn lying_counts_and_bombs_stop_at_the_limit() {
        use flate2::write::ZlibEncoder;
        use std::io::Write;
        let stream = |body: &[u8]| {
            let mut z = ZlibEncoder::new(Vec::new(), flate2::Compression::best());
            z.write_all(body).unwrap();
            let mut out = vec![0x1C, 0x04, 3, 0];
            out.extend(z.finish().unwrap());
            out
        };
        let mut lying = 0x1000u32.to_le_bytes().to_vec();
        lying.extend(u64::MAX.to_le_bytes());
        lying.extend(1u64.to_le_bytes());
        let e = parse(&stream(&lying), 0).unwrap_err().to_string();
        assert!(e.contains("would inflate past the size limit"), "{e}");
        // 40 MB of zeros in a few tens of kilobytes: with a 1 MB limit, refused.
        let mut bomb = 0x1000u32.to_le_bytes().to_vec();
        bomb.extend(((40u64 << 20) / 12).to_le_bytes());
        bomb.extend(0u64.to_le_bytes());
        bomb.resize(40 << 20, 0);
        let bytes = stream(&bomb);
        assert!(bytes.len() < 100_000);
        let e = parse_serialized(&bytes, 0, 1 << 20, Path::new("b.serialized"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("size limit of 1048576 bytes"), "{e}");
        // A stream promising a million vertices that holds one: more than it can inflate to.
        let mut short = 0x1000u32.to_le_bytes().to_vec();
        short.extend(1_000_000u64.to_le_bytes());
        short.extend(0u64.to_le_bytes());
        short.extend([0u8; 12]);
        let e = parse(&stream(&short), 0).unwrap_err().to_string();
        assert!(
            e.contains("are 12000000 bytes, more than 17 compressed bytes can hold"),
            "{e}"
        );
        // One promising 10 vertices and holding 1 is refused where it ends.
        short[4..12].copy_from_slice(&10u64.to_le_bytes());
        let e = parse(&stream(&short), 0).unwrap_err().to_string();
        assert!(e.contains("ends 108 bytes short"), "{e}");
    }
}

//! Mitsuba's binary volume file (`.vol`, version 3), read as hostile input.
//!
//! The layout, all little-endian:
//!
//! | bytes | what |
//! |---|---|
//! | 0–2 | `VOL` |
//! | 3 | the version, 3 |
//! | 4–7 | the encoding (i32), 1: 32-bit floats (the only one Mitsuba reads) |
//! | 8–19 | the resolution along x, y, z (3 × i32) |
//! | 20–23 | the channel count (i32): 1 or 3 here (Mitsuba also takes 6, for the SGGX phase function) |
//! | 24–47 | the grid's bounding box (6 × f32: min x, y, z, then max x, y, z) |
//! | 48– | the values, `((z · ny + y) · nx + x) · channels + c` |
//!
//! The file's length is checked against its header before anything is
//! allocated; trailing bytes are refused as a header that lies. Values must
//! be finite and not negative: every volume a medium reads (an extinction, an
//! albedo) is such, and tracking with a negative density has no meaning.
//! Mitsuba reads them as they are.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::input::{size_limit, InputError, InputFile, DEFAULT_MAX_FILE_SIZE};
use crate::math::{Aabb, Vec3};

/// The header's length in bytes.
pub const HEADER_BYTES: usize = 48;

/// A grid of values as a `.vol` file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct VolGrid {
    /// Voxels along x, y, z, each ≥ 1.
    pub resolution: [u32; 3],
    /// Values per voxel: 1 or 3.
    pub channels: u32,
    /// The box the file says the grid spans (what `use_grid_bbox` reads).
    pub bbox: Aabb,
    /// `resolution[0] · resolution[1] · resolution[2] · channels` values,
    /// x fastest, then y, then z, channels innermost.
    pub data: Vec<f32>,
}

impl VolGrid {
    /// The largest value of any channel.
    pub fn max(&self) -> f32 {
        self.data.iter().fold(0.0f32, |a, &b| a.max(b))
    }

    /// The file's bytes of this grid (the writer tests and tools use).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(HEADER_BYTES + 4 * self.data.len());
        b.extend_from_slice(b"VOL");
        b.push(3);
        b.extend_from_slice(&1i32.to_le_bytes());
        for n in self.resolution {
            b.extend_from_slice(&(n as i32).to_le_bytes());
        }
        b.extend_from_slice(&(self.channels as i32).to_le_bytes());
        for x in self
            .bbox
            .min
            .to_array()
            .into_iter()
            .chain(self.bbox.max.to_array())
        {
            b.extend_from_slice(&x.to_le_bytes());
        }
        for x in &self.data {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b
    }
}

/// Why a `.vol` file was not read; the message starts with the file's path.
#[derive(Debug)]
pub enum VolError {
    Input(InputError),
    Format { path: PathBuf, message: String },
}

impl fmt::Display for VolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VolError::Input(e) => e.fmt(f),
            VolError::Format { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for VolError {}

/// Reads the `.vol` file at `path` (bounded by the input file size limit).
pub fn read_vol(path: &Path) -> Result<VolGrid, VolError> {
    let limit = size_limit(DEFAULT_MAX_FILE_SIZE).map_err(VolError::Input)?;
    let mut file = InputFile::open(path, limit).map_err(VolError::Input)?;
    let bad = |message: String| VolError::Format {
        path: path.to_path_buf(),
        message,
    };
    let head = file.read_head(HEADER_BYTES).map_err(VolError::Input)?;
    let header = parse_header(&head, file.size()).map_err(bad)?;
    let size = file.size();
    let bytes = file.read_rest(head).map_err(VolError::Input)?;
    if bytes.len() as u64 != size {
        return Err(bad(format!(
            "the file shrank while it was read ({} of {size} bytes)",
            bytes.len()
        )));
    }
    let data: Vec<f32> = bytes[HEADER_BYTES..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let channels = header.channels as usize;
    if let Some(i) = data.iter().position(|x| !x.is_finite() || *x < 0.0) {
        let voxel = i / channels;
        let [nx, ny, _] = header.resolution.map(|n| n as usize);
        let (x, y, z) = (voxel % nx, voxel / nx % ny, voxel / (nx * ny));
        let what = if data[i].is_finite() {
            "negative"
        } else {
            "not finite"
        };
        return Err(bad(format!(
            "the value of voxel ({x}, {y}, {z}), channel {}, is {what} ({}); a volume's values must be finite and ≥ 0",
            i % channels,
            data[i]
        )));
    }
    Ok(VolGrid {
        resolution: header.resolution,
        channels: header.channels,
        bbox: header.bbox,
        data,
    })
}

struct Header {
    resolution: [u32; 3],
    channels: u32,
    bbox: Aabb,
}

/// Judges the header `head` of a file of `size` bytes: every field, and
/// the length the header implies against the file's.
fn parse_header(head: &[u8], size: u64) -> Result<Header, String> {
    if head.len() < HEADER_BYTES {
        return Err(format!(
            "not a volume file: {} bytes, shorter than the {HEADER_BYTES}-byte header of a `.vol` file",
            head.len()
        ));
    }
    if &head[..3] != b"VOL" {
        return Err("not a volume file: it does not start with `VOL`".into());
    }
    if head[3] != 3 {
        return Err(format!(
            "volume file version {}; only version 3 is read",
            head[3]
        ));
    }
    let int = |i: usize| i32::from_le_bytes([head[i], head[i + 1], head[i + 2], head[i + 3]]);
    let float = |i: usize| f32::from_le_bytes([head[i], head[i + 1], head[i + 2], head[i + 3]]);
    let encoding = int(4);
    if encoding != 1 {
        return Err(format!(
            "volume encoding {encoding}; only encoding 1 (32-bit floats) is read"
        ));
    }
    let mut resolution = [0u32; 3];
    for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let n = int(8 + 4 * k);
        if n < 1 {
            return Err(format!(
                "the resolution along {axis} is {n}; it must be at least 1"
            ));
        }
        resolution[k] = n as u32;
    }
    let channels = int(20);
    if channels != 1 && channels != 3 {
        let note = if channels == 6 {
            " (6 channels hold the SGGX phase function's parameters, which is not supported)"
        } else {
            ""
        };
        return Err(format!(
            "{channels} channels per voxel; a volume has 1 or 3{note}"
        ));
    }
    let corners: Vec<f32> = (0..6).map(|k| float(24 + 4 * k)).collect();
    if corners.iter().any(|x| !x.is_finite()) {
        return Err(format!("the bounding box {corners:?} is not finite"));
    }
    let values = resolution
        .iter()
        .try_fold(channels as u64, |a, &n| a.checked_mul(u64::from(n)));
    let want = values
        .and_then(|v| v.checked_mul(4))
        .and_then(|b| b.checked_add(HEADER_BYTES as u64));
    if want != Some(size) {
        let [nx, ny, nz] = resolution;
        let want = want.map_or("more than 2^64".to_string(), |w| w.to_string());
        return Err(format!(
            "the header says {nx} × {ny} × {nz} voxels of {channels} channel(s), {want} bytes with the header, but the file has {size} bytes"
        ));
    }
    Ok(Header {
        resolution,
        channels: channels as u32,
        bbox: Aabb {
            min: Vec3::new(corners[0], corners[1], corners[2]),
            max: Vec3::new(corners[3], corners[4], corners[5]),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(resolution: [u32; 3], channels: u32) -> VolGrid {
        let n = resolution.iter().product::<u32>() * channels;
        VolGrid {
            resolution,
            channels,
            bbox: Aabb {
                min: Vec3::new(-1.0, 0.0, 0.5),
                max: Vec3::new(1.0, 2.0, 3.0),
            },
            data: (0..n).map(|i| i as f32 * 0.25).collect(),
        }
    }

    fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }

    /// What is written is read back, 1 and 3 channels.
    #[test]
    fn a_written_grid_reads_back() {
        let dir = tempfile::tempdir().unwrap();
        for (res, ch) in [([2, 3, 4], 1), ([1, 1, 1], 3), ([5, 1, 2], 3)] {
            let g = grid(res, ch);
            let path = write(dir.path(), "g.vol", &g.to_bytes());
            assert_eq!(read_vol(&path).unwrap(), g);
        }
    }

    /// Each lie of a header, each broken value, each file that is not one:
    /// refused with the file's path and what is wrong.
    #[test]
    fn hostile_files_are_refused_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let good = grid([2, 2, 2], 1).to_bytes();
        let with = |offset: usize, bytes: &[u8]| {
            let mut b = good.clone();
            b[offset..offset + bytes.len()].copy_from_slice(bytes);
            b
        };
        let mut nan = good.clone();
        nan[HEADER_BYTES + 4 * 5..HEADER_BYTES + 4 * 6].copy_from_slice(&f32::NAN.to_le_bytes());
        let mut inf = good.clone();
        inf[HEADER_BYTES..HEADER_BYTES + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
        let mut negative = good.clone();
        negative[HEADER_BYTES + 4 * 7..].copy_from_slice(&(-1.0f32).to_le_bytes());
        let mut longer = good.clone();
        longer.extend_from_slice(&[0; 4]);
        let cases: Vec<(&str, Vec<u8>, &str)> = vec![
            ("empty", vec![], "shorter than the 48-byte header"),
            (
                "short header",
                good[..20].to_vec(),
                "shorter than the 48-byte header",
            ),
            ("magic", with(0, b"VOX"), "does not start with `VOL`"),
            ("version", with(3, &[2]), "version 2"),
            ("encoding", with(4, &2i32.to_le_bytes()), "encoding 2"),
            (
                "zero resolution",
                with(12, &0i32.to_le_bytes()),
                "along y is 0",
            ),
            (
                "negative resolution",
                with(16, &(-5i32).to_le_bytes()),
                "along z is -5",
            ),
            ("channels 2", with(20, &2i32.to_le_bytes()), "2 channels"),
            ("channels 6", with(20, &6i32.to_le_bytes()), "SGGX"),
            (
                "channels lie",
                with(20, &3i32.to_le_bytes()),
                "but the file has 80 bytes",
            ),
            (
                "size lies",
                with(8, &3i32.to_le_bytes()),
                "3 × 2 × 2 voxels",
            ),
            (
                "absurd",
                with(
                    8,
                    &[
                        0xff, 0xff, 0xff, 0x7f, 0xff, 0xff, 0xff, 0x7f, 0xff, 0xff, 0xff, 0x7f,
                    ],
                ),
                "2147483647 × 2147483647 × 2147483647",
            ),
            (
                "truncated",
                good[..good.len() - 3].to_vec(),
                "but the file has 77 bytes",
            ),
            ("trailing", longer, "but the file has 84 bytes"),
            ("bbox", with(28, &f32::NAN.to_le_bytes()), "bounding box"),
            ("nan", nan, "voxel (1, 0, 1), channel 0, is not finite"),
            ("inf", inf, "voxel (0, 0, 0), channel 0, is not finite"),
            (
                "negative",
                negative,
                "voxel (1, 1, 1), channel 0, is negative",
            ),
        ];
        for (name, bytes, want) in cases {
            let path = write(dir.path(), &format!("{name}.vol"), &bytes);
            let e = read_vol(&path).unwrap_err().to_string();
            assert!(e.starts_with(&path.display().to_string()), "{name}: {e}");
            assert!(e.contains(want), "{name}: {e}");
        }
        // A directory, a FIFO, a device, a missing file.
        let e = read_vol(dir.path()).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        #[cfg(unix)]
        {
            let fifo = dir.path().join("pipe.vol");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status();
            if made.is_ok_and(|s| s.success()) {
                let e = read_vol(&fifo).unwrap_err().to_string();
                assert!(
                    e.starts_with(&fifo.display().to_string()) && e.contains("FIFO"),
                    "{e}"
                );
            }
            let e = read_vol(Path::new("/dev/zero")).unwrap_err().to_string();
            assert!(
                e.starts_with("/dev/zero") && e.contains("character device"),
                "{e}"
            );
        }
        let e = read_vol(&dir.path().join("none.vol"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("none.vol"), "{e}");
    }
}

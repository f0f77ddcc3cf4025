//! Checkpoint files: a render's state between its tiles, saved so that a
//! render stopped at any moment (a signal, a time limit, a crash) resumes
//! to the very bytes it would have made without stopping.
//!
//! A file is, in order:
//!
//! | bytes | what |
//! |---|---|
//! | 16 | the magic `PENUMBRA-CHKPT\r\n` |
//! | 4 | the format version, little-endian |
//! | 2 + n | the length and text of the version of Penumbra that wrote it |
//! | 32 | the [`Digest`] of what the render depends on |
//! | 8 | the length of the state, little-endian |
//! | … | the state: every tile's film, integrator state, counts and passes done, in serde's `postcard` form |
//! | 4 | CRC-32 of everything before it, little-endian |
//!
//! It is written whole to a temporary file beside the destination, flushed
//! to the disk and renamed over the destination: a crash or a full disk
//! while saving leaves the previous checkpoint as it was.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use sha2::{Digest as _, Sha256};

use crate::integrator::splat::Sums;
use crate::integrator::stopping::PixelSamples;
use crate::integrator::{BadSample, FilmData, RayStats, StageBatches};

const MAGIC: &[u8; 16] = b"PENUMBRA-CHKPT\r\n";

/// The version of the file's layout and of the state it holds: a file of
/// another version is refused.
pub const FORMAT_VERSION: u32 = 1;

/// The version of Penumbra writing checkpoints: one of another version is
/// refused (a pixel's samples may differ between versions).
const WRITER: &str = env!("CARGO_PKG_VERSION");

/// Test hook: with this variable set to a byte count, a save writes that
/// many bytes of the temporary file and aborts the process (a crash in the
/// middle of a save).
const FAULT_VAR: &str = "PENUMBRA_FAULT_ABORT_SAVE_AT";

/// A SHA-256 digest of everything a render's pixels depend on: the scene
/// description as the render options left it, the bytes of every file it
/// read, the region and the passes (see [`DigestInput`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Digest(pub [u8; 32]);

impl Digest {
    /// The digest in hexadecimal.
    pub fn hex(&self) -> String {
        self.0.iter().map(|b| format!("{b:02x}")).collect()
    }
}

/// The digest of a render of `source` (its description as the render
/// options left it) that read the files of digests `reads`, of `region`
/// (`None`: the scene's frame).
pub fn render_digest(
    source: &crate::scene::SceneSource,
    reads: &[[u8; 32]],
    region: Option<super::Region>,
) -> Digest {
    let mut d = DigestInput::new();
    d.add(format!("{:?}", source.root).as_bytes());
    for r in reads {
        d.add(r);
    }
    d.add(format!("{region:?}").as_bytes());
    d.finish()
}

/// Builds a [`Digest`]: each part is added with its length, so that two
/// different sequences of parts never give the same bytes to hash.
#[derive(Clone, Default)]
pub struct DigestInput(Sha256);

impl DigestInput {
    pub fn new() -> DigestInput {
        let mut d = DigestInput(Sha256::new());
        d.add(b"penumbra render");
        d.add(WRITER.as_bytes());
        d.add(&FORMAT_VERSION.to_le_bytes());
        d
    }

    /// Adds one part.
    pub fn add(&mut self, part: &[u8]) -> &mut Self {
        self.0.update((part.len() as u64).to_le_bytes());
        self.0.update(part);
        self
    }

    pub fn finish(&self) -> Digest {
        Digest(self.0.clone().finalize().into())
    }
}

/// Why a checkpoint cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{}: cannot read the checkpoint: {source}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: cannot save the checkpoint: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: not a Penumbra checkpoint", path.display())]
    NotCheckpoint { path: PathBuf },
    #[error(
        "{}: the checkpoint was written by Penumbra {writer} (format {format}); this is \
         Penumbra {WRITER} (format {FORMAT_VERSION}), which cannot resume it",
        path.display()
    )]
    Version {
        path: PathBuf,
        writer: String,
        format: u32,
    },
    #[error(
        "{}: the checkpoint is of another render: the scene, a file it reads, or an option \
         that changes the pixels differs (its digest {found}, this render's {expected})",
        path.display()
    )]
    OtherRender {
        path: PathBuf,
        found: String,
        expected: String,
    },
    #[error("{}: the checkpoint is damaged ({what})", path.display())]
    Corrupt { path: PathBuf, what: String },
}

/// What a checkpoint keeps of one tile of the frame's grid that was
/// started: its passes done and all it holds after them.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct SavedTile<S> {
    pub passes_done: u32,
    pub film: FilmData,
    pub state: S,
    pub rays: RayStats,
    pub batches: StageBatches,
    pub bad: Vec<BadSample>,
    pub samples: Vec<PixelSamples>,
}

/// The state of a render: its tiles in the order of the driver's list,
/// `None` for those not started, and the light image of a light tracer.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct Saved<S> {
    /// The region rendered and the tiles it was cut into.
    pub region: super::Region,
    pub tile_regions: Vec<super::Region>,
    pub passes: u32,
    pub tiles: Vec<Option<SavedTile<S>>>,
    pub light: Vec<Sums>,
    /// Seconds of rendering before this state was saved.
    pub seconds: f64,
}

/// The bytes of a checkpoint of `state` for a render of `digest`.
pub(super) fn encode<S: Serialize>(digest: &Digest, state: &Saved<S>) -> Vec<u8> {
    let payload = postcard::to_stdvec(state).unwrap_or_default();
    let mut out = Vec::with_capacity(payload.len() + 128);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(WRITER.len() as u16).to_le_bytes());
    out.extend_from_slice(WRITER.as_bytes());
    out.extend_from_slice(&digest.0);
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    let sum = crc32fast::hash(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// The state in the checkpoint bytes `bytes` (read from `path`), refused
/// unless it is a checkpoint of this version for a render of `digest`.
pub(super) fn decode<S: DeserializeOwned>(
    path: &Path,
    bytes: &[u8],
    digest: &Digest,
) -> Result<Saved<S>, CheckpointError> {
    let corrupt = |what: &str| CheckpointError::Corrupt {
        path: path.to_path_buf(),
        what: what.to_string(),
    };
    if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
        return Err(CheckpointError::NotCheckpoint {
            path: path.to_path_buf(),
        });
    }
    let mut r = Reader {
        bytes,
        at: MAGIC.len(),
    };
    let short = || corrupt("it ends too soon");
    let format = u32::from_le_bytes(r.array().ok_or_else(short)?);
    let n = u16::from_le_bytes(r.array().ok_or_else(short)?) as usize;
    let writer = String::from_utf8_lossy(r.take(n).ok_or_else(short)?).into_owned();
    if format != FORMAT_VERSION || writer != WRITER {
        return Err(CheckpointError::Version {
            path: path.to_path_buf(),
            writer,
            format,
        });
    }
    let found = Digest(r.array().ok_or_else(short)?);
    let len = u64::from_le_bytes(r.array().ok_or_else(short)?);
    let len = usize::try_from(len).map_err(|_| corrupt("its length is absurd"))?;
    let payload = r.take(len).ok_or_else(short)?;
    let body = r.at;
    let sum = u32::from_le_bytes(r.array().ok_or_else(short)?);
    if r.at != bytes.len() {
        return Err(corrupt("bytes follow its end"));
    }
    if sum != crc32fast::hash(&bytes[..body]) {
        return Err(corrupt("its checksum does not match its bytes"));
    }
    if found != *digest {
        return Err(CheckpointError::OtherRender {
            path: path.to_path_buf(),
            found: found.hex(),
            expected: digest.hex(),
        });
    }
    postcard::from_bytes(payload).map_err(|e| corrupt(&format!("its state does not read: {e}")))
}

/// Reads the parts of a checkpoint one after the other.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let part = self.bytes.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(part)
    }

    fn array<const N: usize>(&mut self) -> Option<[u8; N]> {
        self.take(N)?.try_into().ok()
    }
}

/// Reads the checkpoint at `path` (bounded by the input size limit).
pub(super) fn read<S: DeserializeOwned>(
    path: &Path,
    digest: &Digest,
) -> Result<Saved<S>, CheckpointError> {
    let bytes = crate::input::read_file(path).map_err(|e| CheckpointError::Read {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    })?;
    decode(path, &bytes, digest)
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same
/// folder, flushed to the disk, renamed over `path`, and the folder
/// flushed. On any error the temporary file is removed and `path` is as
/// it was.
pub(super) fn save_atomically(path: &Path, bytes: &[u8]) -> Result<(), CheckpointError> {
    let err = |source: std::io::Error| CheckpointError::Write {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::Builder::new()
        .prefix(".penumbra-checkpoint-")
        .tempfile_in(dir)
        .map_err(err)?;
    match std::env::var(FAULT_VAR)
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        Some(n) => {
            tmp.write_all(&bytes[..n.min(bytes.len())]).map_err(err)?;
            tmp.as_file().sync_all().map_err(err)?;
            std::process::abort();
        }
        None => tmp.write_all(bytes).map_err(err)?,
    }
    tmp.as_file().sync_all().map_err(err)?;
    tmp.persist(path).map_err(|e| err(e.error))?;
    // The rename is durable once the folder is.
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state() -> Saved<u32> {
        Saved {
            region: crate::render::Region {
                x0: 0,
                y0: 0,
                x1: 1,
                y1: 1,
            },
            tile_regions: Vec::new(),
            passes: 3,
            tiles: vec![None],
            light: vec![[1, -2, 3, 4]],
            seconds: 1.5,
        }
    }

    fn digest(s: &str) -> Digest {
        DigestInput::new().add(s.as_bytes()).finish()
    }

    #[test]
    fn a_checkpoint_reads_back() {
        let bytes = encode(&digest("a"), &state());
        let back: Saved<u32> = decode(Path::new("c"), &bytes, &digest("a")).unwrap();
        assert_eq!(back.passes, 3);
        assert_eq!(back.light, vec![[1, -2, 3, 4]]);
        assert_eq!(back.seconds, 1.5);
    }

    /// Every single flipped bit and every truncation is refused.
    #[test]
    fn damage_is_refused() {
        let bytes = encode(&digest("a"), &state());
        for i in 0..bytes.len() {
            for bit in [0, 3, 7] {
                let mut b = bytes.clone();
                b[i] ^= 1 << bit;
                assert!(
                    decode::<u32>(Path::new("c"), &b, &digest("a")).is_err(),
                    "byte {i} bit {bit}"
                );
            }
        }
        for n in 0..bytes.len() {
            assert!(decode::<u32>(Path::new("c"), &bytes[..n], &digest("a")).is_err());
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode::<u32>(Path::new("c"), &longer, &digest("a")).is_err());
    }

    #[test]
    fn another_render_is_named() {
        let bytes = encode(&digest("a"), &state());
        let e = decode::<u32>(Path::new("c"), &bytes, &digest("b")).unwrap_err();
        assert!(matches!(e, CheckpointError::OtherRender { .. }), "{e}");
        assert!(e.to_string().contains("another render"), "{e}");
        let e = decode::<u32>(Path::new("c"), b"hello", &digest("a")).unwrap_err();
        assert!(matches!(e, CheckpointError::NotCheckpoint { .. }), "{e}");
    }

    #[test]
    fn another_version_is_named() {
        let mut bytes = encode(&digest("a"), &state());
        bytes[16] = 9;
        let e = decode::<u32>(Path::new("c"), &bytes, &digest("a")).unwrap_err();
        assert!(e.to_string().contains("format 9"), "{e}");
    }

    #[test]
    fn parts_are_delimited() {
        let a = DigestInput::new().add(b"ab").add(b"c").finish();
        let b = DigestInput::new().add(b"a").add(b"bc").finish();
        assert_ne!(a, b);
    }

    #[test]
    fn a_save_replaces_the_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.ckpt");
        save_atomically(&path, b"first").unwrap();
        save_atomically(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file left");
        let e = save_atomically(&dir.path().join("no/such/dir/r.ckpt"), b"x").unwrap_err();
        assert!(e.to_string().contains("cannot save"), "{e}");
    }
}

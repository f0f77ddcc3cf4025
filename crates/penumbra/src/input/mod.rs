//! Input files, read as hostile: every file the renderer reads (scenes,
//! meshes, image files) comes through [`read_file`] or, for a reader that
//! judges a file by its first bytes before reading the rest, [`InputFile`];
//! every piece of one quoted in a message goes through [`quote`]. Image
//! files become linear pixels through [`image`].
//!
//! Both open without blocking (a named pipe with no writer would
//! otherwise wait for ever), judge the opened handle (symbolic links are
//! followed first) and refuse anything but a regular file, refuse a file
//! larger than its [`size_limit`], and read no more than the size the file had
//! when it was opened (a device or a growing file cannot make it read without
//! bound). The readers on top check every count in a file against the bytes
//! actually present before they allocate.

pub mod image;
pub mod quote;

use std::cell::RefCell;
use std::fmt;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The largest input file read unless [`MAX_FILE_SIZE_VAR`] or
/// [`set_max_file_size`] says otherwise: room for a real mesh of a few
/// gigabytes, while a runaway file is refused before it fills memory.
pub const DEFAULT_MAX_FILE_SIZE: u64 = 4 << 30;

/// The environment variable that sets the largest input file read, in bytes
/// or with a binary suffix: `PENUMBRA_MAX_FILE_SIZE=16G`.
pub const MAX_FILE_SIZE_VAR: &str = "PENUMBRA_MAX_FILE_SIZE";

thread_local! {
    /// The digests of the files read on this thread while recording.
    static READS: RefCell<Option<Vec<[u8; 32]>>> = const { RefCell::new(None) };
}

/// Runs `f` and returns, with its result, the SHA-256 digest of every
/// file it read on this thread, in the order read: what a render's
/// checkpoint is tied to besides its description.
pub fn recording_reads<R>(f: impl FnOnce() -> R) -> (R, Vec<[u8; 32]>) {
    let outer = READS.with(|r| r.borrow_mut().replace(Vec::new()));
    let result = f();
    let reads = READS.with(|r| std::mem::replace(&mut *r.borrow_mut(), outer));
    (result, reads.unwrap_or_default())
}

/// True while a recording runs on this thread.
pub fn is_recording() -> bool {
    READS.with(|r| r.borrow().is_some())
}

/// Records, in a recording running on this thread, the files of digests
/// `reads` as read now: a cache that skips reading files it read before
/// (`scene::WorldCache`) reports them, so that what a render depends on is
/// the same with or without the cache.
pub fn note_reads(reads: &[[u8; 32]]) {
    READS.with(|r| {
        if let Some(recorded) = r.borrow_mut().as_mut() {
            recorded.extend_from_slice(reads);
        }
    });
}

/// Records, in a recording running on this thread, a file of these bytes
/// as read now: for a reader that holds a file's text read earlier (the
/// Python API keeps a scene file's text and parses it again for each
/// render), so that a render depends on what the command line's does.
pub fn note_read(bytes: &[u8]) {
    READS.with(|r| {
        if let Some(reads) = r.borrow_mut().as_mut() {
            use sha2::Digest as _;
            reads.push(sha2::Sha256::digest(bytes).into());
        }
    });
}

/// The limit set in code (the command line's `--max-file-size`); 0: none set.
static LIMIT_SET: AtomicU64 = AtomicU64::new(0);

/// Sets the largest input file read, for the whole process; it wins over
/// [`MAX_FILE_SIZE_VAR`]. A limit of 0 is taken as 1 byte.
pub fn set_max_file_size(bytes: u64) {
    LIMIT_SET.store(bytes.max(1), Ordering::Relaxed);
}

/// The largest input file read: the one [`set_max_file_size`] set, else
/// [`MAX_FILE_SIZE_VAR`]'s, else `default` (each kind of file has its own:
/// [`DEFAULT_MAX_FILE_SIZE`] for meshes, a smaller one for scenes). An empty
/// variable counts as unset; a malformed one is an error rather than
/// silently the default.
pub fn size_limit(default: u64) -> Result<u64, InputError> {
    let set = LIMIT_SET.load(Ordering::Relaxed);
    if set > 0 {
        return Ok(set);
    }
    match std::env::var_os(MAX_FILE_SIZE_VAR).filter(|v| !v.is_empty()) {
        None => Ok(default),
        Some(v) => {
            let text = v.to_string_lossy();
            parse_size(&text).ok_or_else(|| InputError::Limit {
                value: quote::clip(&text, quote::MAX_QUOTED_CHARS).into_owned(),
            })
        }
    }
}

/// A size in bytes: a whole number with an optional binary suffix, `K`, `M`,
/// `G` or `T` (also `KiB`, `MB`, ...; any case), as `--max-file-size 8G`.
/// `None` for anything else, zero or more than 2^64 − 1 bytes.
pub fn parse_size(text: &str) -> Option<u64> {
    let t = text.trim();
    let digits = t.bytes().take_while(u8::is_ascii_digit).count();
    let (number, suffix) = t.split_at(digits);
    let n: u64 = number.parse().ok()?;
    let shift = match suffix.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return None,
    };
    let bytes = n.checked_mul(1 << shift)?;
    (bytes > 0).then_some(bytes)
}

/// Why an input file was not read. Every message starts with the file's path.
#[derive(Debug)]
pub enum InputError {
    /// Opening or reading failed (no such file, permission, ...).
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A FIFO, socket, device or directory.
    NotRegular { path: PathBuf, kind: &'static str },
    /// Larger than the limit.
    TooLarge {
        path: PathBuf,
        size: u64,
        limit: u64,
    },
    /// [`MAX_FILE_SIZE_VAR`] is not a size.
    Limit { value: String },
}

impl InputError {
    /// The file the error is about, if any.
    pub fn path(&self) -> Option<&Path> {
        match self {
            InputError::Io { path, .. }
            | InputError::NotRegular { path, .. }
            | InputError::TooLarge { path, .. } => Some(path),
            InputError::Limit { .. } => None,
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InputError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            InputError::NotRegular { path, kind } => write!(
                f,
                "{}: is {kind}, not a regular file; only regular files are read",
                path.display()
            ),
            InputError::TooLarge { path, size, limit } => write!(
                f,
                "{}: the file is {size} bytes, more than the limit of {limit} bytes \
                 (raise it with --max-file-size or {MAX_FILE_SIZE_VAR})",
                path.display()
            ),
            InputError::Limit { value } => write!(
                f,
                "{MAX_FILE_SIZE_VAR}={value} is not a size: give bytes, or a number \
                 with K, M, G or T (for example 8G)"
            ),
        }
    }
}

impl std::error::Error for InputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            InputError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Reads a whole input file, bounded by [`size_limit`] with the default
/// [`DEFAULT_MAX_FILE_SIZE`].
pub fn read_file(path: &Path) -> Result<Vec<u8>, InputError> {
    read_file_within(path, size_limit(DEFAULT_MAX_FILE_SIZE)?)
}

/// Reads a whole input file of at most `limit` bytes: a regular file only
/// (after following symbolic links), opened without blocking, and no more
/// bytes than it had when it was opened.
pub fn read_file_within(path: &Path, limit: u64) -> Result<Vec<u8>, InputError> {
    InputFile::open(path, limit)?.read_rest(Vec::new())
}

/// An input file opened and judged (a regular file within its size limit),
/// not yet read: a reader can look at its first bytes and refuse a file
/// that is not of its format before reading the rest.
pub struct InputFile {
    path: PathBuf,
    file: File,
    size: u64,
}

impl InputFile {
    /// Opens `path` without blocking and refuses anything but a regular file
    /// of at most `limit` bytes.
    pub fn open(path: &Path, limit: u64) -> Result<InputFile, InputError> {
        let file = open(path)?;
        // The opened handle is judged, not the path: what is read is what was checked.
        let meta = file.metadata().map_err(|e| io_error(path, e))?;
        if let Some(kind) = not_regular(&meta.file_type()) {
            return Err(InputError::NotRegular {
                path: path.to_path_buf(),
                kind,
            });
        }
        let size = meta.len();
        if size > limit {
            return Err(InputError::TooLarge {
                path: path.to_path_buf(),
                size,
                limit,
            });
        }
        Ok(InputFile {
            path: path.to_path_buf(),
            file,
            size,
        })
    }

    /// The file's size when it was opened.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Its first `n` bytes (all of it if it is shorter).
    pub fn read_head(&mut self, n: usize) -> Result<Vec<u8>, InputError> {
        let n = (n as u64).min(self.size);
        let mut head = Vec::with_capacity(n as usize);
        (&self.file)
            .take(n)
            .read_to_end(&mut head)
            .map_err(|e| io_error(&self.path, e))?;
        Ok(head)
    }

    /// The whole file: `head` (what [`read_head`](Self::read_head) gave, or
    /// nothing) followed by the rest, up to the size the file had when it
    /// was opened.
    pub fn read_rest(self, head: Vec<u8>) -> Result<Vec<u8>, InputError> {
        let mut bytes = head;
        let rest = self.size.saturating_sub(bytes.len() as u64);
        let room = usize::try_from(rest)
            .ok()
            .and_then(|r| bytes.try_reserve_exact(r).ok());
        if room.is_none() {
            return Err(io_error(
                &self.path,
                std::io::Error::new(
                    std::io::ErrorKind::OutOfMemory,
                    format!("cannot allocate {} bytes to read the file", self.size),
                ),
            ));
        }
        // `take`: a file that grows while it is read is read as it was at open time.
        (&self.file)
            .take(rest)
            .read_to_end(&mut bytes)
            .map_err(|e| io_error(&self.path, e))?;
        note_read(&bytes);
        Ok(bytes)
    }
}

fn io_error(path: &Path, source: std::io::Error) -> InputError {
    InputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Opens for reading without waiting: on Unix with `O_NONBLOCK`, so that a
/// FIFO without a writer opens at once (to be refused), and with `O_NOCTTY`,
/// so that a terminal named as input never becomes the controlling one.
fn open(path: &Path) -> Result<File, InputError> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY);
    }
    options.open(path).map_err(|source| {
        // A socket cannot be opened at all; say what it is rather than ENXIO.
        match std::fs::metadata(path)
            .ok()
            .and_then(|m| not_regular(&m.file_type()))
        {
            Some(kind) => InputError::NotRegular {
                path: path.to_path_buf(),
                kind,
            },
            None => InputError::Io {
                path: path.to_path_buf(),
                source,
            },
        }
    })
}

/// What a file that is not a regular file is, in words; `None` for a regular file.
fn not_regular(t: &std::fs::FileType) -> Option<&'static str> {
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a named pipe (FIFO)");
        }
        if t.is_socket() {
            return Some("a socket");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
    }
    Some("not a regular file")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_are_recorded_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::fs::write(&a, b"one").unwrap();
        std::fs::write(&b, b"two").unwrap();
        let ((), reads) = recording_reads(|| {
            read_file_within(&a, 10).unwrap();
            let ((), inner) = recording_reads(|| {
                read_file_within(&b, 10).unwrap();
            });
            assert_eq!(inner.len(), 1);
            read_file_within(&b, 10).unwrap();
        });
        use sha2::Digest as _;
        let sha = |b: &[u8]| -> [u8; 32] { sha2::Sha256::digest(b).into() };
        assert_eq!(reads, vec![sha(b"one"), sha(b"two")]);
        read_file_within(&a, 10).unwrap();
    }

    #[test]
    fn sizes_take_binary_suffixes() {
        assert_eq!(parse_size("123"), Some(123));
        assert_eq!(parse_size("4K"), Some(4096));
        assert_eq!(parse_size("2 MiB"), Some(2 << 20));
        assert_eq!(parse_size("8g"), Some(8 << 30));
        assert_eq!(parse_size("1TB"), Some(1 << 40));
        for bad in [
            "",
            "0",
            "G",
            "-1",
            "1.5G",
            "12X",
            "99999999999999999999",
            "16777216T",
        ] {
            assert_eq!(parse_size(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn a_regular_file_is_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        std::fs::write(&path, b"hello").unwrap();
        assert_eq!(read_file_within(&path, 5).unwrap(), b"hello");
    }

    #[test]
    fn the_head_and_the_rest_make_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        std::fs::write(&path, b"0123456789").unwrap();
        let mut f = InputFile::open(&path, 10).unwrap();
        assert_eq!(f.size(), 10);
        let head = f.read_head(4).unwrap();
        assert_eq!(head, b"0123");
        assert_eq!(f.read_rest(head).unwrap(), b"0123456789");
        let mut f = InputFile::open(&path, 10).unwrap();
        let head = f.read_head(100).unwrap();
        assert_eq!(f.read_rest(head).unwrap(), b"0123456789");
    }

    #[test]
    fn a_file_is_read_as_long_as_it_was_at_open() {
        use std::io::Write;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("growing.obj");
        std::fs::write(&path, b"v 0 0 0\n").unwrap();
        let f = InputFile::open(&path, 1 << 20).unwrap();
        let mut more = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .unwrap();
        more.write_all(&[b'x'; 4096]).unwrap();
        assert_eq!(f.read_rest(Vec::new()).unwrap(), b"v 0 0 0\n");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_before_reading() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.ply");
        std::fs::write(&path, b"0123456789").unwrap();
        let e = read_file_within(&path, 9).unwrap_err();
        assert!(matches!(e, InputError::TooLarge { size: 10, .. }), "{e:?}");
        let m = e.to_string();
        assert!(m.starts_with(&format!("{}: ", path.display())), "{m}");
        assert!(
            m.contains("--max-file-size") && m.contains(MAX_FILE_SIZE_VAR),
            "{m}"
        );
    }

    #[test]
    fn a_directory_is_refused_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_file_within(dir.path(), 1 << 20).unwrap_err();
        assert!(
            matches!(
                e,
                InputError::NotRegular {
                    kind: "a directory",
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().starts_with(&dir.path().display().to_string()));
    }

    #[test]
    fn a_missing_file_is_an_io_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("none.toml");
        let e = read_file_within(&path, 1 << 20).unwrap_err();
        assert!(matches!(e, InputError::Io { .. }), "{e:?}");
        assert_eq!(e.path(), Some(path.as_path()));
    }

    #[cfg(unix)]
    #[test]
    fn devices_are_refused_at_once() {
        let start = std::time::Instant::now();
        for dev in ["/dev/zero", "/dev/urandom", "/dev/null"] {
            let path = Path::new(dev);
            if !path.exists() {
                eprintln!("skipped: {dev} does not exist here");
                continue;
            }
            let e = read_file_within(path, u64::MAX).unwrap_err();
            assert!(
                matches!(
                    e,
                    InputError::NotRegular {
                        kind: "a character device",
                        ..
                    }
                ),
                "{dev}: {e:?}"
            );
        }
        assert!(start.elapsed().as_secs() < 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_and_a_link_to_it_are_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe.ply");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !matches!(made, Ok(s) if s.success()) {
            eprintln!("skipped: cannot make a FIFO here (mkfifo: {made:?})");
            return;
        }
        let link = dir.path().join("link.ply");
        std::os::unix::fs::symlink(&fifo, &link).unwrap();
        let start = std::time::Instant::now();
        for path in [&fifo, &link] {
            let e = read_file_within(path, u64::MAX).unwrap_err();
            assert!(
                matches!(
                    e,
                    InputError::NotRegular {
                        kind: "a named pipe (FIFO)",
                        ..
                    }
                ),
                "{e:?}"
            );
            assert!(e.to_string().starts_with(&path.display().to_string()));
        }
        assert!(start.elapsed().as_secs() < 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_socket_is_refused_as_a_socket() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        let _listener = std::os::unix::net::UnixListener::bind(&path).unwrap();
        let e = read_file_within(&path, u64::MAX).unwrap_err();
        assert!(
            matches!(
                e,
                InputError::NotRegular {
                    kind: "a socket",
                    ..
                }
            ),
            "{e:?}"
        );
    }

    #[test]
    fn a_malformed_variable_is_reported_not_ignored() {
        // Parsing only: the process's environment is shared by parallel tests.
        let e = InputError::Limit {
            value: "lots".into(),
        };
        assert!(e.to_string().contains(MAX_FILE_SIZE_VAR));
    }
}

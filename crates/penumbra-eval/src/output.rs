//! Writing the report's files: atomically (through the library's writer, so
//! an interrupted run never leaves half a file) and readable by others.

use std::path::Path;

use crate::error::EvalError;

/// Writes `bytes` to `path` atomically. The library's temporary files are
/// private (mode 0600), which would make a report directory unreadable to a
/// web server or another user; the files get the usual 0644 instead.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), EvalError> {
    let err = |message: String| EvalError::Write {
        path: path.to_path_buf(),
        message,
    };
    penumbra::io::output::write_bytes(path, bytes).map_err(|e| err(e.to_string()))?;
    readable(path).map_err(|e| err(e.to_string()))
}

#[cfg(unix)]
fn readable(path: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o644))
}

#[cfg(not(unix))]
fn readable(_path: &Path) -> std::io::Result<()> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_written_whole_and_readable() {
        let Ok(dir) = tempfile::tempdir() else { return };
        let p = dir.path().join("a.txt");
        assert!(write_file(&p, b"hello").is_ok());
        assert_eq!(std::fs::read(&p).ok(), Some(b"hello".to_vec()));
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&p).map(|m| m.permissions().mode() & 0o777);
            assert_eq!(mode.ok(), Some(0o644));
        }
        let missing = dir.path().join("no/such/dir/a.txt");
        assert!(matches!(
            write_file(&missing, b"x"),
            Err(EvalError::Write { .. })
        ));
    }
}

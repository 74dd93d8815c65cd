//! Write to a temporary file in the target directory, then rename over the target.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::IoError;

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path` through a temporary file in the same directory (created
/// exclusively, synced) and a rename over `path`, so that readers never see a partial file.
///
/// # Errors
/// [`IoError::Io`] naming `path`; the temporary file is removed on failure.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |file| {
        file.write_all(bytes).map_err(|source| IoError::Io {
            path: path.to_path_buf(),
            source,
        })
    })
}

/// Whether [`write_atomic`] could create its temporary file beside `path`: creates one as it
/// would (exclusively, same name pattern) and removes it at once, touching nothing else. For
/// commands that write after minutes of work, to fail before it when the folder does not
/// take files (no permission, a read-only file system, a pseudo-file system such as
/// `/proc`).
///
/// # Errors
/// The [`std::io::Error`] of creating the file.
pub fn probe_writable(path: &Path) -> Result<(), std::io::Error> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let probe = dir.join(format!(
        ".algesurf-probe.{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)?;
    std::fs::remove_file(&probe)
}

/// [`write_atomic`] for content that `fill` writes in pieces (a writer streaming a large mesh,
/// so that no copy of the whole file is built in memory first). `fill`'s error is returned
/// as it is, and the temporary file removed.
pub(crate) fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let io_err = |source| IoError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let tmp = dir.join(format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(io_err)?;
    let result = fill(&mut file).and_then(|()| {
        file.sync_all()
            .and_then(|()| {
                drop(file);
                std::fs::rename(&tmp, path)
            })
            .map_err(io_err)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

//! Write to a temporary file in the target directory, then rename over the target.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use algesurf_mesh::progress::{Cancelled, Progress};

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

/// The largest piece a cancellable write hands to the file at once ([`Watched`]): a megabyte
/// takes a few milliseconds to copy into the page cache, so a stop is answered at once.
pub(crate) const PIECE: usize = 1 << 20;

/// A writer that reports the bytes it passes on to a [`Progress`] sink and refuses to write
/// once the sink is [cancelled](Progress::cancelled), so that a stopped write ends at its
/// next piece: it passes on at most [`PIECE`] bytes per `write` (the streamed writers hand
/// over blocks of [`crate::blocks::BLOCK`] elements, under a megabyte; a buffer made in
/// memory is cut into pieces).
pub(crate) struct Watched<'a> {
    inner: &'a mut dyn Write,
    progress: &'a dyn Progress,
}

impl<'a> Watched<'a> {
    pub(crate) fn new(inner: &'a mut dyn Write, progress: &'a dyn Progress) -> Self {
        Watched { inner, progress }
    }
}

impl Write for Watched<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.progress.cancelled() {
            // Not `ErrorKind::Interrupted`: `write_all` retries that one.
            return Err(std::io::Error::other(Cancelled));
        }
        // At most a piece at a time, so that `write_all` of a large buffer (a glTF's JSON
        // with its data URI, an OBJ built in memory) comes back here between pieces.
        let n = self.inner.write(&buf[..buf.len().min(PIECE)])?;
        self.progress.advance(n as u64);
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

//! Write to a temporary file in the target directory, then rename over the target (following
//! symbolic links; devices and named pipes are written in place).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use algesurf_mesh::progress::{Cancelled, Progress};

use crate::IoError;

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path` through a temporary file in the same directory (created
/// exclusively, synced) and a rename over `path`, so that readers never see a partial file.
/// A symbolic link is followed (the file it points at is replaced, and the link stays a
/// link); a device or named pipe (`/dev/null`, a FIFO) is written in place, not replaced.
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

/// Where a write to a path goes ([`destination`]).
#[derive(Debug, PartialEq, Eq)]
enum Destination {
    /// A regular file, or a name that does not exist yet: written to a temporary file in the
    /// folder of `file` and renamed over it. `file` is the path with its symbolic links
    /// followed, so that a link stays a link and its target gets the new content (renaming
    /// over the link itself would replace the user's link by a plain file).
    Replace { file: PathBuf },
    /// An existing file that is neither a regular file nor a folder: a device such as
    /// `/dev/null`, a named pipe, a socket. Written in place: renaming over it would replace
    /// the device or pipe by a plain file (for `/dev/null`, as root, the whole system's).
    InPlace { file: PathBuf },
}

/// The most symbolic links followed from one path: Linux's own limit (`MAXSYMLINKS`), past
/// which `open` fails with `ELOOP`; the write then fails there too, naming the path.
const MAX_LINKS: usize = 40;

/// Where a write to `path` goes: an existing file as the kernel finds it (every symbolic
/// link followed, `/proc`'s links to open files such as `/dev/stdout` too), or for a name
/// that does not exist yet, the name its links lead to (a link that points at a file not yet
/// made, perhaps through other links).
fn destination(path: &Path) -> Destination {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() && !m.is_dir() => Destination::InPlace {
            file: path.to_path_buf(),
        },
        Ok(m) if m.is_file() => Destination::Replace {
            file: std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
        },
        // A folder stays `path`: the rename fails there, naming it.
        _ => Destination::Replace {
            file: links_followed(path),
        },
    }
}

/// `path` with its symbolic links followed one by one, for a path that does not resolve to an
/// existing file (where `canonicalize` fails): a link to a name not yet made, a chain of them.
fn links_followed(path: &Path) -> PathBuf {
    let mut file = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&file) {
            Ok(m) if m.file_type().is_symlink() => match std::fs::read_link(&file) {
                // A relative target is relative to the link's folder.
                Ok(target) => file = parent_folder(&file).join(target),
                Err(_) => break,
            },
            _ => break,
        }
    }
    file
}

/// The folder `path` is in (`.` for a bare file name).
fn parent_folder(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Whether [`write_atomic`] could create its temporary file beside `path` (beside the file a
/// symbolic link `path` points at): creates one as it would (exclusively, same name pattern)
/// and removes it at once, touching nothing else. For commands that write after minutes of
/// work, to fail before it when the folder does not take files (no permission, a read-only
/// file system, a pseudo-file system such as `/proc`). A device or named pipe (written in
/// place, not replaced) is not opened: opening a pipe waits for its reader.
///
/// # Errors
/// The [`std::io::Error`] of creating the file.
pub fn probe_writable(path: &Path) -> Result<(), std::io::Error> {
    let Destination::Replace { file } = destination(path) else {
        return Ok(());
    };
    let probe = parent_folder(&file).join(format!(
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
/// as it is, and the temporary file removed. A symbolic link is followed and stays a link; a
/// device or named pipe is written in place ([`Destination`]). Errors name `path` as given.
pub(crate) fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let io_err = |source| IoError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = match destination(path) {
        Destination::InPlace { file } => {
            // No `sync_all`: a device or pipe has nothing to make durable (and `fsync` on one
            // fails with `EINVAL` on Linux).
            let mut out = std::fs::OpenOptions::new()
                .write(true)
                .open(&file)
                .map_err(io_err)?;
            return fill(&mut out);
        }
        Destination::Replace { file } => file,
    };
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let tmp = parent_folder(&file).join(format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let mut out = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(io_err)?;
    let result = fill(&mut out).and_then(|()| {
        out.sync_all()
            .and_then(|()| {
                drop(out);
                std::fs::rename(&tmp, &file)
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

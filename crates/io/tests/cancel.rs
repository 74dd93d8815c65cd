//! A cancelled write (`write_with_progress` whose sink says stop, as the command's Ctrl-C
//! does) leaves the target as it was and no temporary file behind, in every format, whether
//! the stop comes before the write or in its middle; an uncancelled one writes the bytes of
//! `write` and reports them.

mod common;

use algesurf_io::{Format, IoError, WriteOptions, write, write_bytes, write_with_progress};
use algesurf_mesh::progress::Progress;
use common::grid;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// A sink that says stop once `after` bytes have been reported written.
struct StopAfter {
    after: u64,
    written: AtomicU64,
}

impl StopAfter {
    fn new(after: u64) -> Self {
        StopAfter {
            after,
            written: AtomicU64::new(0),
        }
    }
}

impl Progress for StopAfter {
    fn start(&self, _name: &str, _total: u64) {}
    fn advance(&self, units: u64) {
        self.written.fetch_add(units, Ordering::Relaxed);
    }
    fn cancelled(&self) -> bool {
        self.written.load(Ordering::Relaxed) >= self.after
    }
}

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

#[test]
fn a_cancelled_write_leaves_the_old_file_and_no_temporary() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-cancel-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Several megabytes in every format, so that a stop after the first piece comes while
    // most of the file is still to be written.
    let mesh = grid(400, 300, true);
    let options = WriteOptions::default();
    for format in Format::ALL {
        let path = dir.join(format!("big.{}", format.extension()));
        // Uncancelled: the bytes of `write`, all of them reported.
        let counted = StopAfter::new(u64::MAX);
        write_with_progress(&path, &mesh, &options, &counted).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        if format != Format::Gltf {
            // (a .gltf's buffer is a data URI of the same bytes; its JSON is what is written)
            assert!(
                bytes == write_bytes(&mesh, format, &options).unwrap(),
                "{format}"
            );
        }
        assert_eq!(
            counted.written.load(Ordering::Relaxed),
            bytes.len() as u64,
            "{format}"
        );
        assert!(bytes.len() > 2 << 20, "{format}: {} bytes", bytes.len());
        // The old file is something else, so that "left as it was" can be seen.
        std::fs::write(&path, b"the user's file").unwrap();
        for after in [0, 1] {
            let stop = StopAfter::new(after);
            let e = write_with_progress(&path, &mesh, &options, &stop).unwrap_err();
            assert!(
                matches!(&e, IoError::Cancelled { path: p } if p == &path),
                "{format}, stop after {after} bytes: {e}"
            );
            assert!(e.to_string().contains("cancelled"), "{e}");
            assert_eq!(std::fs::read(&path).unwrap(), b"the user's file");
            assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
            // Stopped in the middle: some bytes went to the temporary file, not all.
            let written = stop.written.load(Ordering::Relaxed);
            assert!(written < bytes.len() as u64, "{format}: {written} bytes");
        }
        // A cancelled write of a file that did not exist leaves none.
        std::fs::remove_file(&path).unwrap();
        let e = write_with_progress(&path, &mesh, &options, &StopAfter::new(1)).unwrap_err();
        assert!(matches!(e, IoError::Cancelled { .. }), "{e}");
        assert!(!path.exists());
        assert!(temporaries(&dir).is_empty());
    }
    // `write` is the same writer with no sink: the same bytes.
    let path = dir.join("plain.ply");
    write(&path, &mesh, &options).unwrap();
    assert!(std::fs::read(&path).unwrap() == write_bytes(&mesh, Format::Ply, &options).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}

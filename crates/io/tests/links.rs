//! Writes follow symbolic links and keep them (the file a link points at gets the new
//! content), and write devices and named pipes in place instead of replacing them by a plain
//! file: a user's links, pipes and `/dev/null` are theirs, and renaming a temporary file over
//! them would lose them (as root, `/dev/null` itself; not tested on the device: a regression
//! would replace the machine's). The pipe stands for every such file: it takes the same path.
#![cfg(unix)]

mod common;

use std::io::Read;
use std::os::unix::fs::{FileTypeExt, symlink};
use std::path::Path;
use std::process::Command;
use std::time::Duration;

use algesurf_io::{Format, WriteOptions, probe_writable, write, write_as, write_bytes};
use common::tetrahedron;

fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// No `.tmp` file anywhere under `dir`.
fn assert_no_temporaries(dir: &Path) {
    for entry in std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()) {
        let path = entry.path();
        assert!(!path.to_string_lossy().ends_with(".tmp"), "{path:?}");
        if entry.file_type().unwrap().is_dir() {
            assert_no_temporaries(&path);
        }
    }
}

#[test]
fn a_symbolic_link_stays_a_link_and_its_target_gets_the_content() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-links-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for sub in ["a", "b"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
    }
    let mesh = tetrahedron();
    let options = WriteOptions::default();
    let expected = write_bytes(&mesh, Format::Ply, &options).unwrap();

    // A relative link into another folder, to an existing file.
    std::fs::write(dir.join("b/real.ply"), b"old").unwrap();
    symlink("../b/real.ply", dir.join("a/out.ply")).unwrap();
    probe_writable(&dir.join("a/out.ply")).unwrap();
    write(dir.join("a/out.ply"), &mesh, &options).unwrap();
    assert!(is_link(&dir.join("a/out.ply")));
    assert!(std::fs::read(dir.join("b/real.ply")).unwrap() == expected);

    // A link to a link to a file that does not exist yet: made, both links kept.
    symlink("new.ply", dir.join("b/second.ply")).unwrap();
    symlink(dir.join("b/second.ply"), dir.join("a/first.ply")).unwrap();
    write(dir.join("a/first.ply"), &mesh, &options).unwrap();
    assert!(is_link(&dir.join("a/first.ply")) && is_link(&dir.join("b/second.ply")));
    assert!(std::fs::read(dir.join("b/new.ply")).unwrap() == expected);

    // A link into a folder that does not exist: the probe says so (it looks where the
    // temporary file would go, not beside the link), and the write fails naming the link.
    symlink("../missing/x.ply", dir.join("a/nowhere.ply")).unwrap();
    assert!(probe_writable(&dir.join("a/nowhere.ply")).is_err());
    let e = write(dir.join("a/nowhere.ply"), &mesh, &options).unwrap_err();
    assert!(e.to_string().contains("nowhere.ply"), "{e}");
    assert!(is_link(&dir.join("a/nowhere.ply")));

    assert_no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_named_pipe_is_written_in_place() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-fifo-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("out.ply");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    // The probe does not open the pipe (that would wait for a reader).
    probe_writable(&fifo).unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let reading = fifo.clone();
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let r = std::fs::File::open(&reading).and_then(|mut f| f.read_to_end(&mut bytes));
        let _ = tx.send(r.map(|_| bytes));
    });
    let mesh = tetrahedron();
    let options = WriteOptions::default();
    write_as(&fifo, &mesh, Format::Ply, &options).unwrap();
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(kind.is_fifo(), "the pipe was replaced: {kind:?}");
    let read = rx.recv_timeout(Duration::from_secs(30)).unwrap().unwrap();
    assert!(read == write_bytes(&mesh, Format::Ply, &options).unwrap());
    assert_no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

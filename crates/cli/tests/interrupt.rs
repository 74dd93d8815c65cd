//! Ctrl-C (SIGINT) and SIGTERM stop `algesurf smooth` cleanly: exit status 128 + the signal,
//! a message saying so, the user's existing output file as it was, and no temporary file
//! left beside it. Linux only: the tests wait for the handler through `/proc/PID/status`.
#![cfg(target_os = "linux")]

mod common;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use common::{TempDir, obj_bytes, send, wait_for_handler};

use algesurf_mesh::shapes;

/// Starts `algesurf ARGS` in `dir`, its output captured.
fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_algesurf"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start algesurf")
}

/// The files in `dir` whose names end in `.tmp` (a write's temporary file).
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// The signal comes while the command waits for its input (a named pipe that nothing has
/// written yet), so the order is certain: the command reads the mesh, sees the signal after
/// that stage and stops before building or writing anything. `smooth` and `convert`, with
/// SIGINT and SIGTERM.
#[test]
fn a_signal_while_reading_stops_the_command_with_128_plus_the_signal() {
    let commands: [&[&str]; 2] = [
        &["smooth", "in.obj", "-o", "out.ply"],
        &["convert", "in.obj", "out.ply", "--repair"],
    ];
    for (args, (signal, number, status, said)) in commands.into_iter().flat_map(|c| {
        [
            ("INT", 2, 130, "interrupted by Ctrl-C (SIGINT)"),
            ("TERM", 15, 143, "interrupted by SIGTERM"),
        ]
        .map(|s| (c, s))
    }) {
        let dir = TempDir::new("interrupt", &format!("{}-{signal}", args[0]));
        let fifo = dir.path().join("in.obj");
        let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
        assert!(made.success());
        std::fs::write(dir.path().join("out.ply"), b"the user's file").unwrap();
        let child = spawn(dir.path(), args);
        wait_for_handler(child.id(), number);
        send(child.id(), signal);
        // Only now does the input arrive; the command is blocked opening the pipe until then.
        std::fs::write(&fifo, obj_bytes(&shapes::icosphere(1).to_polygon_mesh())).unwrap();
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(status),
            "{args:?}, {signal}: {stderr}"
        );
        assert!(stderr.contains(said), "{args:?}, {signal}: {stderr}");
        assert!(stderr.contains("no output was written"), "{stderr}");
        assert_eq!(
            std::fs::read(dir.path().join("out.ply")).unwrap(),
            b"the user's file"
        );
        assert!(temporaries(dir.path()).is_empty());
    }
}

/// Ctrl-C in the middle of a run of a few seconds (a 5120-face icosphere tessellated into
/// millions of triangles): whichever stage it lands in (the construction and tessellation
/// stop at their next batch of faces or patches, the write at its next megabyte), the
/// command exits with 130 and leaves the user's file as it was, with no temporary file.
#[test]
fn ctrl_c_during_a_run_stops_it_and_keeps_the_users_file() {
    let dir = TempDir::new("interrupt", "midway");
    std::fs::write(
        dir.path().join("in.obj"),
        obj_bytes(&shapes::icosphere(4).to_polygon_mesh()),
    )
    .unwrap();
    std::fs::write(dir.path().join("out.ply"), b"the user's file").unwrap();
    let child = spawn(
        dir.path(),
        &["smooth", "in.obj", "-o", "out.ply", "--resolution", "24"],
    );
    wait_for_handler(child.id(), 2);
    std::thread::sleep(Duration::from_millis(300));
    send(child.id(), "INT");
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted by Ctrl-C"), "{stderr}");
    assert_eq!(
        std::fs::read(dir.path().join("out.ply")).unwrap(),
        b"the user's file"
    );
    assert!(temporaries(dir.path()).is_empty());
}

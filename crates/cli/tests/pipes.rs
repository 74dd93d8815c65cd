//! A closed pipe on stdout or stderr (`algesurf info big.ply | head`, a log reader that went
//! away) is not a panic: the commands finish their work, write their files and exit with the
//! status they would have had. Rust ignores `SIGPIPE`, so such a write fails with
//! `BrokenPipe`, on which `println!` and `eprintln!` panic (exit status 101).

mod common;

use std::process::{Command, Output, Stdio};

use common::{TempDir, obj_bytes};

use algesurf_mesh::shapes;

/// Which of the command's streams goes to a pipe whose reading end is already closed.
#[derive(Clone, Copy, Debug)]
enum Closed {
    Stdout,
    Stderr,
}

/// Runs `algesurf ARGS` in `dir` with `closed` a pipe that nobody reads (its reading end is
/// closed before the command starts, so every write to it fails), the other stream captured.
fn run_with_closed(dir: &std::path::Path, args: &[&str], closed: Closed) -> Output {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let mut command = Command::new(env!("CARGO_BIN_EXE_algesurf"));
    command.current_dir(dir).args(args);
    match closed {
        Closed::Stdout => command.stdout(writer).stderr(Stdio::piped()),
        Closed::Stderr => command.stderr(writer).stdout(Stdio::piped()),
    };
    command.output().expect("run algesurf")
}

#[test]
fn a_closed_pipe_is_not_a_panic() {
    let dir = TempDir::new("pipes", "closed");
    let mesh = shapes::icosphere(1).to_polygon_mesh();
    let obj = obj_bytes(&mesh);
    std::fs::write(dir.path().join("ball.obj"), obj).unwrap();
    let cases: [(&[&str], Closed, i32, Option<&str>); 6] = [
        (&["info", "ball.obj"], Closed::Stdout, 0, None),
        (
            &["smooth", "ball.obj", "-o", "ball.ply"],
            Closed::Stdout,
            0,
            Some("ball.ply"),
        ),
        (
            &["render", "--smooth", "--size", "48x48", "-o", "ball.png"],
            Closed::Stdout,
            0,
            Some("ball.png"),
        ),
        (&["check", "ball.obj"], Closed::Stdout, 0, None),
        // Messages on a closed stderr: a repair report, then an error's.
        (
            &["convert", "ball.obj", "ball.off", "--repair"],
            Closed::Stderr,
            0,
            Some("ball.off"),
        ),
        (
            &["smooth", "missing.obj", "-o", "x.ply"],
            Closed::Stderr,
            1,
            None,
        ),
    ];
    for (args, closed, status, made) in cases {
        let out = run_with_closed(dir.path(), args, closed);
        let seen = format!(
            "{args:?} with {closed:?} closed: status {:?}\nstdout: {}\nstderr: {}",
            out.status.code(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(out.status.code(), Some(status), "{seen}");
        assert!(
            !String::from_utf8_lossy(&out.stderr).contains("panicked"),
            "{seen}"
        );
        if let Some(file) = made {
            let path = dir.path().join(file);
            assert!(path.metadata().is_ok_and(|m| m.len() > 0), "{seen}");
            std::fs::remove_file(path).unwrap();
        }
    }
}

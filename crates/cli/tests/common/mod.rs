//! Helpers shared by the end-to-end tests of the `algesurf` binary.
// Each test binary compiles this module and uses only some of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh, empty directory for one test, removed when dropped.
pub struct TempDir(PathBuf);

impl TempDir {
    /// `algesurf-{command}-{name}-{pid}` under the system temp dir.
    pub fn new(command: &str, name: &str) -> TempDir {
        let dir =
            std::env::temp_dir().join(format!("algesurf-{command}-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the binary in `dir`.
pub fn algesurf(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_algesurf"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run algesurf")
}

/// Status, stdout and stderr, for assertion messages.
pub fn text(out: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// The field `name` of `/proc/PID/status` (`pid` a process id or `self`), trimmed; `None`
/// when the process or the field is not there (a kernel too old for it).
#[cfg(target_os = "linux")]
pub fn proc_status_field(pid: &str, name: &str) -> Option<String> {
    std::fs::read_to_string(format!("/proc/{pid}/status"))
        .ok()?
        .lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(':'))
        .map(|v| v.trim().to_owned())
}

/// Waits until `pid` catches `signal` (its bit in `SigCgt` of `/proc/PID/status`): the
/// handler is installed first thing in `main`, so this is microseconds after the start, but a
/// signal sent before it would end the process by the default action and prove nothing.
#[cfg(target_os = "linux")]
pub fn wait_for_handler(pid: u32, signal: u32) {
    let start = std::time::Instant::now();
    loop {
        let caught = proc_status_field(&pid.to_string(), "SigCgt")
            .and_then(|m| u64::from_str_radix(&m, 16).ok())
            .is_some_and(|mask| mask & (1 << (signal - 1)) != 0);
        if caught {
            return;
        }
        assert!(
            start.elapsed() < std::time::Duration::from_secs(30),
            "the process never installed its handler for signal {signal}"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// Sends `signal` (a name for `kill -s`: `INT`, `TERM`) to `pid`.
#[cfg(unix)]
pub fn send(pid: u32, signal: &str) {
    let ok = Command::new("kill")
        .args(["-s", signal, &pid.to_string()])
        .status()
        .expect("run kill")
        .success();
    assert!(ok, "kill -s {signal} {pid}");
}

/// `mesh` as the bytes of an OBJ file.
pub fn obj_bytes(mesh: &algesurf_mesh::PolygonMesh) -> Vec<u8> {
    algesurf_io::write_bytes(
        mesh,
        algesurf_io::Format::Obj,
        &algesurf_io::WriteOptions::default(),
    )
    .unwrap()
}

/// Writes the triangle mesh `mesh` to `dir/name`, in the format its extension names.
pub fn write_tri_mesh(dir: &TempDir, name: &str, mesh: &algesurf_mesh::TriMesh) {
    let polygons =
        algesurf_mesh::PolygonMesh::from_triangles(mesh.positions().to_vec(), mesh.triangles());
    algesurf_io::write(
        dir.path().join(name),
        &polygons,
        &algesurf_io::WriteOptions::default(),
    )
    .unwrap_or_else(|e| panic!("write {name}: {e}"));
}

/// The JSON file `dir/name` (a command's `--report` or `--json` output), parsed.
pub fn read_json(dir: &TempDir, name: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.path().join(name))
        .unwrap_or_else(|e| panic!("read {name}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{name} is not JSON: {e}"))
}

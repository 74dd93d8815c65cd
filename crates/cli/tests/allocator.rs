//! The command runs with transparent huge pages off (`prctl(PR_SET_THP_DISABLE)` in `main`,
//! see `allocator::no_transparent_huge_pages` in `src/main.rs` for the measurements), and
//! `MIMALLOC_ALLOW_THP` in the environment hands the choice back to mimalloc. Linux only: the
//! tests read the flag from `/proc/PID/status` (`THP_enabled`, Linux 5.0 and later).
#![cfg(target_os = "linux")]

mod common;

use std::process::{Command, Stdio};

use algesurf_mesh::shapes;
use common::{TempDir, obj_bytes, proc_status_field, send, wait_for_handler};

/// `THP_enabled` of `algesurf smooth` while it waits for its input (a named pipe), with
/// `MIMALLOC_ALLOW_THP` set to `allow` or removed. The flag is set before the signal handler
/// is installed, so once the handler is there the value is final; the process is then
/// stopped with SIGTERM and given its input, as in `interrupt.rs`.
fn thp_of_a_running_command(name: &str, allow: Option<&str>) -> String {
    let dir = TempDir::new("allocator", name);
    let fifo = dir.path().join("in.obj");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    let mut command = Command::new(env!("CARGO_BIN_EXE_algesurf"));
    command
        .current_dir(dir.path())
        .args(["smooth", "in.obj", "-o", "out.ply"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .env_remove("MIMALLOC_ALLOW_THP");
    if let Some(value) = allow {
        command.env("MIMALLOC_ALLOW_THP", value);
    }
    let child = command.spawn().expect("start algesurf");
    wait_for_handler(child.id(), 15);
    let value = proc_status_field(&child.id().to_string(), "THP_enabled");
    send(child.id(), "TERM");
    std::fs::write(&fifo, obj_bytes(&shapes::icosphere(1).to_polygon_mesh())).unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(143), "{}", common::text(&out));
    value.expect("THP_enabled was read from this process's status, so the child has it too")
}

#[test]
fn the_command_runs_without_transparent_huge_pages() {
    let Some(own) = proc_status_field("self", "THP_enabled") else {
        eprintln!("skipped: this kernel's /proc/PID/status has no THP_enabled field");
        return;
    };
    assert_eq!(thp_of_a_running_command("default", None), "0");
    // With the variable set, the command leaves the flag to mimalloc: `1` keeps what the test
    // process has (the flag is inherited through `exec`), `0` makes mimalloc switch them off.
    assert_eq!(thp_of_a_running_command("allowed", Some("1")), own);
    assert_eq!(thp_of_a_running_command("refused", Some("0")), "0");
}

//! Project automation for algesurf: `cargo xtask <task>`.
//!
//! * `ci`: what `.ci/run` runs: rustfmt check, clippy with `-D warnings`, the README's test
//!   command (`cargo test --workspace`), then the interoperability checks (our .glb passes the
//!   Khronos glTF validator; our OBJ/PLY/STL/OFF load in trimesh with the right counts).
//! * `interop`: only the interoperability checks (what `.ci/run` runs after the tests).
//! * `dist`: release build of the `algesurf` binary into `dist/` with a SHA-256 file.
//! * `bench [NAME]`: the divan benchmarks (`cargo bench -p algesurf-benches`).
//! * `bench smooth [--mesh PATH] [--no-divan]`: the `smooth` divan benchmarks, then the bunny
//!   (or PATH) smoothed by the release `algesurf smooth` and timed against libigl's Loop
//!   subdivision in the same run (see [`bench_peers`]).
//! * `bench instructions [--mesh PATH] [--top N]`: the same `algesurf smooth` run counted in
//!   instructions by valgrind's cachegrind, in total and per function (see [`instructions`]):
//!   what does not move with the machine's load.
//! * `figures`: regenerates the paper's figures into `docs/figures/` (see [`figures`]).

mod bench_peers;
mod figures;
mod instructions;
mod interop;

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

type Result<T> = std::result::Result<T, String>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace root")
        .to_path_buf()
}

fn cargo() -> Command {
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.current_dir(root());
    c
}

fn run(mut cmd: Command) -> Result<()> {
    eprintln!("xtask: running {cmd:?}");
    let status = cmd
        .status()
        .map_err(|e| format!("cannot start {cmd:?}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{cmd:?} failed with {status}"))
    }
}

fn ci() -> Result<()> {
    let mut fmt = cargo();
    fmt.args(["fmt", "--all", "--check"]);
    run(fmt)?;
    let mut clippy = cargo();
    clippy.args([
        "clippy",
        "--workspace",
        "--all-targets",
        "--",
        "-D",
        "warnings",
    ]);
    run(clippy)?;
    let mut test = cargo();
    test.args(["test", "--workspace"]);
    if std::env::var_os("ALGESURF_CORPUS").is_none() {
        let corpus = root().join("../shared/data");
        if corpus.is_dir() {
            test.env("ALGESURF_CORPUS", corpus);
        }
    }
    run(test)?;
    interop::run_all()
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn dist() -> Result<()> {
    let mut build = cargo();
    build.args(["build", "--release", "--locked", "-p", "algesurf-cli"]);
    run(build)?;
    let src = bench_peers::release_cli(&root());
    let exe = format!("algesurf{}", std::env::consts::EXE_SUFFIX);
    let dir = root().join("dist");
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let dst = dir.join(&exe);
    let bytes = std::fs::read(&src).map_err(|e| format!("cannot read {}: {e}", src.display()))?;
    // Write to a temporary name, then rename: an interrupted dist never leaves a torn binary.
    let tmp = dir.join(format!(".{exe}.tmp"));
    std::fs::write(&tmp, &bytes).map_err(|e| format!("cannot write {}: {e}", tmp.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(0o755))
            .map_err(|e| format!("cannot chmod {}: {e}", tmp.display()))?;
    }
    std::fs::rename(&tmp, &dst).map_err(|e| format!("cannot rename to {}: {e}", dst.display()))?;
    let sum = format!("{}  {exe}\n", hex(&Sha256::digest(&bytes)));
    let sum_path = dir.join(format!("{exe}.sha256"));
    std::fs::write(&sum_path, &sum)
        .map_err(|e| format!("cannot write {}: {e}", sum_path.display()))?;
    print!("{sum}");
    println!("wrote {} and {}", dst.display(), sum_path.display());
    Ok(())
}

fn bench(args: &[String]) -> Result<()> {
    if args.first().map(String::as_str) == Some("instructions") {
        return instructions::run(&root(), &args[1..]);
    }
    let skip_divan = args.iter().any(|a| a == "--no-divan");
    if !skip_divan {
        let mut b = cargo();
        b.args(["bench", "-p", "algesurf-benches"]);
        if let Some(name) = args.first().filter(|a| !a.starts_with("--")) {
            b.args(["--bench", name]);
        }
        run(b)?;
    }
    if args.first().map(String::as_str) == Some("smooth") {
        bench_peers::smooth(&root(), &args[1..])?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("ci") => ci(),
        Some("interop") => interop::run_all(),
        Some("dist") => dist(),
        Some("bench") => bench(&args[1..]),
        Some("figures") => figures::run(&root()).map_err(|e| e.to_string()),
        _ => {
            eprintln!(
                "usage: cargo xtask <ci | interop | dist | figures | bench [bb|roots|smooth [--mesh PATH] [--no-divan]] | bench instructions [--mesh PATH] [--top N]>"
            );
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

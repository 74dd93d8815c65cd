//! `cargo xtask bench smooth`: algesurf's A-patch surface against libigl's Loop subdivision
//! on the same mesh, in the same run.
//!
//! * algesurf: `cargo build --release -p algesurf-cli`, then
//!   `target/release/algesurf smooth MESH -o target/bench-smooth/MESH.ply --resolution N
//!   --across M --report target/bench-smooth/report.json`; the time is the report's
//!   `construction` (`ApatchSurface::new`: hull + function) plus `tessellation`. `N` and
//!   `M ≤ N` are chosen so that the output has the fewest triangles ≥ [`TRIANGLES`] (estimated from the face and edge counts, then checked against
//!   the report and raised if short). Best of [`REPEATS`] runs, each its own process.
//! * libigl: `igl.loop(V, F, k)` in Python (the `libigl` wheel), `k` the least number of
//!   levels giving at least [`TRIANGLES`] triangles (2 for the bunny: 1.11 M), best of
//!   [`REPEATS`] runs after one warm-up. Installed on first use into `target/bench-venv` by
//!   `python3 -m venv` + pip; skipped with a message when `python3` is missing.
//!
//! The mesh is `stanford-bunny.obj` from `$ALGESURF_CORPUS` (default `../shared/data`), or
//! the path after `--mesh`. Prints both times and the ratio.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::Result;

/// Output size both sides must reach (libigl's 2 Loop levels of the bunny: 1,111,216).
pub const TRIANGLES: u64 = 1_100_000;
/// Runs timed on each side (libigl's after one warm-up); the best is reported.
pub const REPEATS: usize = 3;

const LIBIGL: &str = "libigl==2.6.3";
const NUMPY: &str = "numpy==2.4.6";

fn have(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

fn output(mut cmd: Command) -> Result<String> {
    let shown = format!("{cmd:?}");
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start {shown}: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!(
            "{shown} failed with {}:\n{stdout}{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// The Python of `target/bench-venv` with libigl and numpy, created when missing; `None`
/// (after a message) when python3 is not installed.
fn venv_python(root: &Path) -> Result<Option<PathBuf>> {
    let venv = root.join("target/bench-venv");
    let python = venv.join("bin/python");
    let ready = python.is_file() && {
        let mut check = Command::new(&python);
        check.args(["-c", "import igl, numpy"]);
        check.output().is_ok_and(|o| o.status.success())
    };
    if ready {
        return Ok(Some(python));
    }
    if !have("python3") {
        eprintln!("xtask: libigl comparison skipped: python3 not found");
        return Ok(None);
    }
    eprintln!(
        "xtask: installing {LIBIGL} and {NUMPY} into {}",
        venv.display()
    );
    let mut mk = Command::new("python3");
    mk.args(["-m", "venv"]).arg(&venv);
    output(mk)?;
    let mut pip = Command::new(&python);
    pip.args(["-m", "pip", "install", "--quiet", LIBIGL, NUMPY]);
    output(pip)?;
    Ok(Some(python))
}

const IGL_SCRIPT: &str = r#"
import sys, time, json
import igl
V, F = igl.read_triangle_mesh(sys.argv[1])
levels, repeats = int(sys.argv[2]), int(sys.argv[3])
igl.loop(V, F, levels)  # warm-up
times = []
for _ in range(repeats):
    t = time.perf_counter()
    NV, NF = igl.loop(V, F, levels)
    times.append(time.perf_counter() - t)
print(json.dumps({"faces": int(F.shape[0]), "levels": levels, "triangles": int(NF.shape[0]),
                  "vertices": int(NV.shape[0]), "best_s": min(times), "times_s": times}))
"#;

/// Seconds of one stage in the report.
fn stage(report: &serde_json::Value, name: &str) -> Result<f64> {
    report["timings_s"][name]
        .as_f64()
        .ok_or_else(|| format!("the report has no timings_s.{name}"))
}

/// Runs the release binary on `mesh` at resolution `n`, `m` across; returns the report.
fn algesurf_run(root: &Path, mesh: &Path, n: u32, m: u32) -> Result<serde_json::Value> {
    let dir = root.join("target/bench-smooth");
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let stem = mesh
        .file_stem()
        .map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
    let out = dir.join(format!("{stem}.ply"));
    let report = dir.join("report.json");
    let _ = std::fs::remove_file(&report);
    let exe = root
        .join("target/release")
        .join(format!("algesurf{}", std::env::consts::EXE_SUFFIX));
    let mut cmd = Command::new(&exe);
    cmd.arg("smooth")
        .arg(mesh)
        .arg("-o")
        .arg(&out)
        .args([
            "--resolution",
            &n.to_string(),
            "--across",
            &m.to_string(),
            "--report",
        ])
        .arg(&report);
    eprintln!("xtask: running {cmd:?}");
    let result = cmd
        .output()
        .map_err(|e| format!("cannot start {}: {e}", exe.display()))?;
    print!("{}", String::from_utf8_lossy(&result.stdout));
    eprint!("{}", String::from_utf8_lossy(&result.stderr));
    // Exit status 3: written, with missed rays or multiple roots (reported, still timed).
    if !result.status.success() && result.status.code() != Some(3) {
        return Err(format!(
            "algesurf smooth failed with {} on {}",
            result.status,
            mesh.display()
        ));
    }
    let text = std::fs::read_to_string(&report)
        .map_err(|e| format!("cannot read {}: {e}", report.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", report.display()))
}

/// Faces and edges of a triangle mesh in OBJ (`v`/`f` lines; polygons count as fans).
pub fn obj_counts(mesh: &Path) -> Result<(u64, u64)> {
    let text = std::fs::read_to_string(mesh)
        .map_err(|e| format!("cannot read {}: {e}", mesh.display()))?;
    let mut faces = 0u64;
    let mut edges = std::collections::HashSet::new();
    for line in text.lines() {
        let mut w = line.split_whitespace();
        if w.next() != Some("f") {
            continue;
        }
        let ids: Vec<i64> = w
            .filter_map(|c| c.split('/').next()?.parse().ok())
            .collect();
        faces += ids.len().saturating_sub(2) as u64;
        for k in 0..ids.len() {
            let (a, b) = (ids[k], ids[(k + 1) % ids.len()]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    Ok((faces, edges.len() as u64))
}

/// The benchmark mesh: the path after `--mesh`, else `stanford-bunny.obj` from
/// `$ALGESURF_CORPUS` (default `../shared/data`); an error if it is not a file.
pub fn bench_mesh(root: &Path, args: &[String]) -> Result<PathBuf> {
    let mesh = match args.iter().position(|a| a == "--mesh") {
        Some(i) => PathBuf::from(args.get(i + 1).ok_or("--mesh needs a path")?),
        None => {
            let corpus = std::env::var_os("ALGESURF_CORPUS")
                .map(PathBuf::from)
                .unwrap_or_else(|| root.join("../shared/data"));
            corpus.join("stanford-bunny.obj")
        }
    };
    if !mesh.is_file() {
        return Err(format!(
            "{}: no such mesh (set ALGESURF_CORPUS or pass --mesh)",
            mesh.display()
        ));
    }
    Ok(mesh)
}

/// `cargo build --release -p algesurf-cli`.
pub fn build_release_cli(root: &Path) -> Result<()> {
    let mut build = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    build
        .current_dir(root)
        .args(["build", "--release", "-p", "algesurf-cli"]);
    crate::run(build)
}

/// The resolution `(n, m)`, `m ≤ n`, estimated to give the fewest triangles ≥ [`TRIANGLES`]:
/// face patches give n² triangles, edge patches 2m(n − 1) (the two columns at the mesh
/// vertices collapse). `faces` and `edges`: the mesh's counts ([`obj_counts`]).
pub fn estimated_resolution(faces: u64, edges: u64) -> (u32, u32) {
    let estimate = |n: u64, m: u64| faces * n * n + 2 * edges * m * (n - 1);
    (1..=64u64)
        .flat_map(|n| (1..=n).map(move |m| (n, m)))
        .filter(|&(n, m)| estimate(n, m) >= TRIANGLES)
        .min_by_key(|&(n, m)| (estimate(n, m), n))
        .map_or((64, 64), |(n, m)| (n as u32, m as u32))
}

/// `cargo xtask bench smooth [--mesh PATH]`.
pub fn smooth(root: &Path, args: &[String]) -> Result<()> {
    let mesh = bench_mesh(root, args)?;
    build_release_cli(root)?;
    // One read of the OBJ for both sides' sizes.
    let (faces, edges) = obj_counts(&mesh)?;
    let (mut n, mut m) = estimated_resolution(faces, edges);
    // An algesurf failure (e.g. a mesh the hull rejects) is reported after libigl's time.
    let ours = (|| -> Result<f64> {
        let mut report = algesurf_run(root, &mesh, n, m)?;
        while report["output_mesh"]["triangles"].as_u64().unwrap_or(0) < TRIANGLES {
            if m < n {
                m += 1;
            } else {
                n += 1;
            }
            report = algesurf_run(root, &mesh, n, m)?;
        }
        // Best of REPEATS runs, as libigl's side: the run that found (n, m) and REPEATS − 1
        // more (one process each, so every run pays its own page faults; libigl's calls run
        // in one warmed-up Python process).
        let total = |r: &serde_json::Value| -> Result<f64> {
            Ok(stage(r, "construction")? + stage(r, "tessellation")?)
        };
        let mut best = total(&report)?;
        let mut totals = vec![best];
        for _ in 1..REPEATS {
            let again = algesurf_run(root, &mesh, n, m)?;
            let t = total(&again)?;
            totals.push(t);
            if t < best {
                best = t;
                report = again;
            }
        }
        let construction = stage(&report, "construction")?;
        let tessellation = stage(&report, "tessellation")?;
        let tris = report["output_mesh"]["triangles"].as_u64().unwrap_or(0);
        let points = report["output_mesh"]["vertices"].as_u64().unwrap_or(0);
        let faces_in = report["input_mesh"]["faces"].as_u64().unwrap_or(0);
        println!("mesh: {} ({faces_in} faces after repair)", mesh.display());
        let runs: Vec<String> = totals.iter().map(|t| format!("{t:.3}")).collect();
        println!(
            "algesurf smooth, resolution {n} × {m}, best of {REPEATS} (totals {} s): construction \
             {construction:.3} s ({:.0} faces/s), tessellation {tessellation:.3} s ({:.3} M \
             points/s), {tris} triangles; total {:.3} s",
            runs.join(", "),
            faces_in as f64 / construction,
            points as f64 / tessellation / 1e6,
            construction + tessellation
        );
        Ok(construction + tessellation)
    })();
    if let Err(e) = &ours {
        eprintln!("xtask: algesurf side failed: {e}");
    }

    let Some(python) = venv_python(root)? else {
        return ours.map(|_| ());
    };
    let mut levels = 0u32;
    while faces * 4u64.pow(levels) < TRIANGLES {
        levels += 1;
    }
    let mut py = Command::new(&python);
    py.args(["-c", IGL_SCRIPT])
        .arg(&mesh)
        .args([levels.to_string(), REPEATS.to_string()]);
    let igl: serde_json::Value = serde_json::from_str(output(py)?.trim())
        .map_err(|e| format!("libigl script output: {e}"))?;
    let theirs = igl["best_s"].as_f64().ok_or("libigl script: no best_s")?;
    println!(
        "libigl igl.loop(V, F, {levels}): {theirs:.3} s (best of {REPEATS}), {} triangles",
        igl["triangles"]
    );
    let ours = ours?;
    println!(
        "ratio algesurf / libigl: {:.2} ({})",
        ours / theirs,
        if ours < theirs {
            "algesurf faster"
        } else {
            "libigl faster"
        }
    );
    Ok(())
}

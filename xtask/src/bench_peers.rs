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
//!   [`REPEATS`] calls in one Python process after one warm-up call. Installed on first use
//!   into `target/bench-venv` by `python3 -m venv` + pip; skipped with a message when
//!   `python3` is missing.
//!
//! The two sides take turns: algesurf's run `k`, then libigl's call `k` (the Python process
//! waits for its turn on stdin), so that both sides' best runs come from the same minutes.
//! This machine's speed drifts by a third within an hour, and timing all of one side before
//! the other put that drift into the ratio. Each turn's ratio is printed too.
//!
//! The mesh is `stanford-bunny.obj` from `$ALGESURF_CORPUS` (default `../shared/data`), or
//! the path after `--mesh`. Prints both times and the ratio, and each side's CPU time on all
//! threads for its best run: algesurf's from its report (`cpu_s`), libigl's from Python's
//! `time.process_time()` around the call (it runs on one core: its CPU time is its wall
//! time), so that the ratio of wall times can be read with the cores each side used.

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

/// libigl's side: after a warm-up call, prints the output's size as one JSON line, then
/// answers every line on stdin with the seconds of one more `igl.loop` call.
const IGL_SCRIPT: &str = r#"
import sys, time, json
import igl
V, F = igl.read_triangle_mesh(sys.argv[1])
levels = int(sys.argv[2])
NV, NF = igl.loop(V, F, levels)  # warm-up
print(json.dumps({"faces": int(F.shape[0]), "levels": levels, "triangles": int(NF.shape[0]),
                  "vertices": int(NV.shape[0])}), flush=True)
for _ in sys.stdin:
    t, c = time.perf_counter(), time.process_time()
    igl.loop(V, F, levels)
    print(time.perf_counter() - t, time.process_time() - c, flush=True)
"#;

/// libigl's Python process ([`IGL_SCRIPT`]), warmed up and waiting for its turns.
struct Igl {
    child: std::process::Child,
    stdin: std::process::ChildStdin,
    stdout: std::io::BufReader<std::process::ChildStdout>,
    /// The warm-up's output sizes.
    header: serde_json::Value,
}

impl Igl {
    /// Starts the script on `mesh` with `levels` Loop levels and reads its header.
    fn start(python: &Path, mesh: &Path, levels: u32) -> Result<Igl> {
        use std::process::Stdio;
        let mut child = Command::new(python)
            .args(["-c", IGL_SCRIPT])
            .arg(mesh)
            .arg(levels.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start {}: {e}", python.display()))?;
        let stdin = child.stdin.take().ok_or("libigl script: no stdin")?;
        let stdout =
            std::io::BufReader::new(child.stdout.take().ok_or("libigl script: no stdout")?);
        let mut igl = Igl {
            child,
            stdin,
            stdout,
            header: serde_json::Value::Null,
        };
        let line = igl.line()?;
        igl.header =
            serde_json::from_str(&line).map_err(|e| format!("libigl script header: {e}"))?;
        Ok(igl)
    }

    /// One line of the script's output; an error when it has ended.
    fn line(&mut self) -> Result<String> {
        use std::io::BufRead;
        let mut line = String::new();
        let read = self
            .stdout
            .read_line(&mut line)
            .map_err(|e| format!("libigl script: {e}"))?;
        if read == 0 {
            return Err("libigl script ended early (see its error above)".into());
        }
        Ok(line.trim().to_owned())
    }

    /// The seconds of one timed `igl.loop` call: wall time and the Python process's CPU time
    /// (all its threads) during it.
    fn time(&mut self) -> Result<(f64, f64)> {
        use std::io::Write;
        writeln!(self.stdin, "go").map_err(|e| format!("libigl script: {e}"))?;
        let line = self.line()?;
        let times: Vec<f64> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| format!("libigl script: {line:?} is not two times: {e}"))?;
        match times[..] {
            [wall, cpu] => Ok((wall, cpu)),
            _ => Err(format!("libigl script: {line:?} is not two times")),
        }
    }
}

impl Drop for Igl {
    fn drop(&mut self) {
        // Killed and waited for, so that no process is left behind (the script only waits
        // for its turns on stdin).
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Seconds of one stage in the report.
fn stage(report: &serde_json::Value, name: &str) -> Result<f64> {
    report["timings_s"][name]
        .as_f64()
        .ok_or_else(|| format!("the report has no timings_s.{name}"))
}

/// Runs the release binary on `mesh` at resolution `n`, `m` across; returns the report.
fn algesurf_run(root: &Path, mesh: &Path, n: u32, m: u32) -> Result<serde_json::Value> {
    let dir = bench_dir(root)?;
    let out = dir.join(format!("{}.ply", mesh_stem(mesh)));
    let report = dir.join("report.json");
    let _ = std::fs::remove_file(&report);
    let exe = release_cli(root);
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

/// The release `algesurf` binary that [`build_release_cli`] builds.
pub fn release_cli(root: &Path) -> PathBuf {
    root.join("target/release")
        .join(format!("algesurf{}", std::env::consts::EXE_SUFFIX))
}

/// `target/bench-smooth`, where the benchmark's runs write their output, created if missing.
pub fn bench_dir(root: &Path) -> Result<PathBuf> {
    let dir = root.join("target/bench-smooth");
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    Ok(dir)
}

/// The mesh file's name without its extension (`mesh` if it has none), for output names.
pub fn mesh_stem(mesh: &Path) -> String {
    mesh.file_stem()
        .map_or("mesh".into(), |s| s.to_string_lossy().into_owned())
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
    let total = |r: &serde_json::Value| -> Result<f64> {
        Ok(stage(r, "construction")? + stage(r, "tessellation")?)
    };
    // The resolution first: the run that reaches TRIANGLES is algesurf's first turn. An
    // algesurf failure (e.g. a mesh the hull rejects) is reported, and libigl still timed.
    let first = (|| -> Result<serde_json::Value> {
        let mut report = algesurf_run(root, &mesh, n, m)?;
        while report["output_mesh"]["triangles"].as_u64().unwrap_or(0) < TRIANGLES {
            if m < n {
                m += 1;
            } else {
                n += 1;
            }
            report = algesurf_run(root, &mesh, n, m)?;
        }
        Ok(report)
    })();
    if let Err(e) = &first {
        eprintln!("xtask: algesurf side failed: {e}");
    }
    let mut levels = 0u32;
    while faces * 4u64.pow(levels) < TRIANGLES {
        levels += 1;
    }
    let mut igl = match venv_python(root)? {
        Some(python) => Some(Igl::start(&python, &mesh, levels)?),
        None => None,
    };
    // Turns: algesurf's run k (one process each, so every run pays its own page faults),
    // then libigl's call k (in its one warmed-up Python process).
    let mut ours: Vec<(f64, serde_json::Value)> = Vec::new();
    // libigl's (wall, CPU) seconds per call.
    let mut theirs: Vec<(f64, f64)> = Vec::new();
    if let Ok(report) = first {
        ours.push((total(&report)?, report));
    }
    for turn in 0..REPEATS {
        if turn > 0 && !ours.is_empty() {
            let report = algesurf_run(root, &mesh, n, m)?;
            ours.push((total(&report)?, report));
        }
        if let Some(igl) = igl.as_mut() {
            theirs.push(igl.time()?);
        }
    }
    if let Some((_, report)) = ours.iter().min_by(|a, b| a.0.total_cmp(&b.0)) {
        let construction = stage(report, "construction")?;
        let tessellation = stage(report, "tessellation")?;
        let tris = report["output_mesh"]["triangles"].as_u64().unwrap_or(0);
        let points = report["output_mesh"]["vertices"].as_u64().unwrap_or(0);
        let faces_in = report["input_mesh"]["faces"].as_u64().unwrap_or(0);
        // CPU seconds of the same two stages (Linux; absent elsewhere).
        let cpu = report["cpu_s"]["construction"]
            .as_f64()
            .zip(report["cpu_s"]["tessellation"].as_f64())
            .map(|(c, t)| c + t);
        println!("mesh: {} ({faces_in} faces after repair)", mesh.display());
        let runs: Vec<String> = ours.iter().map(|(t, _)| format!("{t:.3}")).collect();
        println!(
            "algesurf smooth, resolution {n} × {m}, best of {REPEATS} (totals {} s): construction \
             {construction:.3} s ({:.0} faces/s), tessellation {tessellation:.3} s ({:.3} M \
             points/s), {tris} triangles; total {:.3} s",
            runs.join(", "),
            faces_in as f64 / construction,
            points as f64 / tessellation / 1e6,
            construction + tessellation
        );
        if let Some(cpu) = cpu {
            println!(
                "algesurf CPU time of the same run: {cpu:.2} s on all threads ({:.1} cores busy \
                 on average)",
                cpu / (construction + tessellation)
            );
        }
    }
    let Some(igl) = igl else {
        return if ours.is_empty() {
            Err("algesurf smooth failed (see above)".into())
        } else {
            Ok(())
        };
    };
    let runs: Vec<String> = theirs.iter().map(|t| format!("{:.3}", t.0)).collect();
    let (best_theirs, best_cpu) =
        theirs.iter().copied().fold(
            (f64::INFINITY, f64::NAN),
            |b, t| if t.0 < b.0 { t } else { b },
        );
    println!(
        "libigl igl.loop(V, F, {levels}): {best_theirs:.3} s (best of {REPEATS}: {} s), {} \
         triangles; CPU time of the best call {best_cpu:.2} s ({:.1} cores busy on average)",
        runs.join(", "),
        igl.header["triangles"],
        best_cpu / best_theirs
    );
    let theirs: Vec<f64> = theirs.iter().map(|t| t.0).collect();
    if ours.is_empty() {
        return Err("algesurf smooth failed (see above)".into());
    }
    let turns: Vec<String> = ours
        .iter()
        .zip(&theirs)
        .map(|((a, _), b)| format!("{:.2}", a / b))
        .collect();
    let best_ours = ours.iter().map(|o| o.0).fold(f64::INFINITY, f64::min);
    let (median_ours, median_theirs) = (
        median(ours.iter().map(|o| o.0).collect()),
        median(theirs.clone()),
    );
    println!(
        "ratio algesurf / libigl: {:.2} ({}); turn by turn: {}; medians {median_ours:.3} \
         against {median_theirs:.3} s, ratio {:.2}",
        best_ours / best_theirs,
        if best_ours < best_theirs {
            "algesurf faster"
        } else {
            "libigl faster"
        },
        turns.join(", "),
        median_ours / median_theirs
    );
    Ok(())
}

/// The median of `times` (the mean of the middle two for an even count; NaN when empty).
/// Printed beside the best of the runs: a best of three hides a slow mode that two runs in
/// three fall into (huge pages on a young virtual machine, docs/PERFORMANCE.md, twenty-third
/// pass), which the median shows.
fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    match times.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => times[n / 2],
        n => (times[n / 2 - 1] + times[n / 2]) / 2.0,
    }
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn median_is_the_middle_run_or_the_mean_of_the_middle_two() {
        assert_eq!(median(vec![1.9, 1.0, 1.3]), 1.3);
        assert_eq!(median(vec![2.0, 1.0, 4.0, 3.0]), 2.5);
        assert!(median(Vec::new()).is_nan());
    }
}

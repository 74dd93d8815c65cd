//! Interoperability checks: our mesh files open in the tools people already use.
//!
//! * [`gltf_validator`]: the Khronos glTF validator (npm package `gltf-validator`, a library
//!   without a command line: we drive it with a few lines of `node`) must report 0 errors.
//! * [`trimesh_loads`]: trimesh (Python) must load our OBJ, PLY and STL files with the right
//!   vertex and face counts.
//! * [`write_samples`]: writes the sample files with
//!   `cargo run -p algesurf-io --example write_samples`.
//! * [`run_all`]: the three together, for `cargo xtask ci`.
//!
//! Tools are installed on first use into a cache folder ([`cache_dir`]:
//! `target/interop`, or `$ALGESURF_INTEROP_DIR`): `node_modules` by npm and a `venv` by
//! `python3 -m venv` + pip. When npm (or python3) is absent the check is skipped with a message
//! ([`Outcome::Skipped`]); when the tool is present but the file fails, the check fails.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Pinned versions of the peer tools.
const GLTF_VALIDATOR: &str = "gltf-validator@2.0.0-dev.3.10";
const TRIMESH: &str = "trimesh==4.5.3";
const NUMPY: &str = "numpy==2.1.3";

/// The result of a check that ran or was skipped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// The check ran and passed; a one-line summary.
    Passed(String),
    /// A tool is missing; why the check did not run.
    Skipped(String),
}

/// A file and the counts a reader must find in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sample {
    /// The file.
    pub path: PathBuf,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of triangles.
    pub faces: usize,
}

/// The workspace root: `$ALGESURF_ROOT` when set, else the parent of the xtask crate.
fn workspace_root() -> PathBuf {
    if let Some(root) = std::env::var_os("ALGESURF_ROOT") {
        return PathBuf::from(root);
    }
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// Where the peer tools are installed: `$ALGESURF_INTEROP_DIR`, else `<workspace>/target/interop`.
pub fn cache_dir() -> PathBuf {
    std::env::var_os("ALGESURF_INTEROP_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("target/interop"))
}

fn have(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

fn output(mut cmd: Command) -> Result<String, String> {
    let program = cmd.get_program().to_string_lossy().into_owned();
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start {program}: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!(
            "{program} failed with {}:\n{stdout}{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Validates a `.glb` (or `.gltf`) file with the Khronos validator; passes when it reports 0
/// errors (warnings and infos are listed in the summary). Installs the npm package into
/// `cache_dir()/node_modules` when absent; skips when `node` or `npm` is missing.
pub fn gltf_validator(glb: &Path) -> Result<Outcome, String> {
    if !have("node") || !have("npm") {
        return Ok(Outcome::Skipped(
            "gltf validator skipped: node/npm not found".into(),
        ));
    }
    let dir = cache_dir();
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    if !dir
        .join("node_modules/gltf-validator/package.json")
        .is_file()
    {
        let mut npm = Command::new("npm");
        npm.args([
            "install",
            "--no-audit",
            "--no-fund",
            "--no-save",
            "--prefix",
        ])
        .arg(&dir)
        .arg(GLTF_VALIDATOR);
        output(npm)?;
    }
    let script = r#"
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');
const file = process.argv[1];
const bytes = new Uint8Array(fs.readFileSync(file));
validator.validateBytes(bytes, {
  uri: path.basename(file),
  externalResourceFunction: (uri) => new Promise((ok, fail) => {
    fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
      err ? fail(err.toString()) : ok(new Uint8Array(data)));
  }),
}).then((report) => {
  const i = report.issues;
  console.log(`errors ${i.numErrors} warnings ${i.numWarnings} infos ${i.numInfos}`);
  for (const m of i.messages) console.log(`${['error','warning','info','hint'][m.severity]} ${m.code} ${m.pointer || ''} ${m.message}`);
  process.exit(i.numErrors === 0 ? 0 : 1);
}, (error) => { console.log(`validator failed: ${error}`); process.exit(2); });
"#;
    let mut node = Command::new("node");
    node.env("NODE_PATH", dir.join("node_modules"))
        .args(["-e", script])
        .arg(glb);
    let out = output(node).map_err(|e| format!("glTF validator rejects {}: {e}", glb.display()))?;
    let summary = out.lines().next().unwrap_or("").to_string();
    if !summary.starts_with("errors 0 ") {
        return Err(format!("glTF validator on {}:\n{out}", glb.display()));
    }
    Ok(Outcome::Passed(format!(
        "gltf-validator {}: {}",
        glb.display(),
        out.trim_end().replace('\n', "\n    ")
    )))
}

/// Creates (once) a venv under `cache_dir()/venv` with trimesh and numpy, and checks that
/// trimesh loads every sample (OBJ, PLY, STL, OFF; other extensions are ignored) with the
/// expected vertex and triangle counts. Skips when `python3` is missing.
pub fn trimesh_loads(samples: &[Sample]) -> Result<Outcome, String> {
    if !have("python3") {
        return Ok(Outcome::Skipped(
            "trimesh check skipped: python3 not found".into(),
        ));
    }
    let venv = cache_dir().join("venv");
    let python = venv.join("bin/python");
    let ready = python.is_file()
        && Command::new(&python)
            .args(["-c", "import trimesh, numpy"])
            .output()
            .is_ok_and(|o| o.status.success());
    if !ready {
        let mut mk = Command::new("python3");
        mk.args(["-m", "venv"]).arg(&venv);
        output(mk)?;
        let mut pip = Command::new(&python);
        pip.args(["-m", "pip", "install", "--quiet", TRIMESH, NUMPY]);
        output(pip)?;
    }
    let script = r#"
import sys, trimesh
bad = 0
for line in sys.stdin.read().splitlines():
    path, nv, nf = line.split('\t')
    ext = path.rsplit('.', 1)[-1].lower()
    # process=False keeps vertices as written; STL has no shared vertices, so merge there.
    m = trimesh.load(path, process=(ext == 'stl'), force='mesh')
    ok = (len(m.vertices), len(m.faces)) == (int(nv), int(nf))
    extra = ''
    if ext == 'ply':
        raw = m.metadata.get('_ply_raw', {}).get('vertex', {}).get('data')
        names = tuple(raw.dtype.names) if hasattr(raw, 'dtype') else tuple(raw) if isinstance(raw, dict) else ()
        if 'patch_id' not in names:
            ok = False
        extra = f' vertex properties {names}'
    print(f"{'ok ' if ok else 'BAD'} {path}: {len(m.vertices)} vertices, {len(m.faces)} faces (expected {nv}, {nf}){extra}")
    bad += not ok
sys.exit(1 if bad else 0)
"#;
    let listing: String = samples
        .iter()
        .filter(|s| {
            s.path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| {
                    ["obj", "ply", "stl", "off"].contains(&e.to_ascii_lowercase().as_str())
                })
        })
        .map(|s| format!("{}\t{}\t{}\n", s.path.display(), s.vertices, s.faces))
        .collect();
    if listing.is_empty() {
        return Err("trimesh check: no OBJ/PLY/STL/OFF samples given".into());
    }
    let mut child = Command::new(&python)
        .args(["-c", script])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", python.display()))?;
    {
        use std::io::Write;
        let mut stdin = child.stdin.take().ok_or("no stdin")?;
        stdin
            .write_all(listing.as_bytes())
            .map_err(|e| format!("cannot write to python: {e}"))?;
    }
    let out = child
        .wait_with_output()
        .map_err(|e| format!("python failed: {e}"))?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    if !out.status.success() {
        return Err(format!("trimesh check failed:\n{text}"));
    }
    Ok(Outcome::Passed(format!(
        "trimesh:\n    {}",
        text.trim_end().replace('\n', "\n    ")
    )))
}

/// Writes the sample files into `dir` with the `write_samples` example of `algesurf-io` and
/// returns what each must contain.
pub fn write_samples(dir: &Path) -> Result<Vec<Sample>, String> {
    let mut cargo = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cargo
        .current_dir(workspace_root())
        .args([
            "run",
            "--quiet",
            "-p",
            "algesurf-io",
            "--example",
            "write_samples",
            "--",
        ])
        .arg(dir);
    let out = output(cargo)?;
    out.lines()
        .map(|line| {
            let mut parts = line.split('\t');
            let (Some(p), Some(v), Some(f)) = (parts.next(), parts.next(), parts.next()) else {
                return Err(format!("write_samples printed an unexpected line: {line}"));
            };
            Ok(Sample {
                path: PathBuf::from(p),
                vertices: v.parse().map_err(|e| format!("{line}: {e}"))?,
                faces: f.parse().map_err(|e| format!("{line}: {e}"))?,
            })
        })
        .collect()
}

/// Writes the samples into `cache_dir()/samples`, validates every `.glb`/`.gltf` with the
/// Khronos validator and loads the rest with trimesh; prints each outcome.
pub fn run_all() -> Result<(), String> {
    let dir = cache_dir().join("samples");
    let samples = write_samples(&dir)?;
    for s in samples.iter().filter(|s| {
        s.path
            .extension()
            .is_some_and(|e| e == "glb" || e == "gltf")
    }) {
        report(gltf_validator(&s.path)?);
    }
    report(trimesh_loads(&samples)?);
    Ok(())
}

fn report(outcome: Outcome) {
    match outcome {
        Outcome::Passed(s) => eprintln!("xtask: interop passed: {s}"),
        Outcome::Skipped(s) => eprintln!("xtask: interop {s}"),
    }
}

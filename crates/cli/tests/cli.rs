//! The `algesurf` binary end to end: `--version`, `--help`, `info` (text and JSON) and
//! `convert` (with and without `--repair`) on generated files in a temporary folder, and the
//! error paths (missing, garbage and unwritable files).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use algesurf_mesh::{PolygonMesh, validate};

const BIN: &str = env!("CARGO_BIN_EXE_algesurf");

/// A fresh, empty folder under the system temp dir, unique to this process and test.
struct TempDir(PathBuf);

impl TempDir {
    fn new(test: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("algesurf-cli-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
    fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        make_writable(&self.0);
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn make_writable(dir: &Path) {
    for entry in walk(dir) {
        if let Ok(meta) = std::fs::metadata(&entry) {
            let mut p = meta.permissions();
            #[allow(clippy::permissions_set_readonly_false)]
            p.set_readonly(false);
            let _ = std::fs::set_permissions(&entry, p);
        }
    }
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = vec![dir.to_path_buf()];
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                out.extend(walk(&p));
            } else {
                out.push(p);
            }
        }
    }
    out
}

fn run(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(BIN).args(args).output().expect("run algesurf")
}

fn run_str(args: &[&str]) -> Output {
    let a: Vec<&std::ffi::OsStr> = args.iter().map(std::ffi::OsStr::new).collect();
    run(&a)
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A unit cube of quads with vertex 8 a duplicate of vertex 6 (used by face 1) and face 4
/// reversed against its neighbours.
///
/// Counted by hand (0-based ids): 9 vertices, 6 quads, edges = the cube's 12 plus (5, 8) and
/// (8, 7) = 14, so V − E + F = 9 − 14 + 6 = 1; the boundary is the loop 5-8-7-6 (4 edges).
/// Repaired: 8 vertices, 12 triangles, 18 edges, χ = 2.
const CUBE_OBJ: &str = "\
# cube with a duplicate vertex and a flipped face
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
v 1 1 1
f 1 4 3 2
f 5 6 9 8
f 1 2 6 5
f 3 4 8 7
f 2 6 7 3
f 1 5 8 4
";

fn cube(dir: &TempDir) -> PathBuf {
    let p = dir.join("cube.obj");
    std::fs::write(&p, CUBE_OBJ).unwrap();
    p
}

#[test]
fn version_and_help() {
    let o = run_str(&["--version"]);
    assert!(o.status.success());
    assert_eq!(
        stdout(&o).trim(),
        format!("algesurf {}", env!("CARGO_PKG_VERSION"))
    );
    let o = run_str(&["--help"]);
    assert!(o.status.success());
    let h = stdout(&o);
    assert!(h.contains("info") && h.contains("convert"), "{h}");
    let o = run_str(&["convert", "--help"]);
    assert!(o.status.success());
    assert!(stdout(&o).contains("--repair"));
    // No arguments: help on stderr and a usage error.
    let o = run_str(&[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("Usage"), "{}", stderr(&o));
}

#[test]
fn info_text() {
    let dir = TempDir::new("info_text");
    let input = cube(&dir);
    let o = run(&["info".as_ref(), input.as_os_str()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = stdout(&o);
    for want in [
        "vertices: 9\n",
        "faces: 6 (6 quads)\n",
        "Euler characteristic V-E+F: 1 ",
        "boundary: 4 edges in 1 loop\n",
        "components: 1\n",
        "inconsistent_orientation",
        "convert --repair would:\n",
        "  welded vertices: 1 [8]\n",
        "  triangulated polygons: 6 [0, 1, 2, 3, 4, 5]\n",
        "  flipped faces: 1 [4]\n",
        "  giving 8 vertices, 12 triangles, 1 component, V-E+F 2: valid\n",
    ] {
        assert!(t.contains(want), "missing {want:?} in:\n{t}");
    }
    assert!(t.contains(&input.display().to_string()));
}

#[test]
fn info_json() {
    let dir = TempDir::new("info_json");
    let input = cube(&dir);
    let o = run(&["info".as_ref(), input.as_os_str(), "--json".as_ref()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    assert_eq!(v["vertices"], 9);
    assert_eq!(v["faces"], 6);
    assert_eq!(v["polygon_sizes"]["4"], 6);
    assert_eq!(v["euler_characteristic"], 1);
    assert_eq!(v["boundary_edges"], 4);
    assert_eq!(v["boundary_loops"], 1);
    assert_eq!(v["valid"], false);
    let comps = v["components"].as_array().unwrap();
    assert_eq!(comps.len(), 1);
    assert_eq!(comps[0]["vertices"], 9);
    assert_eq!(comps[0]["edges"], 14);
    assert!(
        v["findings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| f["kind"] == "inconsistent_orientation")
    );
    let r = &v["repairs"];
    assert_eq!(r["changed"], true);
    assert_eq!(r["welded"], serde_json::json!([[8, 6]]));
    assert_eq!(r["flipped_faces"], serde_json::json!([4]));
    assert_eq!(r["split_vertices"], serde_json::json!([]));
    assert_eq!(r["result"]["vertices"], 8);
    assert_eq!(r["result"]["faces"], 12);
    assert_eq!(r["result"]["euler_characteristic"], 2);
    assert_eq!(r["result"]["valid"], true);
}

fn same_mesh(a: &PolygonMesh, b: &PolygonMesh) {
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.faces().collect::<Vec<_>>(), b.faces().collect::<Vec<_>>());
}

#[test]
fn convert_between_formats() {
    let dir = TempDir::new("convert");
    let input = cube(&dir);
    let original = algesurf_io::read(&input).unwrap();
    let before = std::fs::read(&input).unwrap();
    for ext in ["ply", "off", "obj", "stl", "glb", "gltf"] {
        let out = dir.join(&format!("plain.{ext}"));
        let o = run(&["convert".as_ref(), input.as_os_str(), out.as_os_str()]);
        assert!(o.status.success(), "{ext}: {}", stderr(&o));
        let back = algesurf_io::read(&out).unwrap_or_else(|e| panic!("{ext}: {e}"));
        match ext {
            // Polygon formats with f64 coordinates: the mesh comes back as it was.
            "ply" | "off" | "obj" => same_mesh(&back, &original),
            // Triangle-only formats: quads are split into two triangles each; STL merges
            // the bit-identical vertices 6 and 8.
            "stl" => assert_eq!((back.vertex_count(), back.face_count()), (8, 12)),
            _ => assert_eq!((back.vertex_count(), back.face_count()), (9, 12)),
        }
        // Converting the converted file again (any readable format in) works too.
        let again = dir.join(&format!("again-from-{ext}.ply"));
        let o = run(&["convert".as_ref(), out.as_os_str(), again.as_os_str()]);
        assert!(o.status.success(), "{ext}: {}", stderr(&o));
    }
    assert_eq!(std::fs::read(&input).unwrap(), before, "input untouched");
    // No temporary files left behind.
    let names: Vec<String> = std::fs::read_dir(&dir.0)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}

#[test]
fn convert_with_repair_and_normals() {
    let dir = TempDir::new("repair");
    let input = cube(&dir);
    let before = std::fs::read(&input).unwrap();
    let out = dir.join("fixed.ply");
    let o = run(&[
        "convert".as_ref(),
        input.as_os_str(),
        out.as_os_str(),
        "--repair".as_ref(),
        "--normals".as_ref(),
        "angle".as_ref(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let msg = stderr(&o);
    assert!(
        msg.contains("welded vertices: 1 [8]") && msg.contains("flipped faces: 1 [4]"),
        "{msg}"
    );
    let back = algesurf_io::read(&out).unwrap();
    assert_eq!((back.vertex_count(), back.face_count()), (8, 12));
    assert!(validate(&back).is_valid(), "{}", validate(&back));
    let normals = back.normals.as_ref().expect("normals written");
    assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-12));
    assert_eq!(std::fs::read(&input).unwrap(), before, "input untouched");
    // A bow-tie: --repair splits the shared vertex (and says so); Loop normals then exist at
    // both copies.
    let bow = dir.join("bowtie.obj");
    std::fs::write(
        &bow,
        "v 0 0 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n",
    )
    .unwrap();
    let bow_out = dir.join("bow.ply");
    let o = run(&[
        "convert".as_ref(),
        bow.as_os_str(),
        bow_out.as_os_str(),
        "--normals".as_ref(),
        "loop".as_ref(),
        "--repair".as_ref(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let back = algesurf_io::read(&bow_out).unwrap();
    assert_eq!(back.vertex_count(), 6);
    assert!(validate(&back).is_valid());
    assert!(stderr(&o).contains("split non-manifold vertices: 1 [0 into 2]"));
}

#[test]
fn unreadable_input_names_the_file() {
    let dir = TempDir::new("unreadable");
    let missing = dir.join("does-not-exist.obj");
    let garbage_ply = dir.join("garbage.ply");
    std::fs::write(&garbage_ply, b"\x00\x01 not a mesh at all").unwrap();
    let garbage_obj = dir.join("garbage.obj");
    std::fs::write(&garbage_obj, b"\x00\x01 not a mesh at all").unwrap();
    let bad_index = dir.join("bad-index.obj");
    std::fs::write(&bad_index, "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
    let out = dir.join("out.ply");
    for input in [&missing, &garbage_ply, &garbage_obj, &bad_index] {
        for cmd in [
            vec!["info".as_ref(), input.as_os_str()],
            vec!["convert".as_ref(), input.as_os_str(), out.as_os_str()],
        ] {
            let o = run(&cmd);
            assert!(!o.status.success(), "{input:?} {cmd:?}");
            let e = stderr(&o);
            assert!(e.contains(&input.display().to_string()), "{e}");
            assert!(e.starts_with("algesurf: error: "), "{e}");
            assert!(o.stdout.is_empty());
        }
    }
    assert!(stderr(&run(&["info".as_ref(), bad_index.as_os_str()])).contains("line 3"));
    assert!(!out.exists(), "nothing written on a failed read");
}

#[test]
fn failed_conversion_does_not_clobber_the_output() {
    let dir = TempDir::new("clobber");
    let input = cube(&dir);
    // 1. An existing output stays as it was when the input cannot be read.
    let out = dir.join("existing.ply");
    std::fs::write(&out, b"precious").unwrap();
    let garbage = dir.join("garbage.stl");
    std::fs::write(&garbage, b"short").unwrap();
    let o = run(&["convert".as_ref(), garbage.as_os_str(), out.as_os_str()]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");

    // 2. The final rename fails (the output path is a non-empty folder): error naming it,
    // the folder and its content untouched, no temporary file left.
    let target = dir.join("taken.ply");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep.txt"), b"keep").unwrap();
    let o = run(&["convert".as_ref(), input.as_os_str(), target.as_os_str()]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("taken.ply"), "{}", stderr(&o));
    assert_eq!(std::fs::read(target.join("keep.txt")).unwrap(), b"keep");
    let leftovers: Vec<_> = std::fs::read_dir(&dir.0)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // 3. A read-only output folder: error, the existing file untouched, nothing written.
    let ro = dir.join("readonly");
    std::fs::create_dir(&ro).unwrap();
    let kept = ro.join("mesh.ply");
    std::fs::write(&kept, b"precious").unwrap();
    let mut perm = std::fs::metadata(&ro).unwrap().permissions();
    perm.set_readonly(true);
    std::fs::set_permissions(&ro, perm).unwrap();
    // Permissions are not enforced for every user (root, some file systems): probe first.
    let probe = ro.join("probe");
    if std::fs::write(&probe, b"").is_ok() {
        let _ = std::fs::remove_file(&probe);
        println!("skipped the read-only folder case: this user can write into it anyway");
    } else {
        let o = run(&["convert".as_ref(), input.as_os_str(), kept.as_os_str()]);
        assert!(!o.status.success());
        assert!(stderr(&o).contains("mesh.ply"), "{}", stderr(&o));
        assert_eq!(std::fs::read(&kept).unwrap(), b"precious");
        assert_eq!(std::fs::read_dir(&ro).unwrap().count(), 1);
    }
    make_writable(&ro);

    // 4. An unknown output extension is refused before anything is written.
    let o = run(&[
        "convert".as_ref(),
        input.as_os_str(),
        dir.join("out.xyz").as_os_str(),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("out.xyz"), "{}", stderr(&o));
    assert!(!dir.join("out.xyz").exists());
}

//! End-to-end tests of `algesurf render`: PNGs from a mesh file and from `--smooth` on the
//! built-in icosahedron, and its errors.

mod common;

use std::path::{Path, PathBuf};

use algesurf_mesh::shapes;
use common::{TempDir, algesurf, text};

/// Width, height and the count of opaque pixels of an RGBA PNG (the decoder checks the
/// file's structure and checksums).
fn png_summary(path: &Path) -> (u32, u32, usize) {
    let file = std::fs::File::open(path).expect("open png");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a valid PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("decode");
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let opaque = buf[..info.buffer_size()]
        .chunks_exact(4)
        .filter(|p| p[3] == 255)
        .count();
    (info.width, info.height, opaque)
}

fn write_torus(dir: &Path) -> PathBuf {
    let path = dir.join("torus.obj");
    let mesh = shapes::torus(24, 12, 1.5, 0.6).to_polygon_mesh();
    algesurf_io::write(&path, &mesh, &algesurf_io::WriteOptions::default()).expect("write");
    path
}

#[test]
fn render_writes_a_png_of_the_mesh_in_every_mode() {
    let dir = TempDir::new("render", "modes");
    let torus = write_torus(dir.path());
    for mode in ["shaded", "isophotes", "zebra", "patches", "curvature"] {
        let out_name = format!("{mode}.png");
        let out = algesurf(
            dir.path(),
            &[
                "render",
                torus.to_str().unwrap(),
                "-o",
                &out_name,
                "--mode",
                mode,
                "--size",
                "120x90",
                "--wire",
            ],
        );
        assert!(out.status.success(), "{mode}: {}", text(&out));
        let (w, h, opaque) = png_summary(&dir.path().join(&out_name));
        assert_eq!(h, 90, "{mode}");
        if mode == "curvature" {
            assert!(w > 120, "the legend strip widens the image");
            assert!(String::from_utf8_lossy(&out.stdout).contains("colour range"));
        } else {
            assert_eq!(w, 120, "{mode}");
        }
        assert!(
            opaque > 1000,
            "{mode}: the torus covers part of the image ({opaque})"
        );
    }
}

#[test]
fn render_smooth_on_the_built_in_icosahedron_shows_the_patches() {
    let dir = TempDir::new("render", "smooth");
    let out = algesurf(
        dir.path(),
        &[
            "render",
            "--smooth",
            "--mode",
            "patches",
            "--wire",
            "--view",
            "front,side,top,iso",
            "--size",
            "100x100",
            "--resolution",
            "4",
            "-o",
            "ico.png",
        ],
    );
    assert!(out.status.success(), "{}", text(&out));
    let (w, h, opaque) = png_summary(&dir.path().join("ico.png"));
    assert_eq!((w, h), (200, 200), "four views in a 2×2 grid");
    assert!(opaque > 4 * 3000, "{opaque}");
}

#[test]
fn render_errors_are_clear_and_leave_no_output() {
    let dir = TempDir::new("render", "errors");
    let torus = write_torus(dir.path());
    let t = torus.to_str().unwrap();
    let cases: [(&[&str], &str); 10] = [
        (&["render", t, "-o", "a.png", "--size", "12x"], "bad size"),
        (&["render", t, "-o", "a.png", "--mode", "glossy"], "glossy"),
        (
            &["render", t, "-o", "a.png", "--view", "back"],
            "unknown view",
        ),
        (
            &["render", t, "-o", "a.png", "--background", "#12"],
            "bad background",
        ),
        (&["render", "missing.obj", "-o", "a.png"], "missing.obj"),
        (&["render", "-o", "a.png"], "INPUT mesh is required"),
        (&["render", t, "-o", t], "refusing to overwrite the input"),
        // PNG bytes in a .jpg would mislead whatever opens it; refused before the input is read.
        (
            &["render", "missing.obj", "-o", "a.jpg"],
            "a.jpg: render writes PNG images",
        ),
        // Refused before rendering (it failed only at the write).
        (
            &["render", t, "-o", "missing/a.png", "--smooth"],
            "the folder missing does not exist",
        ),
        // 2.4 G triangles (~217 GB): refused before tessellating, naming the file and grid.
        (
            &[
                "render",
                t,
                "-o",
                "a.png",
                "--smooth",
                "--resolution",
                "1024",
            ],
            "torus.obj: resolution 1024 × 1024",
        ),
    ];
    for (args, needle) in cases {
        let out = algesurf(dir.path(), args);
        assert!(!out.status.success(), "{args:?}: {}", text(&out));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!dir.path().join("a.png").exists(), "{args:?}");
    }
    let garbage = dir.path().join("garbage.obj");
    std::fs::write(&garbage, "not a mesh\n").unwrap();
    let out = algesurf(dir.path(), &["render", "garbage.obj", "-o", "a.png"]);
    assert!(
        !out.status.success() && !dir.path().join("a.png").exists(),
        "{}",
        text(&out)
    );
}

#[test]
fn render_writes_the_same_bytes_on_one_thread_and_on_two() {
    let dir = TempDir::new("render", "threads");
    let torus = write_torus(dir.path());
    let mut files = Vec::new();
    for threads in ["1", "2"] {
        let name = format!("t{threads}.png");
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_algesurf"))
            .current_dir(dir.path())
            .env("RAYON_NUM_THREADS", threads)
            .args(["render", torus.to_str().unwrap(), "-o", &name])
            .args([
                "--mode",
                "zebra",
                "--wire",
                "--view",
                "front,iso",
                "--size",
                "150x100",
            ])
            .output()
            .expect("run algesurf");
        assert!(out.status.success(), "{}", text(&out));
        files.push(std::fs::read(dir.path().join(name)).unwrap());
    }
    assert_eq!(files[0], files[1]);
}

/// `--smooth` builds a far mesh about an origin near it (see `smooth`'s test of a far
/// torus) and renders it in the input's coordinates, which `--eye` and `--target` are given
/// in: the torus moved by 10⁵ (where it failed to build) looks as the torus does from the
/// same relative camera.
#[test]
fn render_smooth_of_a_far_mesh_takes_the_camera_in_the_input_coordinates() {
    let dir = TempDir::new("render", "far");
    let offset = glam::DVec3::new(1e5, -1e5, 1e5);
    let mut covered = Vec::new();
    for (name, shift) in [("near", glam::DVec3::ZERO), ("far", offset)] {
        let mut mesh = shapes::torus(24, 12, 1.5, 0.6).to_polygon_mesh();
        for p in &mut mesh.positions {
            *p += shift;
        }
        let obj = dir.path().join(format!("{name}.obj"));
        algesurf_io::write(&obj, &mesh, &algesurf_io::WriteOptions::default()).expect("write");
        let (eye, target) = (shift + glam::DVec3::new(0.0, -6.0, 4.0), shift);
        let xyz = |p: glam::DVec3| format!("{:?},{:?},{:?}", p.x, p.y, p.z);
        let png = format!("{name}.png");
        let out = algesurf(
            dir.path(),
            &[
                "render",
                obj.to_str().unwrap(),
                "-o",
                &png,
                "--smooth",
                "--size",
                "160x120",
                "--eye",
                &xyz(eye),
                "--target",
                &xyz(target),
                "--up",
                "0,0,1",
            ],
        );
        assert!(out.status.success(), "{name}: {}", text(&out));
        covered.push(png_summary(&dir.path().join(&png)).2);
    }
    let (near, far) = (covered[0], covered[1]);
    assert!(
        near > 2000,
        "the torus fills part of the view ({near} pixels)"
    );
    assert!(
        near.abs_diff(far) * 200 <= near,
        "near {near} and far {far} pixels covered"
    );
}

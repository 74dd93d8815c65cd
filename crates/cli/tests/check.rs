//! End-to-end tests of `algesurf check`: the table on the built-in mesh and on a file, the
//! JSON report, and the exit statuses (0 all hold, 1 errors; 2, a failing property, is tested
//! in the binary's unit tests and by algesurf-inspect's perturbation tests).

mod common;

use common::{TempDir, algesurf, read_json, text};

use algesurf_mesh::{PolygonMesh, shapes};

const PROPERTIES: [&str; 8] = [
    "interpolation",
    "vertex_normals",
    "c1_value",
    "c1_gradient",
    "normal_agreement",
    "missed_rays",
    "euler_characteristic",
    "parameter_margin",
];

#[test]
fn default_mesh_passes_and_prints_the_table() {
    let dir = TempDir::new("check", "default");
    let out = algesurf(dir.path(), &["check"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("built-in icosahedron"), "{stdout}");
    let header = stdout
        .lines()
        .find(|l| l.starts_with("property"))
        .expect("a table header");
    for column in ["worst", "where", "threshold", "result"] {
        assert!(header.contains(column), "{header}");
    }
    for property in PROPERTIES {
        let row = stdout
            .lines()
            .find(|l| l.starts_with(property))
            .unwrap_or_else(|| panic!("no row {property}:\n{stdout}"));
        assert!(row.ends_with("pass"), "{row}");
    }
    assert!(stdout.contains("closed_manifold"), "{stdout}");
    assert!(
        stdout.contains("≤ 1.00e-12"),
        "thresholds are printed: {stdout}"
    );
    assert!(stdout.contains("all 13 properties hold"), "{stdout}");
}

#[test]
fn json_report_is_written_and_parseable() {
    let dir = TempDir::new("check", "json");
    let out = algesurf(dir.path(), &["check", "--json", "report.json"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out));
    let json: serde_json::Value = read_json(&dir, "report.json");
    assert_eq!(json["passed"], true);
    assert_eq!(json["options"]["normals"], "auto");
    let rows = json["rows"].as_array().unwrap();
    for property in PROPERTIES {
        let row = rows
            .iter()
            .find(|r| r["property"] == property)
            .unwrap_or_else(|| panic!("no row {property}"));
        assert_eq!(row["pass"], true, "{row}");
        assert!(
            row["threshold"].is_number() && row["worst"].is_number(),
            "{row}"
        );
    }
    let c1 = rows
        .iter()
        .find(|r| r["property"] == "c1_gradient")
        .unwrap();
    assert!(
        c1["where"]
            .as_str()
            .unwrap()
            .starts_with("facet between face "),
        "{c1}"
    );
    // Atomic write: no temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("report.json")]);
}

#[test]
fn a_torus_file_passes_with_linear_free_parameters() {
    let dir = TempDir::new("check", "torus");
    let torus = shapes::torus(12, 8, 1.5, 0.6);
    let mesh = PolygonMesh::from_triangles(torus.positions().to_vec(), torus.triangles());
    algesurf_io::write(
        dir.path().join("torus.obj"),
        &mesh,
        &algesurf_io::WriteOptions::default(),
    )
    .unwrap();
    let out = algesurf(
        dir.path(),
        &[
            "check",
            "torus.obj",
            "--resolution",
            "3",
            "--free-parameters",
            "linear",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("torus.obj"), "{stdout}");
    assert!(stdout.contains("χ input 0, output 0"), "{stdout}");
}

#[test]
fn missing_input_is_an_error_with_status_one() {
    let dir = TempDir::new("check", "missing");
    let out = algesurf(dir.path(), &["check", "no-such-mesh.obj"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no-such-mesh.obj"), "{stderr}");
}

#[test]
fn report_over_the_input_is_refused() {
    let dir = TempDir::new("check", "overwrite");
    let ico = shapes::icosphere(0);
    let mesh = PolygonMesh::from_triangles(ico.positions().to_vec(), ico.triangles());
    let path = dir.path().join("ico.obj");
    algesurf_io::write(&path, &mesh, &algesurf_io::WriteOptions::default()).unwrap();
    let before = std::fs::read(&path).unwrap();
    let out = algesurf(dir.path(), &["check", "ico.obj", "--json", "ico.obj"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the input is untouched"
    );
}

#[test]
fn report_in_a_missing_folder_is_refused_before_the_battery() {
    let dir = TempDir::new("check", "missing-folder");
    let out = algesurf(dir.path(), &["check", "--json", "missing/report.json"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("the folder missing does not exist"),
        "{stderr}"
    );
    // Nothing was built or measured: no table on stdout.
    assert!(out.stdout.is_empty(), "{}", text(&out));
}

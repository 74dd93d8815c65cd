//! Across the layers, through the facade: an icosphere written to OBJ and read back is smoothed
//! into the exact sphere (Theorem 4.2's quadric precision), closed and watertight, and passes
//! the whole check battery.

use algesurf::apatch::{ApatchSurface, SurfaceOptions};
use algesurf::inspect::check::{ApatchView, CheckOptions, check};
use algesurf::io::{self, WriteOptions};
use algesurf::mesh::{TriMesh, shapes::icosphere};
use glam::DVec3;

#[test]
fn icosphere_round_trips_through_obj_and_smooths_into_the_sphere() {
    let dir = std::env::temp_dir().join(format!("algesurf-e2e-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("sphere.obj");
    let mut poly = icosphere(1).to_polygon_mesh();
    poly.normals = Some(poly.positions.iter().map(|p| p.normalize()).collect());
    io::write(&path, &poly, &WriteOptions::default()).unwrap();

    let back = io::read(&path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        back.positions, poly.positions,
        "OBJ keeps full f64 precision"
    );
    let mesh = TriMesh::from_polygon_mesh(&back).unwrap();
    let normals: Vec<DVec3> = back.normals.clone().unwrap();
    let surface = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    let t = surface.tessellate(5, 5).unwrap();
    let worst = t
        .positions
        .iter()
        .map(|p| (p.length() - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-10, "max |‖p‖ − 1| = {worst:e}");
    assert!(t.missed_rays.is_empty() && t.multiple_roots.is_empty());
    let report = check(&ApatchView::new(&surface), &CheckOptions::default()).unwrap();
    assert!(report.passed(), "{report}");
}

//! Every mesh of the corpus (`ALGESURF_CORPUS`) smooths with default options: no NaN, no
//! missed rays, closed inputs give watertight output; prints a table per mesh.

use algesurf_apatch::{ApatchSurface, SurfaceOptions};
use algesurf_mesh::{NormalMethod, RepairOptions, TriMesh, TriangleBvh, repair, vertex_normals};
use std::time::Instant;

#[test]
fn every_corpus_mesh_smooths_with_default_options() {
    let Some(dir) = std::env::var_os("ALGESURF_CORPUS") else {
        println!("skipped: ALGESURF_CORPUS unset");
        return;
    };
    let mut names: Vec<_> = std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).collect();
    names.sort();
    println!("{:<22} {:>7} {:>8} {:>9} {:>8} {:>11} {:>11}", "mesh", "faces", "patches", "triangles", "seconds", "hausdorff", "min margin");
    let mut failures = Vec::new();
    for path in names {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let start = Instant::now();
        let poly = algesurf_io::read(&path).unwrap();
        let repaired = repair(&poly, &RepairOptions::default()).unwrap().mesh;
        let mesh = TriMesh::from_polygon_mesh(&repaired).unwrap();
        let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
        let surface = match ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()) {
            Ok(s) => s,
            Err(e) => {
                println!("{name:<22} {:>7} FAILED: {e}", mesh.face_count());
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let t = surface.tessellate(2, 2).unwrap();
        let secs = start.elapsed().as_secs_f64();
        assert!(t.positions.iter().all(|p| p.is_finite()), "{name}: NaN in output");
        let bvh = TriangleBvh::new(&mesh);
        let diag = mesh.bounding_box().diagonal();
        let hausdorff = t.positions.iter().map(|p| bvh.closest_point(*p).map_or(f64::INFINITY, |c| c.distance)).fold(0.0, f64::max) / diag;
        let margin = surface.free_parameters().iter().map(|p| p.relative_margin).fold(f64::INFINITY, f64::min);
        let patches = t.triangle_patch.iter().collect::<std::collections::HashSet<_>>().len();
        println!("{name:<22} {:>7} {:>8} {:>9} {:>8.2} {:>11.3e} {:>11.3e}", mesh.face_count(), patches, t.triangles.len(), secs, hausdorff, margin);
        if !t.missed_rays.is_empty() || !t.multiple_roots.is_empty() {
            failures.push(format!("{name}: {} missed rays, {} multiple roots", t.missed_rays.len(), t.multiple_roots.len()));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

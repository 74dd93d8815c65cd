//! The corpus (`ALGESURF_CORPUS`): every mesh either smooths with default options — no NaN, every
//! ray hits with a simple root, closed inputs give closed manifold output — or, for the meshes
//! listed in `FOLDED`, stops with a typed error that names the offending face and vertex.
//! Prints a table per mesh (faces, patches, seconds, Hausdorff distance to the input, least
//! free-parameter margin).
//!
//! `FOLDED`: cow, Stanford bunny and Suzanne contain vertices whose incident faces fold back on
//! each other (face normals that fit in no hemisphere: e.g. the bunny's sliver face 3029 is
//! turned 125° against its neighbours). §3 of Xu–Huang–Bajaj 2001 needs every vertex normal on
//! the positive side of each incident face, which no normal can satisfy there, and local
//! refinement does not unfold them. Handling folds (a local fallback patch or an unfolding
//! repair) is open work; when it lands, these meshes move to the smoothing list and this test
//! catches any that still fail.

use algesurf_apatch::{ApatchSurface, SurfaceOptions};
use algesurf_inspect::check::{ApatchView, PatchSurface, topology};
use algesurf_mesh::{NormalMethod, RepairOptions, TriMesh, TriangleBvh, repair, vertex_normals};
use std::time::Instant;

const FOLDED: [&str; 3] = ["cow.obj", "stanford-bunny.obj", "suzanne.obj"];

#[test]
fn every_corpus_mesh_smooths_or_names_its_fold() {
    let Some(dir) = std::env::var_os("ALGESURF_CORPUS") else {
        println!("skipped: ALGESURF_CORPUS unset");
        return;
    };
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .collect();
    paths.sort();
    println!(
        "{:<22} {:>7} {:>8} {:>9} {:>8} {:>11} {:>11}",
        "mesh", "faces", "patches", "triangles", "seconds", "hausdorff", "min margin"
    );
    let mut failures = Vec::new();
    for path in paths {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let start = Instant::now();
        let poly = algesurf_io::read(&path).unwrap();
        let repaired = repair(&poly, &RepairOptions::default()).unwrap().mesh;
        let mesh = TriMesh::from_polygon_mesh(&repaired).unwrap();
        let closed = mesh.boundary_loops().is_empty();
        let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
        let surface = match ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()) {
            Ok(s) => s,
            Err(e) => {
                let msg = e.to_string();
                println!("{name:<22} {:>7} not smoothed: {msg}", mesh.face_count());
                if !FOLDED.contains(&name.as_str()) {
                    failures.push(format!("{name}: {msg}"));
                } else if !(msg.contains("face") && msg.contains("vertex")) {
                    failures.push(format!(
                        "{name}: the error does not name the face and vertex: {msg}"
                    ));
                }
                continue;
            }
        };
        let view = ApatchView::new(&surface);
        let t = view.tessellate(2).unwrap();
        let secs = start.elapsed().as_secs_f64();
        let bvh = TriangleBvh::new(&mesh);
        let diag = mesh.bounding_box().diagonal();
        let hausdorff = t
            .positions
            .iter()
            .map(|p| bvh.closest_point(*p).map_or(f64::INFINITY, |c| c.distance))
            .fold(0.0, f64::max)
            / diag;
        let margin = surface
            .free_parameters()
            .iter()
            .map(|p| p.relative_margin)
            .fold(f64::INFINITY, f64::min);
        let patches = t
            .triangle_patch
            .iter()
            .collect::<std::collections::HashSet<_>>()
            .len();
        println!(
            "{name:<22} {:>7} {:>8} {:>9} {:>8.2} {:>11.3e} {:>11.3e}",
            mesh.face_count(),
            patches,
            t.triangles.len(),
            secs,
            hausdorff,
            margin
        );
        if t.positions.iter().any(|p| !p.is_finite()) {
            failures.push(format!("{name}: non-finite output"));
        }
        if !t.missed_rays.is_empty() || !t.multiple_roots.is_empty() {
            failures.push(format!(
                "{name}: {} missed rays, {} multiple roots",
                t.missed_rays.len(),
                t.multiple_roots.len()
            ));
        }
        let topo = topology(&t, view.input_topology());
        if closed && topo.bad_edges > 0 {
            failures.push(format!(
                "{name}: closed input, but the output is not a closed manifold"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

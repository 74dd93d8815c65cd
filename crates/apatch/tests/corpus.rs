//! The corpus (`ALGESURF_CORPUS`): every mesh either smooths with default options — no NaN, every
//! ray hits with a simple root, closed inputs give closed manifold output — or, for the meshes
//! listed in `FOLDED`, stops with a typed error that names the offending face and vertex.
//! Prints a table per mesh (faces, patches, seconds, Hausdorff distance to the input, least
//! free-parameter margin).
//!
//! `FOLDED`: cow, Stanford bunny and Suzanne contain folds: vertices whose incident faces'
//! normals fit in no hemisphere (the bunny's sliver caps turned 125° against their
//! neighbours; the rims of the cow's ears, whose two sides cross). §3 of Xu–Huang–Bajaj 2001
//! needs every vertex normal on the positive side of each incident face. The repair now flips
//! folded caps and moves folded vertices the least distance that opens them
//! (`RepairOptions::{flip_folded_caps, unfold_vertices}`), so all three build their initial
//! hull; but the local Butterfly refinement that separates intersecting tetrahedra overshoots
//! next to their sharp features and folds a vertex again (cow and bunny after three rounds,
//! Suzanne after one), which stops the build with an error naming the face and the vertex.
//! Pulling the Butterfly point towards the edge midpoint where it would fold was tried: it
//! then runs out of rounds with tetrahedra of the same input face still intersecting. Handling
//! that is open work; when it lands, these meshes move to the smoothing list and this test
//! catches any that still fail.
use algesurf_apatch::{ApatchSurface, SurfaceOptions, Tessellation};
use algesurf_mesh::{NormalMethod, RepairOptions, TriMesh, TriangleBvh, repair, vertex_normals};
use std::collections::HashMap;
use std::time::Instant;

const FOLDED: [&str; 3] = ["cow.obj", "stanford-bunny.obj", "suzanne.obj"];

fn closed_manifold(t: &Tessellation) -> bool {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for tri in &t.triangles {
        for k in 0..3 {
            *directed.entry((tri[k], tri[(k + 1) % 3])).or_default() += 1;
        }
    }
    directed
        .iter()
        .all(|(&(a, b), &c)| c == 1 && directed.get(&(b, a)) == Some(&1))
}

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
        let t = surface.tessellate(2, 2).unwrap();
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
        if closed && !closed_manifold(&t) {
            failures.push(format!(
                "{name}: closed input, but the output is not a closed manifold"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

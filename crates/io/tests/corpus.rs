//! Corpus run: every mesh in the folder named by `ALGESURF_CORPUS` loads, validates and
//! repairs to a valid, consistently oriented triangle mesh; the test prints what was repaired.
//!
//! ```text
//! ALGESURF_CORPUS=../shared/data cargo test -p algesurf-io --test corpus -- --nocapture
//! ```
//!
//! Reference numbers (after welding) were computed independently in Python with numpy and
//! libigl 2.x (`/tmp/peers` venv: `pip install trimesh numpy libigl`): a plain OBJ parser
//! (fan-triangulating polygons), `igl.remove_duplicate_vertices(V, F, 1e-9 * bbox_diagonal)`,
//! then edges counted with `np.unique(sorted_edges, return_counts=True)`, boundary loops as
//! connected components of the boundary-edge graph, χ = V_used − E + F. trimesh 4
//! (`merge_vertices()`, `remove_unreferenced_vertices()`) gives the same numbers.
//!
//! | mesh | file V | unused | duplicates | boundary edges (unwelded → welded) | loops | χ | genus |
//! |------|--------|--------|------------|------------------------------------|-------|---|-------|
//! | teapot | 3644 | 0 | 403 | 1036 → 160 | 6 | 1 | – |
//! | stanford-bunny | 35947 | 1113 | 0 | 223 → 223 | 5 | −3 | 0 (one component: (2 − χ − b)/2) |

use std::path::PathBuf;

use algesurf_mesh::{Finding, RepairOptions, TriMesh, repair, validate};

const TEAPOT_WELDED_BOUNDARY_EDGES: usize = 160;
const TEAPOT_UNWELDED_BOUNDARY_EDGES: usize = 1036;
const TEAPOT_DUPLICATE_VERTICES: usize = 403;
const BUNNY_GENUS: u32 = 0;
const BUNNY_HOLES: usize = 5;
const BUNNY_UNUSED_VERTICES: usize = 1113;

fn weld_only() -> RepairOptions {
    RepairOptions {
        weld_tolerance: RepairOptions::default().weld_tolerance,
        triangulate: false,
        drop_degenerate_faces: false,
        drop_duplicate_faces: false,
        drop_unused_vertices: true,
        orient: false,
        ..RepairOptions::default()
    }
}

#[test]
fn corpus_loads_validates_and_repairs() {
    let Some(dir) = std::env::var_os("ALGESURF_CORPUS") else {
        println!("skipped: ALGESURF_CORPUS unset");
        return;
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("ALGESURF_CORPUS is a readable folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| algesurf_io::Format::from_path(p).is_some())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no mesh files in {dir:?}");
    let mut seen_teapot = false;
    let mut seen_bunny = false;
    for path in &files {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let mesh = algesurf_io::read(path).unwrap_or_else(|e| panic!("{e}"));
        let report = validate(&mesh);
        println!(
            "== {name}: {} vertices, {} faces",
            mesh.vertex_count(),
            mesh.face_count()
        );
        println!("   findings: {:?}", report.counts());
        let repaired =
            repair(&mesh, &RepairOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        print!("   repaired: {}", repaired.report);
        let out = &repaired.mesh;
        assert!(
            out.faces().all(|f| f.len() == 3),
            "{name}: not all triangles"
        );
        let tri = TriMesh::from_polygon_mesh(out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let after = validate(out);
        let bad: Vec<&Finding> = after
            .findings
            .iter()
            .filter(|f| {
                !matches!(
                    f,
                    Finding::NonManifoldEdge { .. } | Finding::NonManifoldVertex { .. }
                )
            })
            .collect();
        assert!(bad.is_empty(), "{name}: after repair: {bad:?}");
        // Non-manifold configurations are reported, not repaired (no repair step removes
        // faces to make a mesh manifold); everything manifold must be consistently oriented.
        let non_manifold = after.findings.len();
        if non_manifold > 0 {
            println!(
                "   still non-manifold after repair (reported, not repaired): {:?}",
                after.counts()
            );
        }
        for c in after.components.iter().filter(|c| c.manifold) {
            assert!(c.consistently_oriented, "{name}: component not oriented");
        }
        println!(
            "   result: {} vertices, {} triangles, {} components, χ = {}",
            tri.vertex_count(),
            tri.face_count(),
            after.components.len(),
            tri.euler_characteristic()
        );

        if name == "teapot" {
            seen_teapot = true;
            assert_eq!(report.boundary_edge_count(), TEAPOT_UNWELDED_BOUNDARY_EDGES);
            let welded = repair(&mesh, &weld_only()).unwrap();
            assert_eq!(welded.report.welded.len(), TEAPOT_DUPLICATE_VERTICES);
            let v = validate(&welded.mesh);
            println!(
                "   after welding: {} boundary edges",
                v.boundary_edge_count()
            );
            assert_eq!(v.boundary_edge_count(), TEAPOT_WELDED_BOUNDARY_EDGES);
        }
        if name == "stanford-bunny" {
            seen_bunny = true;
            let unused = report
                .findings
                .iter()
                .filter(|f| matches!(f, Finding::UnusedVertex { .. }))
                .count();
            assert_eq!(unused, BUNNY_UNUSED_VERTICES);
            let welded = repair(&mesh, &weld_only()).unwrap();
            let v = validate(&welded.mesh);
            assert_eq!(v.components.len(), 1);
            let c = &v.components[0];
            println!(
                "   after welding: genus {:?}, {} holes, χ = {}",
                c.genus, c.boundary_loop_count, c.euler_characteristic
            );
            assert_eq!(c.genus, Some(BUNNY_GENUS));
            assert_eq!(c.boundary_loop_count, BUNNY_HOLES);
        }
    }
    let has = |n: &str| files.iter().any(|p| p.file_stem().is_some_and(|s| s == n));
    assert_eq!(seen_teapot, has("teapot"));
    assert_eq!(seen_bunny, has("stanford-bunny"));
}

//! Corpus run: every mesh in the folder named by `ALGESURF_CORPUS` loads, validates and
//! repairs to a valid, consistently oriented triangle mesh; the test prints what was repaired.
//!
//! ```text
//! ALGESURF_CORPUS=../shared/data cargo test -p algesurf-io --test corpus -- --nocapture
//! ```
//!
//! Reference numbers were computed independently in Python with numpy and libigl 2.x (`/tmp/peers`
//! venv: `pip install trimesh numpy libigl`), with no algesurf code: a plain OBJ parser keeping
//! polygons, `igl.remove_duplicate_vertices(V, F, 1e-9 * bbox_diagonal)` for welding (faces that
//! then repeat a vertex dropped), edges as the set of sorted corner pairs of every polygon (so
//! χ = V_used − E + F is counted on the polygons and holds for any triangulation that adds no
//! existing edge), non-manifold vertices from fans (faces at a vertex joined across edges with
//! exactly two faces, by union-find), boundary loops counted on the mesh split into one vertex
//! copy per fan (there every boundary vertex has exactly two boundary edges, so loops are the
//! connected components of the boundary-edge graph), components by union-find over shared edges.
//! "repaired" is welded + split per fan. The script printed:
//!
//! | mesh | stage | V used | E | F | χ | boundary edges | loops | components | nm vertices |
//! |------|-------|--------|---|---|---|----------------|-------|------------|-------------|
//! | cow | raw = welded | 2903 | 8706 | 5804 | 1 | 0 | 0 | 1 | 1 |
//! | cow | repaired | 2904 | 8706 | 5804 | 2 | 0 | 0 | 1 | 0 |
//! | fandisk | all | 6475 | 19419 | 12946 | 2 | 0 | 0 | 1 | 0 |
//! | spot | all | 2930 | 8784 | 5856 | 2 | 0 | 0 | 1 | 0 |
//! | stanford-bunny | all | 34834 (+1113 unused) | 104288 | 69451 | −3 | 223 | 5 | 1 | 0 |
//! | suzanne | raw | 507 | 1005 | 500 polygons | 2 | 42 | 4 | 3 | 0 |
//! | suzanne | welded | 505 | 1005 | 500 polygons | 0 | 42 | 4 | 3 | 2 |
//! | suzanne | repaired | 507 | – | – | 2 | 42 | 4 | 3 | 0 |
//! | teapot | raw | 3644 | 9998 | 6320 | −34 | 1036 | 25 | 19 | 38 |
//! | teapot | welded | 3241 | 9560 | 6320 | 1 | 160 | 6 | 4 | 1 |
//! | teapot | repaired | 3242 | 9560 | 6320 | 2 | 160 | 6 | 4 | 0 |
//!
//! The welded bunny is one component with χ = −3 and 5 holes: genus (2 − χ − b)/2 = 0. The welded
//! teapot's components (faces, χ, loops) are (3160, 1, 1), (1560, 1, 1), (800, 0, 2) twice, all
//! genus 0; welding makes two of them touch at one vertex (algesurf names it: input vertex
//! 373), which is why the whole welded mesh has χ = 1 while its components' χ add up to 2.
//! trimesh 4 (`merge_vertices()`, `remove_unreferenced_vertices()`) gives the same welded
//! counts. The script is `tests/corpus_reference.py`; rerun it with
//! `python corpus_reference.py ../shared/data` in a venv with numpy and libigl.

use std::collections::HashSet;

use algesurf_mesh::{Finding, PolygonMesh, RepairOptions, TriMesh, repair, validate};

/// Reference numbers from the table above, for one stage of one mesh.
#[derive(Debug, PartialEq)]
struct Counts {
    vertices_used: usize,
    chi: i64,
    boundary_edges: usize,
    loops: usize,
    components: usize,
}

const fn c(
    vertices_used: usize,
    chi: i64,
    boundary_edges: usize,
    loops: usize,
    components: usize,
) -> Counts {
    Counts {
        vertices_used,
        chi,
        boundary_edges,
        loops,
        components,
    }
}

/// `(mesh, raw, welded, repaired)`.
const REFERENCE: &[(&str, Counts, Counts, Counts)] = &[
    (
        "cow",
        c(2903, 1, 0, 0, 1),
        c(2903, 1, 0, 0, 1),
        c(2904, 2, 0, 0, 1),
    ),
    (
        "fandisk",
        c(6475, 2, 0, 0, 1),
        c(6475, 2, 0, 0, 1),
        c(6475, 2, 0, 0, 1),
    ),
    (
        "spot",
        c(2930, 2, 0, 0, 1),
        c(2930, 2, 0, 0, 1),
        c(2930, 2, 0, 0, 1),
    ),
    (
        "stanford-bunny",
        c(34834, -3, 223, 5, 1),
        c(34834, -3, 223, 5, 1),
        c(34834, -3, 223, 5, 1),
    ),
    (
        "suzanne",
        c(507, 2, 42, 4, 3),
        c(505, 0, 42, 4, 3),
        c(507, 2, 42, 4, 3),
    ),
    (
        "teapot",
        c(3644, -34, 1036, 25, 19),
        c(3241, 1, 160, 6, 4),
        c(3242, 2, 160, 6, 4),
    ),
];

/// V − E + F counted directly from the face list (V: vertices used by a face, E: distinct
/// sorted corner pairs), independently of `Topology`.
fn chi_from_faces(mesh: &PolygonMesh) -> i64 {
    let mut vs = HashSet::new();
    let mut es = HashSet::new();
    for f in mesh.faces() {
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            vs.insert(a);
            es.insert((a.min(b), a.max(b)));
        }
    }
    vs.len() as i64 - es.len() as i64 + mesh.face_count() as i64
}

/// What algesurf says about `mesh`, in the reference's terms; also checks that the library's
/// χ (whole mesh, validation report and `TriMesh`) agrees with the direct count.
fn measure(name: &str, stage: &str, mesh: &PolygonMesh) -> Counts {
    let r = validate(mesh);
    let direct = chi_from_faces(mesh);
    assert_eq!(r.euler_characteristic, direct, "{name} {stage}: χ");
    if mesh.faces().all(|f| f.len() == 3) {
        let t = TriMesh::from_polygon_mesh(mesh).unwrap();
        assert_eq!(
            t.euler_characteristic(),
            direct,
            "{name} {stage}: TriMesh χ"
        );
    }
    let used = mesh.vertex_count()
        - r.findings
            .iter()
            .filter(|f| matches!(f, Finding::UnusedVertex { .. }))
            .count();
    let loops: usize = r.components.iter().map(|c| c.boundary_loop_count).sum();
    assert_eq!(loops, r.boundary_loops.len(), "{name} {stage}: loops");
    // The loops are closed and partition the boundary edges (edges of one face side, counted
    // from the face list): consecutive vertices, and last → first, are boundary edges.
    let mut sides: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for f in mesh.faces() {
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            *sides.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut boundary: HashSet<(u32, u32)> = sides
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect();
    assert_eq!(boundary.len(), r.boundary_edge_count(), "{name} {stage}");
    for lp in &r.boundary_loops {
        for (i, &a) in lp.iter().enumerate() {
            let b = lp[(i + 1) % lp.len()];
            assert!(
                boundary.remove(&(a.min(b), a.max(b))),
                "{name} {stage}: loop edge ({a}, {b}) is not an unused boundary edge"
            );
        }
    }
    assert!(boundary.is_empty(), "{name} {stage}: edges in no loop");
    let got = c(
        used,
        direct,
        r.boundary_edge_count(),
        loops,
        r.components.len(),
    );
    println!("   {stage}: {got:?}");
    got
}

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
        split_non_manifold_vertices: false,
        orient: false,
        ..RepairOptions::default()
    }
}

#[test]
fn corpus_loads_validates_and_repairs() {
    let Some(mut files) = algesurf_mesh::test_corpus::corpus_files() else {
        return;
    };
    files.retain(|p| algesurf_io::Format::from_path(p).is_some());
    assert!(!files.is_empty(), "no mesh files in the corpus folder");
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
        for line in repaired.report.to_string().lines() {
            println!("   repaired: {line}");
        }
        let out = &repaired.mesh;
        assert!(
            out.faces().all(|f| f.len() == 3),
            "{name}: not all triangles"
        );
        let tri = TriMesh::from_polygon_mesh(out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let after = validate(out);
        assert!(after.is_valid(), "{name}: after repair: {after}");
        for c in &after.components {
            assert!(c.manifold && c.consistently_oriented, "{name}: {c:?}");
            assert!(c.genus.is_some(), "{name}: genus of {c:?}");
        }
        if let Some((_, raw, welded, fixed)) = REFERENCE.iter().find(|r| r.0 == name) {
            assert_eq!(&measure(&name, "raw", &mesh), raw, "{name}: raw");
            let w = repair(&mesh, &weld_only()).unwrap();
            assert_eq!(&measure(&name, "welded", &w.mesh), welded, "{name}: welded");
            assert_eq!(&measure(&name, "repaired", out), fixed, "{name}: repaired");
        } else {
            // A mesh added to the corpus later: still check χ against the direct count.
            measure(&name, "raw", &mesh);
            measure(&name, "repaired", out);
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

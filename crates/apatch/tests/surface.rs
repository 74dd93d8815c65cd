//! End-to-end claims of Xu–Huang–Bajaj 2001 on whole meshes, measured on the tessellation.

use algesurf_apatch::{ApatchSurface, PatchKind, SurfaceOptions};
use algesurf_inspect::check::{ApatchView, CheckOptions, CheckReport, check};
use algesurf_mesh::TriMesh;
use algesurf_mesh::shapes::icosphere;
use glam::DVec3;

/// The check battery of algesurf-inspect (interpolation, C1 across every interior facet,
/// normal agreement, simple roots, closed manifold with the input's Euler characteristic, no
/// duplicate positions, parameter margins) at tessellation resolution `resolution`.
fn battery(s: &ApatchSurface, resolution: usize) -> CheckReport {
    let options = CheckOptions {
        resolution,
        ..CheckOptions::default()
    };
    check(&ApatchView::new(s), &options).unwrap()
}

fn sphere_surface(level: u32) -> (TriMesh, ApatchSurface) {
    let mesh = icosphere(level);
    let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    (mesh, s)
}

#[test]
fn sphere_is_recovered_from_icosahedron() {
    for level in 0..=3 {
        let (_, s) = sphere_surface(level);
        let t = s.tessellate(6, 6).unwrap();
        assert!(
            t.missed_rays.is_empty(),
            "level {level}: {} missed rays",
            t.missed_rays.len()
        );
        assert!(
            t.multiple_roots.is_empty(),
            "level {level}: {} multiple roots",
            t.multiple_roots.len()
        );
        let worst = t
            .positions
            .iter()
            .map(|p| (p.length() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst <= 1e-10, "level {level}: max | |p| − 1 | = {worst:e}");
        let worst_n = t
            .positions
            .iter()
            .zip(&t.normals)
            .map(|(p, n)| (n - p.normalize()).length())
            .fold(0.0, f64::max);
        assert!(worst_n <= 1e-8, "level {level}: normal error {worst_n:e}");
    }
}

#[test]
fn closed_input_gives_closed_manifold_output_with_its_euler_characteristic() {
    let (mesh, s) = sphere_surface(1);
    let r = battery(&s, 5);
    for property in [
        "closed_manifold",
        "duplicate_positions",
        "euler_characteristic",
    ] {
        assert!(r.row(property).unwrap().pass, "{r}");
    }
    let t = s.tessellate(5, 4).unwrap();
    // Every input vertex is a tessellation vertex.
    for (i, p) in mesh.positions().iter().enumerate() {
        assert_eq!(t.positions[i], *p);
    }
    let kinds: std::collections::HashSet<PatchKind> = t.triangle_kind.iter().copied().collect();
    assert!(kinds.contains(&PatchKind::Face) && kinds.contains(&PatchKind::Edge));
}

#[test]
fn torus_smooths_to_a_closed_manifold() {
    use algesurf_mesh::shapes::torus;
    use algesurf_mesh::{NormalMethod, vertex_normals};
    let mesh = torus(16, 10, 1.5, 0.5);
    let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    let counts = s.faces().iter().fold([0usize; 3], |mut c, f| {
        match f {
            algesurf_apatch::FaceFunction::Planar => c[0] += 1,
            algesurf_apatch::FaceFunction::Convex { .. } => c[1] += 1,
            algesurf_apatch::FaceFunction::Split(_) => c[2] += 1,
        }
        c
    });
    println!(
        "torus faces: planar {}, convex {}, split {}",
        counts[0], counts[1], counts[2]
    );
    assert!(
        counts[2] > 0,
        "the torus's saddle region has nonconvex faces"
    );
    let r = battery(&s, 4);
    assert!(r.passed(), "{r}");
    assert!(r.row("closed_manifold").is_some());
}

/// A sharp rim (the bicone's, 84° between the rim normals and the rim faces' normals): the
/// default nearest apexes lean over the rim instead of standing several face widths high,
/// and F built on them is still C1 with single-sheeted patches — nothing in §4 assumes the
/// apex on the face normal.
#[test]
fn sharp_rim_smooths_with_nearest_apexes() {
    use algesurf_mesh::shapes::bicone;
    use algesurf_mesh::{NormalMethod, vertex_normals};
    let mesh = bicone(12, 0.1);
    let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    // Apexes at least three times nearer the face than the paper's `c + t_max n_ijk`.
    let lowered = s
        .hull()
        .faces()
        .iter()
        .filter(|f| match (f.u(), f.parameters) {
            (Some(u), Some(a)) => 3.0 * u.distance(f.centroid) < a.t_max,
            _ => false,
        })
        .count();
    println!(
        "{lowered} of {} apexes lowered threefold",
        mesh.face_count()
    );
    assert!(lowered > 0, "the rim's apexes stand lower than the paper's");
    let r = battery(&s, 4);
    println!("{r}");
    assert!(r.passed(), "{r}");
}

/// Theorem 4.1, measured by the check battery: F is C1 across every interior facet of the
/// hull, interpolates the vertices with the given normals, and the patch normals agree at
/// every shared tessellation vertex — on a sphere (convex faces, rational terms) and a torus
/// (split faces, nonconvex edges).
#[test]
fn c1_across_every_interior_facet_and_normals_agree() {
    use algesurf_mesh::shapes::torus;
    use algesurf_mesh::{NormalMethod, vertex_normals};
    let meshes = [
        ("icosphere(1)", icosphere(1)),
        ("torus(12, 8)", torus(12, 8, 1.5, 0.6)),
    ];
    for (name, mesh) in meshes {
        let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
        let r = battery(&s, 4);
        println!("{name}\n{r}");
        assert!(r.passed(), "{name}:\n{r}");
    }
}

/// The two triangles of §6 with the normals of Figs. 6, 7, 9 and 10 (the data in
/// `algesurf_apatch::examples`, quoted from the paper there): classified as the paper says,
/// and the whole check battery passes (C1, interpolation, single sheets, watertightness).
#[test]
fn papers_worked_configurations_are_classified_and_join_c1() {
    use algesurf_apatch::FaceFunction;
    use algesurf_apatch::examples::{ExpectedFace, WorkedExample};
    for ex in WorkedExample::ALL {
        let (mesh, normals) = ex.mesh_and_normals();
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
        let got: Vec<ExpectedFace> = s
            .faces()
            .iter()
            .map(|f| match f {
                FaceFunction::Planar => ExpectedFace::Planar,
                FaceFunction::Convex { .. } => ExpectedFace::Convex,
                FaceFunction::Split(_) => ExpectedFace::Split,
            })
            .collect();
        assert_eq!(got, ex.expected_faces(), "{}", ex.name());
        let r = battery(&s, 8);
        assert!(r.passed(), "{}:\n{r}", ex.name());
    }
}

/// Plane recovery (§1, Theorem 4.1): where all three normals are perpendicular to a face, its
/// patch is that face — on a flat grid every output vertex lies in the plane.
#[test]
fn plane_is_recovered_where_normals_are_perpendicular() {
    let mesh = algesurf_mesh::shapes::grid(4, 3);
    let normals = vec![DVec3::Z; mesh.vertex_count()];
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    assert!(
        s.faces()
            .iter()
            .all(|f| matches!(f, algesurf_apatch::FaceFunction::Planar))
    );
    let t = s.tessellate(4, 4).unwrap();
    assert!(t.positions.iter().all(|p| p.z == 0.0));
    assert!(t.triangle_kind.iter().all(|k| *k == PatchKind::Planar));
}

/// Theorem 4.2 / Corollary 4.3 on an ellipsoid: with the gradients of Q = xᵀAx − 1 at the
/// vertices (not unit normals: READING-NOTES explains why their magnitudes matter), the default
/// free parameters reproduce the ellipsoid.
#[test]
fn ellipsoid_is_recovered_from_its_gradients() {
    let sphere = icosphere(2);
    let axes = DVec3::new(1.5, 1.0, 0.7);
    let pos: Vec<DVec3> = sphere.positions().iter().map(|p| *p * axes).collect();
    let grads: Vec<DVec3> = pos.iter().map(|p| *p / (axes * axes)).collect(); // ∇(Q/2)
    let mesh = TriMesh::new(pos, sphere.triangles().to_vec()).unwrap();
    let s = ApatchSurface::new(&mesh, &grads, &SurfaceOptions::default()).unwrap();
    let t = s.tessellate(6, 6).unwrap();
    assert!(t.missed_rays.is_empty() && t.multiple_roots.is_empty());
    let worst = t
        .positions
        .iter()
        .map(|p| ((*p / axes).length() - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-10, "max |‖p/axes‖ − 1| = {worst:e}");
}

/// A sliver face (a corner 1e-9 of its height from the opposite edge: twice its area over
/// its longest edge squared is ~2e-9, above repair's degenerate-area threshold) makes
/// tetrahedra below `Simplex`'s tolerance; the error names the hull face and the input face
/// it lies on, around the degenerate simplex (it named neither).
#[test]
fn a_degenerate_tetrahedron_on_a_sliver_face_names_the_face() {
    let torus = algesurf_mesh::shapes::torus(24, 12, 1.5, 0.6);
    let [a, b, c] = torus.triangles()[0];
    let mut positions = torus.positions().to_vec();
    let mid = (positions[b as usize] + positions[c as usize]) * 0.5;
    positions[a as usize] = mid + 1e-9 * (positions[a as usize] - mid);
    let mesh = TriMesh::new(positions, torus.triangles().to_vec()).unwrap();
    let normals = algesurf_mesh::vertex_normals(&mesh, algesurf_mesh::NormalMethod::Loop).unwrap();
    let Err(e) = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()) else {
        panic!("the sliver's tetrahedra are degenerate");
    };
    match &e {
        algesurf_apatch::ApatchError::AtFace {
            input_face, source, ..
        } => {
            assert_eq!(*input_face, 0, "{e}");
            assert!(
                matches!(
                    **source,
                    algesurf_apatch::ApatchError::Bb(
                        algesurf_bb::BbError::DegenerateSimplex { .. }
                    )
                ),
                "{e}"
            );
        }
        other => panic!("expected the face named: {other}"),
    }
    assert!(e.to_string().starts_with("hull face "), "{e}");
}

/// Construction and tessellation report their steps, each counted step to exactly its
/// element count, and reporting changes nothing: the same surface, bit for bit, as without.
#[test]
fn construction_and_tessellation_report_their_steps() {
    use algesurf_mesh::progress::ProgressLog;
    use algesurf_mesh::{NormalMethod, shapes, vertex_normals};
    let mesh = shapes::torus(24, 12, 1.5, 0.6);
    let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
    let options = SurfaceOptions::default();
    let log = ProgressLog::default();
    let s = ApatchSurface::with_progress(&mesh, &normals, &options, &log).unwrap();
    let plain = ApatchSurface::new(&mesh, &normals, &options).unwrap();
    let (nf, ne) = (s.faces().len() as u64, s.edges().len() as u64);
    let steps = log.steps();
    let counted: Vec<(&str, u64, u64)> = steps
        .iter()
        .filter(|st| st.name.starts_with("surface: "))
        .map(|st| (st.name.as_str(), st.total, st.done))
        .collect();
    assert_eq!(
        counted,
        [
            ("surface: face functions", nf, nf),
            ("surface: edge cubics", ne, ne),
            ("surface: edge single-sheet bounds", ne, ne),
        ]
    );
    assert_eq!(steps[0].name, "hull: edges");

    let tess_log = ProgressLog::default();
    let t = s.tessellate_with_progress(3, 2, &tess_log).unwrap();
    let plain_t = plain.tessellate(3, 2).unwrap();
    let bits = |p: &[DVec3]| -> Vec<[u64; 3]> {
        p.iter().map(|v| v.to_array().map(f64::to_bits)).collect()
    };
    assert_eq!(bits(&t.positions), bits(&plain_t.positions));
    assert_eq!(bits(&t.normals), bits(&plain_t.normals));
    assert_eq!(t.triangles, plain_t.triangles);
    let tess_steps: Vec<(String, u64, u64)> = tess_log
        .steps()
        .into_iter()
        .map(|st| (st.name, st.total, st.done))
        .collect();
    assert_eq!(
        tess_steps,
        [
            ("tessellation: face patches".into(), nf, nf),
            ("tessellation: edge patches".into(), ne, ne),
            ("tessellation: numbering and triangles".into(), 0, 0),
        ]
    );
}

/// A sink that asks to stop ends construction or tessellation with `Cancelled` (also when it
/// asks during the hull's steps), and a counted step stops well before its end.
#[test]
fn a_cancelled_construction_or_tessellation_stops_with_cancelled() {
    use algesurf_apatch::ApatchError;
    use algesurf_mesh::progress::ProgressLog;
    use algesurf_mesh::{NormalMethod, shapes, vertex_normals};
    let mesh = shapes::torus(48, 24, 1.5, 0.6);
    let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
    let options = SurfaceOptions::default();
    for at in [
        "hull: edges",
        "surface: face functions",
        "surface: edge cubics",
        "surface: edge single-sheet bounds",
    ] {
        let log = ProgressLog::cancelling_at(at);
        let r = ApatchSurface::with_progress(&mesh, &normals, &options, &log);
        assert_eq!(r.err(), Some(ApatchError::Cancelled), "cancelled at {at}");
        let last = log.steps().pop().unwrap();
        assert!(last.name.starts_with(at), "{at}: stopped after {last:?}");
        // Every thread stops at its next batch of 64: far from the step's 2 304 or 3 456.
        assert!(last.done < last.total / 2, "{at}: {last:?}");
    }
    let s = ApatchSurface::new(&mesh, &normals, &options).unwrap();
    for at in ["tessellation: face patches", "tessellation: edge patches"] {
        let log = ProgressLog::cancelling_at(at);
        let r = s.tessellate_with_progress(4, 4, &log);
        assert_eq!(r.err(), Some(ApatchError::Cancelled), "cancelled at {at}");
        assert!(log.steps().pop().unwrap().name.starts_with(at));
    }
}

/// A grid of `n × n` squares of side `h` in the plane z = 0 with a C1 bump
/// `z = a (1 − r²/R²)²` (r < R) over its middle and the bump's exact unit normals: faces
/// outside the bump are planar patches (all three normals perpendicular to them), the others
/// convex or split, and the mesh has a boundary.
fn bumped_grid(n: u32, h: f64) -> (TriMesh, Vec<DVec3>) {
    let flat = algesurf_mesh::shapes::grid(n, n);
    let centre = DVec3::new(0.5, 0.5, 0.0) * (n as f64 * h);
    let (a, radius) = (0.15 * n as f64 * h, 0.3 * n as f64 * h);
    let mut pos = Vec::new();
    let mut normals = Vec::new();
    for p in flat.positions() {
        let q = *p * h;
        let d = q - centre;
        let s = 1.0 - d.length_squared() / (radius * radius);
        if s > 0.0 {
            // ∂z/∂x = −4 a s x / R² (and y alike).
            let slope = -4.0 * a * s / (radius * radius);
            pos.push(DVec3::new(q.x, q.y, a * s * s));
            normals.push(DVec3::new(-slope * d.x, -slope * d.y, 1.0).normalize());
        } else {
            pos.push(q);
            normals.push(DVec3::Z);
        }
    }
    (
        TriMesh::new(pos, flat.triangles().to_vec()).unwrap(),
        normals,
    )
}

/// Meshes with every kind of patch: the bumped grid (planar faces of area h²/2 = 0.005, so
/// their unnormalised normals are far from unit length), a torus (convex and split faces,
/// edge patches), and an ellipsoid given by its gradients (vertex data that are not unit).
fn every_kind_of_patch() -> Vec<(&'static str, TriMesh, Vec<DVec3>)> {
    use algesurf_mesh::{NormalMethod, shapes, vertex_normals};
    let (grid, grid_normals) = bumped_grid(8, 0.1);
    let torus = shapes::torus(12, 8, 1.0, 0.4);
    let torus_normals = vertex_normals(&torus, NormalMethod::Loop).unwrap();
    let sphere = icosphere(1);
    let axes = DVec3::new(1.5, 1.0, 0.7);
    let pos: Vec<DVec3> = sphere.positions().iter().map(|p| *p * axes).collect();
    let grads: Vec<DVec3> = pos.iter().map(|p| *p / (axes * axes)).collect();
    let ellipsoid = TriMesh::new(pos, sphere.triangles().to_vec()).unwrap();
    vec![
        ("bumped grid", grid, grid_normals),
        ("torus", torus, torus_normals),
        ("ellipsoid", ellipsoid, grads),
    ]
}

/// `Tessellation::normals` are unit vectors (`∇F/|∇F|`) on every kind of patch, the planar
/// ones included (whose normal is the face's), and at the mesh vertices.
#[test]
fn tessellation_normals_are_unit_vectors_on_every_kind_of_patch() {
    let mut kinds = std::collections::HashSet::new();
    for (name, mesh, normals) in every_kind_of_patch() {
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
        let t = s.tessellate(3, 2).unwrap();
        kinds.extend(t.triangle_kind.iter().copied());
        // A normalised vector's length is 1 within a few rounding errors (the squares' sum,
        // its square root, the reciprocal and the products: < 4ε).
        let worst = t
            .normals
            .iter()
            .map(|n| (n.length() - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 4.0 * f64::EPSILON,
            "{name}: | |n| − 1 | up to {worst:e}"
        );
    }
    for kind in [PatchKind::Planar, PatchKind::Face, PatchKind::Edge] {
        assert!(kinds.contains(&kind), "no {kind:?} patch among the meshes");
    }
}

/// Every tolerance of the construction is relative to the mesh's size: scaling the input by a
/// power of two (exact in floating point) scales the tessellation by the same factor, bit for
/// bit, and leaves its normals, triangles and patches as they are.
#[test]
fn smoothing_commutes_with_scaling_by_a_power_of_two() {
    for (name, mesh, normals) in every_kind_of_patch() {
        let t = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())
            .unwrap()
            .tessellate(3, 2)
            .unwrap();
        for k in [-20, 10] {
            let s = 2f64.powi(k);
            let scaled = TriMesh::new(
                mesh.positions().iter().map(|p| *p * s).collect(),
                mesh.triangles().to_vec(),
            )
            .unwrap();
            let ts = ApatchSurface::new(&scaled, &normals, &SurfaceOptions::default())
                .unwrap()
                .tessellate(3, 2)
                .unwrap();
            assert_eq!(ts.triangles, t.triangles, "{name} × 2^{k}: triangles");
            assert_eq!(
                ts.triangle_patch, t.triangle_patch,
                "{name} × 2^{k}: patches"
            );
            let moved = t
                .positions
                .iter()
                .zip(&ts.positions)
                .filter(|(a, b)| **a * s != **b)
                .count();
            assert_eq!(moved, 0, "{name} × 2^{k}: positions not scaled exactly");
            let turned = t
                .normals
                .iter()
                .zip(&ts.normals)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(turned, 0, "{name} × 2^{k}: normals changed");
        }
    }
}

#[test]
fn a_resolution_too_large_to_number_is_an_error_before_anything_is_allocated() {
    // Each of these asks for more than 2^32 points (or more than a `usize` counts); counting
    // them must neither overflow nor start allocating the grids.
    let (_, s) = sphere_surface(1);
    for (n, m) in [
        (usize::MAX, 2),
        (2, usize::MAX),
        (usize::MAX, usize::MAX),
        (1 << 40, 1 << 40),
        (1 << 16, 1 << 16),
    ] {
        let msg = s.tessellate(n, m).unwrap_err().to_string();
        assert!(
            msg.contains("more points than 32-bit vertex ids can number")
                && msg.contains(&format!("resolution {n} × {m}")),
            "{n} × {m}: {msg}"
        );
    }
    assert!(
        s.tessellate(0, 2)
            .unwrap_err()
            .to_string()
            .contains("at least 1")
    );
    // A mesh without faces has no patch points at any resolution: its tessellation is its
    // vertices, whatever the resolution.
    for positions in [Vec::new(), vec![DVec3::X]] {
        let normals = vec![DVec3::X; positions.len()];
        let faceless = TriMesh::new(positions, Vec::new()).unwrap();
        let e = ApatchSurface::new(&faceless, &normals, &SurfaceOptions::default()).unwrap();
        let small = e.tessellate(3, 2).unwrap();
        let huge = e.tessellate(1 << 30, 1 << 30).unwrap();
        assert_eq!(huge.positions, faceless.positions());
        assert_eq!(
            (&huge.positions, &huge.normals, &huge.triangles),
            (&small.positions, &small.normals, &small.triangles)
        );
    }
}

#[test]
fn a_sheet_margin_out_of_range_is_refused_naming_it() {
    // A NaN, negative or zero margin would let apex values onto or below their single-sheet
    // bounds (Lemma 2.3 needs them strictly above); an infinite one has no admissible value
    // and sent the build into refinement until it gave up on an edge. Each is refused by
    // name before any work, as the hull's options are.
    let mesh = icosphere(1);
    let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
    for m in [f64::NAN, -0.01, 0.0, -0.0, f64::INFINITY] {
        let options = SurfaceOptions {
            sheet_margin: m,
            ..SurfaceOptions::default()
        };
        let err = ApatchSurface::new(&mesh, &normals, &options).unwrap_err();
        assert!(
            matches!(&err, algesurf_apatch::ApatchError::InvalidOption(msg) if msg.contains("sheet_margin")),
            "{m}: {err}"
        );
    }
    // The hull's options are checked as part of the surface's.
    let mut options = SurfaceOptions::default();
    options.hull.epsilon = f64::NAN;
    let err = options.validate().unwrap_err().to_string();
    assert!(err.contains("epsilon"), "{err}");
    // Tiny and large margins are admissible, and the sphere is still single-sheeted.
    for m in [1e-300, 10.0] {
        let options = SurfaceOptions {
            sheet_margin: m,
            ..SurfaceOptions::default()
        };
        let s = ApatchSurface::new(&mesh, &normals, &options).unwrap();
        let t = s.tessellate(3, 2).unwrap();
        assert!(
            t.missed_rays.is_empty() && t.multiple_roots.is_empty(),
            "{m}"
        );
    }
}

/// The face patches beside a zero convex edge meet along the edge itself (F vanishes there),
/// so the tessellation shares the edge's points between them. A thin plate remeshed at its
/// rims (`algesurf_mesh::flat`) has such edges on its creases whose Loop normals lean a few
/// ulps along the edge (the remeshed rims' one-rings are not exactly symmetric): F at the
/// edge's points is then ~20 ε of the rays' coefficients instead of 0, and the tessellation
/// used to crack there (172 edges of one triangle at resolution 4, Euler characteristic −25
/// instead of 2). The rays on zero convex edges now start on the surface by the edge's
/// classification.
#[test]
fn face_patches_meet_without_cracks_along_zero_convex_edges_whose_normals_lean_by_ulps() {
    use algesurf_hull::Convexity;
    use algesurf_mesh::flat::{FlatRemeshOptions, remesh_flat_regions};
    use algesurf_mesh::shapes::plate;
    use algesurf_mesh::{NormalMethod, vertex_normals};
    let split = FlatRemeshOptions {
        split_narrow_strips: Some(0.0),
        ..FlatRemeshOptions::default()
    };
    let mesh = remesh_flat_regions(&plate(2, 2.0, 0.02), &split)
        .unwrap()
        .mesh;
    let normals = vertex_normals(&mesh, NormalMethod::LoopButterfly).unwrap();
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    // The case the test is about: zero convex interior edges whose slopes are not exactly 0.
    let leaning = s
        .hull()
        .edges()
        .iter()
        .filter(|e| {
            e.convexity == Convexity::ZeroConvex
                && !e.is_boundary()
                && e.slopes.iter().any(|&a| a != 0.0)
        })
        .count();
    assert!(leaning > 100, "{leaning} leaning zero convex edges");
    let r = battery(&s, 4);
    assert!(r.passed(), "{r}");
    let t = s.tessellate(3, 2).unwrap();
    let mut edges: std::collections::HashMap<[u32; 2], u32> = std::collections::HashMap::new();
    for tri in &t.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            *edges.entry([a.min(b), a.max(b)]).or_insert(0) += 1;
        }
    }
    assert!(edges.values().all(|&c| c == 2));
}

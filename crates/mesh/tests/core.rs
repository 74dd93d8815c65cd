//! Adjacency, validation, repair and normals on meshes built in code.
#![allow(clippy::needless_range_loop)]

use algesurf_mesh::shapes::{grid, icosphere, octahedron, torus};
use algesurf_mesh::{
    Finding, NormalMethod, PolygonMesh, RepairOptions, TriMesh, repair, validate, vertex_normals,
};
use glam::DVec3;
use proptest::prelude::*;

/// A deterministic generator, uniform in `[0, 1)` (a linear congruential one; these tests
/// cannot use the crate's `test_rng`, which is compiled for its unit tests only).
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn jitter(mesh: &TriMesh, seed: u64, amount: f64) -> TriMesh {
    let mut m = mesh.clone();
    let mut u = uniform(seed);
    let mut rnd = || u() * 2.0 - 1.0;
    for p in m.positions_mut() {
        *p += amount * DVec3::new(rnd(), rnd(), rnd());
    }
    m
}

fn check_adjacency(m: &TriMesh) {
    let t = m.topology();
    for v in 0..m.vertex_count() as u32 {
        let ring = m.one_ring(v).expect("manifold vertex");
        assert_eq!(ring.neighbors.len(), t.valence(v));
        assert_eq!(ring.faces.len(), t.vertex_corners(v).len());
        for (i, &f) in ring.faces.iter().enumerate() {
            let tri = m.triangles()[f as usize];
            let a = ring.neighbors[i];
            let b = ring.neighbors[(i + 1) % ring.neighbors.len()];
            // Face i is (v, a, b) in the face's own cyclic order.
            let k = tri.iter().position(|&x| x == v).unwrap();
            assert_eq!([tri[(k + 1) % 3], tri[(k + 2) % 3]], [a, b]);
        }
    }
    for e in 0..t.edge_count() as u32 {
        let [a, b] = t.edge(e);
        assert!(a < b);
        assert_eq!(t.find_edge(b, a), Some(e));
        for f in t.edge_faces(e) {
            let tri = m.triangles()[f as usize];
            assert!(tri.contains(&a) && tri.contains(&b));
        }
    }
}

#[test]
fn euler_and_genus() {
    let s = icosphere(2);
    let c = s.components();
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].euler_characteristic, 2);
    assert_eq!(c[0].genus, Some(0));
    assert!(c[0].consistently_oriented);
    check_adjacency(&s);
    let t = torus(12, 8, 3.0, 1.0);
    let c = t.components();
    assert_eq!(c[0].euler_characteristic, 0);
    assert_eq!(c[0].genus, Some(1));
    check_adjacency(&t);
    assert!(s.signed_volume() > 0.0 && t.signed_volume() > 0.0);
}

/// `face_components` numbers the faces' components as `components` lists them: on a mesh of
/// three pieces (a torus, a sphere with its faces interleaved in between, an open grid), in an
/// order where a component's faces are not contiguous.
#[test]
fn face_components_agree_with_components() {
    let parts = [torus(12, 8, 3.0, 1.0), icosphere(1), grid(3, 2)];
    let (mut positions, mut tris) = (Vec::new(), Vec::new());
    let mut per_part = Vec::new();
    for m in &parts {
        let base = positions.len() as u32;
        positions.extend_from_slice(m.positions());
        per_part.push(m.triangles().iter().map(move |t| t.map(|v| v + base)));
    }
    // Round-robin over the parts' faces.
    let mut iters: Vec<_> = per_part.into_iter().collect();
    loop {
        let before = tris.len();
        for it in &mut iters {
            tris.extend(it.next());
        }
        if tris.len() == before {
            break;
        }
    }
    let mesh = TriMesh::new(positions, tris).unwrap();
    let comp = mesh.topology().face_components();
    let count = comp.iter().max().map_or(0, |&c| c as usize + 1);
    let listed = mesh.components();
    assert_eq!((count, listed.len()), (3, 3));
    for (i, c) in listed.iter().enumerate() {
        for &f in &c.faces {
            assert_eq!(comp[f as usize], i as u32, "face {f}");
        }
    }
    assert_eq!(
        listed.iter().map(|c| c.faces.len()).sum::<usize>(),
        comp.len()
    );
}

#[test]
fn open_grid_boundary() {
    let g = grid(4, 3);
    let loops = g.boundary_loops();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), 2 * (4 + 3));
    let c = &g.components()[0];
    assert_eq!(
        (c.euler_characteristic, c.boundary_loop_count, c.genus),
        (1, 1, Some(0))
    );
    // Boundary vertex fans are open and ordered counter-clockwise.
    let ring = g.one_ring(0).unwrap();
    assert!(!ring.closed);
    assert_eq!(ring.neighbors, vec![1, 6, 5]);
    // An annulus: remove the two triangles of the centre square of a 3x3 grid.
    let g = grid(3, 3);
    let tris: Vec<[u32; 3]> = g
        .triangles()
        .iter()
        .enumerate()
        .filter(|(f, _)| *f != 8 && *f != 9)
        .map(|(_, t)| *t)
        .collect();
    let a = TriMesh::new(g.positions().to_vec(), tris).unwrap();
    assert_eq!(a.boundary_loops().len(), 2);
    let c = &a.components()[0];
    assert_eq!((c.euler_characteristic, c.genus), (0, Some(0)));
}

#[test]
fn validation_names_elements() {
    let o = octahedron();
    let mut m = o.to_polygon_mesh();
    m.positions.push(DVec3::new(5.0, 5.0, 5.0)); // unused vertex 6
    m.positions.push(DVec3::new(f64::NAN, 0.0, 0.0)); // non-finite vertex 7
    m.push_face(&[0, 2, 4]); // duplicate of face 0 -> edge (0,2),(2,4),(0,4) have 3 faces
    m.push_face(&[0, 1, 99]); // out of range
    m.push_face(&[0, 1]); // too few corners
    let r = validate(&m);
    assert!(r.findings.contains(&Finding::UnusedVertex { vertex: 6 }));
    assert!(r.findings.contains(&Finding::NonFiniteVertex { vertex: 7 }));
    assert!(r.findings.contains(&Finding::DuplicateFace {
        face: 8,
        duplicate_of: 0
    }));
    assert!(r.findings.contains(&Finding::IndexOutOfRange {
        face: 9,
        corner: 2,
        index: 99
    }));
    assert!(r.findings.contains(&Finding::TooFewCorners {
        face: 10,
        corners: 2
    }));
    assert!(r.findings.iter().any(
        |f| matches!(f, Finding::NonManifoldEdge { vertices: [0, 2], faces } if faces.len() == 3)
    ));
    let text = r.to_string();
    assert!(text.contains("vertex 6 is unused"), "{text}");

    // Bow tie: two triangles sharing only vertex 0.
    let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
    let bow = PolygonMesh::from_triangles(
        vec![p(0., 0.), p(1., 0.), p(1., 1.), p(-1., 0.), p(-1., -1.)],
        &[[0, 1, 2], [0, 3, 4]],
    );
    let r = validate(&bow);
    assert_eq!(
        r.findings,
        vec![Finding::NonManifoldVertex { vertex: 0, fans: 2 }]
    );

    // Flipped face and a degenerate one.
    let mut tris: Vec<[u32; 3]> = o.triangles().to_vec();
    tris[3] = [tris[3][1], tris[3][0], tris[3][2]];
    let mut m = PolygonMesh::from_triangles(o.positions().to_vec(), &tris);
    m.positions.push(DVec3::new(0.5, 0.5, 0.0));
    m.push_face(&[0, 2, 6]);
    let r = validate(&m);
    let flips = r
        .findings
        .iter()
        .filter(
            |f| matches!(f, Finding::InconsistentOrientation { faces, .. } if faces.contains(&3)),
        )
        .count();
    assert_eq!(flips, 3); // all three edges of face 3
    assert!(
        r.findings
            .iter()
            .any(|f| matches!(f, Finding::DegenerateFace { face: 8, .. }))
    );
}

#[test]
fn repair_welds_orients_and_reports() {
    // An icosphere exploded into separate triangles (every corner its own vertex), with all
    // faces reversed and the odd ones reversed back, plus a quad cap elsewhere.
    let s = icosphere(1);
    let mut m = PolygonMesh::new();
    for (f, t) in s.triangles().iter().enumerate() {
        let base = m.positions.len() as u32;
        for &v in t {
            m.positions.push(s.positions()[v as usize]);
        }
        if f % 2 == 0 {
            m.push_face(&[base, base + 2, base + 1]);
        } else {
            m.push_face(&[base, base + 1, base + 2]);
        }
    }
    let r = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(r.mesh.vertex_count(), s.vertex_count());
    assert_eq!(r.report.welded.len(), 3 * s.face_count() - s.vertex_count());
    let out = TriMesh::from_polygon_mesh(&r.mesh).unwrap();
    let c = &out.components()[0];
    assert!(c.consistently_oriented && c.genus == Some(0));
    assert!(out.signed_volume() > 0.0);
    assert_eq!(r.report.flipped_faces.len(), s.face_count().div_ceil(2));
    assert!(validate(&r.mesh).is_valid());
    // Repair is idempotent on its output.
    let again = repair(&r.mesh, &RepairOptions::default()).unwrap();
    assert!(!again.report.changed(), "{}", again.report);
    // Maps: every output face comes from an input face with the same corner positions.
    for (of, &inf) in r.report.face_map.iter().enumerate() {
        let mut a: Vec<[u64; 3]> = r
            .mesh
            .face(of)
            .iter()
            .map(|&v| r.mesh.positions[v as usize].to_array().map(f64::to_bits))
            .collect();
        let mut b: Vec<[u64; 3]> = m
            .face(inf as usize)
            .iter()
            .map(|&v| m.positions[v as usize].to_array().map(f64::to_bits))
            .collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
    }
}

/// Repair and validation are the same at every scale. An icosphere exploded into separate
/// triangles (to be welded), with a collinear face (to be dropped as degenerate) and a quad (to
/// be triangulated), scaled by `2^k`: at `2^±300` it gets the unit mesh's findings and
/// repairs, and the repaired positions are the unit ones scaled, bit for bit. At `2^-300`
/// every face had been "degenerate (area 0)", its areas underflowing, and repair dropped
/// them all.
#[test]
fn repair_and_validation_do_not_depend_on_the_scale() {
    let s = icosphere(1);
    let mut unit = PolygonMesh::new();
    for t in s.triangles() {
        let base = unit.positions.len() as u32;
        unit.positions.extend(t.map(|v| s.positions()[v as usize]));
        unit.push_face(&[base, base + 1, base + 2]);
    }
    let base = unit.positions.len() as u32;
    unit.positions.extend([
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(4.0, 0.0, 0.0),
        DVec3::new(5.0, 0.0, 0.0),
        DVec3::new(3.0, 2.0, 0.0),
        DVec3::new(4.0, 2.0, 0.5),
        DVec3::new(4.0, 3.0, 0.0),
        DVec3::new(3.0, 3.0, 0.0),
    ]);
    unit.push_face(&[base, base + 1, base + 2]);
    unit.push_face(&[base + 3, base + 4, base + 5, base + 6]);
    let unit_findings = validate(&unit).findings;
    let sliver = s.face_count() as u32;
    let unit_repair = repair(&unit, &RepairOptions::default()).unwrap();
    assert!(
        unit_findings
            .iter()
            .any(|f| matches!(f, Finding::DegenerateFace { face, .. } if *face == sliver))
    );
    assert!(!unit_repair.report.welded.is_empty());
    assert_eq!(unit_repair.report.dropped_degenerate_faces, [sliver]);
    for k in [-300, 300] {
        let scale = 2f64.powi(k);
        let mut m = unit.clone();
        m.positions.iter_mut().for_each(|p| *p *= scale);
        let findings = validate(&m).findings;
        assert_eq!(findings.len(), unit_findings.len(), "2^{k}: {findings:?}");
        for (a, b) in findings.iter().zip(&unit_findings) {
            match (a, b) {
                (
                    Finding::DegenerateFace { face, area },
                    Finding::DegenerateFace { face: g, area: h },
                ) => assert!(face == g && *area == h * scale * scale, "2^{k}: {a:?}"),
                _ => assert_eq!(a, b, "2^{k}"),
            }
        }
        let r = repair(&m, &RepairOptions::default()).unwrap();
        assert_eq!(r.report, unit_repair.report, "2^{k}");
        assert!(r.mesh.faces().eq(unit_repair.mesh.faces()), "2^{k}");
        let moved = (r.mesh.positions.iter().zip(&unit_repair.mesh.positions))
            .filter(|(p, q)| **p != **q * scale)
            .count();
        assert_eq!(moved, 0, "2^{k}: positions not the unit ones scaled");
    }
}

/// Vertex normals are directions: those of an icosphere scaled by `2^±300` are the unit
/// one's, bit for bit, by every method (they were all zero there: the face areas underflowed
/// or overflowed).
#[test]
fn vertex_normals_do_not_depend_on_the_scale() {
    let m = icosphere(2);
    for method in [
        NormalMethod::Area,
        NormalMethod::Angle,
        NormalMethod::Loop,
        NormalMethod::LoopButterfly,
    ] {
        let unit = vertex_normals(&m, method).unwrap();
        for k in [-300, -20, 20, 300] {
            let mut scaled = m.clone();
            let s = 2f64.powi(k);
            scaled.positions_mut().iter_mut().for_each(|p| *p *= s);
            assert_eq!(
                vertex_normals(&scaled, method).unwrap(),
                unit,
                "{method:?}, 2^{k}"
            );
        }
    }
}

/// Faces dropped as invalid (fewer than three corners, a non-finite or missing vertex), as
/// collapsed (welded corners repeat) or as degenerate (no area) are reported by input id in
/// face order, and the rest kept in face order: on 300 copies of a block of seven faces, so
/// that the per-face work is split among threads.
#[test]
fn repair_refuses_tolerances_out_of_range_naming_them() {
    // A NaN or negative tolerance used to switch its step off without a word (every
    // comparison with NaN is false), and an infinite weld tolerance merged every vertex.
    let m = icosphere(1).to_polygon_mesh();
    for (options, name) in [
        (
            RepairOptions {
                weld_tolerance: Some(f64::NAN),
                ..RepairOptions::default()
            },
            "weld_tolerance",
        ),
        (
            RepairOptions {
                weld_tolerance: Some(f64::INFINITY),
                ..RepairOptions::default()
            },
            "weld_tolerance",
        ),
        (
            RepairOptions {
                degenerate_area: -1e-12,
                ..RepairOptions::default()
            },
            "degenerate_area",
        ),
        (
            RepairOptions {
                degenerate_area: f64::NAN,
                ..RepairOptions::default()
            },
            "degenerate_area",
        ),
    ] {
        let err = repair(&m, &options).unwrap_err();
        assert!(
            matches!(&err, algesurf_mesh::MeshError::InvalidOption(msg) if msg.contains(name)),
            "{options:?}: {err}"
        );
    }
    // No welding, and zero tolerances, are in range.
    for options in [
        RepairOptions {
            weld_tolerance: None,
            degenerate_area: 0.0,
            ..RepairOptions::default()
        },
        RepairOptions {
            weld_tolerance: Some(0.0),
            ..RepairOptions::default()
        },
    ] {
        assert_eq!(repair(&m, &options).unwrap().mesh.face_count(), 80);
    }
}

#[test]
fn validation_refuses_a_threshold_that_would_flag_nothing_or_everything() {
    use algesurf_mesh::{MeshError, ValidationOptions, validate_with};
    let m = icosphere(1).to_polygon_mesh();
    // NaN and negative thresholds flagged no face, an infinite one every face.
    for x in [f64::NAN, -1e-12, f64::INFINITY, f64::NEG_INFINITY] {
        let err = validate_with(&m, &ValidationOptions { degenerate_area: x }).unwrap_err();
        assert!(
            matches!(&err, MeshError::InvalidOption(msg) if msg.contains("degenerate_area")),
            "{x}: {err}"
        );
    }
    for x in [0.0, 1e-14, 1e-3] {
        let report = validate_with(&m, &ValidationOptions { degenerate_area: x }).unwrap();
        assert!(report.is_valid(), "{x}: {report}");
    }
    let everything = validate_with(
        &m,
        &ValidationOptions {
            degenerate_area: 1.0,
        },
    )
    .unwrap();
    assert_eq!(
        everything.findings.len(),
        80,
        "an area threshold of a diagonal² flags all"
    );
}

#[test]
fn repair_reports_dropped_faces_in_face_order() {
    let block = [
        vec![0, 1, 2],    // kept
        vec![0, 1],       // invalid: two corners
        vec![0, 4, 2],    // invalid: vertex 4 is not finite
        vec![1, 6, 3],    // collapsed: 6 welds onto 1
        vec![0, 1, 5],    // degenerate: on a line
        vec![1, 3, 2],    // kept
        vec![0, 1, 1000], // invalid: no such vertex
    ];
    let mut m = PolygonMesh::new();
    let (mut invalid, mut collapsed, mut degenerate, mut kept) = (vec![], vec![], vec![], vec![]);
    for k in 0..300u32 {
        let base = m.positions.len() as u32;
        let x = 10.0 * k as f64;
        for p in [
            (0.0, 0.0),
            (1.0, 0.0),
            (0.0, 1.0),
            (1.0, 1.0),
            (f64::NAN, 0.0),
            (2.0, 0.0),
            (1.0, 0.0),
        ] {
            m.positions.push(DVec3::new(x + p.0, p.1, 0.0));
        }
        for (j, face) in block.iter().enumerate() {
            let f = m.face_count() as u32;
            let ids: Vec<u32> = face
                .iter()
                .map(|&v| if v == 1000 { 1_000_000 } else { base + v })
                .collect();
            m.push_face(&ids);
            match j {
                1 | 2 | 6 => invalid.push(f),
                3 => collapsed.push(f),
                4 => degenerate.push(f),
                _ => kept.push(f),
            }
        }
    }
    let r = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(r.report.dropped_invalid_faces, invalid);
    assert_eq!(r.report.collapsed_faces, collapsed);
    assert_eq!(r.report.dropped_degenerate_faces, degenerate);
    assert_eq!(r.report.face_map, kept);
    assert!(validate(&r.mesh).is_valid());
}

#[test]
fn repair_flips_single_face_and_keeps_properties() {
    let o = octahedron();
    let mut tris: Vec<[u32; 3]> = o.triangles().to_vec();
    tris[5] = [tris[5][0], tris[5][2], tris[5][1]];
    let mut m = PolygonMesh::from_triangles(o.positions().to_vec(), &tris);
    m.positions.push(DVec3::splat(9.0));
    m.face_properties.push(algesurf_mesh::Property {
        name: "patch_id".into(),
        values: algesurf_mesh::PropertyValues::Int((0..8).collect()),
    });
    let r = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(r.report.flipped_faces, vec![5]);
    assert_eq!(r.report.dropped_unused_vertices, vec![6]);
    assert_eq!(r.mesh.vertex_count(), 6);
    let f5 = r.mesh.face(5);
    let t5 = o.triangles()[5];
    assert!((0..3).any(|k| [f5[k], f5[(k + 1) % 3], f5[(k + 2) % 3]] == t5));
    assert_eq!(
        r.mesh.face_properties[0].values,
        algesurf_mesh::PropertyValues::Int((0..8).collect())
    );
    // A whole closed mesh turned inside out is turned back.
    let inv: Vec<[u32; 3]> = o.triangles().iter().map(|t| [t[0], t[2], t[1]]).collect();
    let r = repair(
        &PolygonMesh::from_triangles(o.positions().to_vec(), &inv),
        &RepairOptions::default(),
    )
    .unwrap();
    assert_eq!(r.report.flipped_faces.len(), 8);
    assert!(TriMesh::from_polygon_mesh(&r.mesh).unwrap().signed_volume() > 0.0);
}

#[test]
fn quads_triangulate_with_source_map() {
    // An L-shaped hexagon and a square.
    let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
    let mut m = PolygonMesh::new();
    m.positions = vec![
        p(0., 0.),
        p(2., 0.),
        p(2., 1.),
        p(1., 1.),
        p(1., 2.),
        p(0., 2.),
        p(3., 0.),
        p(3., 1.),
    ];
    m.push_face(&[0, 1, 2, 3, 4, 5]);
    m.push_face(&[1, 6, 7, 2]);
    let t = TriMesh::from_polygon_mesh(&m).unwrap();
    assert_eq!(t.source_faces(), &[0, 0, 0, 0, 1, 1]);
    let area: f64 = (0..t.face_count())
        .map(|f| 0.5 * t.face_normal(f).length())
        .sum();
    assert!((area - 4.0).abs() < 1e-14);
    assert!((0..t.face_count()).all(|f| t.face_normal(f).z > 0.0));
}

#[test]
fn normals_on_sphere_are_radial() {
    let s = icosphere(2);
    for method in [NormalMethod::Area, NormalMethod::Angle, NormalMethod::Loop] {
        let n = vertex_normals(&s, method).unwrap();
        for (v, nv) in n.iter().enumerate() {
            assert!((nv.length() - 1.0).abs() < 1e-12);
            let radial = s.positions()[v].normalize();
            assert!(nv.dot(radial) > 0.99, "{method:?} at {v}");
        }
    }
    // The Loop limit normal at a vertex of the icosahedron (valence 5, symmetric ring) is
    // exactly radial; on the level-2 icosphere vertices 0..12 keep that symmetry.
    let n = vertex_normals(&s, NormalMethod::Loop).unwrap();
    for v in 0..12 {
        let radial = s.positions()[v].normalize();
        assert!((n[v] - radial).length() < 1e-12, "{v}");
    }
    let o = octahedron();
    let n = vertex_normals(&o, NormalMethod::Loop).unwrap();
    for v in 0..6 {
        assert!((n[v] - o.positions()[v]).length() < 1e-12);
    }
    // Boundary vertices of a flat grid: +z.
    let g = jitter(&grid(4, 4), 3, 0.0);
    for nv in vertex_normals(&g, NormalMethod::Loop).unwrap() {
        assert!((nv - DVec3::Z).length() < 1e-12);
    }
    // From file: normalised and oriented with the faces.
    let mut s2 = s.clone();
    let file: Vec<DVec3> = s
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| if i % 2 == 0 { -3.0 * *p } else { *p })
        .collect();
    s2.set_file_normals(Some(file)).unwrap();
    for (v, nv) in vertex_normals(&s2, NormalMethod::FromFile)
        .unwrap()
        .iter()
        .enumerate()
    {
        assert!((*nv - s.positions()[v]).length() < 1e-12);
    }
    assert!(vertex_normals(&s, NormalMethod::FromFile).is_err());
}

#[test]
fn boundary_loop_normal_on_curved_patch() {
    // A grid bent onto a cylinder of radius 10 about the y axis: normals point to +z side.
    let g = grid(6, 6);
    let mut c = g.clone();
    for p in c.positions_mut() {
        let a = p.x / 10.0;
        *p = DVec3::new(10.0 * a.sin(), p.y, 10.0 * a.cos());
    }
    let n = vertex_normals(&c, NormalMethod::Loop).unwrap();
    for (v, nv) in n.iter().enumerate() {
        let p = c.positions()[v];
        let radial = DVec3::new(p.x, 0.0, p.z).normalize();
        assert!(nv.dot(radial) > 0.98, "{v}: {nv} vs {radial}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn jittered_meshes_keep_invariants(seed in any::<u64>(), level in 0u32..3, amount in 0.0f64..0.05) {
        let s = jitter(&icosphere(level), seed, amount);
        check_adjacency(&s);
        prop_assert_eq!(s.euler_characteristic(), 2);
        let t = jitter(&torus(9, 7, 2.0, 0.7), seed, amount);
        check_adjacency(&t);
        prop_assert_eq!(t.components()[0].genus, Some(1));
        for m in [&s, &t] {
            for method in [NormalMethod::Area, NormalMethod::Angle, NormalMethod::Loop] {
                for n in vertex_normals(m, method).unwrap() {
                    prop_assert!((n.length() - 1.0).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn weld_merges_exact_duplicates(seed in any::<u64>(), level in 0u32..2) {
        // Split every vertex into as many copies as it has faces, then weld.
        let s = jitter(&icosphere(level), seed, 0.01);
        let mut m = PolygonMesh::new();
        for t in s.triangles() {
            let b = m.positions.len() as u32;
            m.positions.extend(t.iter().map(|&v| s.positions()[v as usize]));
            m.push_face(&[b, b + 1, b + 2]);
        }
        let r = repair(&m, &RepairOptions { weld_tolerance: Some(0.0), ..Default::default() }).unwrap();
        prop_assert_eq!(r.mesh.vertex_count(), s.vertex_count());
        prop_assert!(r.report.flipped_faces.is_empty());
        let out = TriMesh::from_polygon_mesh(&r.mesh).unwrap();
        prop_assert_eq!(out.euler_characteristic(), 2);
    }
}

/// `face_components` on random triangle soups over few vertices (edges shared by one to
/// several faces, components interleaved in the face order) equals a search over the faces
/// that share an edge, with components numbered in the order of their lowest face.
#[test]
fn face_components_are_the_edge_connected_sets_numbered_by_lowest_face() {
    let mut u = uniform(5);
    let mut next = |n: usize| (u() * n as f64) as u32;
    for case in 0..40 {
        let nv = 6 + case % 30;
        let nf = 1 + (case * 7) % 60;
        let mut tris = Vec::new();
        while tris.len() < nf {
            let t = [(); 3].map(|_| next(nv));
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                tris.push(t);
            }
        }
        let topo = algesurf_mesh::Topology::from_triangles(nv, &tris).unwrap();
        // Reference: faces by undirected edge, then a search from each lowest unvisited face.
        let mut by_edge: std::collections::HashMap<(u32, u32), Vec<usize>> = Default::default();
        for (f, t) in tris.iter().enumerate() {
            for c in 0..3 {
                let (a, b) = (t[c], t[(c + 1) % 3]);
                by_edge.entry((a.min(b), a.max(b))).or_default().push(f);
            }
        }
        let mut want = vec![u32::MAX; nf];
        let mut count = 0;
        for s in 0..nf {
            if want[s] != u32::MAX {
                continue;
            }
            want[s] = count;
            let mut stack = vec![s];
            while let Some(f) = stack.pop() {
                for c in 0..3 {
                    let (a, b) = (tris[f][c], tris[f][(c + 1) % 3]);
                    for &g in &by_edge[&(a.min(b), a.max(b))] {
                        if want[g] == u32::MAX {
                            want[g] = count;
                            stack.push(g);
                        }
                    }
                }
            }
            count += 1;
        }
        assert_eq!(topo.face_components(), want, "case {case}: {tris:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// `Aabb::exact_local_origin` moves a far box's points exactly: `p − o` is exact (then
    /// `p − (p − o)` gives `o` back) and `(p − o) + o` is `p`, for boxes of any size at any
    /// distance, on either side of the origin, and for every point of the box (its corners
    /// and points inside).
    #[test]
    fn the_local_origin_of_a_far_box_is_an_exact_move(
        centre in prop::array::uniform3(-1e12f64..1e12),
        log_size in -8.0f64..6.0,
        seed in 0u64..1000,
    ) {
        let mut u = uniform(seed);
        let size = 10f64.powf(log_size);
        let c = DVec3::from_array(centre);
        let points: Vec<DVec3> = (0..64)
            .map(|_| c + size * DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5))
            .collect();
        let b = algesurf_mesh::Aabb::from_points(&points);
        let o = b.exact_local_origin();
        for p in points.iter().copied().chain([b.min, b.max]) {
            let d = p - o;
            prop_assert_eq!(d + o, p);
            prop_assert_eq!(p - d, o);
            // The local coordinates are no larger than the box (the far axes are moved).
            for k in 0..3 {
                if o[k] != 0.0 {
                    prop_assert!(d[k].abs() <= b.diagonal(), "{:?} {:?}", d, b);
                }
            }
        }
        // Far axes are moved: a box farther than its diagonal from 0 in an axis.
        let mid = (b.min + b.max) * 0.5;
        for k in 0..3 {
            if mid[k].abs() > 4.0 * b.diagonal() {
                prop_assert!(o[k] != 0.0, "axis {} of {:?}", k, b);
            }
        }
    }
}

#[test]
fn boxes_near_the_origin_keep_it() {
    let near = algesurf_mesh::Aabb::new(DVec3::new(-1.0, 0.5, 1.0), DVec3::new(1.0, 1.5, 2.0));
    // y and z are within the diagonal (√6 ≈ 2.45) of 0; x straddles it.
    assert_eq!(near.exact_local_origin(), DVec3::ZERO);
    assert_eq!(algesurf_mesh::Aabb::EMPTY.exact_local_origin(), DVec3::ZERO);
    // A flat mesh at z = 1000: its z axis is moved to 0 exactly.
    let flat = algesurf_mesh::Aabb::new(DVec3::new(0.0, 0.0, 1000.0), DVec3::new(1.0, 1.0, 1000.0));
    assert_eq!(flat.exact_local_origin(), DVec3::new(0.0, 0.0, 1000.0));
}

//! Non-manifold vertices and edges: boundary loops and Euler characteristic where loops or
//! components touch at a vertex, and the repair step that splits such vertices.

use std::collections::HashSet;

use algesurf_mesh::shapes::grid;
use algesurf_mesh::{
    Finding, PolygonMesh, Property, PropertyValues, RepairOptions, TriMesh, repair, validate,
};
use glam::DVec3;

/// V − E + F counted directly from the face list (V = vertices used by some face), without
/// `Topology`: the independent count the library's Euler characteristic is checked against.
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

fn tri(mesh: &PolygonMesh) -> TriMesh {
    TriMesh::from_polygon_mesh(mesh).unwrap()
}

fn assert_valid(mesh: &PolygonMesh) {
    let r = validate(mesh);
    assert!(r.is_valid(), "{r}");
}

/// Two triangles sharing only vertex 0, with normals and a per-vertex and per-face property.
fn bow_tie() -> PolygonMesh {
    let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
    let mut m = PolygonMesh::new();
    m.positions = vec![p(0., 0.), p(1., -1.), p(1., 1.), p(-1., 1.), p(-1., -1.)];
    m.push_face(&[0, 1, 2]);
    m.push_face(&[0, 3, 4]);
    m.normals = Some(vec![DVec3::Z; 5]);
    m.vertex_properties.push(Property {
        name: "patch_id".into(),
        values: PropertyValues::Int(vec![10, 11, 12, 13, 14]),
    });
    m.face_properties.push(Property {
        name: "weight".into(),
        values: PropertyValues::Float(vec![0.5, 0.25]),
    });
    m
}

#[test]
fn bow_tie_loops_components_and_split() {
    let m = bow_tie();
    let r = validate(&m);
    assert_eq!(
        r.findings,
        vec![Finding::NonManifoldVertex { vertex: 0, fans: 2 }]
    );
    // Two loops touching at vertex 0, one per component; each triangle is a manifold disk.
    assert_eq!(r.boundary_loops.len(), 2);
    assert!(r.boundary_loops.iter().all(|l| l.len() == 3 && l[0] == 0));
    assert_eq!(r.components.len(), 2);
    for c in &r.components {
        assert_eq!(
            (c.manifold, c.boundary_loop_count, c.euler_characteristic),
            (true, 1, 1)
        );
        assert_eq!(c.genus, Some(0));
    }
    // Whole mesh: V − E + F = 5 − 6 + 2 = 1, although the components' χ add up to 2.
    let t = tri(&m);
    assert_eq!(t.euler_characteristic(), 1);
    assert_eq!(t.euler_characteristic(), chi_from_faces(&m));

    let out = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(out.report.split_vertices, vec![(0, 2)]);
    assert!(out.report.detached_non_manifold_edges.is_empty());
    assert!(out.report.changed());
    assert!(
        out.report
            .to_string()
            .contains("split non-manifold vertices: 1 [0 into 2]")
    );
    let o = &out.mesh;
    assert_valid(o);
    assert_eq!(o.vertex_count(), 6);
    assert_eq!(out.report.vertex_map, vec![0, 1, 2, 3, 4, 0]);
    assert_eq!(o.face(0), &[0, 1, 2]);
    assert_eq!(o.face(1), &[5, 3, 4]);
    assert_eq!(o.positions[5], m.positions[0]);
    assert_eq!(o.normals.as_ref().unwrap().len(), 6);
    assert_eq!(
        o.vertex_properties[0].values,
        PropertyValues::Int(vec![10, 11, 12, 13, 14, 10])
    );
    assert_eq!(o.face_properties, m.face_properties);
    // The input vertex maps to the copy that kept its first fan.
    assert_eq!(out.report.input_to_output_vertices(5)[0], Some(0));
    assert_eq!(tri(o).euler_characteristic(), 2);
    assert_eq!(chi_from_faces(o), 2);

    // The step can be turned off; then the vertex stays non-manifold.
    let off = RepairOptions {
        split_non_manifold_vertices: false,
        ..RepairOptions::default()
    };
    let kept = repair(&m, &off).unwrap();
    assert!(kept.report.split_vertices.is_empty());
    assert!(!validate(&kept.mesh).is_valid());
}

/// Two closed cones (side and base cap) touching at their common apex, vertex 0.
fn double_cone(n: u32) -> PolygonMesh {
    let mut m = PolygonMesh::new();
    m.positions.push(DVec3::ZERO);
    for z in [1.0, -1.0] {
        let base = m.positions.len() as u32;
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            m.positions.push(DVec3::new(a.cos(), a.sin(), z));
        }
        let centre = m.positions.len() as u32;
        m.positions.push(DVec3::new(0.0, 0.0, z));
        for i in 0..n {
            let (a, b) = (base + i, base + (i + 1) % n);
            m.push_face(&[0, a, b]);
            m.push_face(&[centre, b, a]);
        }
    }
    m
}

#[test]
fn cones_touching_at_apex() {
    let n = 8;
    let m = double_cone(n);
    let r = validate(&m);
    assert!(
        r.findings
            .contains(&Finding::NonManifoldVertex { vertex: 0, fans: 2 }),
        "{r}"
    );
    assert!(r.boundary_loops.is_empty());
    assert_eq!(r.components.len(), 2);
    for c in &r.components {
        assert!(c.manifold);
        assert_eq!((c.euler_characteristic, c.genus), (2, Some(0)));
    }
    // V = 2n + 3, E = 6n, F = 4n: χ = 3.
    assert_eq!(tri(&m).euler_characteristic(), 3);
    assert_eq!(chi_from_faces(&m), 3);

    let out = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(out.report.split_vertices, vec![(0, 2)]);
    let o = &out.mesh;
    assert_valid(o);
    assert_eq!(o.vertex_count(), 2 * n as usize + 4);
    assert_eq!(*out.report.vertex_map.last().unwrap(), 0);
    let t = tri(o);
    assert_eq!(t.euler_characteristic(), 4);
    assert_eq!(chi_from_faces(o), 4);
    // Both spheres end up oriented outward.
    for c in t.components() {
        assert_eq!(c.genus, Some(0));
        assert!(t.signed_volume_of(&c.faces) > 0.0);
    }
}

/// An open cylinder of 3 bands (4 rings of `n` vertices) whose top ring's vertex 0 is
/// identified with the bottom ring's vertex 0: one component, two boundary loops touching at
/// vertex 0.
fn pinched_cylinder(n: u32) -> PolygonMesh {
    let id = |k: u32, i: u32| -> u32 {
        let i = i % n;
        match (k, i) {
            (3, 0) => 0,
            (3, _) => 3 * n + i - 1,
            _ => k * n + i,
        }
    };
    let mut m = PolygonMesh::new();
    for k in 0..4 {
        for i in 0..n {
            if (k, i) != (3, 0) {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                m.positions.push(DVec3::new(a.cos(), a.sin(), k as f64));
            }
        }
    }
    for k in 0..3 {
        for i in 0..n {
            m.push_face(&[id(k, i), id(k, i + 1), id(k + 1, i + 1)]);
            m.push_face(&[id(k, i), id(k + 1, i + 1), id(k + 1, i)]);
        }
    }
    m
}

#[test]
fn boundary_loops_touching_in_one_component() {
    let n = 6;
    let m = pinched_cylinder(n);
    let r = validate(&m);
    assert_eq!(
        r.findings,
        vec![Finding::NonManifoldVertex { vertex: 0, fans: 2 }]
    );
    assert_eq!(r.components.len(), 1);
    let c = &r.components[0];
    // The two rims stay two loops (each traced within its own fan at vertex 0).
    assert_eq!(r.boundary_loops.len(), 2);
    assert!(
        r.boundary_loops
            .iter()
            .all(|l| l.len() == n as usize && l.contains(&0))
    );
    assert_eq!(c.boundary_loop_count, 2);
    assert_eq!(c.boundary_edge_count, 2 * n as usize);
    // Cylinder χ = 0, minus the identified vertex.
    assert_eq!(c.euler_characteristic, -1);
    assert_eq!(chi_from_faces(&m), -1);
    assert_eq!(tri(&m).euler_characteristic(), -1);
    assert!(!c.manifold);
    assert_eq!(c.genus, None);

    let out = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(out.report.split_vertices, vec![(0, 2)]);
    assert_valid(&out.mesh);
    let t = tri(&out.mesh);
    let c = &t.components()[0];
    assert_eq!((c.euler_characteristic, c.boundary_loop_count), (0, 2));
    assert_eq!(c.genus, Some(0));
    assert_eq!(chi_from_faces(&out.mesh), 0);
}

#[test]
fn pinched_holes_form_one_loop_through_the_vertex() {
    // A 4x4 grid without two triangles that meet only at vertex (2, 2) = 12: the holes are
    // joined at 12, whose two remaining fans each run from one hole to the other, so the
    // boundary walk crosses 12 twice: one inner loop of 6 edges plus the outer loop of 16.
    let g = grid(4, 4);
    let tris: Vec<[u32; 3]> = g
        .triangles()
        .iter()
        .enumerate()
        .filter(|(f, _)| *f != 10 && *f != 21)
        .map(|(_, t)| *t)
        .collect();
    assert!(g.triangles()[10].contains(&12) && g.triangles()[21].contains(&12));
    let m = PolygonMesh::from_triangles(g.positions().to_vec(), &tris);
    let r = validate(&m);
    assert_eq!(
        r.findings,
        vec![Finding::NonManifoldVertex {
            vertex: 12,
            fans: 2
        }]
    );
    let mut lens: Vec<usize> = r.boundary_loops.iter().map(Vec::len).collect();
    lens.sort_unstable();
    assert_eq!(lens, vec![6, 16]);
    let inner = r.boundary_loops.iter().find(|l| l.len() == 6).unwrap();
    assert_eq!(inner.iter().filter(|&&v| v == 12).count(), 2);
    // V − E + F = 25 − 56 + 30.
    assert_eq!(r.components[0].euler_characteristic, -1);
    assert_eq!(chi_from_faces(&m), -1);
    let out = repair(&m, &RepairOptions::default()).unwrap();
    assert_valid(&out.mesh);
    let c = &tri(&out.mesh).components()[0];
    // Split at 12 the surface is an annulus.
    assert_eq!(
        (c.euler_characteristic, c.boundary_loop_count, c.genus),
        (0, 2, Some(0))
    );
}

#[test]
fn non_manifold_edges_are_detached() {
    // Three triangles on edge (0, 1): each gets its own copies of 0 and 1.
    let mut m = PolygonMesh::new();
    m.positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(0.5, 1.0, 0.0),
        DVec3::new(0.5, -1.0, 0.0),
        DVec3::new(0.5, 0.0, 1.0),
    ];
    m.push_face(&[0, 1, 2]);
    m.push_face(&[1, 0, 3]);
    m.push_face(&[0, 1, 4]);
    let r = validate(&m);
    assert!(r.findings.contains(&Finding::NonManifoldEdge {
        vertices: [0, 1],
        faces: vec![0, 1, 2]
    }));
    let out = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(out.report.detached_non_manifold_edges, vec![[0, 1]]);
    assert_eq!(out.report.split_vertices, vec![(0, 3), (1, 3)]);
    assert_eq!(out.mesh.face_count(), 3, "no face is dropped");
    assert_valid(&out.mesh);
    assert_eq!(out.mesh.vertex_count(), 9);
    assert_eq!(tri(&out.mesh).components().len(), 3);
}

#[test]
fn tetrahedra_sharing_an_edge_separate_into_two_closed_ones() {
    // Edge (0, 1) has four faces, two from each tetrahedron. At both endpoints each
    // tetrahedron's faces form one fan, so after the split each tetrahedron keeps its own
    // copy of the edge with two faces on it: two closed spheres, nothing dropped.
    let mut m = PolygonMesh::new();
    m.positions = vec![
        DVec3::ZERO,
        DVec3::Z,
        DVec3::new(1.0, 0.0, 0.5),
        DVec3::new(0.0, 1.0, 0.5),
        DVec3::new(-1.0, 0.0, 0.5),
        DVec3::new(0.0, -1.0, 0.5),
    ];
    for t in [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]] {
        m.push_face(&t);
    }
    for t in [[0, 1, 4], [0, 4, 5], [0, 5, 1], [1, 5, 4]] {
        m.push_face(&t);
    }
    let r = validate(&m);
    assert!(r.findings.iter().any(
        |f| matches!(f, Finding::NonManifoldEdge { vertices: [0, 1], faces } if faces.len() == 4)
    ));
    assert_eq!(chi_from_faces(&m), 6 - 11 + 8);
    let out = repair(&m, &RepairOptions::default()).unwrap();
    assert_eq!(out.report.detached_non_manifold_edges, vec![[0, 1]]);
    assert_eq!(out.report.split_vertices, vec![(0, 2), (1, 2)]);
    assert_valid(&out.mesh);
    let t = tri(&out.mesh);
    assert_eq!(t.euler_characteristic(), 4);
    assert_eq!(chi_from_faces(&out.mesh), 4);
    for c in t.components() {
        assert_eq!((c.euler_characteristic, c.genus), (2, Some(0)));
        assert!(t.signed_volume_of(&c.faces) > 0.0);
    }
}

mod random {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Any triangle soup over a few vertices (non-manifold edges and vertices, flipped and
        /// duplicate faces galore) repairs to a mesh that validates clean, unless a component
        /// cannot be oriented (then only orientation findings may remain); χ always matches the
        /// direct count and no face is lost to the split step.
        #[test]
        fn default_repair_yields_valid_meshes(
            pts in proptest::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 4..9),
            tris in proptest::collection::vec((0u32..9, 0u32..9, 0u32..9), 1..24),
        ) {
            let n = pts.len() as u32;
            let mut m = PolygonMesh::new();
            m.positions = pts.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect();
            for (a, b, c) in tris {
                m.push_face(&[a % n, b % n, c % n]);
            }
            let out = repair(&m, &RepairOptions::default()).unwrap();
            let r = validate(&out.mesh);
            if out.report.non_orientable_components == 0 {
                prop_assert!(r.is_valid(), "{}", r);
            } else {
                prop_assert!(r.findings.iter().all(|f| matches!(f, Finding::InconsistentOrientation { .. })), "{}", r);
            }
            prop_assert_eq!(r.euler_characteristic, chi_from_faces(&out.mesh));
            let t = TriMesh::from_polygon_mesh(&out.mesh).unwrap();
            prop_assert_eq!(t.euler_characteristic(), chi_from_faces(&out.mesh));
            let loops: usize = r.components.iter().map(|c| c.boundary_loop_count).sum();
            prop_assert_eq!(loops, r.boundary_loops.len());
            // Loops of a manifold mesh are closed and partition its boundary edges.
            let closed = r.boundary_loops.iter().all(|l| {
                (0..l.len()).all(|i| {
                    let (a, b) = (l[i], l[(i + 1) % l.len()]);
                    t.topology().find_edge(a, b).is_some_and(|e| t.topology().is_boundary_edge(e))
                })
            });
            prop_assert!(closed);
            let edges_in_loops: usize = r.boundary_loops.iter().map(Vec::len).sum();
            prop_assert_eq!(edges_in_loops, r.boundary_edge_count());
        }
    }
}

//! End-to-end claims of Xu–Huang–Bajaj 2001 on whole meshes, measured on the tessellation.

use algesurf_apatch::{ApatchSurface, PatchKind, SurfaceOptions, Tessellation};
use algesurf_mesh::TriMesh;
use algesurf_mesh::shapes::icosphere;
use glam::DVec3;
use std::collections::HashMap;

/// Every undirected edge of the output is used by exactly two triangles, in opposite
/// directions (closed, consistently oriented 2-manifold); returns V − E + F.
fn closed_manifold_euler(t: &Tessellation) -> i64 {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for tri in &t.triangles {
        for k in 0..3 {
            *directed.entry((tri[k], tri[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &c) in &directed {
        assert_eq!(c, 1, "directed edge ({a}, {b}) used {c} times");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge ({a}, {b}) has no opposite"
        );
    }
    let used: std::collections::HashSet<u32> = t.triangles.iter().flatten().copied().collect();
    used.len() as i64 - (directed.len() / 2) as i64 + t.triangles.len() as i64
}

fn no_duplicate_positions(t: &Tessellation) {
    let mut seen = HashMap::new();
    for (i, p) in t.positions.iter().enumerate() {
        let key = p.to_array().map(f64::to_bits);
        if let Some(j) = seen.insert(key, i) {
            panic!("vertices {j} and {i} share the position {p}");
        }
    }
}

fn sphere_surface(level: u32) -> (TriMesh, ApatchSurface) {
    let mesh = icosphere(level);
    let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    (mesh, s)
}

#[test]
fn sphere_is_recovered_from_icosahedron() {
    for level in 0..=2 {
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
    let t = s.tessellate(5, 4).unwrap();
    no_duplicate_positions(&t);
    assert_eq!(closed_manifold_euler(&t), mesh.euler_characteristic());
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
    let t = s.tessellate(4, 4).unwrap();
    assert!(
        t.missed_rays.is_empty(),
        "{} missed rays",
        t.missed_rays.len()
    );
    assert!(
        t.multiple_roots.is_empty(),
        "{} multiple roots",
        t.multiple_roots.len()
    );
    no_duplicate_positions(&t);
    assert_eq!(closed_manifold_euler(&t), 0);
}

/// Theorem 4.1, measured: F is C1 across every interior facet of the hull, interpolates the
/// vertices with the given normals, and the patch normals agree at every shared tessellation
/// vertex — on a sphere (convex faces, rational terms) and a torus (split faces, nonconvex
/// edges).
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
        let c = s.continuity_report(6);
        println!(
            "{name}: {} facets, {} samples, value {:e} at {:?}, gradient {:e} at {:?}",
            c.facets, c.samples, c.value.value, c.value.at, c.gradient.value, c.gradient.at
        );
        assert!(c.samples >= 16 * c.facets, "{name}: too few samples");
        assert!(
            c.value.value <= 1e-10,
            "{name}: value mismatch {:e} at {:?}",
            c.value.value,
            c.value.at
        );
        assert!(
            c.gradient.value <= 1e-8,
            "{name}: gradient mismatch {:e} at {:?}",
            c.gradient.value,
            c.gradient.at
        );
        let i = s.interpolation_report();
        println!(
            "{name}: |F(p_i)| {:e}, normal angle {:e}",
            i.value.value, i.normal_angle.value
        );
        assert!(
            i.value.value <= 1e-12,
            "{name}: F(p_i) = {:e} at vertex {:?}",
            i.value.value,
            i.value.at
        );
        assert!(
            i.normal_angle.value <= 1e-9,
            "{name}: normal angle {:e} at vertex {:?}",
            i.normal_angle.value,
            i.normal_angle.at
        );
        let t = s.tessellate(4, 4).unwrap();
        let n = s.normal_agreement(&t);
        println!("{name}: normal agreement {:e} at {:?}", n.value, n.at);
        assert!(
            n.value <= 1e-8,
            "{name}: normals differ by {:e} rad at vertex {:?}",
            n.value,
            n.at
        );
    }
}

/// The two triangles of §6 with the normals of Figs. 6, 7, 9 and 10: classified as the paper
/// says, and F joins C1 with every patch single sheeted.
#[test]
fn papers_worked_configurations_are_classified_and_join_c1() {
    use algesurf_apatch::FaceFunction;
    let p = vec![
        DVec3::new(-2.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 4.0, -1.0),
        DVec3::new(0.0, -4.0, -1.0),
    ];
    let tris = vec![[0u32, 1, 2], [1, 0, 3]];
    let n = |v: [f64; 3]| DVec3::from_array(v).normalize();
    // (figure, p4.z, normals, expected kinds of [p1p2p3], [p1p2p4]: 0 planar, 1 convex, 2 split)
    let cases = [
        (
            "Fig. 6",
            -1.0,
            [
                n([-1.0, 0.0, 1.0]),
                n([1.0, 0.0, 1.0]),
                n([0.0, 1.0, 1.0]),
                n([0.0, -1.0, 1.0]),
            ],
            [1, 1],
        ),
        (
            "Fig. 7",
            -1.0,
            [
                n([-1.0, 0.0, 1.0]),
                n([1.0, 0.0, 1.0]),
                n([0.0, 1.0, 1.5]),
                n([0.0, 1.0, 1.5]),
            ],
            [1, 2],
        ),
        (
            "Fig. 9",
            -1.0,
            [
                n([1.0, 0.0, 1.0]),
                n([1.0, 0.0, 1.0]),
                n([0.0, -1.0, 1.5]),
                n([0.0, 1.0, 1.5]),
            ],
            [2, 2],
        ),
        (
            "Fig. 10",
            0.0,
            [
                n([0.0, 0.0, 1.0]),
                n([0.0, 0.0, 1.0]),
                n([0.0, -1.0, 1.5]),
                n([0.0, 0.0, 1.0]),
            ],
            [2, 0],
        ),
    ];
    for (fig, z4, normals, kinds) in cases {
        let mut pos = p.clone();
        pos[3].z = z4;
        let mesh = TriMesh::new(pos, tris.clone()).unwrap();
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
        let got: Vec<usize> = s
            .faces()
            .iter()
            .map(|f| match f {
                FaceFunction::Planar => 0,
                FaceFunction::Convex { .. } => 1,
                FaceFunction::Split(_) => 2,
            })
            .collect();
        assert_eq!(got, kinds.to_vec(), "{fig}");
        let c = s.continuity_report(6);
        assert!(
            c.value.value <= 1e-10 && c.gradient.value <= 1e-8,
            "{fig}: {c:?}"
        );
        let i = s.interpolation_report();
        assert!(
            i.value.value <= 1e-12 && i.normal_angle.value <= 1e-9,
            "{fig}: {i:?}"
        );
        let t = s.tessellate(8, 8).unwrap();
        assert!(
            t.missed_rays.is_empty() && t.multiple_roots.is_empty(),
            "{fig}: {} missed, {} multiple",
            t.missed_rays.len(),
            t.multiple_roots.len()
        );
        let na = s.normal_agreement(&t);
        assert!(na.value <= 1e-8, "{fig}: normals differ by {:e}", na.value);
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

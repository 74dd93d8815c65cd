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
        assert_eq!(directed.get(&(b, a)), Some(&1), "edge ({a}, {b}) has no opposite");
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
        assert!(t.missed_rays.is_empty(), "level {level}: {} missed rays", t.missed_rays.len());
        assert!(t.multiple_roots.is_empty(), "level {level}: {} multiple roots", t.multiple_roots.len());
        let worst = t.positions.iter().map(|p| (p.length() - 1.0).abs()).fold(0.0, f64::max);
        assert!(worst <= 1e-10, "level {level}: max | |p| − 1 | = {worst:e}");
        let worst_n = t.positions.iter().zip(&t.normals).map(|(p, n)| (n - p.normalize()).length()).fold(0.0, f64::max);
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

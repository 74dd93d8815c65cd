//! Random perturbations of icospheres and tori (vertex and normal jitter) keep every property of
//! Theorem 4.1 — C1 across every interior facet, interpolation, normal agreement, single-sheeted
//! patches, closed manifold output with the input's Euler characteristic — everything except
//! quadric precision, which needs exact quadric data.

use algesurf_apatch::{ApatchSurface, SurfaceOptions};
use algesurf_mesh::shapes::{icosphere, torus};
use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};
use glam::DVec3;
use proptest::prelude::*;
use std::collections::HashMap;

fn jitter(mesh: &TriMesh, seed: u64, amount: f64) -> TriMesh {
    // Deterministic per-vertex offsets from a small LCG (proptest supplies the seed).
    let mut state = seed | 1;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let scale = mesh.bounding_box().diagonal();
    let pos = mesh
        .positions()
        .iter()
        .map(|p| *p + DVec3::new(next(), next(), next()) * amount * scale)
        .collect();
    TriMesh::new(pos, mesh.triangles().to_vec()).unwrap()
}

fn check(mesh: &TriMesh, normal_tilt: f64, seed: u64) -> Result<(), TestCaseError> {
    let mut normals = vertex_normals(mesh, NormalMethod::Loop).unwrap();
    let mut s = seed.rotate_left(17) | 1;
    for n in &mut normals {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
        let a = ((s >> 11) as f64 / (1u64 << 53) as f64) * std::f64::consts::TAU;
        let perp = n.any_orthonormal_vector();
        let other = n.cross(perp);
        *n = (*n + (perp * a.cos() + other * a.sin()) * normal_tilt).normalize();
    }
    let surface = ApatchSurface::new(mesh, &normals, &SurfaceOptions::default())
        .map_err(|e| TestCaseError::fail(format!("construction: {e}")))?;
    let c = surface.continuity_report(6);
    prop_assert!(c.value.value <= 1e-10 && c.gradient.value <= 1e-8, "{c:?}");
    let i = surface.interpolation_report();
    prop_assert!(
        i.value.value <= 1e-12 && i.normal_angle.value <= 1e-9,
        "{i:?}"
    );
    let t = surface.tessellate(3, 3).unwrap();
    prop_assert!(
        t.missed_rays.is_empty() && t.multiple_roots.is_empty(),
        "{} missed, {} multiple",
        t.missed_rays.len(),
        t.multiple_roots.len()
    );
    let na = surface.normal_agreement(&t);
    prop_assert!(na.value <= 1e-8, "normals differ by {:e}", na.value);
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for tri in &t.triangles {
        for k in 0..3 {
            *directed.entry((tri[k], tri[(k + 1) % 3])).or_default() += 1;
        }
    }
    prop_assert!(
        directed
            .iter()
            .all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1)),
        "not a closed manifold"
    );
    let used: std::collections::HashSet<u32> = t.triangles.iter().flatten().copied().collect();
    let euler = used.len() as i64 - (directed.len() / 2) as i64 + t.triangles.len() as i64;
    prop_assert_eq!(euler, surface.hull().mesh().euler_characteristic());
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]

    #[test]
    fn jittered_icospheres_keep_theorem_4_1(seed in any::<u64>(), amount in 0.0..0.02f64, tilt in 0.0..0.15f64) {
        check(&jitter(&icosphere(1), seed, amount), tilt, seed)?;
    }

    #[test]
    fn jittered_tori_keep_theorem_4_1(seed in any::<u64>(), amount in 0.0..0.01f64, tilt in 0.0..0.1f64) {
        check(&jitter(&torus(12, 8, 1.5, 0.6), seed, amount), tilt, seed)?;
    }
}

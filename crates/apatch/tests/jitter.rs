//! Random perturbations of icospheres and tori (vertex and normal jitter) keep every property of
//! Theorem 4.1 — C1 across every interior facet, interpolation, normal agreement, single-sheeted
//! patches, closed manifold output with the input's Euler characteristic — everything except
//! quadric precision, which needs exact quadric data.

use algesurf_apatch::{ApatchSurface, SurfaceOptions};
use algesurf_inspect::check::{ApatchView, CheckOptions, check};
use algesurf_mesh::shapes::{icosphere, torus};
use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};
use glam::DVec3;
use proptest::prelude::*;

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

fn keeps_theorem_4_1(mesh: &TriMesh, normal_tilt: f64, seed: u64) -> Result<(), TestCaseError> {
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
    // The whole check battery: C1, interpolation, normal agreement, simple roots, closed
    // manifold with the input's Euler characteristic, no duplicates, parameter margins.
    let options = CheckOptions {
        resolution: 3,
        ..CheckOptions::default()
    };
    let r = check(&ApatchView::new(&surface), &options)
        .map_err(|e| TestCaseError::fail(format!("check: {e}")))?;
    prop_assert!(r.passed(), "\n{}", r);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]

    #[test]
    fn jittered_icospheres_keep_theorem_4_1(seed in any::<u64>(), amount in 0.0..0.02f64, tilt in 0.0..0.15f64) {
        keeps_theorem_4_1(&jitter(&icosphere(1), seed, amount), tilt, seed)?;
    }

    #[test]
    fn jittered_tori_keep_theorem_4_1(seed in any::<u64>(), amount in 0.0..0.01f64, tilt in 0.0..0.1f64) {
        keeps_theorem_4_1(&jitter(&torus(12, 8, 1.5, 0.6), seed, amount), tilt, seed)?;
    }
}

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

/// Far beyond the jitter above: vertices moved by up to 15 % of the shape's size, normals
/// tilted by up to 3 (unit) and scaled by 0.5–2.5, each option drawn at random. A build may
/// fail, but only for a reason the input has (a normal on the wrong side of a face, a vertex
/// whose faces fold over, tetrahedra that refinement does not separate), never by a panic;
/// and every surface it builds is single-sheeted and finite at every tessellation point.
#[test]
fn heavily_perturbed_meshes_build_valid_surfaces_or_fail_for_a_named_reason() {
    use algesurf_apatch::{ApatchError, FreeParameterRule, GradientMagnitudes};
    use algesurf_hull::{ApexPlacement, HullError, HullOptions};
    use algesurf_mesh::shapes::octahedron;
    let mut state = 77u64;
    let mut rnd = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut built, mut failed) = (0, 0);
    for case in 0..300 {
        let base = match case % 3 {
            0 => octahedron(),
            1 => icosphere(1),
            _ => torus(8, 5, 1.0, 0.4),
        };
        let amount = [0.0, 0.02, 0.15][(rnd() * 3.0) as usize];
        let mesh = jitter(&base, (rnd() * 1e9) as u64, amount);
        let tilt = [0.0, 0.3, 1.0, 3.0][(rnd() * 4.0) as usize];
        let normals: Vec<DVec3> = vertex_normals(&mesh, NormalMethod::Area)
            .unwrap()
            .iter()
            .map(|n| {
                let d = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
                (*n + tilt * d) * (0.5 + 2.0 * rnd())
            })
            .collect();
        let options = SurfaceOptions {
            free_parameters: [FreeParameterRule::Quadric, FreeParameterRule::Linear]
                [(rnd() * 2.0) as usize],
            gradient_magnitudes: [
                GradientMagnitudes::AsGiven,
                GradientMagnitudes::QuadricConsistent,
            ][(rnd() * 2.0) as usize],
            condition_normals: rnd() < 0.7,
            hull: HullOptions {
                apex: [ApexPlacement::Nearest, ApexPlacement::FaceNormal][(rnd() * 2.0) as usize],
                ..HullOptions::default()
            },
            ..SurfaceOptions::default()
        };
        match ApatchSurface::new(&mesh, &normals, &options) {
            Ok(s) => {
                built += 1;
                let t = s.tessellate(3, 2).unwrap();
                assert!(
                    t.missed_rays.is_empty() && t.multiple_roots.is_empty(),
                    "case {case}: {} missed, {} multiple",
                    t.missed_rays.len(),
                    t.multiple_roots.len()
                );
                assert!(
                    t.positions.iter().chain(&t.normals).all(|p| p.is_finite()),
                    "case {case}: a non-finite point"
                );
            }
            Err(e) => {
                failed += 1;
                let named = match &e {
                    // Conditioning puts every normal that can be on the positive side of
                    // its faces there: with it, only a fold leaves one on the wrong side.
                    ApatchError::Hull(HullError::NormalNotOnPositiveSide { .. }) => {
                        !options.condition_normals
                    }
                    ApatchError::Hull(HullError::FoldedVertex { .. })
                    | ApatchError::Hull(HullError::UnresolvedIntersection { .. }) => true,
                    _ => false,
                };
                assert!(named, "case {case} (options {options:?}): {e}");
            }
        }
    }
    println!("{built} built, {failed} failed for a named reason");
    // Not a property, a guard against a vacuous test: most failures come from the tilted
    // normals left unconditioned (a third of the cases), so at least a third must build.
    assert!(built >= 100, "only {built} of 300 built");
}

//! Property: jittered icospheres (vertex and normal jitter) give hulls whose tetrahedra are
//! nondegenerate and pairwise interior-disjoint (checked by brute force over all pairs), with
//! the apex margins of §3.1.

mod common;

use algesurf_hull::{HullOptions, SimplicialHull};
use common::{brute_force_overlaps, check_apex_properties, icosphere, min_relative_measure};
use glam::DVec3;
use proptest::prelude::*;

fn jittered(
    level: u32,
    vj: &[(f64, f64, f64)],
    nj: &[(f64, f64, f64)],
) -> (Vec<DVec3>, Vec<[u32; 3]>, Vec<DVec3>) {
    let (p, f) = icosphere(level);
    let q: Vec<DVec3> = p
        .iter()
        .zip(vj)
        .map(|(x, &(a, b, c))| *x + DVec3::new(a, b, c))
        .collect();
    let n: Vec<DVec3> = p
        .iter()
        .zip(nj)
        .map(|(x, &(a, b, c))| (*x + DVec3::new(a, b, c)).normalize())
        .collect();
    (q, f, n)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Level 1 (42 vertices, edge ≈ 0.55): vertex jitter up to 0.12 per coordinate, normal
    /// jitter up to about 0.5 rad (this occasionally needs refinement).
    #[test]
    fn jittered_icosphere_hulls_are_valid(
        vj in prop::collection::vec((-0.12f64..0.12, -0.12f64..0.12, -0.12f64..0.12), 42),
        nj in prop::collection::vec((-0.3f64..0.3, -0.3f64..0.3, -0.3f64..0.3), 42),
    ) {
        let (p, f, n) = jittered(1, &vj, &nj);
        let hull = SimplicialHull::new(&p, &f, &n, &HullOptions::default()).unwrap();
        prop_assert!(min_relative_measure(&hull) > 1e-4);
        prop_assert_eq!(brute_force_overlaps(&hull, 1e-9), 0);
        prop_assert!(hull.intersections().is_empty());
        check_apex_properties(&hull);
        prop_assert_eq!(hull.face_map().len(), hull.faces().len());
        prop_assert!(hull.face_map().iter().all(|&g| (g as usize) < f.len()));
    }
}

//! BVH queries agree with brute force.

use algesurf_mesh::primitives::{closest_point_on_triangle, ray_triangle, triangle_box_overlap};
use algesurf_mesh::shapes::{icosphere, torus};
use algesurf_mesh::{Aabb, BoxBvh, TriMesh, TriangleBvh};
use glam::DVec3;
use proptest::prelude::*;

fn brute_closest(m: &TriMesh, p: DVec3) -> f64 {
    (0..m.face_count())
        .map(|f| {
            let [a, b, c] = m.triangle_points(f);
            closest_point_on_triangle(p, a, b, c).0.distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

fn v3() -> impl Strategy<Value = DVec3> {
    (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

#[test]
fn closest_point_regions() {
    let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
    let cases = [
        (DVec3::new(0.2, 0.2, 1.0), DVec3::new(0.2, 0.2, 0.0)),
        (DVec3::new(-1.0, -1.0, 0.0), a),
        (DVec3::new(2.0, -0.5, 0.3), b),
        (DVec3::new(-0.5, 2.0, 0.0), c),
        (DVec3::new(0.5, -1.0, 0.0), DVec3::new(0.5, 0.0, 0.0)),
        (DVec3::new(-1.0, 0.5, 0.0), DVec3::new(0.0, 0.5, 0.0)),
        (DVec3::new(1.0, 1.0, 0.0), DVec3::new(0.5, 0.5, 0.0)),
    ];
    for (p, want) in cases {
        assert!(
            (closest_point_on_triangle(p, a, b, c).0 - want).length() < 1e-15,
            "{p}"
        );
    }
    // Degenerate (collinear) triangle falls back to its edges.
    let (q, _) = closest_point_on_triangle(DVec3::new(0.5, 1.0, 0.0), a, b, 2.0 * b);
    assert!((q - DVec3::new(0.5, 0.0, 0.0)).length() < 1e-15);
    assert_eq!(
        ray_triangle(DVec3::new(0.2, 0.2, 1.0), -DVec3::Z, [a, b, c], 0.0, 10.0).map(|h| h.0),
        Some(1.0)
    );
    assert!(triangle_box_overlap(
        [a, b, c],
        &Aabb::new(DVec3::new(0.4, 0.4, -0.1), DVec3::new(0.6, 0.6, 0.1))
    ));
    assert!(!triangle_box_overlap(
        [a, b, c],
        &Aabb::new(DVec3::new(0.6, 0.6, -1.0), DVec3::new(1.0, 1.0, 1.0))
    ));
}

#[test]
fn empty_and_box_bvh() {
    let t = TriangleBvh::from_triangles(Vec::new());
    assert!(t.closest_point(DVec3::ZERO).is_none());
    assert!(t.ray_hits(DVec3::ZERO, DVec3::X, 0.0, 1.0).is_empty());
    let boxes: Vec<Aabb> = (0..50)
        .map(|i| {
            let c = DVec3::new(i as f64 * 0.1, (i % 7) as f64 * 0.3, (i % 3) as f64);
            Aabb::new(c, c + DVec3::splat(0.15))
        })
        .collect();
    let b = BoxBvh::new(boxes.clone());
    let q = Aabb::new(DVec3::new(1.0, 0.0, 0.0), DVec3::new(2.0, 1.0, 1.0));
    let want: Vec<u32> = (0..50)
        .filter(|&i| boxes[i as usize].overlaps(&q))
        .collect();
    assert_eq!(b.overlapping(&q), want);
    // Touching boxes count, including at a single shared f64 point.
    let p = boxes[10].max;
    assert!(b.containing(p).contains(&10));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]
    #[test]
    fn queries_match_brute_force(ps in prop::collection::vec(v3(), 20), dirs in prop::collection::vec(v3(), 20), level in 1u32..3) {
        let meshes = [icosphere(level), torus(10, 6, 1.5, 0.5)];
        for m in &meshes {
            let bvh = TriangleBvh::new(m);
            for (p, d) in ps.iter().zip(&dirs) {
                let c = bvh.closest_point(*p).unwrap();
                let want = brute_closest(m, *p);
                prop_assert!((c.distance - want).abs() <= 1e-15 * (1.0 + want));
                prop_assert!((c.point.distance(*p) - c.distance).abs() < 1e-12);
                // Rays from p in direction d (and through the centre, which always hits).
                for dir in [*d, -*p] {
                    if dir.length() == 0.0 { continue; }
                    let brute: Vec<(f64, u32)> = (0..m.face_count())
                        .filter_map(|f| ray_triangle(*p, dir, m.triangle_points(f), 0.0, f64::INFINITY).map(|h| (h.0, f as u32)))
                        .collect();
                    let hits = bvh.ray_hits(*p, dir, 0.0, f64::INFINITY);
                    let mut got: Vec<(f64, u32)> = hits.iter().map(|h| (h.t, h.face)).collect();
                    let mut b2 = brute.clone();
                    got.sort_by_key(|a| a.1);
                    b2.sort_by_key(|a| a.1);
                    prop_assert_eq!(&got, &b2);
                    let first = bvh.ray_hit(*p, dir, 0.0, f64::INFINITY);
                    let bmin = brute.iter().map(|h| h.0).fold(f64::INFINITY, f64::min);
                    prop_assert_eq!(first.map(|h| h.t), (bmin.is_finite()).then_some(bmin));
                }
                // Box overlap.
                let q = Aabb::new(*p, *p + 0.3 * *d);
                let want: Vec<u32> = (0..m.face_count() as u32).filter(|&f| triangle_box_overlap(m.triangle_points(f as usize), &q)).collect();
                prop_assert_eq!(bvh.triangles_overlapping_box(&q), want);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The self-join finds every overlapping pair of boxes once, as brute force does: random
    /// boxes of mixed sizes (many touching and nested ones at small counts, 1 to 600 boxes so
    /// that the parallel levels and deep leaves are both exercised), and a non-finite box that
    /// is never reported.
    #[test]
    fn overlapping_pairs_match_brute_force(
        corners in prop::collection::vec((v3(), v3()), 1..600),
        scale in 0.05f64..2.0,
    ) {
        let mut boxes: Vec<Aabb> = corners
            .iter()
            .map(|(a, d)| Aabb::new(*a, *a + *d * scale))
            .collect();
        boxes.push(Aabb {
            min: DVec3::splat(f64::NAN),
            max: DVec3::ONE,
        });
        let bvh = BoxBvh::new(boxes.clone());
        let mut got = bvh.overlapping_pairs(|i, j| Some((i, j)));
        got.sort_unstable();
        let finite = |b: &Aabb| b.min.is_finite() && b.max.is_finite();
        let mut want = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if finite(&boxes[i]) && finite(&boxes[j]) && boxes[i].overlaps(&boxes[j]) {
                    want.push((i as u32, j as u32));
                }
            }
        }
        prop_assert_eq!(got, want);
    }
}

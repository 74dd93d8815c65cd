//! Faces of a mesh that pass through each other.

use crate::Aabb;
use crate::TriMesh;
use crate::morton::MortonBvh;
use crate::primitives::{longest_edge_length, triangle_overlap_depth};
use glam::DVec3;
use rayon::prelude::*;

/// Relative depth beyond which two triangles count as crossing in [`self_intersections`]:
/// `1e-9` of the longer of their longest edges. Rounding in [`triangle_overlap_depth`] is a
/// few ulps of the triangles' size (about `1e-15` of it), so touching and coplanar neighbours
/// stay below it by six orders of magnitude, while a real crossing of a mesh (the cow's ears
/// through its head: an eighth of a face width) is eight orders of magnitude above it.
pub const SELF_INTERSECTION_TOLERANCE: f64 = 1e-9;

/// The pairs of faces `[f, g]` (`f < g`, ascending) that share no vertex and pass through each
/// other: their interiors cross by more than [`SELF_INTERSECTION_TOLERANCE`] times their size
/// ([`triangle_overlap_depth`]). Faces that share a vertex meet there by construction and are
/// not tested; coplanar overlaps do not count.
///
/// Such a mesh is not the boundary of a solid, and no refinement makes it one: every method
/// that encloses the faces in disjoint cells (the simplicial hull of an A-patch surface) must
/// treat the crossing as the input's, as it treats two separate surfaces that meet.
///
/// Candidates come from a [`MortonBvh`] (boxes that overlap), so the cost is about
/// `O(n log n)` for a mesh without large overlapping regions.
///
/// ```
/// use algesurf_mesh::{TriMesh, self_intersections};
/// use glam::DVec3;
///
/// // Two triangles crossing like the links of a chain, and one far away.
/// let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
/// let mesh = TriMesh::new(
///     vec![
///         p(0., 0., 0.), p(2., 0., 0.), p(1., 2., 0.),
///         p(1., 1., -1.), p(1., 1., 1.), p(1., -1., 0.5),
///         p(9., 9., 9.), p(10., 9., 9.), p(9., 10., 9.),
///     ],
///     vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]],
/// )?;
/// assert_eq!(self_intersections(&mesh), vec![[0, 1]]);
/// # Ok::<(), algesurf_mesh::MeshError>(())
/// ```
pub fn self_intersections(mesh: &TriMesh) -> Vec<[u32; 2]> {
    let tris = mesh.triangles();
    // A Morton tree over the faces' boxes (`MortonBvh`: built by a parallel sort, where the
    // surface-area tree of `TriangleBvh` took 25 ms of one thread on the bunny for a single
    // walk), then one self-join of it, in parallel, each pair met once. A face with a
    // non-finite corner takes part in no pair. The sort makes the result independent of the
    // thread count.
    let boxes: Vec<(DVec3, DVec3)> = (0..tris.len())
        .into_par_iter()
        .map(|f| {
            let b = Aabb::from_points(&mesh.triangle_points(f));
            (b.min, b.max)
        })
        .collect();
    let tree = MortonBvh::new(boxes);
    let order = tree.order();
    let mut out: Vec<[u32; 2]> = tree.slot_pairs(|sa, sb| {
        let (f, g) = (order[sa].min(order[sb]), order[sa].max(order[sb]));
        let (t, u) = (tris[f as usize], tris[g as usize]);
        if t.iter().any(|v| u.contains(v)) {
            return None;
        }
        let (a, b) = (
            mesh.triangle_points(f as usize),
            mesh.triangle_points(g as usize),
        );
        if !a.iter().chain(&b).all(|p| p.is_finite()) {
            return None;
        }
        let size = longest_edge_length(a).max(longest_edge_length(b));
        (triangle_overlap_depth(a, b) > SELF_INTERSECTION_TOLERANCE * size).then_some([f, g])
    });
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use glam::DVec3;

    #[test]
    fn closed_convex_shapes_do_not_intersect_themselves() {
        for mesh in [shapes::icosphere(2), shapes::torus(24, 12, 1.0, 0.3)] {
            assert!(self_intersections(&mesh).is_empty());
        }
    }

    #[test]
    fn a_vertex_pushed_through_the_opposite_side_is_found() {
        // An icosphere with one vertex pushed through the sphere's centre and out through the
        // middle of a face on the other side: its fan now crosses that face, which shares no
        // vertex with it.
        let sphere = shapes::icosphere(1);
        let mut p = sphere.positions().to_vec();
        let far = (0..sphere.face_count())
            .map(|f| sphere.triangle_points(f).iter().sum::<DVec3>() / 3.0)
            .min_by(|a, b| a.dot(p[0]).total_cmp(&b.dot(p[0])))
            .unwrap();
        p[0] = 1.5 * far.normalize();
        let mesh = TriMesh::new(p, sphere.triangles().to_vec()).unwrap();
        let hits = self_intersections(&mesh);
        assert!(!hits.is_empty());
        for [f, g] in hits {
            assert!(f < g);
            let (a, b) = (mesh.triangles()[f as usize], mesh.triangles()[g as usize]);
            assert!(!a.iter().any(|v| b.contains(v)));
            // One of the two is in the pushed vertex's fan.
            assert!(a.contains(&0) || b.contains(&0));
        }
    }

    /// The tree finds exactly the pairs a test of every pair of faces finds, on a torus
    /// crumpled until dozens of its faces pass through each other.
    #[test]
    fn the_same_crossings_as_every_pair() {
        let torus = shapes::torus(20, 10, 1.0, 0.45);
        let mut rng = crate::test_rng::Lcg(0x9e37_79b9_7f4a_7c15);
        let mut next = || rng.next() - 0.5;
        let p: Vec<DVec3> = torus
            .positions()
            .iter()
            .map(|x| *x + DVec3::new(next(), next(), next()) * 0.5)
            .collect();
        let mesh = TriMesh::new(p, torus.triangles().to_vec()).unwrap();
        let tris = mesh.triangles();
        let mut want = Vec::new();
        for f in 0..tris.len() {
            for g in f + 1..tris.len() {
                if tris[f].iter().any(|v| tris[g].contains(v)) {
                    continue;
                }
                let (a, b) = (mesh.triangle_points(f), mesh.triangle_points(g));
                let size = longest_edge_length(a).max(longest_edge_length(b));
                if triangle_overlap_depth(a, b) > SELF_INTERSECTION_TOLERANCE * size {
                    want.push([f as u32, g as u32]);
                }
            }
        }
        assert!(want.len() > 20, "the test needs crossings: {}", want.len());
        assert_eq!(self_intersections(&mesh), want);
    }

    #[test]
    fn touching_and_coplanar_triangles_do_not_count() {
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        // Corner of one triangle on the interior of the other (touching), and a coplanar
        // overlapping pair.
        let mesh = TriMesh::new(
            vec![
                p(0., 0., 0.),
                p(2., 0., 0.),
                p(0., 2., 0.),
                p(0.5, 0.5, 0.),
                p(1.5, 0.5, 1.),
                p(0.5, 1.5, 1.),
                p(0.2, 0.2, 0.),
                p(1.0, 0.2, 0.),
                p(0.2, 1.0, 0.),
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        )
        .unwrap();
        assert!(self_intersections(&mesh).is_empty());
        let coplanar = TriMesh::new(mesh.positions().to_vec(), vec![[0, 1, 2], [6, 7, 8]]).unwrap();
        assert!(self_intersections(&coplanar).is_empty());
    }
}

//! The hull's tetrahedra and the overlapping pairs among them (§3's intersection test): every
//! pair once for a new hull, and after a refinement round only the pairs with a new
//! tetrahedron.

use super::{Element, HullTetrahedron, Intersection, SimplicialHull};
use crate::overlap::{FacePlanes, common_diagonal, depth_until, tet_box};
use algesurf_mesh::morton::MortonBvh;
use glam::DVec3;
use rayon::prelude::*;

impl SimplicialHull {
    /// The tetrahedra of element `k`, positive before negative: face `k` for
    /// `k < faces().len()`, else edge `k − faces().len()`.
    fn element_tets(&self, k: usize) -> impl Iterator<Item = HullTetrahedron> + '_ {
        let nf = self.faces.len();
        let (element, sides) = if k < nf {
            let face = &self.faces[k];
            let of = |t: &Option<crate::FaceTetrahedron>| {
                t.as_ref().map(|t| (t.side, *t.tetrahedron.vertices()))
            };
            (
                Element::Face(k as u32),
                [of(&face.positive), of(&face.negative)],
            )
        } else {
            let edge = &self.edges[k - nf];
            let of = |t: &Option<crate::EdgeTetrahedron>| {
                t.as_ref().map(|t| (t.side, *t.tetrahedron.vertices()))
            };
            (
                Element::Edge((k - nf) as u32),
                [of(&edge.positive), of(&edge.negative)],
            )
        };
        sides
            .into_iter()
            .flatten()
            .map(move |(side, vertices)| HullTetrahedron {
                element,
                side,
                vertices,
            })
    }

    /// Every tetrahedron of Σ: face tetrahedra in face order (positive before negative), then
    /// edge tetrahedra in edge order.
    pub fn tetrahedra(&self) -> Vec<HullTetrahedron> {
        // Collected in parallel, in order (rayon keeps the sequence's order).
        (0..self.faces.len() + self.edges.len())
            .into_par_iter()
            .flat_map_iter(|k| self.element_tets(k))
            .collect()
    }

    /// Tetrahedron `s` (0 or 1: positive before negative) of element `k`, as numbered by
    /// [`SimplicialHull::element_tets`].
    fn element_tet(&self, (k, s): (u32, u8)) -> HullTetrahedron {
        self.element_tets(k as usize)
            .nth(s as usize)
            .expect("an element's tetrahedra are counted before they are named")
    }

    /// All pairs of tetrahedra of Σ whose interiors overlap by more than
    /// [`crate::HullOptions::overlap_tolerance`] — adjacent or not — ordered by their indices
    /// in [`SimplicialHull::tetrahedra`]. Candidate pairs come from a bounding-volume hierarchy
    /// over the tetrahedra's boxes; each candidate is decided by [`crate::overlap_depth`].
    /// Empty for a valid hull.
    pub fn intersections(&self) -> Vec<Intersection> {
        let tol = self.options.overlap_tolerance;
        // Each tetrahedron named by its element and its place there, in `tetrahedra()` order
        // (8 bytes each instead of the 112 of a listed tetrahedron: the list is 30 MB on the
        // bunny, and only the overlapping pairs are ever looked up by index).
        let ids: Vec<(u32, u8)> = (0..self.faces.len() + self.edges.len())
            .into_par_iter()
            .flat_map_iter(|k| (0..self.element_tets(k).count()).map(move |s| (k as u32, s as u8)))
            .collect();
        // One self-join of a tree over every box, in parallel, every pair tested once. The
        // vertices and face planes (computed once per tetrahedron: each takes part in ~40
        // candidate pairs on the bunny) are copied into the tree's Morton order, so that the
        // pairs of neighbouring leaves read neighbouring memory. Each pair is tested in the
        // order of its indices, `depth_until(lower, higher)`, whichever way the walk meets it.
        let bvh = MortonBvh::new(
            ids.par_iter()
                .map(|&id| tet_box(&self.element_tet(id).vertices))
                .collect(),
        );
        let order = bvh.order();
        let verts: Vec<[DVec3; 4]> = order
            .par_iter()
            .map(|&i| self.element_tet(ids[i as usize]).vertices)
            .collect();
        let planes: Vec<FacePlanes> = verts.par_iter().map(FacePlanes::of).collect();
        let mut pairs: Vec<(u32, u32, f64)> = bvh.slot_pairs(|a, b| {
            let (a, b) = if order[a] < order[b] { (a, b) } else { (b, a) };
            // The pair's common box from the two boxes the tree holds: the same corners
            // (min and max are exact) as from the eight vertices.
            let d = common_diagonal(bvh.slot_box(a), bvh.slot_box(b));
            let depth = depth_until(&verts[a], &planes[a], &verts[b], &planes[b], d, tol);
            (depth > tol).then_some((order[a], order[b], depth))
        });
        // Sorting makes the list (and the refinement driven by it) independent of the thread
        // count.
        pairs.sort_unstable_by_key(|&(a, b, _)| (a, b));
        pairs
            .into_iter()
            .map(|(a, b, depth)| Intersection {
                first: self.element_tet(ids[a as usize]),
                second: self.element_tet(ids[b as usize]),
                depth,
            })
            .collect()
    }

    /// The pairs of [`SimplicialHull::intersections`] that involve a tetrahedron of a face or
    /// edge marked fresh, in the same order, without listing every tetrahedron.
    ///
    /// Refinement rounds check only the new tetrahedra: those of an element that survived the
    /// round (`hull::PreviousRound`: a face with the same id and corners, an edge with two such
    /// faces) are that round's, reused, not rebuilt, and every pair of two such was checked
    /// then and did not overlap — had it overlapped, its faces would have been bisected,
    /// changing their corners (overlaps left alone as the input's are reported by
    /// [`SimplicialHull::distant_intersections`], which checks every pair).
    ///
    /// A tree over the fresh tetrahedra (a few hundred of the bunny's 270 k) is queried with
    /// every tetrahedron's box, each made from its element on the spot, so the 30 MB list of
    /// [`SimplicialHull::tetrahedra`] is not built each round; indices are counted per element.
    /// The face planes are computed per pair, as most tetrahedra take part in none.
    pub(crate) fn fresh_intersections(
        &self,
        fresh_faces: &[bool],
        fresh_edges: &[bool],
    ) -> Vec<Intersection> {
        let nf = self.faces.len();
        let n = nf + self.edges.len();
        let fresh = |k: usize| {
            if k < nf {
                fresh_faces[k]
            } else {
                fresh_edges[k - nf]
            }
        };
        // The index in `tetrahedra()` of each element's first tetrahedron.
        let counts: Vec<u32> = (0..n)
            .into_par_iter()
            .map(|k| self.element_tets(k).count() as u32)
            .collect();
        let first: Vec<u32> = counts
            .iter()
            .scan(0u32, |acc, &c| {
                let at = *acc;
                *acc += c;
                Some(at)
            })
            .collect();
        let first = &first;
        let indexed = |k: usize| {
            let at = first[k];
            self.element_tets(k)
                .enumerate()
                .map(move |(s, t)| (at + s as u32, t))
        };
        let marked: Vec<(u32, (DVec3, DVec3), HullTetrahedron)> = (0..n)
            .filter(|&k| fresh(k))
            .flat_map(indexed)
            .map(|(i, t)| (i, tet_box(&t.vertices), t))
            .collect();
        let items = (0..n).into_par_iter().flat_map_iter(|k| {
            indexed(k).map(move |(i, t)| (i, tet_box(&t.vertices), fresh(k), t))
        });
        let tol = self.options.overlap_tolerance;
        let mut pairs = MortonBvh::marked_pairs(&marked, items, |(i, a), (j, b)| {
            let (va, vb) = (&a.vertices, &b.vertices);
            let d = common_diagonal(&tet_box(va), &tet_box(vb));
            let depth = depth_until(va, &FacePlanes::of(va), vb, &FacePlanes::of(vb), d, tol);
            (depth > tol).then_some((
                i,
                j,
                Intersection {
                    first: *a,
                    second: *b,
                    depth,
                },
            ))
        });
        pairs.sort_unstable_by_key(|&(i, j, _)| (i, j));
        pairs.into_iter().map(|(_, _, hit)| hit).collect()
    }
}

#[cfg(test)]
mod tests {
    use crate::{HullOptions, SimplicialHull};
    use glam::DVec3;

    /// `fresh_intersections` is `intersections` restricted to the pairs with a marked
    /// element, in the same order with the same depths: on a coarse wave whose face
    /// tetrahedra overlap (built without the check, so the overlaps stay), with every element
    /// marked, with none, and with every third face and every second edge.
    #[test]
    fn fresh_intersections_are_the_intersections_with_a_fresh_element() {
        // z = ½ sin 4x sin 4y on a 2 × 2 grid over [−1, 1]², exact normals (the coarse wave
        // of `tests/refinement.rs`, whose face tetrahedra overlap with the paper's apexes).
        let n = 2;
        let (mut p, mut normals, mut t) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (
                    -1.0 + 2.0 * i as f64 / n as f64,
                    -1.0 + 2.0 * j as f64 / n as f64,
                );
                let (s, c) = ((4.0 * x).sin(), (4.0 * x).cos());
                let (sy, cy) = ((4.0 * y).sin(), (4.0 * y).cos());
                p.push(DVec3::new(x, y, 0.5 * s * sy));
                normals.push(DVec3::new(-2.0 * c * sy, -2.0 * s * cy, 1.0).normalize());
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let options = HullOptions {
            apex: crate::ApexPlacement::FaceNormal,
            max_refinement_rounds: 0,
            check_intersections: false,
            ..HullOptions::default()
        };
        let hull = SimplicialHull::new(&p, &t, &normals, &options).unwrap();
        let all = hull.intersections();
        assert!(all.len() > 3, "the test needs overlaps: {}", all.len());
        let (nf, ne) = (hull.faces().len(), hull.edges().len());
        for (faces, edges) in [
            (vec![true; nf], vec![true; ne]),
            (vec![false; nf], vec![false; ne]),
            (
                (0..nf).map(|f| f % 3 == 0).collect(),
                (0..ne).map(|e| e % 2 == 0).collect(),
            ),
        ] {
            let marked = |el: crate::Element| match el {
                crate::Element::Face(f) => faces[f as usize],
                crate::Element::Edge(e) => edges[e as usize],
            };
            let want: Vec<_> = all
                .iter()
                .filter(|h| marked(h.first.element) || marked(h.second.element))
                .copied()
                .collect();
            assert_eq!(hull.fresh_intersections(&faces, &edges), want);
        }
    }
}

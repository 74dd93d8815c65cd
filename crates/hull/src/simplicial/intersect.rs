//! The hull's tetrahedra and the overlapping pairs among them (§3's intersection test): every
//! pair once for a new hull, and after a refinement round only the pairs with a new
//! tetrahedron.

use super::{Element, HullTetrahedron, Intersection, SimplicialHull};
use crate::Side;
use crate::overlap::{FacePlanes, common_diagonal, depth_beyond, depth_until, tet_box};
use algesurf_mesh::Aabb;
use algesurf_mesh::morton::MortonBvh;
use glam::DVec3;
use rayon::prelude::*;

/// Tetrahedra per leaf of the overlap check's tree: a hull's tetrahedra overlap ~40 others'
/// boxes each, and larger leaves than the default four, with fewer nodes to visit, made the
/// bunny's hull faster: `hull_bunny` 594–659 → 569–616 ms fastest, the check alone
/// (`hull_intersections_bunny`) by 0–15 % (alternating divan runs of 4, 8 and 16 per leaf;
/// `docs/PERFORMANCE.md`, sixth pass).
const TET_LEAF_SIZE: usize = 16;

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
        self.check_every_pair().hits
    }

    /// [`SimplicialHull::intersections`], with the tree and the tetrahedra it was found with,
    /// for the refinement rounds to check their new tetrahedra against
    /// ([`SimplicialHull::fresh_intersections`]).
    pub(crate) fn indexed_intersections(&self) -> (Vec<Intersection>, TetIndex) {
        let checked = self.check_every_pair();
        let order = checked.tree.order();
        let keys = order
            .par_iter()
            .map(|&i| {
                let (k, s) = checked.ids[i as usize];
                self.tet_key(k as usize, self.element_tet((k, s)).side)
            })
            .collect();
        (
            checked.hits,
            TetIndex {
                tree: checked.tree,
                keys,
                verts: checked.verts,
                later: Vec::new(),
            },
        )
    }

    /// The work of [`SimplicialHull::intersections`], with what it was done on.
    fn check_every_pair(&self) -> EveryPair {
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
        let bvh = MortonBvh::with_leaf_size(
            ids.par_iter()
                .map(|&id| tet_box(&self.element_tet(id).vertices))
                .collect(),
            TET_LEAF_SIZE,
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
        let hits = pairs
            .into_iter()
            .map(|(a, b, depth)| Intersection {
                first: self.element_tet(ids[a as usize]),
                second: self.element_tet(ids[b as usize]),
                depth,
            })
            .collect();
        EveryPair {
            hits,
            tree: bvh,
            ids,
            verts,
        }
    }

    /// The round-independent name of element `k`'s tetrahedron on `side`.
    fn tet_key(&self, k: usize, side: Side) -> TetKey {
        let nf = self.faces.len();
        if k < nf {
            TetKey::Face(k as u32, side)
        } else {
            TetKey::Edge(self.edges[k - nf].vertices, side)
        }
    }

    /// The pairs of [`SimplicialHull::intersections`] that involve a tetrahedron of a face or
    /// edge marked fresh, in the same order, given the `index` of the first round's check
    /// (to which this adds the fresh tetrahedra).
    ///
    /// Refinement rounds check only the new tetrahedra: those of an element that survived the
    /// round (`hull::PreviousRound`: a face with the same id and corners, an edge with two such
    /// faces) are that round's, reused, not rebuilt, and every pair of two such was checked
    /// then and did not overlap — had it overlapped, its faces would have been bisected,
    /// changing their corners (overlaps left alone as the input's are reported by
    /// [`SimplicialHull::distant_intersections`], which checks every pair).
    ///
    /// Each fresh tetrahedron (a few hundred of the bunny's 270 k) is queried against the
    /// first round's tree and the tetrahedra later rounds made. A tetrahedron found there
    /// counts when its key (a face by id, an edge by its vertices, and the side) names a
    /// tetrahedron of this hull with the same four vertices: then it is that tetrahedron.
    /// Every tetrahedron of this hull is there, as it was made either by the first round or,
    /// fresh, by a later one. So a round costs the count of every element's tetrahedra (for
    /// their indices) and the fresh ones' queries, not a pass over every tetrahedron's box.
    pub(crate) fn fresh_intersections(
        &self,
        index: &mut TetIndex,
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
        // This hull's tetrahedron named by `key`, with its index.
        let topology = self.mesh.topology();
        let resolve = |key: TetKey| -> Option<(u32, HullTetrahedron)> {
            let (k, side) = match key {
                TetKey::Face(f, side) => ((f as usize) < nf).then_some((f as usize, side))?,
                TetKey::Edge([a, b], side) => (nf + topology.find_edge(a, b)? as usize, side),
            };
            self.element_tets(k)
                .enumerate()
                .find(|(_, t)| t.side == side)
                .map(|(s, t)| (first[k] + s as u32, t))
        };
        let new: Vec<(u32, HullTetrahedron)> = (0..n)
            .filter(|&k| fresh(k))
            .flat_map(|k| {
                self.element_tets(k)
                    .enumerate()
                    .map(move |(s, t)| (first[k] + s as u32, t))
            })
            .collect();
        index.later.extend(new.iter().map(|&(_, t)| {
            let k = match t.element {
                Element::Face(f) => f as usize,
                Element::Edge(e) => nf + e as usize,
            };
            (self.tet_key(k, t.side), t.vertices, aabb(&t.vertices))
        }));
        let tol = self.options.overlap_tolerance;
        let index = &*index;
        let mut pairs: Vec<(u32, u32, Intersection)> = new
            .par_iter()
            .map_init(Vec::new, |stack, &(i, t)| {
                let b = aabb(&t.vertices);
                let mut candidates: Vec<(TetKey, &[DVec3; 4])> = Vec::new();
                index
                    .tree
                    .overlapping_slots(&(b.min, b.max), stack, |slot| {
                        candidates.push((index.keys[slot], &index.verts[slot]));
                    });
                candidates.extend(
                    index
                        .later
                        .iter()
                        .filter(|(_, _, lb)| lb.overlaps(&b))
                        .map(|(key, v, _)| (*key, v)),
                );
                let mut out = Vec::new();
                for (key, v) in candidates {
                    let Some((j, u)) = resolve(key).filter(|(j, u)| *j != i && u.vertices == *v)
                    else {
                        continue;
                    };
                    let ((i, a), (j, b)) = if i < j {
                        ((i, t), (j, u))
                    } else {
                        ((j, u), (i, t))
                    };
                    let depth = depth_beyond(&a.vertices, &b.vertices, tol);
                    if depth > tol {
                        out.push((
                            i,
                            j,
                            Intersection {
                                first: a,
                                second: b,
                                depth,
                            },
                        ));
                    }
                }
                out
            })
            .flatten_iter()
            .collect();
        // A pair of two fresh tetrahedra is met from both; a tetrahedron can be listed twice
        // (a later round remade it as it was).
        pairs.sort_unstable_by_key(|&(i, j, _)| (i, j));
        pairs.dedup_by_key(|&mut (i, j, _)| (i, j));
        pairs.into_iter().map(|(_, _, hit)| hit).collect()
    }
}

/// What [`SimplicialHull::intersections`] found and what it worked on: the tree over every
/// tetrahedron's box, each tetrahedron as (element, place in the element) in `tetrahedra()`
/// order, and their vertices in the tree's slot order.
struct EveryPair {
    hits: Vec<Intersection>,
    tree: MortonBvh,
    ids: Vec<(u32, u8)>,
    verts: Vec<[DVec3; 4]>,
}

/// A hull tetrahedron named independently of the refinement round: a face by its id (which a
/// face keeps while it is not split), an edge by its vertices (edge ids are renumbered every
/// round), and the side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TetKey {
    Face(u32, Side),
    Edge([u32; 2], Side),
}

/// The first round's tree over every tetrahedron's box with each slot's key and vertices, and
/// the tetrahedra later rounds made (key, vertices, box), for
/// [`SimplicialHull::fresh_intersections`].
pub(crate) struct TetIndex {
    tree: MortonBvh,
    keys: Vec<TetKey>,
    verts: Vec<[DVec3; 4]>,
    later: Vec<(TetKey, [DVec3; 4], Aabb)>,
}

/// A tetrahedron's bounding box as an [`Aabb`] ([`tet_box`]'s corners).
fn aabb(v: &[DVec3; 4]) -> Aabb {
    let (min, max) = tet_box(v);
    Aabb { min, max }
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
        let (all, mut index) = hull.indexed_intersections();
        assert_eq!(all, hull.intersections());
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
            // The index gains the marked tetrahedra each time, as a round's would: the same
            // tetrahedra again, which must not give a pair twice.
            assert_eq!(hull.fresh_intersections(&mut index, &faces, &edges), want);
        }
    }
}

//! The hull's tetrahedra and the overlapping pairs among them (§3's intersection test): every
//! pair once for a new hull, and after a refinement round only the pairs with a new
//! tetrahedron.

use super::rounds::{Overlap, Part, RoundTet};
use super::{Element, HullTetrahedron, Intersection, SimplicialHull};
use crate::Side;
use crate::overlap::{FacePlanes, common_diagonal, depth_beyond, depth_until, tet_box};
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
    /// ([`TetIndex::overlaps_of`]).
    pub(crate) fn indexed_intersections(&self) -> (Vec<Intersection>, TetIndex) {
        let checked = self.check_every_pair();
        (
            checked.hits,
            TetIndex {
                trees: vec![Indexed {
                    tree: checked.tree,
                    keys: checked.keys,
                    verts: checked.verts,
                }],
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
        // Each tetrahedron's vertices and key in one pass over the tree's order, which reads
        // the face and edge records at random (the keys' own pass was 15–20 ms on the bunny).
        let (verts, keys): (Vec<[DVec3; 4]>, Vec<TetKey>) = order
            .par_iter()
            .map(|&i| {
                let (k, s) = ids[i as usize];
                let t = self.element_tet((k, s));
                (t.vertices, self.tet_key(k as usize, t.side))
            })
            .unzip();
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
            keys,
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
}

/// What [`SimplicialHull::intersections`] found and what it worked on: the tree over every
/// tetrahedron's box, and each tetrahedron's key and vertices in the tree's slot order.
struct EveryPair {
    hits: Vec<Intersection>,
    tree: MortonBvh,
    keys: Vec<TetKey>,
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

/// A tree over tetrahedra's boxes with each slot's key and vertices.
struct Indexed {
    tree: MortonBvh,
    keys: Vec<TetKey>,
    verts: Vec<[DVec3; 4]>,
}

/// Every tetrahedron made so far, for [`TetIndex::overlaps_of`]: the first round's tree over
/// every tetrahedron of the hull, then one tree per later round over the tetrahedra it made.
///
/// A tree per round, not a list: Suzanne's 17 rounds make 5 272 splits, and scanning a list
/// of every tetrahedron made since for each new one was 80 % of its `perf` samples (the
/// hull took 9–11 s).
pub(crate) struct TetIndex {
    trees: Vec<Indexed>,
}

impl TetIndex {
    /// The overlaps of the tetrahedra `new` (made by a refinement round, in
    /// [`RoundTet::order`]) with every tetrahedron of the hull, each pair once, in that order;
    /// `new` joins the index.
    ///
    /// Each new tetrahedron (a few hundred of the bunny's 270 k) is queried against the first
    /// round's tree and the tetrahedra later rounds made. A tetrahedron found there counts
    /// when `resolve` (the hull as it is now) gives a tetrahedron with the same name (a face
    /// by id, an edge by its vertices, and the side) and the same four vertices: then it is
    /// that tetrahedron. Every tetrahedron of the hull is there, as it was made either by the
    /// first round or by a later one; every pair of two tetrahedra that are not new was
    /// checked when the later of them was made, and did not overlap (had it overlapped, its
    /// faces would have been bisected, changing their corners; overlaps left alone as the
    /// input's are reported by [`SimplicialHull::distant_intersections`], which checks every
    /// pair).
    pub(crate) fn overlaps_of(
        &mut self,
        new: &[RoundTet],
        resolve: impl Fn(TetKey) -> Option<RoundTet> + Sync,
        tol: f64,
    ) -> Vec<Overlap> {
        let name = |t: &RoundTet| match t.part {
            Part::Face(f) => TetKey::Face(f, t.side),
            Part::Edge { vertices, .. } => TetKey::Edge(vertices, t.side),
        };
        if !new.is_empty() {
            let tree = MortonBvh::with_leaf_size(
                new.iter().map(|t| tet_box(&t.vertices)).collect(),
                TET_LEAF_SIZE,
            );
            let order = tree.order();
            let keys = order.iter().map(|&i| name(&new[i as usize])).collect();
            let verts = order.iter().map(|&i| new[i as usize].vertices).collect();
            self.trees.push(Indexed { tree, keys, verts });
        }
        let trees = &self.trees;
        let mut pairs: Vec<Overlap> = new
            .par_iter()
            .map_init(Vec::new, |stack, t| {
                let b = tet_box(&t.vertices);
                let mut candidates: Vec<(TetKey, &[DVec3; 4])> = Vec::new();
                for indexed in trees {
                    indexed.tree.overlapping_slots(&b, stack, |slot| {
                        candidates.push((indexed.keys[slot], &indexed.verts[slot]));
                    });
                }
                let mut out = Vec::new();
                for (key, v) in candidates {
                    let Some(u) =
                        resolve(key).filter(|u| u.order() != t.order() && u.vertices == *v)
                    else {
                        continue;
                    };
                    let (first, second) = if t.order() < u.order() {
                        (*t, u)
                    } else {
                        (u, *t)
                    };
                    let depth = depth_beyond(&first.vertices, &second.vertices, tol);
                    if depth > tol {
                        out.push(Overlap {
                            first,
                            second,
                            depth,
                        });
                    }
                }
                out
            })
            .flatten_iter()
            .collect();
        // A pair of two new tetrahedra is met from both; a tetrahedron can be listed twice
        // (a later round remade it as it was).
        let orders = |o: &Overlap| (o.first.order(), o.second.order());
        pairs.sort_unstable_by_key(orders);
        pairs.dedup_by_key(|o| orders(o));
        pairs
    }
}

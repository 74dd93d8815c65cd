//! The hull's tetrahedra and the overlapping pairs among them (§3's intersection test): every
//! pair once for a new hull, and after a refinement round only the pairs with a new
//! tetrahedron.

use super::rounds::{Overlap, RoundTet};
use super::{Element, HullTetrahedron, Intersection, SimplicialHull};
use crate::Side;
use crate::overlap::{FacePlanes, common_diagonal, depth_above, tet_box};
use crate::refine::key;
use algesurf_bb::Tetrahedron;
use algesurf_mesh::morton::MortonBvh;
use algesurf_mesh::progress::{Cancelled, NoProgress, Progress};
use glam::DVec3;
use rayon::prelude::*;

/// Tetrahedra per leaf of the overlap check's tree: a hull's tetrahedra overlap ~40 others'
/// boxes each, and larger leaves than the default four, with fewer nodes to visit, made the
/// bunny's hull faster: `hull_bunny` 594–659 → 569–616 ms fastest, the check alone
/// (`hull_intersections_bunny`) by 0–15 % (alternating divan runs of 4, 8 and 16 per leaf;
/// `docs/PERFORMANCE.md`, sixth pass).
const TET_LEAF_SIZE: usize = 16;

/// Tetrahedron `s` (0 or 1) of an element's sides, positive before negative: the numbering
/// of [`SimplicialHull::element_tets`], which lists the present ones.
fn nth_side(sides: [Option<(Side, &Tetrahedron)>; 2], s: u8) -> (Side, &Tetrahedron) {
    match sides {
        [Some(p), Some(n)] => {
            if s == 0 {
                p
            } else {
                n
            }
        }
        [Some(t), None] | [None, Some(t)] => t,
        [None, None] => unreachable!("an element's tetrahedra are counted before they are named"),
    }
}

impl SimplicialHull {
    /// Element `k` (face `k` for `k < faces().len()`, else edge `k − faces().len()`) and its
    /// tetrahedra by reference, `[positive, negative]`: the one place that reads the records,
    /// for listing, naming and counting them.
    fn element_sides(&self, k: usize) -> (Element, [Option<(Side, &Tetrahedron)>; 2]) {
        let nf = self.faces.len();
        if k < nf {
            let f = &self.faces[k];
            (
                Element::Face(k as u32),
                [
                    f.positive.as_ref().map(|t| (t.side, &t.tetrahedron)),
                    f.negative.as_ref().map(|t| (t.side, &t.tetrahedron)),
                ],
            )
        } else {
            let e = &self.edges[k - nf];
            (
                Element::Edge((k - nf) as u32),
                [
                    e.positive.as_ref().map(|t| (t.side, &t.tetrahedron)),
                    e.negative.as_ref().map(|t| (t.side, &t.tetrahedron)),
                ],
            )
        }
    }

    /// Tetrahedron `s` of element `k` (0 or 1: positive before negative, as numbered by
    /// [`SimplicialHull::element_tets`]) and its side, by reference.
    ///
    /// The overlap check reads each tetrahedron twice through this (for its box, then for
    /// its vertices in the tree's order). Through [`SimplicialHull::element_tet`] as it was
    /// (`element_tets(k).nth(s)`, a listed tetrahedron built and copied), the second read
    /// took 22 ms of the bunny's check; by reference it takes 13 ms (two threads).
    fn element_side(&self, k: usize, s: u8) -> (Side, &Tetrahedron) {
        nth_side(self.element_sides(k).1, s)
    }

    /// The tetrahedra of element `k`, positive before negative (see
    /// [`SimplicialHull::element_sides`]). Each one's vertices are copied only when it is
    /// yielded.
    fn element_tets(&self, k: usize) -> impl Iterator<Item = HullTetrahedron> + '_ {
        let (element, sides) = self.element_sides(k);
        sides
            .into_iter()
            .flatten()
            .map(move |(side, t)| HullTetrahedron {
                element,
                side,
                vertices: *t.vertices(),
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
        let (element, sides) = self.element_sides(k as usize);
        let (side, t) = nth_side(sides, s);
        HullTetrahedron {
            element,
            side,
            vertices: *t.vertices(),
        }
    }

    /// How many tetrahedra element `k` has (0, 1 or 2).
    fn element_tet_count(&self, k: usize) -> usize {
        self.element_sides(k).1.iter().flatten().count()
    }

    /// All pairs of tetrahedra of Σ whose interiors overlap by more than
    /// [`crate::HullOptions::overlap_tolerance`] — adjacent or not — ordered by their indices
    /// in [`SimplicialHull::tetrahedra`]. Candidate pairs come from a bounding-volume hierarchy
    /// over the tetrahedra's boxes; each candidate is decided by [`crate::overlap_depth`].
    /// Empty for a valid hull.
    pub fn intersections(&self) -> Vec<Intersection> {
        // `NoProgress` never asks to stop.
        self.check_every_pair(&NoProgress)
            .map(|checked| checked.hits)
            .unwrap_or_default()
    }

    /// [`SimplicialHull::intersections`], with the tree and the tetrahedra it was found with,
    /// for the refinement rounds to check their new tetrahedra against
    /// ([`TetIndex::overlaps_of`]).
    pub(crate) fn indexed_intersections(
        &self,
        progress: &dyn Progress,
    ) -> Result<(Vec<Intersection>, TetIndex), Cancelled> {
        let checked = self.check_every_pair(progress)?;
        Ok((
            checked.hits,
            TetIndex {
                first: Indexed {
                    tree: checked.tree,
                    keys: checked.keys,
                    verts: checked.verts,
                    planes: checked.planes,
                },
                later_tree: None,
            },
        ))
    }

    /// The work of [`SimplicialHull::intersections`], with what it was done on; the step
    /// "hull: overlap check" of `progress`, counted in tetrahedra.
    fn check_every_pair(&self, progress: &dyn Progress) -> Result<EveryPair, Cancelled> {
        let tol = self.options.overlap_tolerance;
        // Each tetrahedron named by its element and its place there, in `tetrahedra()` order
        // (8 bytes each instead of the 112 of a listed tetrahedron: the list is 30 MB on the
        // bunny, and only the overlapping pairs are ever looked up by index).
        let ids: Vec<(u32, u8)> = (0..self.faces.len() + self.edges.len())
            .into_par_iter()
            .flat_map_iter(|k| (0..self.element_tet_count(k)).map(move |s| (k as u32, s as u8)))
            .collect();
        // Started here: the tree and the tetrahedra's data below take a fifth of the step.
        progress.start("hull: overlap check", ids.len() as u64);
        // One self-join of a tree over every box, in parallel, every pair tested once. The
        // vertices and face planes (computed once per tetrahedron: each takes part in ~40
        // candidate pairs on the bunny) are copied into the tree's Morton order, so that the
        // pairs of neighbouring leaves read neighbouring memory. Each pair is tested in the
        // order of its indices, `depth_above(lower, higher)`, whichever way the walk meets it.
        let bvh = MortonBvh::with_leaf_size(
            ids.par_iter()
                .map(|&(k, s)| tet_box(self.element_side(k as usize, s).1.vertices()))
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
                let (side, t) = self.element_side(k as usize, s);
                (*t.vertices(), self.tet_key(k as usize, side))
            })
            .unzip();
        let planes: Vec<FacePlanes> = verts.par_iter().map(FacePlanes::of).collect();
        // Only pairs whose boxes share interior points: two tetrahedra whose boxes merely
        // touch (meet in one value along an axis) are separated by that coordinate plane, so
        // their interiors are disjoint and `depth_until` could only answer ≤ 0 up to its
        // rounding (≤ 1e-17 on the bunny, against the tolerance's 1e-9), i.e. "touching".
        // That is 2.84 M of the bunny's 5.33 M candidate pairs: tetrahedra sharing a vertex
        // that is the highest of one and the lowest of the other along some axis.
        let pairs = bvh.interior_slot_pairs_with_progress(
            |a, b| {
                let (a, b) = if order[a] < order[b] { (a, b) } else { (b, a) };
                // The pair's common box from the two boxes the tree holds: the same corners
                // (min and max are exact) as from the eight vertices.
                let d = common_diagonal(bvh.slot_box(a), bvh.slot_box(b));
                depth_above(&verts[a], &planes[a], &verts[b], &planes[b], d, tol)
                    .map(|depth| (order[a], order[b], depth))
            },
            progress,
        );
        let mut pairs: Vec<(u32, u32, f64)> = pairs?;
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
        Ok(EveryPair {
            hits,
            tree: bvh,
            keys,
            verts,
            planes,
        })
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
/// tetrahedron's box, and each tetrahedron's key, vertices and face planes in the tree's slot
/// order.
struct EveryPair {
    hits: Vec<Intersection>,
    tree: MortonBvh,
    keys: Vec<TetKey>,
    verts: Vec<[DVec3; 4]>,
    planes: Vec<FacePlanes>,
}

/// A hull tetrahedron named independently of the refinement round: a face by its id (which a
/// face keeps while it is not split), an edge by its vertices (edge ids are renumbered every
/// round), and the side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TetKey {
    Face(u32, Side),
    Edge([u32; 2], Side),
}

impl TetKey {
    /// The tetrahedron's place in the whole hull's numbering (`SimplicialHull::tetrahedra`):
    /// faces by id, then edges in the topology's order (by their `[smaller, larger]` vertex
    /// ids), the positive tetrahedron of an element before the negative.
    pub(crate) fn order(&self) -> (u8, u64, u8) {
        let rank = |side: Side| (side == Side::Negative) as u8;
        match *self {
            TetKey::Face(f, side) => (0, f as u64, rank(side)),
            TetKey::Edge([a, b], side) => {
                let [lo, hi] = key(a, b);
                (1, (lo as u64) << 32 | hi as u64, rank(side))
            }
        }
    }
}

/// A tree over tetrahedra's boxes with each slot's key, vertices and face planes.
struct Indexed {
    tree: MortonBvh,
    keys: Vec<TetKey>,
    verts: Vec<[DVec3; 4]>,
    planes: Vec<FacePlanes>,
}

impl Indexed {
    /// The tree over `tets` (key, vertices, face planes), copied into its slot order.
    ///
    /// The boxes and the copies in parallel: a later round rebuilds this over every
    /// tetrahedron the rounds made (~250 bytes each, tens of thousands by Suzanne's last
    /// rounds), and on one core that was most of the main thread's work while the other waited
    /// (`perf`: about 0.1 s of Suzanne's 0.9 s hull stage, in `overlaps_of`).
    fn over(tets: &[(TetKey, [DVec3; 4], FacePlanes)]) -> Indexed {
        Indexed::over_with(tets.len(), |i| tets[i])
    }

    /// [`Indexed::over`] the `n` tetrahedra `entry(0..n)`, read where they are (a later
    /// round's tree is made from the last one's and the new tetrahedra).
    fn over_with(
        n: usize,
        entry: impl Fn(usize) -> (TetKey, [DVec3; 4], FacePlanes) + Sync,
    ) -> Indexed {
        let boxes = (0..n)
            .into_par_iter()
            .with_min_len(GATHER_GRAIN)
            .map(|i| tet_box(&entry(i).1))
            .collect();
        let tree = MortonBvh::with_leaf_size(boxes, TET_LEAF_SIZE);
        let (keys, (verts, planes)) = tree
            .order()
            .par_iter()
            .with_min_len(GATHER_GRAIN)
            .map(|&i| {
                let (key, verts, planes) = entry(i as usize);
                (key, (verts, planes))
            })
            .unzip();
        Indexed {
            keys,
            verts,
            planes,
            tree,
        }
    }

    /// Slot `s`'s key, vertices and face planes.
    fn entry(&self, s: usize) -> (TetKey, [DVec3; 4], FacePlanes) {
        (self.keys[s], self.verts[s], self.planes[s])
    }

    fn len(&self) -> usize {
        self.keys.len()
    }
}

/// Tetrahedra a thread takes at least, in the index's parallel gathers: each is a few hundred
/// bytes to copy or a box to compute, so smaller pieces would cost more in scheduling.
const GATHER_GRAIN: usize = 1024;

/// Every tetrahedron of the hull, for [`TetIndex::overlaps_of`]: the first round's tree over
/// every tetrahedron it made (which may go on listing those later rounds replace), and a tree
/// over the current tetrahedra later rounds made, made again by each round (a few thousand on
/// the bunny, up to ~40 k on Suzanne, where the first round's join them in the second round).
///
/// Each tetrahedron's face planes are kept with it, computed once. Scanning a list of the
/// later tetrahedra for each new one was 80 % of Suzanne's `perf` samples (the hull took
/// 9–11 s); one tree per round still left 17 trees to descend per query, and computing both
/// tetrahedra's planes for every candidate pair was another 14 %.
pub(crate) struct TetIndex {
    first: Indexed,
    later_tree: Option<Indexed>,
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
        if new.is_empty() {
            return Vec::new();
        }
        // Each new tetrahedron's planes, once: for the index and for its own queries.
        let new_planes: Vec<FacePlanes> = new
            .par_iter()
            .with_min_len(GATHER_GRAIN)
            .map(|t| FacePlanes::of(&t.vertices))
            .collect();
        // The later rounds' tree is made again over the tetrahedra it listed, less those a
        // round since has replaced, and the new ones. The replaced leave because the
        // queries below would skip them (`resolve` names a tetrahedron with other vertices,
        // or none), and a replaced one stays replaced (a tetrahedron remade as it was is
        // listed again, in `new`); refinement replaces tetrahedra where it refines again, so
        // they piled up where the queries look: over Suzanne's 17 rounds 8 of every 11
        // candidates were replaced ones. Once the first round's tree holds no more
        // tetrahedra than the later rounds', its tetrahedra join theirs, to leave the same
        // way (Suzanne's first 3 750, all replaced within a few rounds, were still 1.9 M of
        // the 4.9 M candidates left); the bunny's 270 k stay in their tree. The survivors are
        // found in parallel and read from the old trees where they are: keeping them in a
        // list of their own, pruned and grown every round, was 11–20 % of the main thread's
        // samples.
        let old = self.later_tree.take();
        let later_len = old.as_ref().map_or(0, Indexed::len);
        let first = (self.first.len() <= later_len + new.len())
            .then(|| std::mem::replace(&mut self.first, Indexed::over(&[])));
        let empty = Indexed::over(&[]);
        let current = |ix: &Indexed| -> Vec<u32> {
            (0..ix.len() as u32)
                .into_par_iter()
                .with_min_len(GATHER_GRAIN)
                .filter(|&s| {
                    let (key, v) = (ix.keys[s as usize], &ix.verts[s as usize]);
                    resolve(key).is_some_and(|u| u.vertices == *v)
                })
                .collect()
        };
        let (old, first) = (
            old.as_ref().unwrap_or(&empty),
            first.as_ref().unwrap_or(&empty),
        );
        let (kept_old, kept_first) = (current(old), current(first));
        let (a, b) = (kept_old.len(), kept_old.len() + kept_first.len());
        self.later_tree = Some(Indexed::over_with(b + new.len(), |i| {
            if i < a {
                old.entry(kept_old[i] as usize)
            } else if i < b {
                first.entry(kept_first[i - a] as usize)
            } else {
                let k = i - b;
                (new[k].key(), new[k].vertices, new_planes[k])
            }
        }));
        // Each tree with whether every tetrahedron it lists is the hull's: the later rounds'
        // list was just pruned to those (and queries only run when it was), so its candidates
        // need no look-up unless they overlap; the first round's tree may still list
        // replaced ones.
        let trees: Vec<(&Indexed, bool)> = std::iter::once((&self.first, false))
            .chain(self.later_tree.iter().map(|t| (t, true)))
            .collect();
        let mut pairs: Vec<Overlap> = new
            .par_iter()
            .zip(&new_planes)
            .map_init(Vec::new, |stack, (t, planes)| {
                let order = t.key().order();
                let b = tet_box(&t.vertices);
                let mut out = Vec::new();
                for &(indexed, all_current) in &trees {
                    indexed.tree.overlapping_slots(&b, stack, |slot| {
                        let (key, v) = (indexed.keys[slot], &indexed.verts[slot]);
                        let other = key.order();
                        if other == order {
                            return; // t itself, as listed when it was made
                        }
                        // A listed tetrahedron counts if it is still the hull's: the hull's
                        // own with the same name has the same vertices. Checked before the
                        // overlap where the tree may list replaced ones, which overlap their
                        // replacements (Suzanne's hull took 50 % longer with the overlap
                        // computed first); after it, for an overlap only, where every listed
                        // one is current (the look-ups were an eighth of Suzanne's samples).
                        let current = || resolve(key).filter(|u| u.vertices == *v);
                        let checked = if all_current { None } else { current() };
                        if !all_current && checked.is_none() {
                            return;
                        }
                        // `depth_beyond` of the pair in order, with the planes at hand.
                        let ((va, pa), (vb, pb)) = if order < other {
                            ((&t.vertices, planes), (v, &indexed.planes[slot]))
                        } else {
                            ((v, &indexed.planes[slot]), (&t.vertices, planes))
                        };
                        let d = common_diagonal(&tet_box(va), &tet_box(vb));
                        let Some(depth) = depth_above(va, pa, vb, pb, d, tol) else {
                            return;
                        };
                        let Some(u) = checked.or_else(current) else {
                            return;
                        };
                        let (first, second) = if order < other { (*t, u) } else { (u, *t) };
                        out.push(Overlap {
                            first,
                            second,
                            depth,
                        });
                    });
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simplicial::rounds::Part;

    /// The positive tetrahedron of face `f`: a corner of the unit cube at `at`.
    fn tet(f: u32, at: DVec3) -> RoundTet {
        RoundTet {
            part: Part::Face(f),
            side: Side::Positive,
            vertices: [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z].map(|v| v + at),
        }
    }

    /// A refinement round on `hull` (the tetrahedra as they are now): `made` replace those of
    /// their faces or join them, and the index answers their overlaps, as pairs of faces.
    fn round(index: &mut TetIndex, hull: &mut Vec<RoundTet>, made: &[RoundTet]) -> Vec<[u32; 2]> {
        for t in made {
            hull.retain(|h| h.key() != t.key());
            hull.push(*t);
        }
        let now = hull.clone();
        let resolve = |k: TetKey| now.iter().find(|t| t.key() == k).copied();
        let face = |t: &RoundTet| match t.part {
            Part::Face(f) => f,
            Part::Edge { .. } => unreachable!("faces only"),
        };
        index
            .overlaps_of(made, resolve, 1e-9)
            .iter()
            .map(|o| [face(&o.first), face(&o.second)])
            .collect()
    }

    /// A round's new tetrahedra meet every tetrahedron of the hull as it is now: the first
    /// round's, those of earlier later rounds, each other; never one a round has replaced,
    /// although the index listed it. Four first-round tetrahedra, then rounds of two, so that
    /// the first round's join the later rounds' list (and are pruned with it) from the second.
    #[test]
    fn new_tetrahedra_meet_the_hull_as_it_is_now() {
        let at = |x: f64| DVec3::new(x, 0.0, 0.0);
        let mut hull: Vec<RoundTet> = (0..4).map(|f| tet(f, at(10.0 * f as f64))).collect();
        let entries: Vec<_> = hull
            .iter()
            .map(|t| (t.key(), t.vertices, FacePlanes::of(&t.vertices)))
            .collect();
        let mut index = TetIndex {
            first: Indexed::over(&entries),
            later_tree: None,
        };
        let nudge = DVec3::new(0.1, 0.1, 0.1);
        // Face 4 overlaps face 0 (first round); face 5 lies apart, at 100.
        assert_eq!(
            round(&mut index, &mut hull, &[tet(4, nudge), tet(5, at(100.0))]),
            [[0, 4]]
        );
        assert_eq!(index.first.keys.len(), 4, "not yet joined");
        // Face 5 moves to 200 and face 1 (first round) to 300. Then face 6 lies where face 5
        // was, and face 7 on the moved face 5, an earlier later round's, not new.
        let made = [tet(5, at(200.0)), tet(1, at(300.0))];
        assert_eq!(round(&mut index, &mut hull, &made), Vec::<[u32; 2]>::new());
        assert!(index.first.keys.is_empty(), "joined the later rounds' list");
        let made = [tet(6, at(100.0) + nudge), tet(7, at(200.0) + nudge)];
        assert_eq!(round(&mut index, &mut hull, &made), [[5, 7]]);
        let made = [
            tet(8, at(10.0) + nudge),
            tet(9, at(30.0) + nudge),
            tet(10, nudge),
        ];
        // Face 8 lies where face 1 was, face 9 on face 3 (first round, now in the list),
        // face 10 on faces 0 and 4 (pairs of two old tetrahedra are not the round's).
        assert_eq!(
            round(&mut index, &mut hull, &made),
            [[0, 10], [3, 9], [4, 10]]
        );
        // Replaced tetrahedra left the list: 4 + 2 + 2 + 2 + 3 listed, 11 of the hull.
        assert_eq!(
            index.later_tree.as_ref().map_or(0, Indexed::len),
            hull.len()
        );
    }
}

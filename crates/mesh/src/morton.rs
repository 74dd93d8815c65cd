//! A linear bounding-volume hierarchy over axis-aligned boxes for finding the pairs that
//! overlap (never all pairs): the simplicial hull's candidate pairs of tetrahedra
//! (`algesurf-hull`) and a mesh's candidate pairs of crossing faces ([`crate::self_intersections`]).
//! Built in one parallel sort and a parallel split pass; for queries of the closest point or a
//! ray, whose trees are built once and walked millions of times, [`crate::BoxBvh`] (a
//! surface-area-optimised tree) is the better tree.
//!
//! ```
//! use algesurf_mesh::morton::MortonBvh;
//! use glam::DVec3;
//! let unit = |x: f64| (DVec3::splat(x), DVec3::splat(x + 1.0));
//! let tree = MortonBvh::new(vec![unit(0.0), unit(0.5), unit(3.0)]);
//! // Pairs by slot, mapped to box ids.
//! let mut pairs = tree.slot_pairs(|a, b| {
//!     let (i, j) = (tree.order()[a], tree.order()[b]);
//!     Some((i.min(j), i.max(j)))
//! });
//! pairs.sort();
//! assert_eq!(pairs, vec![(0, 1)]);
//! ```

use crate::progress::{Cancelled, NoProgress, Progress, UnitTally};
use crate::self_join::{JoinTree, self_join_leaves};
use glam::DVec3;
use rayon::prelude::*;

/// Boxes per leaf of [`MortonBvh::new`]: for faces, whose boxes overlap only their
/// neighbours'. Trees over boxes that overlap many others (a hull's tetrahedra) join faster
/// with larger leaves ([`MortonBvh::with_leaf_size`]).
pub const DEFAULT_LEAF_SIZE: usize = 4;

/// Subtrees over more slots than this are built in parallel with their siblings
/// ([`MortonBvh::build`]): 16 k slots are ~1 ms of serial build, well above rayon's cost of a
/// join, and leave 16 parallel subtrees on the bunny's 270 k tetrahedra.
const PARALLEL_SLOTS: usize = 1 << 14;

#[derive(Debug, PartialEq)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: range into `order`; inner: children.
    kind: Kind,
}

#[derive(Debug, PartialEq)]
enum Kind {
    Leaf(usize, usize),
    Inner(usize, usize),
}

/// An AABB tree over boxes in Morton order (a linear BVH: Lauterbach et al., "Fast BVH
/// Construction on GPUs", 2009). Sorting the box centres along the Z-order curve and splitting
/// each range where its codes first differ builds the tree in one sort and one linear pass,
/// instead of a selection per level over randomly placed boxes; the splits are spatial
/// midpoints (octree cells), which for a surface's tetrahedra give boxes as tight as median
/// splits do. Rebuilt every refinement round over 350 k tetrahedra (the bunny), the build cost
/// 150 ms with median splits.
pub struct MortonBvh {
    /// The boxes in Morton order (`sorted[k]` is box `order[k]`), so that a leaf's boxes, and
    /// the leaves a walk meets together, lie next to each other in memory.
    sorted: Vec<(DVec3, DVec3)>,
    /// Box ids in Morton order; leaves are ranges of it (of "slots").
    order: Vec<u32>,
    /// Morton code of `order[k]`.
    codes: Vec<u64>,
    nodes: Vec<Node>,
    /// Most boxes in a leaf.
    leaf: usize,
}

fn overlaps(a: &(DVec3, DVec3), lo: DVec3, hi: DVec3) -> bool {
    // `&`, not `&&`: six comparisons without a branch between them.
    (a.0.x <= hi.x)
        & (a.0.y <= hi.y)
        & (a.0.z <= hi.z)
        & (lo.x <= a.1.x)
        & (lo.y <= a.1.y)
        & (lo.z <= a.1.z)
}

/// Whether the interiors of two boxes intersect: [`overlaps`] less the boxes that only touch
/// (their intervals meet in one point along some axis), with which a plane `x_k = const`
/// separates the two boxes' contents.
fn interiors_overlap(a: &(DVec3, DVec3), lo: DVec3, hi: DVec3) -> bool {
    (a.0.x < hi.x)
        & (a.0.y < hi.y)
        & (a.0.z < hi.z)
        & (lo.x < a.1.x)
        & (lo.y < a.1.y)
        & (lo.z < a.1.z)
}

/// The mask of the boxes of `boxes` (at most 64) that `hit` `b`: bit `j` for `boxes[j]`.
/// Every box is tested, with no branch on the outcome.
#[inline(always)]
fn hits_of(
    b: &(DVec3, DVec3),
    boxes: &[(DVec3, DVec3)],
    hit: &impl Fn(&(DVec3, DVec3), DVec3, DVec3) -> bool,
) -> u64 {
    debug_assert!(boxes.len() <= 64);
    let mut mask = 0u64;
    for (j, x) in boxes.iter().enumerate() {
        mask |= u64::from(hit(b, x.0, x.1)) << j;
    }
    mask
}

/// The positions of the set bits of `mask`, lowest first.
#[inline(always)]
fn set_bits(mut mask: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let j = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            j
        })
    })
}

/// Bits per axis of a Morton code: 21 × 3 fit in a `u64`.
const MORTON_BITS: u32 = 21;

/// `x`'s low 21 bits spread to every third bit.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | (x << 32)) & 0x1f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x1f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// The cells of a Morton code: the bounding box of some points cut into 2^21 slabs per axis.
struct MortonGrid {
    lo: DVec3,
    scale: [f64; 3],
}

impl MortonGrid {
    /// The grid over the bounding box of `points`.
    fn around(points: impl Iterator<Item = DVec3>) -> MortonGrid {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for c in points {
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let cells = ((1u64 << MORTON_BITS) - 1) as f64;
        // Zero extents (all centres on a plane) give a zero scale, not a division by zero.
        let scale = (hi - lo)
            .to_array()
            .map(|e| if e > 0.0 { cells / e } else { 0.0 });
        MortonGrid { lo, scale }
    }

    /// The Morton code of `p`'s cell: its three cell coordinates' bits interleaved.
    fn code(&self, p: DVec3) -> u64 {
        let cells = (1u64 << MORTON_BITS) - 1;
        let c = (p - self.lo).to_array();
        // Non-finite points land in cell 0 (`as` saturates; NaN gives 0).
        let q = |k: usize| ((c[k] * self.scale[k]) as u64).min(cells);
        spread(q(0)) | (spread(q(1)) << 1) | (spread(q(2)) << 2)
    }
}

/// The ids of `points` sorted along the Z-order (Morton) curve through their bounding box,
/// ties broken by id: points near each other on the curve are near each other in space, so
/// data stored in this order is read with fewer cache misses by a walk that goes from
/// neighbour to neighbour. Deterministic (the same order in parallel and in series).
///
/// ```
/// use algesurf_mesh::morton::morton_order;
/// use glam::DVec3;
/// let points = [DVec3::splat(1.0), DVec3::ZERO, DVec3::splat(0.9), DVec3::splat(0.1)];
/// assert_eq!(morton_order(&points), vec![1, 3, 2, 0]);
/// ```
pub fn morton_order(points: &[DVec3]) -> Vec<u32> {
    let grid = MortonGrid::around(points.iter().copied());
    let keyed_at = |i: usize| (grid.code(points[i]), i as u32);
    let mut keyed: Vec<(u64, u32)> = if points.len() < crate::parallel::SERIAL_BELOW {
        (0..points.len()).map(keyed_at).collect()
    } else {
        (0..points.len()).into_par_iter().map(keyed_at).collect()
    };
    // The radix sort: ids are numbered in order, so ties keep the order of ids.
    crate::radix::sort_pairs(&mut keyed);
    keyed.into_iter().map(|k| k.1).collect()
}

impl MortonBvh {
    /// Builds the tree over `boxes` (`(min, max)` corners), at most
    /// [`DEFAULT_LEAF_SIZE`] boxes per leaf.
    pub fn new(boxes: Vec<(DVec3, DVec3)>) -> MortonBvh {
        MortonBvh::with_leaf_size(boxes, DEFAULT_LEAF_SIZE)
    }

    /// [`MortonBvh::new`] with at most `leaf` boxes per leaf (1 when 0 is given). The pairs a
    /// walk finds do not depend on it, only the work: a leaf's boxes are tested against each
    /// other, and against the boxes of an overlapping leaf (up to 64 boxes a leaf, only those
    /// of each leaf that meet the other's bounding box; larger leaves box by box), so larger
    /// leaves trade node visits for box tests. For the bunny's 270 k hull tetrahedra (each box
    /// overlaps ~40 others) 16 boxes per leaf made the hull 4–5 % faster than 4; for its 70 k
    /// faces (`self_intersections`) 4 stays the better, by 1–2 ms of 17.
    pub fn with_leaf_size(boxes: Vec<(DVec3, DVec3)>, leaf: usize) -> MortonBvh {
        MortonBvh::build_with(boxes, leaf.max(1), PARALLEL_SLOTS)
    }

    /// The tree with at most `leaf` boxes per leaf and subtrees over more than
    /// `parallel_slots` slots built in parallel.
    fn build_with(boxes: Vec<(DVec3, DVec3)>, leaf: usize, parallel_slots: usize) -> MortonBvh {
        let centre = |(a, b): &(DVec3, DVec3)| (*a + *b) * 0.5;
        let grid = MortonGrid::around(boxes.iter().map(centre));
        let code = |b: &(DVec3, DVec3)| grid.code(centre(b));
        // Ties broken by id: the tree, and every traversal order, is deterministic (and the
        // same in parallel and in series).
        let serial = boxes.len() < crate::parallel::SERIAL_BELOW;
        let keyed_at = |(i, b): (usize, &(DVec3, DVec3))| (code(b), i as u32);
        let mut keyed: Vec<(u64, u32)>;
        let sorted: Vec<(DVec3, DVec3)>;
        // The pairs are numbered in order, so the radix sort's order is the pairs' own. In
        // parallel the comparison sort stays: on two cores it sorted 305 k codes (the bunny's
        // hull) in 5.2–5.8 ms, the radix sort's six passes over 63-bit codes in 7.4–8.0 ms
        // (`--bench mesh -- sort_pairs`); the edge keys' three passes are the faster there.
        if serial {
            keyed = boxes.iter().enumerate().map(keyed_at).collect();
            crate::radix::sort_pairs(&mut keyed);
            sorted = keyed.iter().map(|k| boxes[k.1 as usize]).collect();
        } else {
            keyed = boxes.par_iter().enumerate().map(keyed_at).collect();
            keyed.par_sort_unstable();
            sorted = keyed.par_iter().map(|k| boxes[k.1 as usize]).collect();
        }
        let mut b = MortonBvh {
            sorted,
            order: keyed.iter().map(|k| k.1).collect(),
            codes: keyed.iter().map(|k| k.0).collect(),
            nodes: Vec::with_capacity(2 * keyed.len() / leaf + 1),
            leaf,
        };
        if !b.sorted.is_empty() {
            let mut nodes = std::mem::take(&mut b.nodes);
            b.build(&mut nodes, 0, b.order.len(), parallel_slots);
            b.nodes = nodes;
        }
        b
    }

    /// Builds the subtree over `order[start..end]` into `nodes` and returns its node: parents
    /// are pushed before their children, bounds filled in after them.
    ///
    /// Above `parallel` slots ([`PARALLEL_SLOTS`]) the right subtree is built at the same time as the left
    /// one, into a vector of its own with ids from 0, then appended with its ids shifted: the
    /// same nodes in the same order as a serial build (the tree depends only on the codes).
    fn build(&self, nodes: &mut Vec<Node>, start: usize, end: usize, parallel: usize) -> usize {
        let id = nodes.len();
        nodes.push(Node {
            lo: DVec3::INFINITY,
            hi: DVec3::NEG_INFINITY,
            kind: Kind::Leaf(start, end),
        });
        let (lo, hi) = if end - start > self.leaf {
            let mid = self.split(start, end);
            let (l, r) = if end - start > parallel {
                let (l, right) = rayon::join(
                    || self.build(nodes, start, mid, parallel),
                    || {
                        let mut right = Vec::with_capacity(2 * (end - mid) / self.leaf + 1);
                        self.build(&mut right, mid, end, parallel);
                        right
                    },
                );
                let shift = nodes.len();
                nodes.extend(right.into_iter().map(|mut n| {
                    if let Kind::Inner(a, b) = &mut n.kind {
                        *a += shift;
                        *b += shift;
                    }
                    n
                }));
                (l, shift)
            } else {
                (
                    self.build(nodes, start, mid, parallel),
                    self.build(nodes, mid, end, parallel),
                )
            };
            nodes[id].kind = Kind::Inner(l, r);
            let (a, b) = (&nodes[l], &nodes[r]);
            (a.lo.min(b.lo), a.hi.max(b.hi))
        } else {
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for b in &self.sorted[start..end] {
                lo = lo.min(b.0);
                hi = hi.max(b.1);
            }
            (lo, hi)
        };
        nodes[id].lo = lo;
        nodes[id].hi = hi;
        id
    }

    /// Where `order[start..end]` (more than one box) splits: the first position whose code
    /// has the highest bit in which the range's codes differ set; the middle when they are all
    /// equal (boxes with one centre cell).
    fn split(&self, start: usize, end: usize) -> usize {
        let (first, last) = (self.codes[start], self.codes[end - 1]);
        if first == last {
            return (start + end) / 2;
        }
        let bit = 63 - (first ^ last).leading_zeros();
        let prefix = first >> bit;
        // Codes are sorted: those sharing `first`'s prefix down to `bit` come first.
        start + self.codes[start..end].partition_point(|&c| c >> bit == prefix)
    }

    /// `f(a, b)` for every unordered pair of intersecting boxes (closed boxes), given by their
    /// Morton positions ("slots": `order()[a]`, `order()[b]` are their ids), in no particular
    /// order of the pairs or within one; pairs where `f` gives `None` are dropped. For callers
    /// that keep their own data in Morton order.
    ///
    /// A walk of the tree with itself ([`crate::self_join`]): every pair of boxes is
    /// tested once (a query per box tests it twice and walks from the root each time). The
    /// first levels run in parallel.
    pub fn slot_pairs<T: Send>(&self, f: impl Fn(usize, usize) -> Option<T> + Sync) -> Vec<T> {
        // `NoProgress` never asks to stop.
        self.slot_pairs_with_progress(f, &NoProgress)
            .unwrap_or_default()
    }

    /// [`MortonBvh::slot_pairs`], reporting to `progress` the boxes of each leaf as units
    /// once the leaf's pairs among themselves are done (the step's total is the number of
    /// boxes; the caller starts it). The walk meets the leaves in Morton order, interleaved
    /// with the pairs across them, so the count tracks the work closely but not exactly.
    ///
    /// # Errors
    /// [`Cancelled`] when `progress` asks to stop (polled every
    /// [`crate::progress::REPORT_EVERY`] boxes, [`UnitTally`]): the leaves not yet joined are
    /// skipped and no pairs are returned.
    pub fn slot_pairs_with_progress<T: Send>(
        &self,
        f: impl Fn(usize, usize) -> Option<T> + Sync,
        progress: &dyn Progress,
    ) -> Result<Vec<T>, Cancelled> {
        self.leaf_pairs(f, progress, overlaps)
    }

    /// [`MortonBvh::slot_pairs_with_progress`] for the pairs of boxes whose *interiors*
    /// intersect: two boxes whose intervals along some axis meet in a single value (they touch
    /// along a face, an edge or at a corner) are skipped, since a plane `x_k = const`
    /// separates whatever they bound.
    ///
    /// For callers that only care about interiors: the hull's overlap check, where half the
    /// candidate pairs are tetrahedra that share a vertex which is the highest of one and the
    /// lowest of the other along some axis (2.84 M of the bunny's 5.33 M pairs).
    ///
    /// ```
    /// use algesurf_mesh::morton::MortonBvh;
    /// use glam::DVec3;
    /// let unit = |o: DVec3| (o, o + DVec3::ONE);
    /// // Two boxes touching along a face, one overlapping the first.
    /// let tree = MortonBvh::new(vec![unit(DVec3::ZERO), unit(DVec3::X), unit(DVec3::splat(0.5))]);
    /// let ids = |pairs: Vec<(usize, usize)>| {
    ///     let mut ids: Vec<[u32; 2]> = pairs
    ///         .into_iter()
    ///         .map(|(a, b)| {
    ///             let (a, b) = (tree.order()[a], tree.order()[b]);
    ///             [a.min(b), a.max(b)]
    ///         })
    ///         .collect();
    ///     ids.sort();
    ///     ids
    /// };
    /// let none = algesurf_mesh::progress::NoProgress;
    /// let closed = tree.slot_pairs_with_progress(|a, b| Some((a, b)), &none).unwrap();
    /// let open = tree.interior_slot_pairs_with_progress(|a, b| Some((a, b)), &none).unwrap();
    /// assert_eq!(ids(closed), vec![[0, 1], [0, 2], [1, 2]]);
    /// assert_eq!(ids(open), vec![[0, 2], [1, 2]]);
    /// ```
    ///
    /// # Errors
    /// As [`MortonBvh::slot_pairs_with_progress`].
    pub fn interior_slot_pairs_with_progress<T: Send>(
        &self,
        f: impl Fn(usize, usize) -> Option<T> + Sync,
        progress: &dyn Progress,
    ) -> Result<Vec<T>, Cancelled> {
        self.leaf_pairs(f, progress, interiors_overlap)
    }

    /// The walk of [`MortonBvh::slot_pairs_with_progress`] with `hit` as the test of two
    /// boxes (a function item, so each caller's loop gets its own test inlined).
    fn leaf_pairs<T: Send>(
        &self,
        f: impl Fn(usize, usize) -> Option<T> + Sync,
        progress: &dyn Progress,
        hit: impl Fn(&(DVec3, DVec3), DVec3, DVec3) -> bool + Sync,
    ) -> Result<Vec<T>, Cancelled> {
        if self.nodes.is_empty() {
            return Ok(Vec::new());
        }
        // Each box counted once, when its own leaf's pairs are done (a leaf meets itself
        // once); the tally's latched stop skips every leaf pair after it.
        let tally = UnitTally::counting(progress, self.sorted.len());
        // The pairs of two leaves' slots (of one leaf's, `a < b`), in `self_join`'s order,
        // with the boxes read from slices and the test inlined.
        let pairs = self_join_leaves(self, 0, |ra, rb, out| {
            if tally.stopped() {
                return;
            }
            let same = ra == rb;
            if !same && ra.len() <= 64 && rb.len() <= 64 {
                self.across_leaves(ra, rb, &f, &hit, out);
                return;
            }
            for a in ra {
                let ba = self.sorted[a];
                // As `leaf_pair_rows` (whose iterator cost 6 M more instructions on spot).
                let first = if same { a + 1 } else { rb.start };
                // The row's box tests first, into a bit mask, then `f` for its set bits: the
                // tests have no branch to mispredict (a fifth of the bunny's hull's 24 M tests
                // hit, at no pattern).
                for (c, chunk) in self.sorted[first..rb.end].chunks(64).enumerate() {
                    let mask = hits_of(&ba, chunk, &hit);
                    for j in set_bits(mask) {
                        if let Some(x) = f(a, first + 64 * c + j) {
                            out.push(x);
                        }
                    }
                }
                if same {
                    tally.unit_done(a);
                }
            }
        });
        tally.finish()?;
        Ok(pairs)
    }

    /// `f(a, b)` for the pairs of slots `a ∈ ra`, `b ∈ rb` of two leaves (of at most 64 boxes
    /// each) whose boxes `hit`, in the order of [`MortonBvh::leaf_pairs`]' rows (`a`, then
    /// `b`, ascending).
    ///
    /// Only the boxes of each leaf that `hit` the other leaf's bounding box are tested
    /// against each other: a box that misses the bound misses every box inside it (`hit` is
    /// monotone in its second box: the closed and the open overlap test both are). Two
    /// leaves whose bounds overlap mostly do so at their facing sides, so this skips most of
    /// the 16 × 16 tests of two of the hull's leaves.
    fn across_leaves<T>(
        &self,
        ra: std::ops::Range<usize>,
        rb: std::ops::Range<usize>,
        f: &impl Fn(usize, usize) -> Option<T>,
        hit: &impl Fn(&(DVec3, DVec3), DVec3, DVec3) -> bool,
        out: &mut Vec<T>,
    ) {
        let (sa, sb) = (&self.sorted[ra.clone()], &self.sorted[rb.clone()]);
        let bound = |boxes: &[(DVec3, DVec3)]| {
            boxes
                .iter()
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), b| {
                    (lo.min(b.0), hi.max(b.1))
                })
        };
        let (ba, bb) = (bound(sa), bound(sb));
        let near_b = hits_of(&ba, sb, hit);
        if near_b == 0 {
            return;
        }
        for i in set_bits(hits_of(&bb, sa, hit)) {
            let a = &sa[i];
            let mut row = 0u64;
            for j in set_bits(near_b) {
                row |= u64::from(hit(a, sb[j].0, sb[j].1)) << j;
            }
            for j in set_bits(row) {
                if let Some(x) = f(ra.start + i, rb.start + j) {
                    out.push(x);
                }
            }
        }
    }

    /// The box in slot `k` (box `order()[k]`).
    pub fn slot_box(&self, k: usize) -> &(DVec3, DVec3) {
        &self.sorted[k]
    }

    /// Box ids in Morton order: slot `k` holds box `order()[k]`.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Calls `hit` with the slot of every box of the tree that intersects `b` (closed boxes),
    /// in no particular order; `stack` is scratch space, kept by the caller across queries.
    /// For a few boxes against a tree built once (the hull's refinement rounds query the new
    /// tetrahedra against the first round's tree).
    pub fn overlapping_slots(
        &self,
        b: &(DVec3, DVec3),
        stack: &mut Vec<usize>,
        mut hit: impl FnMut(usize),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        stack.clear();
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            if !overlaps(b, node.lo, node.hi) {
                continue;
            }
            match node.kind {
                Kind::Leaf(s, e) => {
                    for (slot, bk) in self.sorted[s..e].iter().enumerate() {
                        if overlaps(b, bk.0, bk.1) {
                            hit(s + slot);
                        }
                    }
                }
                Kind::Inner(l, r) => {
                    stack.push(r);
                    stack.push(l);
                }
            }
        }
    }
}

/// The tree as [`crate::self_join::self_join`] walks it: slots are positions in the Morton
/// order.
impl JoinTree for MortonBvh {
    fn children(&self, n: usize) -> Option<(usize, usize)> {
        match self.nodes[n].kind {
            Kind::Leaf(..) => None,
            Kind::Inner(l, r) => Some((l, r)),
        }
    }

    fn nodes_overlap(&self, a: usize, b: usize) -> bool {
        let (na, nb) = (&self.nodes[a], &self.nodes[b]);
        overlaps(&(na.lo, na.hi), nb.lo, nb.hi)
    }

    fn node_extent(&self, n: usize) -> f64 {
        (self.nodes[n].hi - self.nodes[n].lo).length_squared()
    }

    fn leaf_slots(&self, n: usize) -> std::ops::Range<usize> {
        match self.nodes[n].kind {
            Kind::Leaf(s, e) => s..e,
            Kind::Inner(..) => 0..0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// `n` boxes with corners in `[0, 10)³` and sides in `[0, 1)`, from generator seed `seed`.
    fn random_boxes(seed: u64, n: usize) -> Vec<(DVec3, DVec3)> {
        let mut rng = Lcg(seed);
        let mut next = || rng.next();
        (0..n)
            .map(|_| {
                let lo = DVec3::new(next(), next(), next()) * 10.0;
                (lo, lo + DVec3::new(next(), next(), next()))
            })
            .collect()
    }

    #[test]
    fn morton_spread_puts_bit_k_at_bit_3k() {
        assert_eq!(spread(0b111), 0b1001001);
        assert_eq!(spread(1 << 20), 1 << 60);
        assert_eq!(spread(u64::MAX), 0x1249_2492_4924_9249);
    }

    /// The parallel build gives the serial build's tree, node for node: with subtrees over
    /// more than 8 slots built in parallel (hundreds of joins and shifted appends) and with
    /// none.
    #[test]
    fn parallel_build_is_the_serial_tree() {
        let boxes = random_boxes(99, 3000);
        let serial = MortonBvh::build_with(boxes.clone(), DEFAULT_LEAF_SIZE, usize::MAX);
        let parallel = MortonBvh::build_with(boxes, DEFAULT_LEAF_SIZE, 8);
        assert!(serial.nodes.len() > 1000);
        assert_eq!(serial.nodes, parallel.nodes);
        assert_eq!(serial.order, parallel.order);
    }

    /// The self-join, and the marked query, find exactly the intersecting pairs that brute
    /// force finds, each once, whatever the leaf size (one box per leaf, the default, 16, and
    /// every box in one leaf).
    #[test]
    fn self_join_finds_every_intersecting_pair_once() {
        let mut boxes = random_boxes(12345, 700);
        // A NaN corner: such a box meets no other (every comparison with NaN is false),
        // also where the leaves' bounds are tested first (they skip NaN, as `f64::min` does).
        boxes[7].0.x = f64::NAN;
        boxes[300].1.y = f64::NAN;
        let marked: Vec<bool> = (0..boxes.len()).map(|i| i % 3 == 0).collect();
        // Leaves of up to 64 boxes are joined through their bounds (`across_leaves`), larger
        // ones box by box: 64, 65 and 100 try both sides of that limit.
        for (leaf, marks) in [1, DEFAULT_LEAF_SIZE, 16, 64, 65, 100, 1000]
            .into_iter()
            .flat_map(|leaf| [(leaf, None), (leaf, Some(&marked[..]))])
        {
            let bvh = MortonBvh::with_leaf_size(boxes.clone(), leaf);
            let mut found = match marks {
                None => bvh.slot_pairs(|a, b| {
                    let (i, j) = (bvh.order()[a], bvh.order()[b]);
                    Some((i.min(j), i.max(j)))
                }),
                // Each marked box queried: its pairs, each once (a pair of two marked boxes
                // from its smaller id's side).
                Some(m) => {
                    let mut stack = Vec::new();
                    let mut out = Vec::new();
                    for i in (0..boxes.len()).filter(|&i| m[i]) {
                        bvh.overlapping_slots(&boxes[i], &mut stack, |slot| {
                            let j = bvh.order()[slot] as usize;
                            if j != i && (!m[j] || i < j) {
                                out.push((i.min(j) as u32, i.max(j) as u32));
                            }
                        });
                    }
                    out
                }
            };
            found.sort_unstable();
            let mut expected = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    let wanted = marks.is_none_or(|m| m[i] || m[j]);
                    if wanted && overlaps(&boxes[i], boxes[j].0, boxes[j].1) {
                        expected.push((i as u32, j as u32));
                    }
                }
            }
            assert!(
                expected.len() > 100,
                "the test needs pairs: {}",
                expected.len()
            );
            assert_eq!(found, expected, "{leaf} boxes per leaf");
        }
    }

    /// The interior walk finds exactly the pairs whose open boxes intersect, on boxes with
    /// integer corners, where many pairs touch along a face, an edge or at a corner (as the
    /// hull's tetrahedra around a shared vertex do), whatever the leaf size.
    #[test]
    fn interior_pairs_are_the_closed_pairs_less_those_that_only_touch() {
        let mut rng = Lcg(99);
        let mut cell = || (rng.next() * 6.0).floor();
        let boxes: Vec<(DVec3, DVec3)> = (0..400)
            .map(|_| {
                let lo = DVec3::new(cell(), cell(), cell());
                let size = DVec3::new(1.0 + cell() % 2.0, 1.0 + cell() % 2.0, 1.0);
                (lo, lo + size)
            })
            .collect();
        let brute = |test: fn(&(DVec3, DVec3), DVec3, DVec3) -> bool| {
            let mut expected = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if test(&boxes[i], boxes[j].0, boxes[j].1) {
                        expected.push((i as u32, j as u32));
                    }
                }
            }
            expected
        };
        let (closed, open) = (brute(overlaps), brute(interiors_overlap));
        assert!(
            open.len() > 100 && closed.len() > open.len() + 100,
            "the test needs both kinds of pair: {} closed, {} open",
            closed.len(),
            open.len()
        );
        for leaf in [1, 16, 64, 100, 1000] {
            let bvh = MortonBvh::with_leaf_size(boxes.clone(), leaf);
            let ids = |a: usize, b: usize| {
                let (i, j) = (bvh.order()[a], bvh.order()[b]);
                Some((i.min(j), i.max(j)))
            };
            let mut found_closed = bvh.slot_pairs_with_progress(ids, &NoProgress).unwrap();
            let mut found_open = bvh
                .interior_slot_pairs_with_progress(ids, &NoProgress)
                .unwrap();
            found_closed.sort_unstable();
            found_open.sort_unstable();
            assert_eq!(found_closed, closed, "{leaf} boxes per leaf");
            assert_eq!(found_open, open, "{leaf} boxes per leaf");
        }
    }

    /// The walk with progress finds the same pairs and counts every box once; asked to stop,
    /// it skips the rest of the walk and returns `Cancelled`.
    #[test]
    fn slot_pairs_count_every_box_and_stop_when_asked() {
        use crate::progress::{Cancelled, Progress, ProgressCounter};
        let boxes = random_boxes(777, 5000);
        let bvh = MortonBvh::with_leaf_size(boxes, 16);
        let pair = |a: usize, b: usize| Some((a.min(b), a.max(b)));
        let counter = ProgressCounter::new();
        counter.start("pairs", 5000);
        let mut with = bvh.slot_pairs_with_progress(pair, &counter).unwrap();
        let mut without = bvh.slot_pairs(pair);
        with.sort_unstable();
        without.sort_unstable();
        assert_eq!(with, without);
        assert_eq!(counter.snapshot().done, 5000);
        // Stopped after the first leaves: `Cancelled`, and most leaves not walked.
        let stopping = ProgressCounter::new();
        stopping.start("pairs", 5000);
        let r = bvh.slot_pairs_with_progress(
            |a, b| {
                stopping.cancel();
                pair(a, b)
            },
            &stopping,
        );
        assert_eq!(r, Err(Cancelled));
        assert!(stopping.snapshot().done < 2500, "{:?}", stopping.snapshot());
    }
}

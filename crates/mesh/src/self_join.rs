//! Every overlapping pair of boxes under a binary bounding-volume tree, by walking the tree
//! with itself (a self-join): two subtrees whose boxes are disjoint are skipped whole, and
//! every pair of leaves is reached along one path, so each pair of items is met once, where a
//! query per item meets it twice and descends from the root each time. The upper levels run
//! in parallel (`rayon::join`).
//!
//! [`crate::BoxBvh::overlapping_pairs`] and `algesurf-hull`'s tree over hull tetrahedra both
//! walk their trees with [`self_join`].

use std::marker::PhantomData;
use std::ops::Range;

/// A binary tree of boxes as [`self_join`] walks it. Nodes and leaf slots are the tree's own
/// indices; a leaf holds a range of slots of the tree's item order.
pub trait JoinTree: Sync {
    /// The children of inner node `n`, `None` for a leaf.
    fn children(&self, n: usize) -> Option<(usize, usize)>;
    /// Whether the (closed) boxes of nodes `a` and `b` share a point.
    fn nodes_overlap(&self, a: usize, b: usize) -> bool;
    /// A size of node `n`'s box that grows with it (its diagonal, say): of two inner nodes
    /// met together, the larger is split.
    fn node_extent(&self, n: usize) -> f64;
    /// The slots of leaf `n`.
    fn leaf_slots(&self, n: usize) -> Range<usize>;
}

/// Node depth down to which [`self_join`] forks: 2^8 tasks are plenty for any thread count
/// here, and below it a subtree's work is too small to be worth a task.
const PARALLEL_DEPTH: usize = 8;

/// Calls `pair(a, b, out)` once for every unordered pair of distinct slots `a`, `b` whose
/// leaves' boxes overlap (within one leaf `a < b`; across two leaves in no particular order)
/// under the subtree `root`, and returns what the calls pushed to `out`, in no particular
/// order. `pair` makes the item-level test (the items' own boxes, then whatever the caller
/// needs).
///
/// ```
/// use algesurf_mesh::self_join::{JoinTree, self_join};
/// use std::ops::Range;
/// /// Intervals on a line under one root with two leaves: [0, 1], [1, 2] | [5, 6].
/// struct Line;
/// const ITEMS: [(f64, f64); 3] = [(0.0, 1.0), (1.0, 2.0), (5.0, 6.0)];
/// const NODES: [(f64, f64); 3] = [(0.0, 6.0), (0.0, 2.0), (5.0, 6.0)];
/// impl JoinTree for Line {
///     fn children(&self, n: usize) -> Option<(usize, usize)> {
///         (n == 0).then_some((1, 2))
///     }
///     fn nodes_overlap(&self, a: usize, b: usize) -> bool {
///         NODES[a].0 <= NODES[b].1 && NODES[b].0 <= NODES[a].1
///     }
///     fn node_extent(&self, n: usize) -> f64 {
///         NODES[n].1 - NODES[n].0
///     }
///     fn leaf_slots(&self, n: usize) -> Range<usize> {
///         if n == 1 { 0..2 } else { 2..3 }
///     }
/// }
/// let pairs = self_join(&Line, 0, |a, b, out: &mut Vec<(usize, usize)>| {
///     let (x, y) = (ITEMS[a], ITEMS[b]);
///     if x.0 <= y.1 && y.0 <= x.1 {
///         out.push((a.min(b), a.max(b)));
///     }
/// });
/// assert_eq!(pairs, vec![(0, 1)]);
/// ```
pub fn self_join<R: Send>(
    tree: &impl JoinTree,
    root: usize,
    pair: impl Fn(usize, usize, &mut Vec<R>) + Sync,
) -> Vec<R> {
    self_join_leaves(
        tree,
        root,
        |a: Range<usize>, b: Range<usize>, out: &mut Vec<R>| {
            for (x, ys) in leaf_pair_rows(a, b) {
                for y in ys {
                    pair(x, y, out);
                }
            }
        },
    )
}

/// The slot pairs of two leaves as [`self_join`] visits them, a row at a time: each slot `x`
/// of `a` with the slots it is paired with, all of `b`, or when `a == b` (one leaf) the slots
/// after `x`.
///
/// ```
/// use algesurf_mesh::self_join::leaf_pair_rows;
/// let rows: Vec<_> = leaf_pair_rows(0..3, 0..3).collect();
/// assert_eq!(rows, vec![(0, 1..3), (1, 2..3), (2, 3..3)]);
/// let rows: Vec<_> = leaf_pair_rows(0..2, 5..7).collect();
/// assert_eq!(rows, vec![(0, 5..7), (1, 5..7)]);
/// ```
#[inline]
pub fn leaf_pair_rows(
    a: Range<usize>,
    b: Range<usize>,
) -> impl Iterator<Item = (usize, Range<usize>)> {
    let same = a == b;
    a.map(move |x| (x, if same { x + 1..b.end } else { b.clone() }))
}

/// [`self_join`] a pair of leaves at a time: `leaves(a, b, out)` for every pair of leaves
/// whose boxes overlap, with their slots `a` and `b`, and once per leaf with `a == b` (its
/// slots' pairs among themselves). [`self_join`] is this with a loop over the slot pairs in
/// the order its documentation gives; a caller that keeps its items' boxes in slot order
/// loops over them itself, with its own item test inlined in the loop (a call per slot
/// pair, through `self_join`'s `pair`, was a fifth of the hull's pair check on the bunny:
/// ~24 M calls for 5.3 M overlapping boxes).
pub fn self_join_leaves<R: Send>(
    tree: &impl JoinTree,
    root: usize,
    leaves: impl Fn(Range<usize>, Range<usize>, &mut Vec<R>) + Sync,
) -> Vec<R> {
    Join {
        tree,
        leaves: &leaves,
        _out: PhantomData,
    }
    .within(root, 0)
}

struct Join<'a, T, P, R> {
    tree: &'a T,
    leaves: &'a P,
    /// What `leaves` pushes.
    _out: PhantomData<fn() -> R>,
}

impl<T: JoinTree, R: Send, P: Fn(Range<usize>, Range<usize>, &mut Vec<R>) + Sync>
    Join<'_, T, P, R>
{
    /// The pairs within subtree `n`.
    fn within(&self, n: usize, depth: usize) -> Vec<R> {
        match self.tree.children(n) {
            None => {
                let mut out = Vec::new();
                let slots = self.tree.leaf_slots(n);
                (self.leaves)(slots.clone(), slots, &mut out);
                out
            }
            Some((l, r)) => {
                let (mut a, (b, c)) = self.fork(
                    depth,
                    || self.within(l, depth + 1),
                    || {
                        self.fork(
                            depth,
                            || self.within(r, depth + 1),
                            || self.across(l, r, depth + 1),
                        )
                    },
                );
                a.extend(b);
                a.extend(c);
                a
            }
        }
    }

    /// The pairs with one slot in subtree `a` and one in subtree `b` (disjoint subtrees).
    fn across(&self, a: usize, b: usize, depth: usize) -> Vec<R> {
        if !self.tree.nodes_overlap(a, b) {
            return Vec::new();
        }
        match (self.tree.children(a), self.tree.children(b)) {
            (None, None) => {
                let mut out = Vec::new();
                (self.leaves)(self.tree.leaf_slots(a), self.tree.leaf_slots(b), &mut out);
                out
            }
            // Split the inner one, the larger when both are inner.
            (Some((l, r)), None) => self.both(l, r, b, depth),
            (None, Some((l, r))) => self.both(l, r, a, depth),
            (Some((al, ar)), Some((bl, br))) => {
                if self.tree.node_extent(a) >= self.tree.node_extent(b) {
                    self.both(al, ar, b, depth)
                } else {
                    self.both(bl, br, a, depth)
                }
            }
        }
    }

    /// `across(l, other)` and `across(r, other)`.
    fn both(&self, l: usize, r: usize, other: usize, depth: usize) -> Vec<R> {
        let (mut x, y) = self.fork(
            depth,
            || self.across(l, other, depth + 1),
            || self.across(r, other, depth + 1),
        );
        x.extend(y);
        x
    }

    fn fork<A: Send, B: Send>(
        &self,
        depth: usize,
        a: impl FnOnce() -> A + Send,
        b: impl FnOnce() -> B + Send,
    ) -> (A, B) {
        if depth < PARALLEL_DEPTH {
            rayon::join(a, b)
        } else {
            (a(), b())
        }
    }
}

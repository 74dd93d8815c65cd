//! Spatial queries in f64 on an `obvhs` BVH.
//!
//! obvhs builds the tree over f32 boxes. Every f64 box is rounded *outward* to f32 and then
//! widened by one more f32 ulp on each side (a relative padding of about `6e-8`), so each f32
//! box contains its f64 box and the tree can never prune a primitive that the exact test
//! would accept; node boxes are unions of those, hence conservative too. The traversal is our
//! own (f64 tests against the node boxes), and the primitive tests are exact f64 tests
//! ([`crate::primitives`]). Coordinates beyond the f32 range map to ±infinity in the node
//! boxes, so they are conservative as well. Non-finite primitives are left out of the tree.

use crate::TriMesh;
use crate::geometry::Aabb;
use crate::primitives::{closest_point_on_triangle, ray_box, ray_triangle, triangle_box_overlap};
use crate::self_join::{JoinTree, leaf_pair_rows, self_join_leaves};
use glam::DVec3;
use obvhs::bvh2::Bvh2;
use std::time::Duration;

fn down(x: f64) -> f32 {
    let f = x as f32;
    let f = if f as f64 > x { f.next_down() } else { f };
    f.next_down()
}
fn up(x: f64) -> f32 {
    let f = x as f32;
    let f = if (f as f64) < x { f.next_up() } else { f };
    f.next_up()
}
fn widen(x: f32, lower: bool) -> f64 {
    match (x.is_finite(), lower) {
        (true, _) if x.abs() < f32::MAX => x as f64,
        (_, true) => f64::NEG_INFINITY,
        (_, false) => f64::INFINITY,
    }
}

/// A BVH over arbitrary f64 boxes (the primitives are box ids `0..n`).
#[derive(Clone)]
pub struct BoxBvh {
    tree: Option<Bvh2>,
    boxes: Vec<Aabb>,
    /// The f64 widening of every tree node's f32 box, by node index. Converting once at build
    /// time instead of at every visit keeps the traversal's inner loop to one f64 box test.
    node_boxes: Vec<Aabb>,
    /// Box id of each tree primitive slot, in the tree's leaf order (`primitive_indices`
    /// already resolved), so a leaf reads its ids contiguously.
    leaf_ids: Vec<u32>,
    /// The f64 widening of each primitive's padded f32 box, in the same leaf order. It
    /// contains the exact f64 box (see the module comment), so it is as conservative a
    /// prefilter for a single primitive as the node boxes are for subtrees.
    leaf_boxes: Vec<Aabb>,
}

/// The tree as [`crate::self_join::self_join`] walks it (only called on a built tree).
impl JoinTree for BoxBvh {
    fn children(&self, n: usize) -> Option<(usize, usize)> {
        let node = &self.tree.as_ref()?.nodes[n];
        (!node.is_leaf()).then(|| (node.first_index as usize, node.first_index as usize + 1))
    }

    fn nodes_overlap(&self, a: usize, b: usize) -> bool {
        self.node_boxes[a].overlaps(&self.node_boxes[b])
    }

    fn node_extent(&self, n: usize) -> f64 {
        self.node_boxes[n].diagonal()
    }

    fn leaf_slots(&self, n: usize) -> std::ops::Range<usize> {
        self.tree.as_ref().map_or(0..0, |t| {
            let node = &t.nodes[n];
            let s = node.first_index as usize;
            s..s + node.prim_count as usize
        })
    }
}

impl std::fmt::Debug for BoxBvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BoxBvh")
            .field("boxes", &self.boxes.len())
            .field("nodes", &self.tree.as_ref().map_or(0, |t| t.nodes.len()))
            .finish()
    }
}

/// The conservative f64 box of an f32 box (infinite where the f32 bound is at the f32 range).
fn widen_box(a: &obvhs::aabb::Aabb) -> Aabb {
    let (mn, mx) = (a.min.to_array(), a.max.to_array());
    Aabb {
        min: DVec3::new(widen(mn[0], true), widen(mn[1], true), widen(mn[2], true)),
        max: DVec3::new(
            widen(mx[0], false),
            widen(mx[1], false),
            widen(mx[2], false),
        ),
    }
}

/// Depth-first traversal stack: 64 entries inline, spilling to the heap only for deeper
/// trees, so a query allocates nothing in the common case (a balanced tree over 2^64
/// primitives would not need more; degenerate trees still work through the spill).
struct Stack<T: Copy> {
    inline: [T; 64],
    len: usize,
    spill: Vec<T>,
}

impl<T: Copy> Stack<T> {
    fn new(fill: T) -> Self {
        Stack {
            inline: [fill; 64],
            len: 0,
            spill: Vec::new(),
        }
    }
    #[inline]
    fn push(&mut self, x: T) {
        if self.len < 64 {
            self.inline[self.len] = x;
            self.len += 1;
        } else {
            self.spill.push(x);
        }
    }
    #[inline]
    fn pop(&mut self) -> Option<T> {
        // The spill holds the entries pushed after the inline part filled up: pop those first.
        if let Some(x) = self.spill.pop() {
            return Some(x);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }
}

impl BoxBvh {
    /// Builds the tree over `boxes`. Non-finite or empty boxes are kept (ids stay stable) but
    /// never reported by queries.
    pub fn new(boxes: Vec<Aabb>) -> BoxBvh {
        let mut ids = Vec::new();
        let mut fboxes = Vec::new();
        for (i, b) in boxes.iter().enumerate() {
            if b.min.is_finite() && b.max.is_finite() && !b.is_empty() {
                ids.push(i as u32);
                fboxes.push(obvhs::aabb::Aabb::new(
                    [down(b.min.x), down(b.min.y), down(b.min.z)].into(),
                    [up(b.max.x), up(b.max.y), up(b.max.z)].into(),
                ));
            }
        }
        let tree = (!fboxes.is_empty()).then(|| {
            obvhs::bvh2::builder::build_bvh2(
                &fboxes,
                obvhs::BvhBuildParams::medium_build(),
                &mut Duration::default(),
            )
        });
        let (mut node_boxes, mut leaf_ids, mut leaf_boxes) = (Vec::new(), Vec::new(), Vec::new());
        if let Some(t) = &tree {
            node_boxes = t.nodes.iter().map(|n| widen_box(n.aabb())).collect();
            leaf_ids = t
                .primitive_indices
                .iter()
                .map(|&pi| ids[pi as usize])
                .collect();
            leaf_boxes = t
                .primitive_indices
                .iter()
                .map(|&pi| widen_box(&fboxes[pi as usize]))
                .collect();
        }
        BoxBvh {
            tree,
            boxes,
            node_boxes,
            leaf_ids,
            leaf_boxes,
        }
    }

    /// The boxes the tree was built over.
    pub fn boxes(&self) -> &[Aabb] {
        &self.boxes
    }

    /// Visits the leaves whose node box passes `node`, calling `leaf` with box ids; `node`
    /// receives the conservative f64 node box and returns a key (or `None` to prune), and
    /// `live` is asked again when a deferred node is popped, with that key, so that state
    /// updated by `leaf` since the node was pushed (a shrinking search radius) prunes it then.
    /// Children are visited nearer (smaller key) first, the left one on ties.
    pub(crate) fn traverse(
        &self,
        mut node: impl FnMut(&Aabb) -> Option<f64>,
        mut live: impl FnMut(f64) -> bool,
        mut leaf: impl FnMut(u32),
    ) {
        let Some(tree) = &self.tree else { return };
        if tree.nodes.is_empty() {
            return;
        }
        let mut stack: Stack<(u32, f64)> = Stack::new((0, 0.0));
        if let Some(k) = node(&self.node_boxes[0]) {
            stack.push((0, k));
        }
        while let Some((i, k)) = stack.pop() {
            if !live(k) {
                continue;
            }
            let n = &tree.nodes[i as usize];
            if n.is_leaf() {
                let s = n.first_index as usize;
                for &id in &self.leaf_ids[s..s + n.prim_count as usize] {
                    leaf(id);
                }
                continue;
            }
            let (l, r) = (n.first_index, n.first_index + 1);
            let kl = node(&self.node_boxes[l as usize]);
            let kr = node(&self.node_boxes[r as usize]);
            // Pushed far-first so that the nearer one pops first.
            match (kl, kr) {
                (Some(a), Some(b)) if a <= b => {
                    stack.push((r, b));
                    stack.push((l, a));
                }
                (Some(a), Some(b)) => {
                    stack.push((l, a));
                    stack.push((r, b));
                }
                (Some(a), None) => stack.push((l, a)),
                (None, Some(b)) => stack.push((r, b)),
                (None, None) => {}
            }
        }
    }

    /// Branch-and-bound nearest search: calls `leaf(id, bound)` for every primitive whose
    /// conservative box is within squared distance `bound` of `p`, where `bound` is the
    /// squared distance `leaf` returned last (initially infinite). Subtrees and primitives
    /// farther than the current bound are skipped, and nodes are expanded nearest first.
    /// The comparisons are `<=`, so every primitive at exactly the final best distance is
    /// still visited (ties are then decided by the caller independently of the
    /// visiting order).
    fn nearest(&self, p: DVec3, mut leaf: impl FnMut(u32, f64) -> f64) {
        use std::cmp::Reverse;
        let Some(tree) = &self.tree else { return };
        if tree.nodes.is_empty() {
            return;
        }
        let mut bound = f64::INFINITY;
        // Best-first: nodes pop in increasing box distance. Depth-first order is poor here
        // because many nested boxes contain an interior query point (distance 0 for all),
        // so the first leaves reached can be far from the surface. The keys are squared
        // distances, never NaN (finite `p`) and never negative, so their bit patterns order
        // as the values do.
        let mut heap: std::collections::BinaryHeap<(Reverse<u64>, u32)> =
            std::collections::BinaryHeap::with_capacity(64);
        heap.push((Reverse(0f64.to_bits()), 0));
        while let Some((Reverse(kb), i)) = heap.pop() {
            // Every node left has a key at least this one: all beyond the bound.
            if f64::from_bits(kb) > bound {
                break;
            }
            let n = &tree.nodes[i as usize];
            if n.is_leaf() {
                let s = n.first_index as usize;
                let e = s + n.prim_count as usize;
                for (b, &id) in self.leaf_boxes[s..e].iter().zip(&self.leaf_ids[s..e]) {
                    if b.distance_squared(p) <= bound {
                        bound = leaf(id, bound);
                    }
                }
            } else {
                for c in [n.first_index, n.first_index + 1] {
                    let d = self.node_boxes[c as usize].distance_squared(p);
                    if d <= bound {
                        heap.push((Reverse(d.to_bits()), c));
                    }
                }
            }
        }
    }

    /// Every unordered pair `(i, j)`, `i < j`, of overlapping boxes (closed boxes; touching
    /// counts), mapped through `f` (pairs where it gives `None` are dropped), in no particular
    /// order.
    ///
    /// A walk of the tree with itself ([`crate::self_join`]): each pair of boxes is tested
    /// once, where a query per box tests it twice and descends from the root each time. The
    /// upper levels run in parallel.
    ///
    /// ```
    /// use algesurf_mesh::bvh::BoxBvh;
    /// use algesurf_mesh::geometry::Aabb;
    /// use glam::DVec3;
    /// let unit = |x: f64| Aabb::new(DVec3::new(x, 0.0, 0.0), DVec3::new(x + 1.0, 1.0, 1.0));
    /// // [0, 1] and [1, 2] touch, [0.5, 1.5] overlaps both, [5, 6] is alone.
    /// let bvh = BoxBvh::new(vec![unit(0.0), unit(1.0), unit(0.5), unit(5.0)]);
    /// let mut pairs = bvh.overlapping_pairs(|i, j| Some((i, j)));
    /// pairs.sort_unstable();
    /// assert_eq!(pairs, vec![(0, 1), (0, 2), (1, 2)]);
    /// ```
    pub fn overlapping_pairs<T: Send>(&self, f: impl Fn(u32, u32) -> Option<T> + Sync) -> Vec<T> {
        if self.tree.as_ref().is_none_or(|t| t.nodes.is_empty()) {
            return Vec::new();
        }
        // Slots are positions in the leaf order: padded boxes first, then the exact ones.
        // The slot pairs in `self_join`'s order, leaf boxes read from slices, the tests inlined.
        self_join_leaves(self, 0, |ra, rb, out| {
            for (a, rest) in leaf_pair_rows(ra, rb) {
                let (la, i) = (self.leaf_boxes[a], self.leaf_ids[a]);
                let slots = self.leaf_boxes[rest.clone()]
                    .iter()
                    .zip(&self.leaf_ids[rest]);
                for (lb, &j) in slots {
                    if la.overlaps(lb)
                        && self.boxes[i as usize].overlaps(&self.boxes[j as usize])
                        && let Some(x) = f(i.min(j), i.max(j))
                    {
                        out.push(x);
                    }
                }
            }
        })
    }

    /// Ids of the boxes that overlap `query` (closed boxes; touching counts), ascending.
    pub fn overlapping(&self, query: &Aabb) -> Vec<u32> {
        let mut out = Vec::new();
        self.traverse(
            |b| b.overlaps(query).then_some(0.0),
            |_| true,
            |i| {
                if self.boxes[i as usize].overlaps(query) {
                    out.push(i);
                }
            },
        );
        out.sort_unstable();
        out
    }

    /// Ids of the boxes that contain `p`, ascending.
    pub fn containing(&self, p: DVec3) -> Vec<u32> {
        self.overlapping(&Aabb { min: p, max: p })
    }
}

/// The closest point on a mesh to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The triangle it lies on.
    pub face: u32,
    /// The point.
    pub point: DVec3,
    /// Its barycentric coordinates in the triangle.
    pub barycentric: [f64; 3],
    /// The distance to the query point.
    pub distance: f64,
}

/// A ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The triangle hit.
    pub face: u32,
    /// Ray parameter: the hit is at `origin + t * dir`.
    pub t: f64,
    /// Barycentric coordinates `(1 − u − v, u, v)` of the hit.
    pub barycentric: [f64; 3],
}

/// A BVH over the triangles of a mesh, with exact f64 closest-point, ray and box queries.
#[derive(Clone, Debug)]
pub struct TriangleBvh {
    boxes: BoxBvh,
    triangles: Vec<[DVec3; 3]>,
}

impl TriangleBvh {
    /// Builds the tree over the triangles of `mesh` (face ids are the mesh's).
    pub fn new(mesh: &TriMesh) -> TriangleBvh {
        TriangleBvh::from_triangles(
            (0..mesh.face_count())
                .map(|f| mesh.triangle_points(f))
                .collect(),
        )
    }

    /// Builds the tree over triangles given by their corners.
    pub fn from_triangles(triangles: Vec<[DVec3; 3]>) -> TriangleBvh {
        let boxes = triangles.iter().map(Aabb::from_points).collect();
        TriangleBvh {
            boxes: BoxBvh::new(boxes),
            triangles,
        }
    }

    /// The triangles.
    pub fn triangles(&self) -> &[[DVec3; 3]] {
        &self.triangles
    }

    /// The closest point on the triangles to `p` (ties go to the lowest face id among those
    /// visited first), or `None` when there are no finite triangles or `p` is not finite.
    pub fn closest_point(&self, p: DVec3) -> Option<ClosestPoint> {
        if !p.is_finite() {
            return None;
        }
        let mut best: Option<ClosestPoint> = None;
        self.boxes.nearest(p, |f, bound| {
            let [a, b, c] = self.triangles[f as usize];
            let (q, bary) = closest_point_on_triangle(p, a, b, c);
            let d2 = q.distance_squared(p);
            if d2 < bound || (d2 == bound && best.is_some_and(|x| f < x.face)) {
                best = Some(ClosestPoint {
                    face: f,
                    point: q,
                    barycentric: bary,
                    distance: d2.sqrt(),
                });
                return d2;
            }
            bound
        });
        best
    }

    /// All hits of the ray `origin + t dir`, `t` in `[t_min, t_max]`, sorted by `t` (then face).
    pub fn ray_hits(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> Vec<RayHit> {
        let mut out = Vec::new();
        self.boxes.traverse(
            |b| ray_box(origin, dir, b, t_min, t_max).map(|(t, _)| t),
            |_| true,
            |f| {
                if let Some((t, u, v)) =
                    ray_triangle(origin, dir, self.triangles[f as usize], t_min, t_max)
                {
                    out.push(RayHit {
                        face: f,
                        t,
                        barycentric: [1.0 - u - v, u, v],
                    });
                }
            },
        );
        out.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.face.cmp(&b.face)));
        out
    }

    /// The first hit of the ray (smallest `t` in `[t_min, t_max]`, ties to the lowest face).
    pub fn ray_hit(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> Option<RayHit> {
        let mut best: Option<RayHit> = None;
        let limit = std::cell::Cell::new(t_max);
        self.boxes.traverse(
            |b| ray_box(origin, dir, b, t_min, limit.get()).map(|(t, _)| t),
            // The key is the entry parameter of the node box: a node entered beyond the best
            // hit so far cannot hold a better one (ties stay, for the lower face id; written
            // so that a NaN key, which the push-time test let through, is kept too).
            |t| t.partial_cmp(&limit.get()) != Some(std::cmp::Ordering::Greater),
            |f| {
                if let Some((t, u, v)) =
                    ray_triangle(origin, dir, self.triangles[f as usize], t_min, t_max)
                {
                    let better = match best {
                        None => true,
                        Some(h) => t < h.t || (t == h.t && f < h.face),
                    };
                    if better {
                        limit.set(t);
                        best = Some(RayHit {
                            face: f,
                            t,
                            barycentric: [1.0 - u - v, u, v],
                        });
                    }
                }
            },
        );
        best
    }

    /// Ids of the triangles whose bounding boxes meet the closed box `query` (a conservative
    /// prefilter: it contains every triangle that shares a point with the box), ascending.
    pub fn boxes_overlapping(&self, query: &Aabb) -> Vec<u32> {
        self.boxes.overlapping(query)
    }

    /// [`BoxBvh::overlapping_pairs`] over the triangles' bounding boxes.
    pub fn overlapping_box_pairs<T: Send>(
        &self,
        f: impl Fn(u32, u32) -> Option<T> + Sync,
    ) -> Vec<T> {
        self.boxes.overlapping_pairs(f)
    }

    /// Ids of the triangles that share a point with the closed box `query` (exact
    /// separating-axis test), ascending.
    pub fn triangles_overlapping_box(&self, query: &Aabb) -> Vec<u32> {
        self.boxes
            .overlapping(query)
            .into_iter()
            .filter(|&f| triangle_box_overlap(self.triangles[f as usize], query))
            .collect()
    }
}

//! A small bounding-volume hierarchy over axis-aligned boxes, used to find candidate pairs of
//! hull tetrahedra (never all pairs). Private: `algesurf-mesh` has no box-pair query.

use glam::DVec3;

const LEAF: usize = 4;

struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: range into `order`; inner: children.
    kind: Kind,
}

enum Kind {
    Leaf(usize, usize),
    Inner(usize, usize),
}

/// A median-split AABB tree.
pub(crate) struct Bvh {
    boxes: Vec<(DVec3, DVec3)>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

fn overlaps(a: &(DVec3, DVec3), lo: DVec3, hi: DVec3) -> bool {
    a.0.cmple(hi).all() && lo.cmple(a.1).all()
}

impl Bvh {
    /// Builds the tree over `boxes` (`(min, max)` corners).
    pub(crate) fn new(boxes: Vec<(DVec3, DVec3)>) -> Bvh {
        let mut b = Bvh {
            order: (0..boxes.len() as u32).collect(),
            boxes,
            nodes: Vec::new(),
        };
        if !b.boxes.is_empty() {
            b.build(0, b.order.len());
        }
        b
    }

    fn build(&mut self, start: usize, end: usize) -> usize {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &i in &self.order[start..end] {
            lo = lo.min(self.boxes[i as usize].0);
            hi = hi.max(self.boxes[i as usize].1);
        }
        let id = self.nodes.len();
        self.nodes.push(Node {
            lo,
            hi,
            kind: Kind::Leaf(start, end),
        });
        if end - start > LEAF {
            let ext = hi - lo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = (start + end) / 2;
            let boxes = &self.boxes;
            let centre = |i: &u32| {
                let (a, b) = boxes[*i as usize];
                (a[axis] + b[axis]) * 0.5
            };
            self.order[start..end]
                .select_nth_unstable_by(mid - start, |x, y| centre(x).total_cmp(&centre(y)));
            let l = self.build(start, mid);
            let r = self.build(mid, end);
            self.nodes[id].kind = Kind::Inner(l, r);
        }
        id
    }

    /// Calls `f(j)` for every box `j ≠ i` that intersects box `i` (closed boxes) and that
    /// `keep` accepts, in the tree's order: a query per box, so callers can run the boxes in
    /// parallel.
    pub(crate) fn overlapping(
        &self,
        i: usize,
        keep: impl Fn(usize) -> bool,
        mut f: impl FnMut(u32),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let bx = &self.boxes[i];
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            if !overlaps(bx, node.lo, node.hi) {
                continue;
            }
            match node.kind {
                Kind::Leaf(s, e) => {
                    for &j in &self.order[s..e] {
                        if j as usize != i
                            && keep(j as usize)
                            && overlaps(bx, self.boxes[j as usize].0, self.boxes[j as usize].1)
                        {
                            f(j);
                        }
                    }
                }
                Kind::Inner(l, r) => {
                    stack.push(l);
                    stack.push(r);
                }
            }
        }
    }

    /// Number of boxes.
    pub(crate) fn len(&self) -> usize {
        self.boxes.len()
    }
}

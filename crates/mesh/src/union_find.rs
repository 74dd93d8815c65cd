//! Disjoint sets over `0..n` as a parent array whose roots are each set's lowest element, so
//! the sets' roots do not depend on the order of the joins (`Topology::face_components`,
//! `flat::flat_regions`).

/// The root of `x`'s set (its lowest element, as [`union`] keeps it), halving the path as
/// the walk goes.
#[inline]
pub(crate) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Joins the sets of `a` and `b`, hanging the larger root under the smaller, so that
/// `parent[x] ≤ x` always.
#[inline]
pub(crate) fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

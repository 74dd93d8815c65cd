//! Interior-overlap test for two tetrahedra by the separating axis theorem.

use glam::DVec3;

/// The edges of a tetrahedron as vertex index pairs.
const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
/// The faces of a tetrahedron as vertex index triples.
const FACES: [(usize, usize, usize); 4] = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)];

/// How deeply two tetrahedra (given by their vertices) interpenetrate, relative to their size.
///
/// Two convex polyhedra have disjoint interiors iff some axis separates their projections;
/// for tetrahedra it suffices to try the 8 face normals and the 36 cross products of an edge of
/// each (the face normals of the Minkowski difference; parallel edge pairs give zero vectors
/// and are skipped, as they are not needed). For every axis `w` the overlap of the projected
/// intervals is divided by `|w| · D`, `D` the diagonal of the two tetrahedra's common bounding
/// box; the result is the minimum over the axes. It is `≤ 0` (up to rounding) when the
/// interiors are disjoint (touching along a shared face, edge or vertex gives 0) and positive
/// when they overlap: then no axis separates them, and the value bounds from below how far one
/// must move one tetrahedron, in units of `D`, to separate them along the tried axes.
///
/// Projections are taken relative to `a[0]`, so rounding scales with the tetrahedra's size, not
/// with their distance from the origin: a shared vertex projects to bit-identical values and
/// a shared face's vertices to values within a few ulps of `D`.
pub fn overlap_depth(a: &[DVec3; 4], b: &[DVec3; 4]) -> f64 {
    let o = a[0];
    let la: [DVec3; 4] = std::array::from_fn(|k| a[k] - o);
    let lb: [DVec3; 4] = std::array::from_fn(|k| b[k] - o);
    let (mut lo, mut hi) = (la[0], la[0]);
    for p in la.iter().chain(lb.iter()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let d = (hi - lo).length();
    if d == 0.0 || !d.is_finite() {
        return 0.0;
    }
    let mut depth = f64::INFINITY;
    let mut test = |w: DVec3| -> bool {
        let len = w.length();
        if len == 0.0 || !len.is_finite() {
            return false;
        }
        let (mut amin, mut amax) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in &la {
            let x = p.dot(w);
            amin = amin.min(x);
            amax = amax.max(x);
        }
        let (mut bmin, mut bmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in &lb {
            let x = p.dot(w);
            bmin = bmin.min(x);
            bmax = bmax.max(x);
        }
        let ov = (amax.min(bmax) - amin.max(bmin)) / (len * d);
        depth = depth.min(ov);
        depth < 0.0
    };
    for t in [&la, &lb] {
        for &(i, j, k) in &FACES {
            if test((t[j] - t[i]).cross(t[k] - t[i])) {
                return depth;
            }
        }
    }
    for &(i, j) in &EDGES {
        let ea = la[j] - la[i];
        for &(k, l) in &EDGES {
            if test(ea.cross(lb[l] - lb[k])) {
                return depth;
            }
        }
    }
    depth
}

/// True when the interiors of the two tetrahedra overlap by more than `tolerance` (relative to
/// their size; see [`overlap_depth`]). Tetrahedra that share a face, an edge or a vertex and
/// lie on the two sides of it do not overlap.
///
/// ```
/// use algesurf_hull::tetrahedra_overlap;
/// use glam::DVec3;
/// let a = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
/// let b = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE]; // shares the face [X Y Z], other side
/// assert!(!tetrahedra_overlap(&a, &b, 1e-9));
/// let c = [DVec3::splat(0.1), DVec3::X, DVec3::Y, DVec3::Z]; // same side
/// assert!(tetrahedra_overlap(&a, &c, 1e-9));
/// ```
pub fn tetrahedra_overlap(a: &[DVec3; 4], b: &[DVec3; 4], tolerance: f64) -> bool {
    overlap_depth(a, b) > tolerance
}

//! Exact f64 geometric tests used by the BVH queries (hand-written: obvhs works in f32).

use crate::geometry::Aabb;
use glam::DVec3;

/// The closest point to `p` on the segment `a`–`b`, with its parameter in `[0, 1]`.
pub fn closest_point_on_segment(p: DVec3, a: DVec3, b: DVec3) -> (DVec3, f64) {
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 <= 0.0 || l2.is_nan() {
        return (a, 0.0);
    }
    let t = ((p - a).dot(ab) / l2).clamp(0.0, 1.0);
    (a + t * ab, t)
}

/// The closest point to `p` on the triangle `(a, b, c)` and its barycentric coordinates,
/// by Ericson's Voronoi-region method (Real-Time Collision Detection, §5.1.5). Degenerate
/// triangles (where the method would divide by zero) fall back to the closest of the three
/// edges.
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, [f64; 3]) {
    let r = ericson(p, a, b, c);
    if r.0.is_finite() && r.1.iter().all(|x| x.is_finite()) {
        return r;
    }
    let (q0, t0) = closest_point_on_segment(p, a, b);
    let (q1, t1) = closest_point_on_segment(p, b, c);
    let (q2, t2) = closest_point_on_segment(p, c, a);
    let cands = [
        (q0, [1.0 - t0, t0, 0.0]),
        (q1, [0.0, 1.0 - t1, t1]),
        (q2, [t2, 0.0, 1.0 - t2]),
    ];
    let mut best = cands[0];
    for c in &cands[1..] {
        if c.0.distance_squared(p) < best.0.distance_squared(p) {
            best = *c;
        }
    }
    best
}

fn ericson(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, [f64; 3]) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + v * ab, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + w * ac, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + w * (c - b), [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

/// Möller–Trumbore ray/triangle intersection in f64: the ray parameter `t` (point
/// `origin + t * dir`) and barycentrics `(u, v)` of the hit with `t` in `[t_min, t_max]`,
/// or `None`. Hits on edges and vertices count; rays parallel to the plane (determinant
/// exactly zero) miss.
pub fn ray_triangle(
    origin: DVec3,
    dir: DVec3,
    [a, b, c]: [DVec3; 3],
    t_min: f64,
    t_max: f64,
) -> Option<(f64, f64, f64)> {
    let e1 = b - a;
    let e2 = c - a;
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = origin - a;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = dir.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    (t >= t_min && t <= t_max).then_some((t, u, v))
}

/// Slab test: the parameter interval where the ray meets the (closed) box, if any, clipped
/// to `[t_min, t_max]`.
pub fn ray_box(origin: DVec3, dir: DVec3, b: &Aabb, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (t_min, t_max);
    for k in 0..3 {
        let (o, d) = (origin[k], dir[k]);
        if d == 0.0 {
            if o < b.min[k] || o > b.max[k] {
                return None;
            }
            continue;
        }
        let (t1, t2) = ((b.min[k] - o) / d, (b.max[k] - o) / d);
        let (t1, t2) = if t1 <= t2 { (t1, t2) } else { (t2, t1) };
        lo = lo.max(t1);
        hi = hi.min(t2);
        if lo > hi {
            return None;
        }
    }
    Some((lo, hi))
}

/// Exact separating-axis test of triangle `(a, b, c)` against a closed box
/// (Akenine-Möller's 13 axes): true when they share a point.
pub fn triangle_box_overlap([a, b, c]: [DVec3; 3], bx: &Aabb) -> bool {
    if bx.is_empty() {
        return false;
    }
    let center = 0.5 * (bx.min + bx.max);
    let h = 0.5 * (bx.max - bx.min);
    let v = [a - center, b - center, c - center];
    let sep = |axis: DVec3| -> bool {
        let p = [axis.dot(v[0]), axis.dot(v[1]), axis.dot(v[2])];
        let r = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
        let (mn, mx) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
        mn > r || mx < -r
    };
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    if axes.iter().any(|&u| sep(u)) {
        return false;
    }
    if sep(e[0].cross(e[1])) {
        return false;
    }
    for ei in e {
        for u in axes {
            if sep(ei.cross(u)) {
                return false;
            }
        }
    }
    true
}

/// The length of the longest edge of triangle `t`: the size that tolerances on a triangle are
/// taken relative to.
pub fn longest_edge_length(t: [DVec3; 3]) -> f64 {
    (0..3)
        .map(|k| t[k].distance(t[(k + 1) % 3]))
        .fold(0.0, f64::max)
}

/// How deeply two triangles interpenetrate: over the separating axes of two triangles (the two
/// face normals and the nine cross products of an edge of each, each normalised), the least
/// distance one triangle's projection must move to clear the other's, as a length. It is
/// negative (a gap) or zero (touching, or coplanar) when some tried axis separates them, and
/// positive exactly when none does: then the triangles cross, and the value is how far one
/// must move to separate them along the best of the tried axes.
///
/// The separating axis theorem for convex polytopes makes these eleven axes sufficient for
/// non-coplanar triangles; for coplanar ones every axis is the common normal (or zero and
/// skipped), whose overlap is 0, so coplanar triangles never count as crossing. Projections are
/// taken relative to `a[0]`, so rounding scales with the triangles' size (a few ulps of it),
/// not with their distance from the origin; callers compare the result with a tolerance
/// relative to that size (see [`crate::self_intersections`]).
pub fn triangle_overlap_depth(a: [DVec3; 3], b: [DVec3; 3]) -> f64 {
    let o = a[0];
    let la = a.map(|p| p - o);
    let lb = b.map(|p| p - o);
    let ea = [la[1] - la[0], la[2] - la[1], la[0] - la[2]];
    let eb = [lb[1] - lb[0], lb[2] - lb[1], lb[0] - lb[2]];
    let mut depth = f64::INFINITY;
    let mut test = |w: DVec3| {
        let len = w.length();
        if len == 0.0 || !len.is_finite() {
            return;
        }
        let w = w / len;
        let pa = la.map(|p| p.dot(w));
        let pb = lb.map(|p| p.dot(w));
        let (amin, amax) = (pa[0].min(pa[1]).min(pa[2]), pa[0].max(pa[1]).max(pa[2]));
        let (bmin, bmax) = (pb[0].min(pb[1]).min(pb[2]), pb[0].max(pb[1]).max(pb[2]));
        // The shorter push that separates the two intervals along `w` (for a flat triangle on
        // its own normal, a point inside the other interval: the distance to its nearer end).
        depth = depth.min((amax - bmin).min(bmax - amin));
    };
    test(ea[0].cross(ea[1]));
    test(eb[0].cross(eb[1]));
    for x in ea {
        for y in eb {
            test(x.cross(y));
        }
    }
    if depth == f64::INFINITY { 0.0 } else { depth }
}

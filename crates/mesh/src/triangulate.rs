//! Ear-clipping triangulation of (possibly non-convex, roughly planar) polygons.
//!
//! The polygon is projected onto the plane perpendicular to its Newell normal, which is the
//! least-squares plane normal for planar-ish polygons and fixes the orientation: ears are the
//! convex corners (counter-clockwise seen from the normal) whose triangle contains no other
//! polygon vertex. Triangles keep the polygon's orientation.

use crate::geometry::newell_normal;
use glam::{DVec2, DVec3};

fn cross2(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// True when `p` lies inside or on the triangle `(a, b, c)` (counter-clockwise).
fn in_triangle(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    cross2(b - a, p - a) >= 0.0 && cross2(c - b, p - b) >= 0.0 && cross2(a - c, p - c) >= 0.0
}

/// Triangulates the polygon with corners `points` (in order) by ear clipping and returns
/// `points.len() - 2` triangles as local corner indices, oriented like the polygon.
///
/// Works for non-convex simple polygons. For a polygon with (numerically) zero Newell normal
/// the projection is undefined and a fan from corner 0 is returned; when no strict ear exists
/// (self-intersecting or badly non-planar input) the most convex corner is clipped, so the
/// result always has `n - 2` triangles and never panics. Fewer than three corners give none.
pub fn triangulate_polygon(points: &[DVec3]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    let normal = newell_normal(points);
    let len = normal.length();
    if len.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !len.is_finite() {
        return (1..n - 1).map(|i| [0, i, i + 1]).collect();
    }
    let nz = normal / len;
    let u = nz.any_orthonormal_vector();
    let v = nz.cross(u);
    let o = points[0];
    let p2: Vec<DVec2> = points
        .iter()
        .map(|&p| DVec2::new((p - o).dot(u), (p - o).dot(v)))
        .collect();
    let mut ring: Vec<usize> = (0..n).collect();
    let mut tris = Vec::with_capacity(n - 2);
    while ring.len() > 3 {
        let m = ring.len();
        let mut best: Option<(usize, f64)> = None;
        let mut ear = None;
        for i in 0..m {
            let (ia, ib, ic) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            let (a, b, c) = (p2[ia], p2[ib], p2[ic]);
            let turn = cross2(b - a, c - b);
            if best.is_none_or(|(_, t)| turn > t) {
                best = Some((i, turn));
            }
            if turn <= 0.0 {
                continue;
            }
            let blocked = ring.iter().any(|&j| {
                j != ia && j != ib && j != ic && {
                    let q = p2[j];
                    q != a && q != b && q != c && in_triangle(q, a, b, c)
                }
            });
            if !blocked {
                ear = Some(i);
                break;
            }
        }
        let i = ear.or(best.map(|(i, _)| i)).unwrap_or(0);
        let m = ring.len();
        tris.push([ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]]);
        ring.remove(i);
    }
    tris.push([ring[0], ring[1], ring[2]]);
    tris
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::triangle_area;

    fn area(points: &[DVec3], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|t| triangle_area(points[t[0]], points[t[1]], points[t[2]]))
            .sum()
    }

    #[test]
    fn l_shape_and_comb() {
        // L-shape, area 3, tilted out of the xy-plane.
        let l: Vec<DVec3> = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]
            .iter()
            .map(|p| DVec3::new(p[0], p[1], 0.3 * p[0] - 0.2 * p[1]))
            .collect();
        let t = triangulate_polygon(&l);
        assert_eq!(t.len(), 4);
        let n = newell_normal(&l);
        assert!((area(&l, &t) - 0.5 * n.length()).abs() < 1e-12);
        for tri in &t {
            let tn = crate::geometry::triangle_normal(l[tri[0]], l[tri[1]], l[tri[2]]);
            assert!(tn.dot(n) > 0.0);
        }
        // A comb with three teeth (area: base 5x1 + 3 teeth of 1x2 = 11).
        let comb: Vec<DVec3> = [
            [0., 0.],
            [5., 0.],
            [5., 3.],
            [4., 3.],
            [4., 1.],
            [3., 1.],
            [3., 3.],
            [2., 3.],
            [2., 1.],
            [1., 1.],
            [1., 3.],
            [0., 3.],
        ]
        .iter()
        .map(|p| DVec3::new(p[0], p[1], 0.0))
        .collect();
        let t = triangulate_polygon(&comb);
        assert_eq!(t.len(), 10);
        assert!((area(&comb, &t) - 11.0).abs() < 1e-12);
    }

    #[test]
    fn clockwise_polygon_keeps_orientation() {
        let sq: Vec<DVec3> = [[0., 0.], [0., 1.], [1., 1.], [1., 0.]]
            .iter()
            .map(|p| DVec3::new(p[0], p[1], 0.0))
            .collect();
        let t = triangulate_polygon(&sq);
        for tri in &t {
            let tn = crate::geometry::triangle_normal(sq[tri[0]], sq[tri[1]], sq[tri[2]]);
            assert!(tn.z < 0.0);
        }
        assert!((area(&sq, &t) - 1.0).abs() < 1e-15);
    }
}

//! A row of points along a region's boundary, inserted before Delaunay refinement so that
//! the faces on the boundary come out near equilateral.
//!
//! Why: refinement with an angle bound alone leaves the faces on a kept boundary edge as
//! flat as the bound allows (a 25° bound admits 25°/25°/130° triangles standing on the
//! edge), and at a sharp rim such faces make the simplicial hull refine: a puck of 96
//! segments whose fan caps were refined so needed 1265 refinements in 8 rounds; with a
//! triangulation whose rim faces are near equilateral, none (`docs/ARCHITECTURE.md`).

use super::grid::{FaceGrid, Grid};
use glam::DVec2;

/// How far inside a face a candidate point must lie (its least barycentric coordinate): off
/// the old faces' edges by more than rounding, so that no point falls on a boundary edge.
const INSIDE: f64 = 1e-9;

/// Distance from `p` to the segment `a b`.
fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    p.distance(a + d * t)
}

/// For each boundary edge `a → b` (local ids into `q`, the region on its left), the apex of
/// the equilateral triangle on it inside the region, where that apex lies inside an old face,
/// at least `0.8` of its height from every other boundary edge and outside their diametral
/// circles (so that refinement, which keeps those edges, never has to split them), and at
/// least `0.6` of the edge's length from the region's vertices and the points taken before.
/// Edges in the order given (sorted), so the result is deterministic.
pub(super) fn rim_points(q: &[DVec2], boundary: &[[usize; 2]], faces: &FaceGrid) -> Vec<DVec2> {
    let mut segments = Grid::new(boundary.len());
    for (i, &[a, b]) in boundary.iter().enumerate() {
        let (mid, r) = ((q[a] + q[b]) * 0.5, q[a].distance(q[b]) * 0.5);
        segments.insert(i as u32, mid - DVec2::splat(r), mid + DVec2::splat(r));
    }
    let mut points: Vec<DVec2> = q.to_vec();
    let mut near_points = Grid::new(q.len() + boundary.len());
    for (i, p) in points.iter().enumerate() {
        near_points.insert(i as u32, *p, *p);
    }
    let mut out = Vec::new();
    for (own, &[a, b]) in boundary.iter().enumerate() {
        let (pa, pb) = (q[a], q[b]);
        let d = pb - pa;
        let l = d.length();
        let h = 0.75f64.sqrt() * l;
        let p = (pa + pb) * 0.5 + d.perp() / l * h;
        if !faces.locate(p).is_some_and(|(_, depth)| depth > INSIDE) {
            continue;
        }
        let reach = DVec2::splat(h);
        let blocked = segments.near(p - reach, p + reach).any(|s| {
            let [c, e] = boundary[s as usize];
            let (pc, pe) = (q[c], q[e]);
            s as usize != own
                && (segment_distance(p, pc, pe) < 0.8 * h
                    || p.distance((pc + pe) * 0.5) <= 0.5 * pc.distance(pe))
        });
        if blocked {
            continue;
        }
        let gap = DVec2::splat(0.6 * l);
        if near_points
            .near(p - gap, p + gap)
            .any(|k| points[k as usize].distance(p) < 0.6 * l)
        {
            continue;
        }
        near_points.insert(points.len() as u32, p, p);
        points.push(p);
        out.push(p);
    }
    out
}

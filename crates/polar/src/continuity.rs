//! C^k conditions between two patches whose domain triangles share an edge (thesis §3.1–3.3):
//! residuals, imposition, measured derivative jumps and the C^1 "diamond" rule (3.5).
//!
//! # Conditions
//! Let A = Δprs and B = Δqrs share the edge (r, s). By Lemma 3.1.4, `F_A` and `F_B` join with
//! C^k continuity along (r, s) iff their polar forms agree on every multiset with at least
//! m − k points on the line rs. Writing the arbitrary points in the frame Δqrs and using
//! multi-affinity, this is iff
//!
//! `f_A(q^h r^i s^j) = f_B(q^h r^i s^j)` for all `h + i + j = m`, `h ≤ k`,
//!
//! i.e. the first k + 1 rows (parallel to the edge) of A's control net written over B's frame
//! equal B's. For k = 0 these are conditions (3.4) (shared boundary curve); for k = 1 the row
//! h = 1 is (3.5):
//! `f_B(q r^i s^{m−i−1}) = λ f_A(p r^i s^{m−i−1}) + μ f_A(r^{i+1} s^{m−i−1}) + ν f_A(r^i s^{m−i})`
//! with `q = λ p + μ r + ν s`: every "diamond" of control points is the affine image of the
//! domain diamond (p, r, s, q).
//!
//! The frames' vertices need not be listed in any particular order: the shared edge is found by
//! matching points ([`SharedEdge::between`]).

use crate::patch::bbox_diagonal;
use crate::{AffineFrame, PolarError, PolarLabel, PolarPatch};
use glam::{DVec2, DVec3};

/// Relative tolerance (times the larger frame diameter) within which two frame points are taken
/// to be the same domain vertex.
pub const VERTEX_MATCH_TOLERANCE: f64 = 1e-9;

/// The common edge (r, s) of two adjacent domain triangles A = Δprs and B = Δqrs (thesis
/// Figure 3.1), with the positions of these points in each patch's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedEdge {
    /// First endpoint of the common edge (the one that comes first in A's frame).
    pub r: DVec2,
    /// Second endpoint of the common edge.
    pub s: DVec2,
    /// The vertex of A opposite the edge.
    pub p: DVec2,
    /// The vertex of B opposite the edge.
    pub q: DVec2,
    /// Indices (0 = r, 1 = s, 2 = t of the frame) of `[r, s, p]` in A's frame.
    pub a_index: [usize; 3],
    /// Indices of `[r, s, q]` in B's frame.
    pub b_index: [usize; 3],
}

impl SharedEdge {
    /// Finds the common edge of two frames: exactly two points must coincide (within
    /// [`VERTEX_MATCH_TOLERANCE`]) and the third points must lie strictly on opposite sides of
    /// the edge (adjacent triangles, as Lemma 3.1.4 and Definition 5.3.2 require); otherwise
    /// [`PolarError::NotAdjacent`].
    pub fn between(a: &AffineFrame, b: &AffineFrame) -> Result<Self, PolarError> {
        let tol = VERTEX_MATCH_TOLERANCE * a.diameter().max(b.diameter());
        let (pa, pb) = (a.points(), b.points());
        let mut pairs = Vec::new();
        for (i, x) in pa.iter().enumerate() {
            if let Some(j) = pb.iter().position(|y| x.distance(*y) <= tol) {
                pairs.push((i, j));
            }
        }
        if pairs.len() != 2 {
            return Err(PolarError::NotAdjacent(format!(
                "the frames share {} points, an edge needs exactly 2",
                pairs.len()
            )));
        }
        let ap = 3 - pairs[0].0 - pairs[1].0;
        let bq = 3 - pairs[0].1 - pairs[1].1;
        let (r, s, p, q) = (pa[pairs[0].0], pa[pairs[1].0], pa[ap], pb[bq]);
        let e = s - r;
        let side_p = e.perp_dot(p - r);
        let side_q = e.perp_dot(q - r);
        if side_p * side_q >= 0.0 {
            return Err(PolarError::NotAdjacent(
                "the opposite vertices lie on the same side of the common edge (the triangles overlap)".into(),
            ));
        }
        Ok(SharedEdge {
            r,
            s,
            p,
            q,
            a_index: [pairs[0].0, pairs[1].0, ap],
            b_index: [pairs[0].1, pairs[1].1, bq],
        })
    }

    /// The domain diamond `[p, r, s, q]`.
    pub fn diamond(&self) -> [DVec2; 4] {
        [self.p, self.r, self.s, self.q]
    }

    /// The point `(1 − u) r + u s` of the edge line.
    pub fn point(&self, u: f64) -> DVec2 {
        self.r + (self.s - self.r) * u
    }
}

/// The multi-index with `counts[c]` copies of the frame point `index[c]`.
fn label_of(index: [usize; 3], counts: [usize; 3]) -> PolarLabel {
    let mut m = [0; 3];
    for c in 0..3 {
        m[index[c]] += counts[c];
    }
    PolarLabel::from_multi_index(m)
}

fn check_degrees(a: &PolarPatch, b: &PolarPatch) -> Result<(), PolarError> {
    if a.degree() != b.degree() {
        return Err(PolarError::DegreeMismatch {
            left: a.degree(),
            right: b.degree(),
        });
    }
    Ok(())
}

fn relative(x: f64, scale: f64) -> f64 {
    if scale > 0.0 { x / scale } else { x }
}

/// How far two patches on adjacent triangles are from a C^k join along their common edge
/// (Lemma 3.1.4): `max |f_A(q^h r^i s^j) − f_B(q^h r^i s^j)|` over `h ≤ k`, divided by the
/// larger control-net size ([`PolarPatch::net_size`]; absolute when both nets are points).
/// Zero (up to rounding) iff the join is C^k. `k ≥ m` measures identity of the polynomials.
pub fn continuity_residual(a: &PolarPatch, b: &PolarPatch, k: usize) -> Result<f64, PolarError> {
    check_degrees(a, b)?;
    let edge = SharedEdge::between(a.frame(), b.frame())?;
    let a_in_b = a.reparametrize(*b.frame());
    let q = edge.b_index[2];
    let worst = b
        .net()
        .zip(a_in_b.control_points())
        .filter(|((l, _), _)| l.multi_index()[q] <= k)
        .map(|((_, pb), pa)| (*pa - pb).length())
        .fold(0.0, f64::max);
    Ok(relative(worst, a.net_size().max(b.net_size())))
}

/// [`continuity_residual`] with k = 0: the boundary curves differ (conditions (3.4)).
pub fn c0_residual(a: &PolarPatch, b: &PolarPatch) -> Result<f64, PolarError> {
    continuity_residual(a, b, 0)
}

/// [`continuity_residual`] with k = 1: conditions (3.4)–(3.5).
pub fn c1_residual(a: &PolarPatch, b: &PolarPatch) -> Result<f64, PolarError> {
    continuity_residual(a, b, 1)
}

/// [`continuity_residual`] with k = 2.
pub fn c2_residual(a: &PolarPatch, b: &PolarPatch) -> Result<f64, PolarError> {
    continuity_residual(a, b, 2)
}

/// Imposes C^k continuity on `b` from `a`: returns `b` with its control points
/// `f_B(q^h r^i s^j)`, `h ≤ k`, replaced by `f_A(q^h r^i s^j)` (for k = 1 these are (3.4) and
/// the diamond rule (3.5)); the rows `h > k` of `b` are kept. With `k ≥ m` the result is the
/// polynomial continuation of `a` (C^∞).
pub fn impose_continuity(
    a: &PolarPatch,
    b: &PolarPatch,
    k: usize,
) -> Result<PolarPatch, PolarError> {
    check_degrees(a, b)?;
    let edge = SharedEdge::between(a.frame(), b.frame())?;
    let a_in_b = a.reparametrize(*b.frame());
    let q = edge.b_index[2];
    let points = b
        .net()
        .zip(a_in_b.control_points())
        .map(|((l, pb), pa)| if l.multi_index()[q] <= k { *pa } else { pb })
        .collect();
    PolarPatch::new(*b.frame(), b.degree(), points)
}

/// The measured jump of derivatives of order ≤ k across the common edge at the edge point
/// `(1 − u) r + u s`: the largest `|D_{d_1}⋯D_{d_j} F_A − D_{d_1}⋯D_{d_j} F_B|` over
/// `j ≤ k` and unit directions `d_i` along and across the edge, each order divided by its
/// natural scale `net_size · n!/(n−j)! / |s − r|^j`. Independent of the control-net test in
/// [`continuity_residual`]: this is Definition 3.1.2 sampled at one point.
pub fn derivative_jump(
    a: &PolarPatch,
    b: &PolarPatch,
    k: usize,
    u: f64,
) -> Result<f64, PolarError> {
    check_degrees(a, b)?;
    let edge = SharedEdge::between(a.frame(), b.frame())?;
    let x = edge.point(u);
    let len = (edge.s - edge.r).length();
    let along = (edge.s - edge.r) / len;
    let across = along.perp();
    let n = a.degree();
    let size = a.net_size().max(b.net_size());
    let mut worst: f64 = 0.0;
    for j in 0..=k.min(n) {
        let falling: f64 = (0..j).map(|i| (n - i) as f64).product();
        let scale = size * falling / len.powi(j as i32);
        for n_along in 0..=j {
            let mut dirs = vec![along; n_along];
            dirs.resize(j, across);
            let d = (a.derivative_along(x, &dirs) - b.derivative_along(x, &dirs)).length();
            worst = worst.max(relative(d, scale));
        }
    }
    Ok(worst)
}

/// The angle (radians) between the unit normals of the two patches at the edge point
/// `(1 − u) r + u s`: 0 for a tangent-plane continuous (G^1) join there. Fails where either
/// patch is singular.
pub fn normal_jump(a: &PolarPatch, b: &PolarPatch, u: f64) -> Result<f64, PolarError> {
    let edge = SharedEdge::between(a.frame(), b.frame())?;
    let x = edge.point(u);
    let (na, nb) = (a.normal(x)?, b.normal(x)?);
    Ok(na.cross(nb).length().atan2(na.dot(nb)))
}

/// The control-point diamonds of the C^1 conditions (3.5) (thesis Figure 3.2), one for each
/// `0 ≤ i ≤ m − 1`: `[f_A(p r^i s^{m−i−1}), f_A(r^{i+1} s^{m−i−1}), f_A(r^i s^{m−i}),
/// f_B(q r^i s^{m−i−1})]`, to be compared with the domain diamond [`SharedEdge::diamond`]
/// `[p, r, s, q]` (e.g. by [`diamond_residual`]).
pub fn c1_diamonds(a: &PolarPatch, b: &PolarPatch) -> Result<Vec<[DVec3; 4]>, PolarError> {
    check_degrees(a, b)?;
    let m = a.degree();
    if m == 0 {
        return Ok(Vec::new());
    }
    let edge = SharedEdge::between(a.frame(), b.frame())?;
    let get_a = |c: [usize; 3]| {
        a.control_point(label_of(edge.a_index, c))
            .expect("degree m label")
    };
    let get_b = |c: [usize; 3]| {
        b.control_point(label_of(edge.b_index, c))
            .expect("degree m label")
    };
    Ok((0..m)
        .map(|i| {
            [
                get_a([i, m - i - 1, 1]),
                get_a([i + 1, m - i - 1, 0]),
                get_a([i, m - i, 0]),
                get_b([i, m - i - 1, 1]),
            ]
        })
        .collect())
}

/// The affine propagation rule of §3.3 and §4.2: the point `z = λ z_0 + μ z_1 + ν z_2` where
/// `target = λ d_0 + μ d_1 + ν d_2` in the domain. Any three non-collinear domain points of a
/// diamond or a corner star determine the fourth this way (choose another three when these are
/// collinear, §4.4.4). Fails with [`PolarError::DegenerateFrame`] when the domain points are
/// collinear.
pub fn affine_propagate(
    domain: [DVec2; 3],
    points: [DVec3; 3],
    target: DVec2,
) -> Result<DVec3, PolarError> {
    let frame = AffineFrame::from_points(domain)?;
    let w = frame.barycentric(target);
    Ok(points[0] * w[0] + points[1] * w[1] + points[2] * w[2])
}

/// The diamond rule (3.5): given `z_p = f_A(p r^i s^{m−i−1})`, `z_r = f_A(r^{i+1} s^{m−i−1})`
/// and `z_s = f_A(r^i s^{m−i})`, the control point `f_B(q r^i s^{m−i−1}) = λ z_p + μ z_r + ν z_s`
/// of the C^1 neighbour, where `q = λ p + μ r + ν s`.
pub fn diamond_apex(
    p: DVec2,
    r: DVec2,
    s: DVec2,
    q: DVec2,
    zp: DVec3,
    zr: DVec3,
    zs: DVec3,
) -> Result<DVec3, PolarError> {
    affine_propagate([p, r, s], [zp, zr, zs], q)
}

/// How far four control points are from being the affine image of four domain points (the
/// quadrilateral rule of the C^1 conditions, §3.3.2): the best-conditioned three domain points
/// predict the fourth control point by [`affine_propagate`]; the result is the prediction error
/// divided by the diagonal of the four points' bounding box (absolute when they coincide).
/// Fails when all four domain points are collinear.
pub fn diamond_residual(domain: [DVec2; 4], points: [DVec3; 4]) -> Result<f64, PolarError> {
    let mut best: Option<(f64, usize, AffineFrame)> = None;
    for skip in 0..4 {
        let idx: Vec<usize> = (0..4).filter(|&i| i != skip).collect();
        if let Ok(f) = AffineFrame::new(domain[idx[0]], domain[idx[1]], domain[idx[2]])
            && best.as_ref().is_none_or(|b| f.relative_area() > b.0)
        {
            best = Some((f.relative_area(), skip, f));
        }
    }
    let Some((_, skip, frame)) = best else {
        return Err(PolarError::DegenerateFrame {
            relative_area: 0.0,
            tolerance: algesurf_bb::simplex::DEGENERACY_TOLERANCE,
        });
    };
    let idx: Vec<usize> = (0..4).filter(|&i| i != skip).collect();
    let w = frame.barycentric(domain[skip]);
    let predicted = points[idx[0]] * w[0] + points[idx[1]] * w[1] + points[idx[2]] * w[2];
    Ok(relative(
        (predicted - points[skip]).length(),
        bbox_diagonal(&points),
    ))
}

//! The nearest apex ([`crate::ApexPlacement::Nearest`]): the point nearest the face's centroid that meets every condition §3.1's
//! `t_max` / `t_min` exist for, without requiring it to lie on the face normal.
//!
//! §3.1 puts the apex on the line `c + t n_ijk` and takes the smallest `t` that lies beyond the
//! three tangent planes (Step 2's coefficients `f_2001`, `f_0201`, `f_0021` positive) and makes
//! the three Step 4 coefficients `f_1101`, `f_0111`, `f_1011` nonnegative. Where a vertex
//! normal `n_l` makes an angle near 90° with the face normal — the rim of a thin sheet — that
//! tangent plane is nearly orthogonal to the face, `t_l = (p_l − c)ᵀn_l / n_ijkᵀn_l` explodes,
//! and the spike crosses its neighbours whatever the refinement (docs/ARCHITECTURE.md, "Apex
//! placement: the nearest apex"). But every one of those conditions is an *affine* inequality in
//! the apex `u`:
//!
//! * Step 2: `(u − p_l)ᵀn_l ≥ ε ℓ n_ijkᵀn_l` — the margin the paper's `t_l + ε` gives on the
//!   normal line (`ℓ` the face's longest edge, `ε` = [`crate::HullOptions::epsilon`]);
//! * Step 4: [`crate::mid_edge_coefficient`]`(u, p_l, p_m, n_l, n_m) ≥ 0`, affine because the
//!   foot of `u` on the edge — hence `α(u, p_l, p_m) = 2 − 3s` — moves affinely with `u`;
//! * a nondegenerate tetrahedron: `(u − c)ᵀn_ijk ≥ h ℓ`
//!   ([`crate::HullOptions::min_apex_height`]);
//!
//! (all reversed for the negative side). Their feasible set is a convex polyhedron containing
//! the paper's apex, so its point nearest `c` — a 3-variable quadratic program — is never
//! farther from the face than the paper's and keeps every sign the construction of §4.2 relies
//! on: nothing downstream assumes the apex lies on the normal (the A-patch rays, the
//! coefficients of Steps 2–4 and the C1 conditions (4.15)–(4.17) are written for a general
//! tetrahedron). At a rim it is the point just beyond the rim and just above the face, so the
//! tetrahedra of the two sides of a thin sheet stay on their own sides.

use crate::classify::Side;
use crate::classify::mid_edge_coefficient;
use glam::DVec3;

/// One affine constraint `aᵀx ≥ b` on the apex offset `x = u − c`.
#[derive(Clone, Copy, Debug)]
struct HalfSpace {
    a: DVec3,
    b: f64,
}

/// The affine constraints of the apex on `side` of the face with corners `p`, vertex normals
/// (gradients) `n` and unit face normal `face_normal`, in the offset `x = u − c`.
fn half_spaces(
    p: [DVec3; 3],
    n: [DVec3; 3],
    face_normal: DVec3,
    margin: f64,
    height: f64,
    side: Side,
) -> [HalfSpace; 7] {
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let s = match side {
        Side::Positive => 1.0,
        Side::Negative => -1.0,
    };
    let mut out = [HalfSpace {
        a: DVec3::ZERO,
        b: 0.0,
    }; 7];
    for l in 0..3 {
        // s (c + x − p_l)ᵀn_l ≥ margin · n_ijkᵀn_l
        out[l] = HalfSpace {
            a: s * n[l],
            b: margin * face_normal.dot(n[l]) - s * (c - p[l]).dot(n[l]),
        };
    }
    // The Step 4 coefficient is affine in u; its gradient is read off exactly from three
    // differences of size ℓ around c (affine, so the differences are the gradient up to
    // rounding of order ε_mach · |coefficient| / ℓ).
    let ell = (0..3)
        .map(|k| p[k].distance(p[(k + 1) % 3]))
        .fold(0.0, f64::max);
    for (e, (l, m)) in [(0, 1), (1, 2), (0, 2)].into_iter().enumerate() {
        let f = |x: DVec3| mid_edge_coefficient(c + x, p[l], p[m], n[l], n[m]);
        let f0 = f(DVec3::ZERO);
        let g = DVec3::new(
            f(DVec3::X * ell) - f0,
            f(DVec3::Y * ell) - f0,
            f(DVec3::Z * ell) - f0,
        ) / ell;
        out[3 + e] = HalfSpace {
            a: s * g,
            b: -s * f0,
        };
    }
    out[6] = HalfSpace {
        a: s * face_normal,
        b: height,
    };
    out
}

/// The point nearest the centroid of the face `p` (corners in mesh order) that satisfies the
/// apex conditions of §3.1 on `side` (see the module docs): Step 2 margins
/// `margin · n_ijkᵀn_l`, Step 4 coefficients of the right sign, and at least `height` off the
/// face. `None` only when no candidate passes the feasibility check (rounding on degenerate
/// input); the caller then keeps the paper's apex.
///
/// Solved exactly by enumerating active sets: the minimiser of `|x|²` over a polyhedron is the
/// projection of 0 onto the affine hull of the constraints active there, at most three of them
/// in 3D; so the nearest feasible point among the projections onto every set of at most three
/// constraint planes (64 small solves) is the optimum.
pub(crate) fn nearest_apex(
    p: [DVec3; 3],
    n: [DVec3; 3],
    face_normal: DVec3,
    margin: f64,
    height: f64,
    side: Side,
) -> Option<DVec3> {
    let c = (p[0] + p[1] + p[2]) / 3.0;
    nearest_in(&half_spaces(p, n, face_normal, margin, height, side)).map(|x| c + x)
}

/// Whether `x` lies in every half-space of `hs` (`norm[i] = |a_i|`), up to the rounding of
/// `aᵀx − b`: a slack of 1e-12 of the terms' size.
fn feasible_in(hs: &[HalfSpace; 7], norm: &[f64; 7], x: DVec3) -> bool {
    let len = x.length();
    hs.iter().zip(norm).all(|(h, an)| {
        let scale = an * len + h.b.abs();
        h.a.dot(x) - h.b >= -1e-12 * scale
    })
}

/// The least-norm point of the half-spaces `hs` (offsets from the centroid; see
/// [`nearest_apex`]), `None` when no candidate passes the feasibility check.
fn nearest_in(hs: &[HalfSpace; 7]) -> Option<DVec3> {
    // Feasibility slack: rounding of aᵀx − b, relative to the terms' size.
    let norm: [f64; 7] = std::array::from_fn(|i| hs[i].a.length());
    let feasible = |x: DVec3| feasible_in(hs, &norm, x);
    // d_i: the distance from 0 (the centroid) to half-space i. Every feasible point is at
    // least max_i d_i away, and the projection onto a set S of planes at least max_{i∈S} d_i:
    // a set whose bound is no better than the best feasible point so far is skipped. The
    // common case — one binding condition — ends at the first candidate.
    let dist: [f64; 7] = std::array::from_fn(|i| hs[i].b.max(0.0) / norm[i]);
    let mut best: Option<DVec3> = None;
    let mut best_len = f64::INFINITY;
    // No feasible point is nearer than the farthest half-space, `dist[order[0]]`: a candidate
    // at that distance (to the rounding of the projection, 1e-12 relative) is the optimum, and
    // the enumeration stops there — the common case, one binding condition, after the first
    // projection instead of all 64 sets. With two or three binding conditions (a symmetric
    // face, a rim) the enumeration stops at the first feasible projection whose multipliers
    // are all non-negative, the optimum by KKT. `consider` says whether either happened.
    let mut order: [usize; 7] = std::array::from_fn(|i| i);
    order.sort_by(|&i, &j| dist[j].total_cmp(&dist[i]));
    let lower = dist[order[0]] * (1.0 + 1e-12);
    let mut consider = |set: &[usize]| -> bool {
        let bound = set.iter().map(|&i| dist[i]).fold(0.0, f64::max);
        if bound >= best_len {
            return best_len <= lower;
        }
        let mut planes = [hs[0]; 3];
        for (slot, &i) in planes.iter_mut().zip(set) {
            *slot = hs[i];
        }
        let (x, lambda) = if set.is_empty() {
            (DVec3::ZERO, [0.0; 3])
        } else {
            project(&planes[..set.len()])
        };
        if !(x.is_finite() && feasible(x)) {
            return false;
        }
        // Karush–Kuhn–Tucker: a feasible `x = Σ_{i∈S} λ_i a_i` with every `λ_i ≥ 0` and
        // `a_iᵀx = b_i` on `S` is the minimiser of the convex problem min ‖x‖² subject to
        // `aᵀx ≥ b` (Nocedal–Wright, Theorem 16.4; the objective is strictly convex, so it is
        // the only one): stop. A multiplier rounded below zero where the exact one is zero
        // (a degenerate vertex) only delays the stop; the enumeration still finds the point.
        let optimal = lambda[..set.len()].iter().all(|&l| l >= 0.0);
        if x.length() < best_len || optimal {
            best = Some(x);
            best_len = x.length();
        }
        optimal || best_len <= lower
    };
    'sets: {
        if consider(&[]) || consider(&[order[0]]) {
            break 'sets;
        }
        for i in 0..7 {
            if consider(&[i]) {
                break 'sets;
            }
            for j in i + 1..7 {
                if consider(&[i, j]) {
                    break 'sets;
                }
                for k in j + 1..7 {
                    if consider(&[i, j, k]) {
                        break 'sets;
                    }
                }
            }
        }
    }
    best
}

/// The apexes `(u, v)` of a nonconvex face, which has both: each at the smallest distance
/// from the centroid on one common line through it.
///
/// The two sides of a nonconvex face are split into three cubics each around the centroid
/// (§4.1), and F must be C1 across the face between them; with `u`, `c`, `v` on one line the
/// internal facets `[p_l, c, u]` and `[p_l, c, v]` are coplanar, the configuration the paper's
/// `u = c + t_max n`, `v = c + t_min n` has, for which the C1 conditions around the edges
/// `[p_l, c]` are consistent (with four different planes around an edge they are not in
/// general). Candidate directions: towards [`nearest_apex`] of either side, and the face
/// normal (the paper's, always feasible); along each the least distances that satisfy each
/// side's conditions, and the direction whose farther apex is nearest wins.
pub(crate) fn nearest_apex_pair(
    p: [DVec3; 3],
    n: [DVec3; 3],
    face_normal: DVec3,
    margin: f64,
    height: f64,
) -> Option<(DVec3, DVec3)> {
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let pos = half_spaces(p, n, face_normal, margin, height, Side::Positive);
    let neg = half_spaces(p, n, face_normal, margin, height, Side::Negative);
    let mut dirs = [face_normal; 3];
    let mut count = 1;
    for (hs, sign) in [(&pos, 1.0), (&neg, -1.0)] {
        if let Some(x) = nearest_in(hs) {
            // The same offset `(c + x) − c` as through `nearest_apex`, bit for bit.
            let d = sign * ((c + x) - c);
            if d.dot(face_normal) > 0.0 {
                dirs[count] = d.normalize();
                count += 1;
            }
        }
    }
    let mut best: Option<(f64, DVec3, DVec3)> = None;
    for &d in &dirs[..count] {
        let (Some(tu), Some(tv)) = (least_along(&pos, d), least_along(&neg, -d)) else {
            continue;
        };
        let score = tu.max(tv);
        if best.is_none_or(|b| score < b.0) {
            best = Some((score, c + tu * d, c - tv * d));
        }
    }
    best.map(|(_, u, v)| (u, v))
}

/// The least `t ≥ 0` with `x = t d` in every half-space (`None` if the ray misses their
/// intersection).
fn least_along(hs: &[HalfSpace; 7], d: DVec3) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    for h in hs {
        let ad = h.a.dot(d);
        // Constraint t·(aᵀd) ≥ b; |aᵀd| at rounding size counts as 0 (then 0 ≥ b must hold).
        if ad.abs() <= 1e-12 * h.a.length() {
            if h.b > 1e-12 * h.b.abs().max(h.a.length()) {
                return None;
            }
        } else if ad > 0.0 {
            lo = lo.max(h.b / ad);
        } else {
            hi = hi.min(h.b / ad);
        }
    }
    (lo <= hi && lo.is_finite()).then_some(lo)
}

/// The least-norm `x` with `aᵀx = b` for the given planes (NaN where they are dependent) and
/// its coefficients `λ` in `x = Σ λ_i a_i` (the Lagrange multipliers of the planes).
///
/// `x = Aᵀλ` with `(A Aᵀ) λ = b`: a Gram system of size ≤ 3, solved by Cramer's rule with a
/// relative singularity test (dependent planes give no unique projection; their projection is
/// covered by a smaller set). Nearly parallel planes make the Gram matrix ill-conditioned: on
/// the slivers of a 512-segment fan (planes 0.7° apart) the solve left residuals of 1.0e-12 of
/// the terms' size on its own planes, just beyond [`feasible_in`]'s slack, so the optimum was
/// rejected and an apex 1e-3 away taken, by the last bit of a normal (the surface moved by
/// 1.5 % of the fan's radius with the order of the faces). Where the residual is beyond
/// [`REFINE_RESIDUAL`], one step of iterative refinement (solve `G δ = b − A x` with the same
/// matrix, `λ += δ`; Higham, *Accuracy and Stability of Numerical Algorithms*, §12.2) brings
/// it to rounding size; elsewhere the solution is the plain solve's, bit for bit.
fn project(planes: &[HalfSpace]) -> (DVec3, [f64; 3]) {
    let k = planes.len();
    let mut g = [[0.0; 3]; 3];
    let mut rhs = [0.0; 3];
    for r in 0..k {
        rhs[r] = planes[r].b;
        for s in 0..k {
            g[r][s] = planes[r].a.dot(planes[s].a);
        }
    }
    let Some(mut lambda) = solve_gram(&g, rhs, k) else {
        return (DVec3::NAN, [f64::NAN; 3]);
    };
    let combine = |lambda: &[f64; 3]| {
        planes
            .iter()
            .zip(lambda)
            .fold(DVec3::ZERO, |x, (h, &l)| x + l * h.a)
    };
    let mut x = combine(&lambda);
    if k < 2 {
        // One plane: x = (b / |a|²) a, within a few roundings of it (no system to condition).
        return (x, lambda);
    }
    let mut residual = [0.0; 3];
    let mut refine = false;
    for (r, h) in residual.iter_mut().zip(planes) {
        *r = h.b - h.a.dot(x);
        // The size of the terms `b − aᵀx` sums: its rounding scale.
        let terms = (h.a * x).abs().element_sum() + h.b.abs();
        refine |= r.abs() > REFINE_RESIDUAL * terms;
    }
    if refine && let Some(delta) = solve_gram(&g, residual, k) {
        for (l, d) in lambda.iter_mut().zip(delta) {
            *l += d;
        }
        x = combine(&lambda);
    }
    (x, lambda)
}

/// Relative residual of a projection on its own planes beyond which [`project`] refines it:
/// 1e-13, a hundred times the rounding of a well-conditioned solve (a few `u = 1.1e-16` of the
/// terms' size) and a tenth of [`feasible_in`]'s slack.
const REFINE_RESIDUAL: f64 = 1e-13;

/// `λ` with `G λ = rhs` for the leading `k × k` block of the Gram matrix `g`, by Cramer's rule;
/// `None` when the block is singular relative to its diagonal.
#[inline(always)]
fn solve_gram(g: &[[f64; 3]; 3], rhs: [f64; 3], k: usize) -> Option<[f64; 3]> {
    match k {
        1 => (g[0][0] > 0.0).then(|| [rhs[0] / g[0][0], 0.0, 0.0]),
        2 => {
            let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
            (det.abs() > 1e-12 * g[0][0] * g[1][1]).then(|| {
                [
                    (rhs[0] * g[1][1] - g[0][1] * rhs[1]) / det,
                    (g[0][0] * rhs[1] - rhs[0] * g[1][0]) / det,
                    0.0,
                ]
            })
        }
        _ => {
            let m = glam::DMat3::from_cols_array_2d(g).transpose();
            let det = m.determinant();
            (det.abs() > 1e-12 * g[0][0] * g[1][1] * g[2][2])
                .then(|| (m.inverse() * DVec3::from_array(rhs)).to_array())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::apex_parameters;

    /// The least-norm point of `hs` that the enumeration of every active set gives (the
    /// feasible projection of least norm), without the early stops: the reference for the
    /// stops.
    fn exhaustive_in(hs: &[HalfSpace; 7]) -> Option<DVec3> {
        let norm: [f64; 7] = std::array::from_fn(|i| hs[i].a.length());
        let feasible = |x: DVec3| feasible_in(hs, &norm, x);
        let mut sets: Vec<Vec<usize>> = vec![vec![]];
        for i in 0..7 {
            sets.push(vec![i]);
            for j in i + 1..7 {
                sets.push(vec![i, j]);
                for k in j + 1..7 {
                    sets.push(vec![i, j, k]);
                }
            }
        }
        sets.iter()
            .map(|set| {
                let planes: Vec<HalfSpace> = set.iter().map(|&i| hs[i]).collect();
                if set.is_empty() {
                    DVec3::ZERO
                } else {
                    project(&planes).0
                }
            })
            .filter(|x| x.is_finite() && feasible(*x))
            .min_by(|a, b| a.length().total_cmp(&b.length()))
    }

    /// The early stops (one binding condition at its distance; a KKT point) give the apex the
    /// whole enumeration gives, on faces with one, two and three binding conditions:
    /// regular faces with symmetric normals (three), rims (two) and random ones.
    #[test]
    fn early_stops_give_the_least_norm_apex() {
        let mut rng = algesurf_mesh::test_rng::Lcg(3);
        let mut worst = 0.0f64;
        let mut found = 0;
        for case in 0..600 {
            let p = if case % 3 == 0 {
                // Regular, with normals tilted symmetrically away from the centroid.
                [0.0f64, 1.0, 2.0].map(|k| {
                    let a = k * std::f64::consts::TAU / 3.0;
                    DVec3::new(a.cos(), a.sin(), 0.0)
                })
            } else {
                [rng.point(), rng.point(), rng.point()]
            };
            let nf = (p[1] - p[0]).cross(p[2] - p[0]);
            if nf.length() < 1e-3 {
                continue;
            }
            let nf = nf.normalize();
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let spread = [0.2, 0.6, 1.2][case % 3];
            let n = p.map(|x| {
                let out = (x - c) * spread * (0.5 + rng.next());
                (nf + out + rng.vec() * 0.3 * (case % 2) as f64).normalize()
            });
            let margin = 0.1 * p[0].distance(p[1]);
            for side in [Side::Positive, Side::Negative] {
                let hs = half_spaces(p, n, nf, margin, margin, side);
                let (fast, all) = (
                    nearest_in(&hs).map(|x| c + x),
                    exhaustive_in(&hs).map(|x| c + x),
                );
                assert_eq!(fast.is_some(), all.is_some(), "case {case} {side:?}");
                if let (Some(a), Some(b)) = (fast, all) {
                    found += 1;
                    worst = worst.max(a.distance(b) / a.distance(c).max(margin));
                }
            }
        }
        assert!(found > 800, "{found} apexes");
        assert!(worst < 1e-12, "largest relative distance {worst:e}");
    }

    /// A face along a rim: the corners on the rim edge carry normals 80° from the face
    /// normal, tilted away from the face across that edge.
    #[test]
    fn nearest_apex_meets_every_condition_and_is_never_farther_than_the_papers() {
        let p = [
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.1, 0.0),
            DVec3::new(0.2, 1.5, 0.1),
        ];
        let tilt = 80f64.to_radians();
        let n = [
            DVec3::new(-0.1, -tilt.sin(), tilt.cos()).normalize(),
            DVec3::new(0.1, -tilt.sin(), tilt.cos()).normalize(),
            DVec3::new(0.0, 0.2, 1.0).normalize(),
        ];
        let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let margin = 0.1 * p[0].distance(p[2]).max(p[0].distance(p[1]));
        let ap = apex_parameters(p, n, nf, margin).unwrap();
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let u = nearest_apex(p, n, nf, margin, margin, Side::Positive).unwrap();
        // The paper's apex climbs the normal until it clears the steep tangent planes (2.80
        // here); the nearest one (1.60) is never farther.
        assert!(
            u.distance(c) <= ap.t_max,
            "{} vs {}",
            u.distance(c),
            ap.t_max
        );
        for l in 0..3 {
            assert!((u - p[l]).dot(n[l]) >= margin * nf.dot(n[l]) * (1.0 - 1e-9));
        }
        for (l, m) in [(0, 1), (1, 2), (0, 2)] {
            assert!(mid_edge_coefficient(u, p[l], p[m], n[l], n[m]) >= -1e-12);
        }
        assert!((u - c).dot(nf) >= margin * (1.0 - 1e-9));
        // The negative side, mirrored.
        let v = nearest_apex(p, n, nf, margin, margin, Side::Negative).unwrap();
        for l in 0..3 {
            assert!((v - p[l]).dot(n[l]) <= -margin * nf.dot(n[l]) * (1.0 - 1e-9));
        }
    }

    /// A sliver of a 512-segment fan (cap at z = 1, hub normal +z, rim normals 72.7° off the
    /// cap), with a rim normal in two versions 5e-16 apart. The binding planes (Step 2 at the
    /// two rim corners, Step 4 along a long edge) are 0.7° apart; the optimum, computed in
    /// exact rational arithmetic over all 64 active sets (Python `fractions`), is the same
    /// projection for both to 17 digits. The plain solve missed it for the first version
    /// (residual 1.0e-12 on its own planes, just beyond the feasibility slack) and returned
    /// a vertex 1e-3 away.
    #[test]
    fn a_fan_slivers_apex_is_the_exact_optimum() {
        let p = [
            [0.0, 0.0, 1.0],
            [0.9972904566786902, 0.07356456359966743, 1.0],
            [0.996312612182778, 0.0857973123444399, 1.0],
        ]
        .map(DVec3::from_array);
        let rim = [0.9511116663061405, 0.08102136719009032, 0.29803042843811317];
        let n_a = [
            [0.0, 0.0, 1.0],
            [0.9520343061567059, 0.06934366319792615, 0.29803042843812433],
            rim,
        ]
        .map(DVec3::from_array);
        let n_b = [
            [0.0, 0.0, 1.0],
            [0.9520343061567064, 0.06934366319792139, 0.29803042843812433],
            rim,
        ]
        .map(DVec3::from_array);
        let face_normal = DVec3::new(0.0, 0.0, 0.9999999999999999);
        let longest = (0..3)
            .map(|k| p[k].distance(p[(k + 1) % 3]))
            .fold(0.0, f64::max);
        let exact = DVec3::new(
            0.039983162002660076,
            0.0025423661646639816,
            1.0394048900159922,
        );
        let c = (p[0] + p[1] + p[2]) / 3.0;
        for n in [n_a, n_b] {
            let (margin, height) = (0.1 * longest, 0.1 * longest);
            let u = nearest_apex(p, n, face_normal, margin, height, Side::Positive).unwrap();
            let off = (u - c).distance(exact);
            // The offset's own rounding: |x| ≈ 1, a few units in its last place.
            assert!(off <= 1e-14, "{off:e}");
            let hs = half_spaces(p, n, face_normal, margin, height, Side::Positive);
            assert_eq!(exhaustive_in(&hs).map(|x| c + x), Some(u));
        }
    }
}
#[cfg(test)]
mod cone_probe {
    use super::*;
    #[test]
    fn cone_probe() {
        let p = [
            [0.0, 0.0, 1.5],
            [-0.9569403357322089, -0.2902846772544621, 0.0],
            [-0.9238795325112868, -0.38268343236508967, 0.0],
        ]
        .map(DVec3::from_array);
        let n1 = [
            [-3.4694469519536136e-17, -1.1449174941446927e-16, 1.0],
            [-0.9569403357322638, -0.2902846772542814, 0.0],
            [-0.9238795325112755, -0.38268343236511676, 0.0],
        ]
        .map(DVec3::from_array);
        let n2 = [
            [3.4760810780567357e-17, -1.144716250129491e-16, 1.0],
            [-0.9569403357322638, -0.2902846772542814, 0.0],
            [-0.9238795325112755, -0.38268343236511676, 0.0],
        ]
        .map(DVec3::from_array);
        let fnorm = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let longest = (0..3)
            .map(|k| p[k].distance(p[(k + 1) % 3]))
            .fold(0.0, f64::max);
        for n in [n1, n2] {
            let hs = half_spaces(p, n, fnorm, 0.1 * longest, 0.1 * longest, Side::Positive);
            for h in hs.iter() {
                eprintln!("HS {:?} {:?} {:?} {:?}", h.a.x, h.a.y, h.a.z, h.b);
            }
            let x = nearest_in(&hs).unwrap();
            eprintln!("X {:?} {}", x.to_array(), x.length());
        }
        eprintln!("FN {:?}", fnorm.to_array());
    }
}

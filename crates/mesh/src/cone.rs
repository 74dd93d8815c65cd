//! The axis of the narrowest cone around unit normals that fit in an open hemisphere, exactly
//! (to rounding): the direction `m` that maximises `t = min_i n_iᵀm`.
//!
//! For `t > 0` the problem is the least-norm point of the polyhedron `{x : n_iᵀx ≥ 1}`: a
//! point `x` of it gives the direction `x/|x|` with every `n_iᵀ(x/|x|) ≥ 1/|x|`, so the
//! least-norm point gives the largest least cosine, `t = 1/|x|`, at `m = x/|x|`. That is a
//! strictly convex quadratic program in three variables, an LP-type problem of combinatorial
//! dimension three (Seidel 1991; Matoušek, Sharir and Welzl 1996): taking the constraints in
//! turn, the optimum of the first `i` either satisfies constraint `i + 1` or the new optimum
//! lies on its plane, which is the same problem one dimension down. The recursion ends at
//! three planes, which fix a point. Taking the constraints most binding first (least cosine
//! with an approximate axis) makes the later ones rarely violated, so a vertex's handful of
//! faces costs a few projections.

use glam::{DMat3, DVec3};

/// Slack of the test `n_iᵀx ≥ 1` (the right side is 1 and `|n_i| = 1`, so this is relative
/// to the terms' size whenever `|x|` is of order one, and generous beyond, where `x` is long
/// because the cone is wide and its least cosine `1/|x|` small): a thousand roundings.
const VIOLATION: f64 = 1e-13;

/// The least-norm point `x` with `n_iᵀx ≥ 1` for every unit `n_i` in `normals`; `None` when
/// there is none (the normals fit in no open hemisphere), or when rounding makes three
/// binding planes indistinguishable. `order` lists the indices of `normals` in the order they
/// are taken (any order gives the same point, up to rounding).
pub(crate) fn least_norm_point(normals: &[DVec3], order: &[usize]) -> Option<DVec3> {
    let taken: Vec<DVec3> = order.iter().map(|&i| normals[i]).collect();
    solve(&taken, &[])
}

/// The least-norm point on the planes `n_eᵀx = 1` (`on`, at most three) that satisfies every
/// constraint of `constraints`.
fn solve(constraints: &[DVec3], on: &[DVec3]) -> Option<DVec3> {
    let mut x = project(on)?;
    for (i, &n) in constraints.iter().enumerate() {
        if n.dot(x) >= 1.0 - VIOLATION * x.length().max(1.0) {
            continue;
        }
        if on.len() == 3 {
            // Three planes fix the point, and it violates another constraint: no point of
            // the polyhedron lies on those three planes.
            return None;
        }
        let mut planes = on.to_vec();
        planes.push(n);
        x = solve(&constraints[..i], &planes)?;
    }
    Some(x)
}

/// The least-norm point on the planes `n_eᵀx = 1` (`x = Σ λ_e n_e` with the Gram system
/// `(n_eᵀn_f) λ = 1`), `None` where the planes are dependent (relative to the Gram matrix's
/// diagonal): the origin for no plane.
fn project(on: &[DVec3]) -> Option<DVec3> {
    match on {
        [] => Some(DVec3::ZERO),
        [a] => Some(*a / a.length_squared()),
        [a, b] => {
            let (aa, ab, bb) = (a.dot(*a), a.dot(*b), b.dot(*b));
            let det = aa * bb - ab * ab;
            if det <= 1e-12 * aa * bb {
                return None;
            }
            let (la, lb) = ((bb - ab) / det, (aa - ab) / det);
            Some(*a * la + *b * lb)
        }
        [a, b, c] => {
            let m = DMat3::from_cols(*a, *b, *c).transpose();
            let det = m.determinant();
            if det.abs() <= 1e-12 * a.length() * b.length() * c.length() {
                return None;
            }
            // x with a·x = b·x = c·x = 1: the rows of `m` are the planes' normals.
            Some(m.inverse() * DVec3::ONE)
        }
        _ => None,
    }
}

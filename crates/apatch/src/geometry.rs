//! Small geometric helpers shared by the face, split-face and edge constructions.

use algesurf_bb::{BbPoly, Tetrahedron};
use glam::DVec3;

/// The point on the line through `a` and `b` closest to `x`.
pub(crate) fn foot(x: DVec3, a: DVec3, b: DVec3) -> DVec3 {
    let e = b - a;
    a + e * ((x - a).dot(e) / e.length_squared())
}

/// Barycentric coordinates of `p` in `t`, with exact unit vectors for `t`'s own vertices
/// (`Tetrahedron::barycentric` would round them, and blossoms at vertices must be exact for the
/// C0/C1 coefficients they produce to match their neighbours bit for bit where possible).
pub(crate) fn exact_barycentric(t: &Tetrahedron, p: DVec3) -> [f64; 4] {
    if let Some(i) = (0..4).find(|&i| t.vertex(i) == p) {
        let mut e = [0.0; 4];
        e[i] = 1.0;
        return e;
    }
    t.barycentric(p)
}

/// Components of the barycentric coordinates of a split face's sub-tetrahedron vertex in its
/// neighbour's coordinates that are zero in exact arithmetic come out of
/// [`Tetrahedron::barycentric`] as rounding, ~1e-16 of the largest (up to ~1e-13 where the
/// apexes were placed far from the origin relative to the face size): `1e-11` of the largest
/// is above that, and far below any component the geometry gives there — the other face
/// vertex is `(−1, −1, 3, 0)` in a sub-tetrahedron of the same side, the other apex
/// `(0, 0, 1 + r, −r)` with `r` the ratio of the two apex distances from the centroid, both of
/// order 1.
/// Not for general points or directions: the mid-edge directions of a split face have
/// components that are zero in exact arithmetic too, but there the computed ones matter (see
/// `split::constraints`).
const ROUNDING_ZERO: f64 = 1e-11;

/// `x` with the components at rounding level (at most [`ROUNDING_ZERO`] of the largest) made
/// exact zeros, their sum moved onto the largest component so that the total (1 for a point)
/// is kept. The point moves by at most `1e-11` of the tetrahedron's size; C1 rows built from it
/// then carry exact zero weights where the geometry has them (a split face's centroid lies in
/// the plane of every sub-triangle, its two apexes on one line through the centroid), which
/// lets the split-face solve eliminate them one at a time (`split::force_determined_unknowns`)
/// instead of densely.
pub(crate) fn snap_rounding_zeros(mut x: [f64; 4]) -> [f64; 4] {
    let (big, largest) = x.iter().enumerate().fold((0, 0.0f64), |(bi, bv), (i, v)| {
        if v.abs() > bv { (i, v.abs()) } else { (bi, bv) }
    });
    let mut moved = 0.0;
    for (i, v) in x.iter_mut().enumerate() {
        if i != big && *v != 0.0 && v.abs() <= ROUNDING_ZERO * largest {
            moved += *v;
            *v = 0.0;
        }
    }
    x[big] += moved;
    x
}

/// Value and Cartesian gradient at `x` of `poly + R` on `tet`, where `rational(τ)` returns R's
/// value and formal partials `∂R/∂τ_i` (R homogeneous of degree 3, so the partials combine with
/// the barycentric gradients like a polynomial's).
pub(crate) fn value_gradient_with(
    tet: &Tetrahedron,
    poly: &BbPoly<f64, 4>,
    x: DVec3,
    rational: impl Fn([f64; 4]) -> (f64, [f64; 4]),
) -> (f64, DVec3) {
    let tau = tet.barycentric(x);
    let (r, dr) = rational(tau);
    let g = tet.barycentric_gradients();
    let mut grad = poly.gradient_at(tet, x);
    for i in 0..4 {
        grad += g[i] * dr[i];
    }
    (poly.eval(tau) + r, grad)
}

/// Cartesian gradient `Σ_i (∂P/∂τ_i + ∂R/∂τ_i) ∇τ_i` from the formal partials of the
/// polynomial part `dp` and of the rational part `dr` (both homogeneous of degree 3, so the
/// formal partials combine with the constant barycentric gradients, see `rational`).
pub(crate) fn gradient_from_partials(tet: &Tetrahedron, dp: [f64; 4], dr: [f64; 4]) -> DVec3 {
    let g = tet.barycentric_gradients();
    let mut grad = DVec3::ZERO;
    for i in 0..4 {
        grad += g[i] * (dp[i] + dr[i]);
    }
    grad
}

/// `τ_apex²` as a cubic on a tetrahedron with the apex last: 1/3 on the layer λ_3 = 2, 1 at the
/// apex. Raising a face side's apex value by δ adds exactly δ·τ_apex² to its pieces: for a convex
/// face through (4.14); for a split face because τ_apex² meets every hard constraint (zero value
/// and gradient on the face plane, C1 everywhere) with 1 at the apex, so the constrained
/// least-squares solution moves by exactly that. (Construction adds it in place,
/// [`add_apex_square`]; the tests compare with this polynomial.)
#[cfg(test)]
pub(crate) fn apex_square() -> BbPoly<f64, 4> {
    BbPoly::from_fn(3, |l| match l[3] {
        2 => 1.0 / 3.0,
        3 => 1.0,
        _ => 0.0,
    })
}

/// `poly + δ·τ_apex²` in place (`apex_square`): `(1/3)·δ` added on the layer λ_3 = 2 and δ at
/// the apex, the same products and sums as `poly.add_poly(&apex_square().scale(δ))` (the other
/// coefficients would add `0·δ`), without the two allocations.
pub(crate) fn add_apex_square(poly: &mut BbPoly<f64, 4>, delta: f64) {
    debug_assert_eq!(poly.degree(), 3);
    for (l, c) in crate::cubic::INDICES3.iter().zip(poly.coeffs_mut()) {
        match l[3] {
            2 => *c += (1.0 / 3.0) * delta,
            3 => *c += delta,
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Adding in place gives the bits of adding the scaled polynomial.
    #[test]
    fn apex_square_is_added_in_place_bit_for_bit() {
        let poly =
            BbPoly::<f64, 4>::new(3, (0..20).map(|i| (i as f64 * 0.37).sin()).collect()).unwrap();
        for delta in [0.7, -1.3e-3, 123.456] {
            let mut fast = poly.clone();
            add_apex_square(&mut fast, delta);
            let slow = poly.add_poly(&apex_square().scale(delta));
            let bits =
                |p: &BbPoly<f64, 4>| p.coeffs().iter().map(|c| c.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&slow), "δ = {delta}");
        }
    }
}

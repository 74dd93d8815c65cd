//! The rational terms of (4.1)–(4.4) of Xu–Huang–Bajaj 2001 and their derivatives.
//!
//! Both are homogeneous of degree 3 in the barycentric coordinates, so their formal partial
//! derivatives combine with the barycentric gradients exactly like those of a BB polynomial
//! (`∇F = Σ_i ∂F/∂τ_i ∇τ_i`, valid for any extension off the plane Σ τ = 1 because
//! Σ ∇τ_i = 0).

/// Face term (4.1), evaluated at the coordinates clamped to the tetrahedron (τ_i ≥ 0): `6 τ0τ1τ2 · (r0 τ1τ2 + r1 τ0τ2 + r2 τ0τ1) / (τ1τ2 + τ0τ2 + τ0τ1)`.
///
/// `r[a]` is the value the blend takes on the face edge opposite vertex `a` (where `τ_a = 0`),
/// so near that edge the term acts like an extra `r[a]` on the centre coefficient `f_1110`.
/// Where two of τ0, τ1, τ2 vanish (the segments from a face vertex to the apex) the blend is
/// undefined but the term vanishes to second order, so value and gradient are 0 there.
/// Returns the value and the formal partials `∂/∂τ_i`, i = 0..4 (the last is 0).
pub fn face_term(tau: [f64; 4], r: [f64; 3]) -> (f64, [f64; 4]) {
    // The blend is a convex combination of r only for τ ≥ 0. At a mesh vertex the computed
    // coordinates carry ±ε noise; with mixed signs the denominator cancels and the blend leaves
    // [min r, max r], which showed up as 1e-13 errors in ∇F at vertices. F lives inside its
    // tetrahedron, so evaluating at the clamped coordinates is exact there and changes values on
    // the boundary only by rounding.
    let [t0, t1, t2, _] = tau.map(|t| t.max(0.0));
    let s = t1 * t2 + t0 * t2 + t0 * t1;
    let w = [t1 * t2, t0 * t2, t0 * t1];
    let scale = (t0.abs() + t1.abs() + t2.abs()).powi(2);
    // |s| below 1e-300 relative: on the singular segments; the term and its gradient vanish.
    if s.abs() <= 1e-300 * scale.max(f64::MIN_POSITIVE) {
        return (0.0, [0.0; 4]);
    }
    let num = r[0] * w[0] + r[1] * w[1] + r[2] * w[2];
    let blend = num / s;
    let b = 6.0 * t0 * t1 * t2;
    // ∂w/∂τ: w0 = τ1τ2, w1 = τ0τ2, w2 = τ0τ1.
    let dw = [
        [0.0, t2, t1], // ∂/∂τ0 of (w0, w1, w2)
        [t2, 0.0, t0], // ∂/∂τ1
        [t1, t0, 0.0], // ∂/∂τ2
    ];
    let ds = [t1 + t2, t0 + t2, t0 + t1];
    let db = [6.0 * t1 * t2, 6.0 * t0 * t2, 6.0 * t0 * t1];
    let mut grad = [0.0; 4];
    for i in 0..3 {
        let dnum = r[0] * dw[i][0] + r[1] * dw[i][1] + r[2] * dw[i][2];
        let dblend = (dnum * s - num * ds[i]) / (s * s);
        grad[i] = dblend * b + blend * db[i];
    }
    (blend * b, grad)
}

/// Edge term of (4.3)/(4.4) on the edge tetrahedron `[u_l, p_i, p_j, u_k]`:
/// `Σ_{m = 1,2} (a_m τ0 + b_m τ3)/(τ0 + τ3) · 6 τ0 τ_m τ3`, with `(a_1, b_1)` the pair of
/// `B_1101` and `(a_2, b_2)` that of `B_1011`. On the face `τ0 = 0` (shared with the face
/// tetrahedron of `u_k`) the blend is `b`, on `τ3 = 0` it is `a`. Where τ0 = τ3 = 0 (the mesh
/// edge) the term vanishes to second order. Returns value and formal partials.
pub fn edge_term(tau: [f64; 4], ab: [[f64; 2]; 2]) -> (f64, [f64; 4]) {
    // Clamped for the same reason as in `face_term`.
    let [t0, t1, t2, t3] = tau.map(|t| t.max(0.0));
    let s = t0 + t3;
    if s.abs() <= 1e-300 {
        return (0.0, [0.0; 4]);
    }
    let mut val = 0.0;
    let mut grad = [0.0; 4];
    for (m, tm) in [(1usize, t1), (2usize, t2)] {
        let [a, b] = ab[m - 1];
        let blend = (a * t0 + b * t3) / s;
        let dblend0 = (a * s - (a * t0 + b * t3)) / (s * s);
        let dblend3 = (b * s - (a * t0 + b * t3)) / (s * s);
        let basis = 6.0 * t0 * tm * t3;
        val += blend * basis;
        grad[0] += dblend0 * basis + blend * 6.0 * tm * t3;
        grad[3] += dblend3 * basis + blend * 6.0 * t0 * tm;
        grad[m] += blend * 6.0 * t0 * t3;
    }
    (val, grad)
}

//! Smooth joins of BB polynomials across a shared facet, and the vertex formulas.
//!
//! Two polynomials `p` on `T = [v_0 … v_{N−1}]` and `q` on `T' = T` with vertex `j` replaced by
//! a point `w` (barycentric coordinates `β` with respect to `T`) join with C^r continuity across
//! the common facet iff every coefficient of `q` with `λ_j ≤ r` equals the corresponding
//! coefficient of `p` re-expressed on `T'`:
//!
//! `q_λ = b[β^{λ_j}, v_i^{λ_i} (i ≠ j)]` for all `λ_j ≤ r`,
//!
//! the blossom of `p` with `λ_j` copies of `β` and `λ_i` copies of the unit vector `e_i`
//! (Farin 1990 p. 318; Lemma 2.3 (2.7)–(2.9) of Bajaj–Chen–Xu 1994 for r ≤ 2 with j the first
//! vertex; Lemma 2.2 (2.2)–(2.3) of Xu–Huang–Bajaj 2001 for r = 1). Note (2.9) of the 1994 paper
//! misprints its left side as `b_{1λ2λ3λ4}`; it is `b_{2λ2λ3λ4}` (READING-NOTES.md).
//!
//! ```
//! use algesurf_bb::{BbPoly, continuity};
//! // A cubic on the reference tetrahedron, continued C^1 across the facet opposite vertex 0
//! // to the tetrahedron whose apex has barycentric coordinates (−1, 0.5, 0.3, 1.2).
//! let p = BbPoly::<f64, 4>::from_fn(3, |l| (l[0] * l[0] + 2 * l[1] + l[3]) as f64);
//! let beta = [-1.0, 0.5, 0.3, 1.2];
//! let mut q = BbPoly::<f64, 4>::zero(3);
//! continuity::impose_cr(&p, &mut q, 0, beta, 1).unwrap();
//! let res = continuity::cr_residual(&p, &q, 0, beta, 1).unwrap();
//! assert!(res.iter().all(|&r| r < 1e-14));
//! ```

use crate::multi_index::{self, MultiIndex};
use crate::{BbError, BbPoly, Coeff};
use glam::{DMat3, DVec3};

fn check_facet<const N: usize>(j: usize, beta: &[f64; N]) -> Result<(), BbError> {
    if j >= N {
        return Err(BbError::Index(format!(
            "vertex {j} of a simplex with {N} vertices"
        )));
    }
    if beta.iter().any(|b| !b.is_finite()) {
        return Err(BbError::NonFinite {
            what: "barycentric coordinates β of the opposite vertex",
        });
    }
    if beta[j].abs() < 1e-12 {
        // β_j is the signed volume ratio vol(T')/vol(T): zero means T' is flat.
        return Err(BbError::InvalidArgument(format!(
            "the opposite vertex lies on the shared facet (β_{j} = {:e}): the neighbour simplex is degenerate",
            beta[j]
        )));
    }
    let sum: f64 = beta.iter().sum();
    if (sum - 1.0).abs() > 1e-9 {
        return Err(BbError::InvalidArgument(format!(
            "barycentric coordinates must sum to 1, they sum to {sum}"
        )));
    }
    Ok(())
}

/// The coefficient of `p` re-expressed on the neighbour simplex (vertex `j` replaced by `β`):
/// the blossom `b[β^{λ_j}, e_i^{λ_i}]`.
pub fn neighbour_coefficient<C: Coeff, const N: usize>(
    p: &BbPoly<C, N>,
    j: usize,
    beta: [f64; N],
    lambda: MultiIndex<N>,
) -> C {
    let mut args = Vec::with_capacity(p.degree());
    for (i, &l) in lambda.iter().enumerate() {
        let mut v = [0.0; N];
        if i == j {
            v = beta;
        } else {
            v[i] = 1.0;
        }
        args.extend(std::iter::repeat_n(v, l));
    }
    p.blossom(&args)
        .expect("argument count equals the degree by construction")
}

/// The whole polynomial `p` written on the neighbour simplex (vertex `j` replaced by the point
/// with barycentric coordinates `β`): its analytic continuation, C^∞ across the facet.
pub fn continuation<C: Coeff, const N: usize>(
    p: &BbPoly<C, N>,
    j: usize,
    beta: [f64; N],
) -> Result<BbPoly<C, N>, BbError> {
    check_facet(j, &beta)?;
    Ok(BbPoly::from_fn(p.degree(), |l| {
        neighbour_coefficient(p, j, beta, l)
    }))
}

/// The coefficients of the neighbour that C^r continuity determines: every `λ` with
/// `λ_j ≤ r`, with its value, in storage order.
pub fn cr_coefficients<C: Coeff, const N: usize>(
    p: &BbPoly<C, N>,
    j: usize,
    beta: [f64; N],
    r: usize,
) -> Result<Vec<(MultiIndex<N>, C)>, BbError> {
    check_facet(j, &beta)?;
    Ok(multi_index::iter::<N>(p.degree())
        .filter(|l| l[j] <= r)
        .map(|l| (l, neighbour_coefficient(p, j, beta, l)))
        .collect())
}

/// Sets the coefficients of `q` (on the neighbour simplex) that C^r continuity with `p`
/// determines, leaving the others (`λ_j > r`) free.
pub fn impose_cr<C: Coeff, const N: usize>(
    p: &BbPoly<C, N>,
    q: &mut BbPoly<C, N>,
    j: usize,
    beta: [f64; N],
    r: usize,
) -> Result<(), BbError> {
    if q.degree() != p.degree() {
        return Err(BbError::Degree(format!(
            "both sides of a facet need one degree ({} vs {})",
            p.degree(),
            q.degree()
        )));
    }
    for (l, c) in cr_coefficients(p, j, beta, r)? {
        q.set(l, c);
    }
    Ok(())
}

/// How far `p` (on T) and `q` (on T') are from a C^r join across the facet opposite vertex
/// `j`: entry `k` (k = 0..=r) is `max |q_λ − b[β^k, …]|` over the layer `λ_j = k`, divided by
/// the larger coefficient norm of the two polynomials (1 when both vanish). Entry k is ~ε for
/// a C^k join and of order one when the join is not C^k.
pub fn cr_residual<C: Coeff, const N: usize>(
    p: &BbPoly<C, N>,
    q: &BbPoly<C, N>,
    j: usize,
    beta: [f64; N],
    r: usize,
) -> Result<Vec<f64>, BbError> {
    if q.degree() != p.degree() {
        return Err(BbError::Degree(format!(
            "both sides of a facet need one degree ({} vs {})",
            p.degree(),
            q.degree()
        )));
    }
    let scale = p.max_coeff_norm().max(q.max_coeff_norm());
    let scale = if scale > 0.0 { scale } else { 1.0 };
    let mut res = vec![0.0; r.min(p.degree()) + 1];
    for (l, c) in cr_coefficients(p, j, beta, r)? {
        let d = (q.coeff(l) - c).norm() / scale;
        res[l[j]] = f64::max(res[l[j]], d);
    }
    Ok(res)
}

/// The first two layers of [`vertex_coefficients`] without a Hessian, in a fixed array: the
/// vertex coefficient `b_{n e_i} = value` first, then (2.5) `b_{(n−1)e_i+e_j}` for each
/// `j ≠ i` in increasing order (the same numbers, in the same order, as
/// [`vertex_coefficients`] with `hessian = None`). For degree `n ≥ 1`; no allocation, for
/// callers that set these coefficients on many small polynomials (a split face sets twelve
/// such groups).
///
/// ```
/// use algesurf_bb::continuity::vertex_and_neighbours;
/// use glam::DVec3;
/// let v = [DVec3::ZERO, DVec3::X, DVec3::Y];
/// // f = x + 2y on the unit triangle: b_{2,1,0} = 0 + 1/3, b_{2,0,1} = 0 + 2/3.
/// let c = vertex_and_neighbours(&v, 3, 0, 0.0, DVec3::new(1.0, 2.0, 0.0)).unwrap();
/// assert_eq!(c[0], ([3, 0, 0], 0.0));
/// assert_eq!(c[1], ([2, 1, 0], 1.0 / 3.0));
/// assert_eq!(c[2], ([2, 0, 1], 2.0 / 3.0));
/// ```
///
/// # Errors
/// [`BbError::Index`] when `i ≥ N`; [`BbError::Degree`] when `n = 0` (a constant has no
/// layer next to a vertex).
pub fn vertex_and_neighbours<const N: usize>(
    vertices: &[DVec3; N],
    n: usize,
    i: usize,
    value: f64,
    gradient: DVec3,
) -> Result<[(MultiIndex<N>, f64); N], BbError> {
    if i >= N {
        return Err(BbError::Index(format!(
            "vertex {i} of a simplex with {N} vertices"
        )));
    }
    if n == 0 {
        return Err(BbError::Degree(
            "a degree-0 polynomial has no layer next to a vertex".into(),
        ));
    }
    let mut out = [(multi_index::vertex(n, i), value); N];
    for (at, j) in (1..).zip((0..N).filter(|&j| j != i)) {
        let mut l = multi_index::vertex(n, i);
        l[i] -= 1;
        l[j] += 1;
        out[at] = (
            l,
            value + (vertices[j] - vertices[i]).dot(gradient) / n as f64,
        );
    }
    Ok(out)
}

/// The coefficients at and around vertex `i` of a degree-`n` polynomial on the simplex with
/// the given vertices, from the value, gradient and (optionally) Hessian there:
///
/// * `b_{n e_i} = value`
/// * (2.5) `b_{(n−1)e_i+e_j} = b_{n e_i} + (1/n) (p_j − p_i)ᵀ ∇f(p_i)`
/// * (2.6) `b_{(n−2)e_i+e_j+e_k} = −b_{n e_i} + b_{(n−1)e_i+e_j} + b_{(n−1)e_i+e_k}
///   + (p_j − p_i)ᵀ ∇²f(p_i) (p_k − p_i) / (n(n−1))`, including `j = k`
///
/// (Lemma 2.2 of Bajaj–Chen–Xu 1994; (2.1) of Xu–Huang–Bajaj 2001). The Hessian layer is
/// returned only when `hessian` is given and `n ≥ 2`.
pub fn vertex_coefficients<const N: usize>(
    vertices: &[DVec3; N],
    n: usize,
    i: usize,
    value: f64,
    gradient: DVec3,
    hessian: Option<DMat3>,
) -> Result<Vec<(MultiIndex<N>, f64)>, BbError> {
    if i >= N {
        return Err(BbError::Index(format!(
            "vertex {i} of a simplex with {N} vertices"
        )));
    }
    if n == 0 {
        return Ok(vec![(multi_index::vertex(0, i), value)]);
    }
    // The vertex, its N − 1 neighbours, and with a Hessian the N(N − 1)/2 second-layer
    // coefficients: allocated once (this runs a dozen times per split face).
    let layer2 = if hessian.is_some() && n >= 2 {
        N * (N - 1) / 2
    } else {
        0
    };
    let mut out = Vec::with_capacity(N + layer2);
    out.extend(vertex_and_neighbours(vertices, n, i, value, gradient)?);
    let first = |j: usize| value + (vertices[j] - vertices[i]).dot(gradient) / n as f64;
    if let (Some(h), true) = (hessian, n >= 2) {
        for j in (0..N).filter(|&j| j != i) {
            for k in (j..N).filter(|&k| k != i) {
                let mut l = multi_index::vertex(n, i);
                l[i] -= 2;
                l[j] += 1;
                l[k] += 1;
                let dj = vertices[j] - vertices[i];
                let dk = vertices[k] - vertices[i];
                let c = -value + first(j) + first(k) + dj.dot(h * dk) / (n * (n - 1)) as f64;
                out.push((l, c));
            }
        }
    }
    Ok(out)
}

//! Single-sheetedness: Lemma 2.3 of Xu–Huang–Bajaj 2001 (the lower bound `b_min` of the free
//! coefficient that makes the smallest root of the lifted cubic simple) and Theorem 2.1 of
//! Bajaj–Chen–Xu 1994 (the sign condition under which the zero set in a tetrahedron is a
//! triangular j-patch).

pub mod square;
use crate::multi_index;
use crate::roots::{UNIT_ROUNDOFF as U, cubic_root_estimates};
use crate::{BbError, BbPoly};

/// Which of the two bounds of Lemma 2.3 attains `b_min`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LiftCase {
    /// `b_min^(1) = min_t max{−3F_2(t)/(βt²), −F_3(t)/(βt²)}`.
    One,
    /// `b_min^(2) = min_{t: F_1(t) ≤ 0} −F_3(t)/(βt²)`.
    Two,
}

/// The result of [`lemma_2_3_b_min`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiftBound {
    /// `b_min = min{b_min^(1), b_min^(2)}`, rounded upwards (see [`lemma_2_3_b_min`]).
    pub b_min: f64,
    /// `b_min^(1)` (rounded upwards).
    pub b_min_1: f64,
    /// `b_min^(2)` (rounded upwards).
    pub b_min_2: f64,
    /// The `t_min ∈ (0, 1]` of the Lemma's proof where `b_min` is attained: for `b > b_min`
    /// the Bézier coefficients of `F(·, b)` on `[0, t_min]` change sign exactly once.
    pub t_min: f64,
    /// Which bound attains `b_min`.
    pub case: LiftCase,
}

/// Lemma 2.3 of Xu–Huang–Bajaj 2001: for `F(t, b) = Σ_{i=0}^{3} b_i B_i^3(t) + β t² b` with
/// `b_0 < 0 < β`, every `b > b_min` makes the smallest zero of `F(·, b)` in `[0, 1)` simple.
///
/// With `F_j(t) = Σ_{i≤j} b_i B_i^j(t)` (the left de Casteljau coefficients at t),
/// `b_min^(1) = min_{t∈(0,1]} max{g_2(t), g_3(t)}` and
/// `b_min^(2) = min_{t∈(0,1], F_1(t)≤0} g_3(t)`, with `g_2 = −3F_2/(βt²)`, `g_3 = −F_3/(βt²)`.
///
/// Computed exactly as the Note after the proof says, from critical points, not a grid. Both
/// functions tend to +∞ as t → 0+ (`F_j(0) = b_0 < 0`), so the minimum of `max{g_2, g_3}` is
/// attained at t = 1, at a critical point of g_2 where g_2 ≥ g_3, at a critical point of g_3
/// where g_3 ≥ g_2, or where g_2 = g_3; evaluating `max{g_2, g_3}` at all of these candidates and
/// taking the least value gives the minimum. With monomial coefficients
/// `F_2 = A + Bt + C₂t²`, `F_3 = A + B₃t + C₃t² + Dt³`:
/// * `(F_2/t²)' = 0 ⟺ F_2' t − 2F_2 = −Bt − 2A = 0` (linear: the t² terms cancel);
/// * `(F_3/t²)' = 0 ⟺ F_3' t − 2F_3 = Dt³ − B₃t − 2A = 0` (cubic without t² term);
/// * `g_2 = g_3 ⟺ 3F_2 − F_3 = 0` (cubic).
///
/// The cubics' roots are estimated by [`cubic_root_estimates`] (Cardano and Newton, no
/// allocation): the candidates need no certificate (see the guarantee below), and a candidate
/// within δ of a critical point moves the value by O(δ²), of a crossing by O(δ). `b_min^(2)` takes t = 1 or the zero of the linear
/// `F_1` (the end of `{F_1 ≤ 0}`, which starts at t = 0 since `F_1(0) = b_0 < 0`) and the
/// critical points of g_3 inside.
///
/// Guarantee: every candidate value is `max{g_2, g_3}` (or g_3) at an actual point t, and the
/// proof of the Lemma only needs *some* t with `b > g(t)`. So each value is rounded upwards
/// by its evaluation error bound (de Casteljau: `4(j+1)u Σ|b_i|` for F_j, then one division);
/// then any `b > b_min` satisfies the proof's strict inequalities at `t_min` in exact
/// arithmetic, whatever the rounding of the candidate points themselves.
///
/// Errors: non-finite input, `b_0 ≥ 0` or `β ≤ 0`.
///
/// ```
/// use algesurf_bb::roots::find_roots;
/// use algesurf_bb::sheet::lemma_2_3_b_min;
/// let (b, beta) = ([-1.0, 2.0, -3.0, 0.5], 1.0);
/// let bound = lemma_2_3_b_min(b, beta)?;
/// let lifted = |x: f64| [b[0], b[1], b[2] + beta * x / 3.0, b[3] + beta * x];
/// // Above b_min the smallest root in [0, 1) is simple.
/// let roots = find_roots(&lifted(bound.b_min + 1e-3))?;
/// assert!(roots[0].is_simple() && roots[0].t < 1.0);
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
pub fn lemma_2_3_b_min(b: [f64; 4], beta: f64) -> Result<LiftBound, BbError> {
    if b.iter().any(|x| !x.is_finite()) || !beta.is_finite() {
        return Err(BbError::NonFinite {
            what: "Lemma 2.3 coefficient",
        });
    }
    if b[0] >= 0.0 {
        return Err(BbError::InvalidArgument(format!(
            "Lemma 2.3 needs b_0 < 0, got {}",
            b[0]
        )));
    }
    if beta <= 0.0 {
        return Err(BbError::InvalidArgument(format!(
            "Lemma 2.3 needs β > 0, got {beta}"
        )));
    }
    let f2 = [b[0], b[1], b[2]];
    let abs_sum = b.iter().map(|x| x.abs()).sum::<f64>();
    // Upper bounds of g_2 and g_3 at t (see the doc comment): de Casteljau's error on F_j is
    // at most 4(j+1)u Σ|b_i| for t ∈ [0, 1] (j levels of convex combinations with rounded
    // weights), and the division by βt² adds 3u relative.
    let g_up = |f: f64, j: usize, scale: f64, t: f64| {
        let num = -scale * f + scale * 4.0 * (j as f64 + 1.0) * U * abs_sum;
        let den = beta * t * t;
        let g = num / den;
        g + 3.0 * U * g.abs()
    };
    let g2 = |t: f64| g_up(crate::roots::eval(&f2, t), 2, 3.0, t);
    let g3 = |t: f64| g_up(crate::roots::eval(&b, t), 3, 1.0, t);

    // Monomial coefficients: F_2 = A + Bt + C t², F_3 = A + B₃ t + C₃ t² + D t³.
    let a0 = b[0];
    let b2m = 2.0 * (b[1] - b[0]);
    let b3m = 3.0 * (b[1] - b[0]);
    let d3m = b[3] - 3.0 * b[2] + 3.0 * b[1] - b[0];
    let crit2 = (b2m != 0.0).then(|| -2.0 * a0 / b2m);
    // h_3(t) = D t³ − B₃ t − 2A in Bernstein form (monomial → Bernstein of degree 3:
    // c_k = Σ_{i≤k} C(k,i)/C(3,i) m_i, Farin 1990 §5.7).
    let m = [-2.0 * a0, -b3m, 0.0, d3m];
    let h3 = [
        m[0],
        m[0] + m[1] / 3.0,
        m[0] + 2.0 * m[1] / 3.0 + m[2] / 3.0,
        m[0] + m[1] + m[2] + m[3],
    ];
    let (crit3, n3) = cubic_root_estimates(h3);
    let crit3 = &crit3[..n3];
    // 3F_2 − F_3 in Bernstein degree 3: F_2 elevated is (b0, (b0 + 2b1)/3, (2b1 + b2)/3, b2).
    let cross = [
        3.0 * b[0] - b[0],
        (b[0] + 2.0 * b[1]) - b[1],
        (2.0 * b[1] + b[2]) - b[2],
        3.0 * b[2] - b[3],
    ];
    let (crossings, nx) = cubic_root_estimates(cross);
    let crossings = &crossings[..nx];

    let inside = |t: &f64| *t > 0.0 && *t <= 1.0;
    let mut best1 = (f64::INFINITY, 1.0);
    for t in std::iter::once(1.0)
        .chain(crit2)
        .chain(crit3.iter().copied())
        .chain(crossings.iter().copied())
        .filter(inside)
    {
        let v = g2(t).max(g3(t));
        if v < best1.0 {
            best1 = (v, t);
        }
    }
    // {F_1 ≤ 0} = (0, t1] with t1 the zero of b0(1 − t) + b1 t when b1 > 0, else (0, 1].
    let t1 = if b[1] > 0.0 {
        b[0] / (b[0] - b[1])
    } else {
        1.0
    };
    let mut best2 = (f64::INFINITY, t1);
    for t in std::iter::once(t1)
        .chain(crit3.iter().copied())
        .filter(|t| inside(t) && *t <= t1)
    {
        let v = g3(t);
        if v < best2.0 {
            best2 = (v, t);
        }
    }
    let (b_min, t_min, case) = if best1.0 <= best2.0 {
        (best1.0, best1.1, LiftCase::One)
    } else {
        (best2.0, best2.1, LiftCase::Two)
    };
    Ok(LiftBound {
        b_min,
        b_min_1: best1.0,
        b_min_2: best2.0,
        t_min,
        case,
    })
}

/// The lifting factor β of Step 6 (§4.2 of Xu–Huang–Bajaj 2001) for the edge A-patch's
/// shooting polynomial (4.9): `β(y) = B_0^3(y) + (2/3)ν₁ B_1^3(y) + (2/3)μ₄ B_2^3(y) + B_3^3(y)
/// + y(1 − y)`, with ν₁ and μ₄ of (4.15). Pass `β(y)` to [`lemma_2_3_b_min`] for each y.
pub fn edge_lifting_beta(nu1: f64, mu4: f64, y: f64) -> f64 {
    let s = 1.0 - y;
    s * s * s + 2.0 * nu1 * y * s * s + 2.0 * mu4 * y * y * s + y * y * y + y * s
}

/// Theorem 2.1 of Bajaj–Chen–Xu 1994: the sufficient condition for the zero set of the
/// tetrahedral BB polynomial `f` (degree m, any) to be a triangular j-patch — every segment from
/// vertex `j` to a point of the open opposite face meets it exactly once.
///
/// Returns the least `k ∈ (0, m)` with `b_λ ≥ 0` for `λ_j < k` (2.3), `b_λ ≤ 0` for `λ_j > k`
/// (2.4), the layer `λ_j = 0` not all zero, and some layer `λ_j = i > k` not all zero; `None`
/// when there is none. (The text's "Σ b_λ > 0 / Σ b_λ < 0" for those layers is the same as
/// "not all zero", given the sign conditions.) Vertex `j` is 0-based here (the paper's j − 1).
///
/// Why it works: along the segment from q on the open face to vertex j, f has the Bernstein
/// coefficients `B_s(q)` of the layers `λ_j = s` ((4.8) of Xu–Huang–Bajaj 2001). In the open
/// face every Bernstein basis function is positive, so `B_0(q) > 0`, `B_s(q) ≥ 0` for s < k,
/// `B_s(q) ≤ 0` for s > k and `B_i(q) < 0`: exactly one sign change, so by the
/// variation-diminishing property exactly one simple root in (0, 1).
///
/// ```
/// use algesurf_bb::BbPoly;
/// use algesurf_bb::sheet::j_patch_level;
/// // Layers along vertex 3 (λ_3 = 0, 1, 2, 3) with constant values 1, −0.5, −1, −2.
/// let f = BbPoly::<f64, 4>::from_fn(3, |l| [1.0, -0.5, -1.0, -2.0][l[3]]);
/// assert_eq!(j_patch_level(&f, 3)?, Some(1));
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
pub fn j_patch_level(f: &BbPoly<f64, 4>, j: usize) -> Result<Option<usize>, BbError> {
    if j >= 4 {
        return Err(BbError::Index(format!(
            "vertex {j} of a tetrahedron (0..4)"
        )));
    }
    if f.coeffs().iter().any(|x| !x.is_finite()) {
        return Err(BbError::NonFinite {
            what: "tetrahedral coefficient",
        });
    }
    let m = f.degree();
    // Per layer s: (all ≥ 0, all ≤ 0, not all zero).
    let mut nonneg = vec![true; m + 1];
    let mut nonpos = vec![true; m + 1];
    let mut nonzero = vec![false; m + 1];
    for (lambda, c) in multi_index::iter::<4>(m).zip(f.coeffs()) {
        let s = lambda[j];
        nonneg[s] &= *c >= 0.0;
        nonpos[s] &= *c <= 0.0;
        nonzero[s] |= *c != 0.0;
    }
    for k in 1..m {
        let below = (0..k).all(|s| nonneg[s]);
        let above = (k + 1..=m).all(|s| nonpos[s]);
        if below && above && nonzero[0] && (k + 1..=m).any(|s| nonzero[s]) {
            return Ok(Some(k));
        }
    }
    Ok(None)
}

/// The result of [`certified_triangle_b_min`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleBound {
    /// Guaranteed upper bound of `b_min^(1)(q)` over every point `q` of the triangle with
    /// `b_0(q) < 0` (`−∞` when `b_0 ≥ 0` on the whole triangle).
    pub upper: f64,
    /// The largest `b_min^(1)` found at sample points (cell centroids): a lower bound of the
    /// true maximum, so the true maximum lies in `[sampled, upper]`.
    pub sampled: f64,
    /// Cells the triangle was subdivided into.
    pub cells: usize,
}

/// A cell of a branch-and-bound subdivision (`T` its geometry) ordered by its upper bound, so
/// a max-heap pops the cell with the largest bound first.
pub(crate) struct Ranked<T> {
    pub(crate) upper: f64,
    pub(crate) cell: T,
}

impl<T> PartialEq for Ranked<T> {
    fn eq(&self, other: &Self) -> bool {
        self.upper.total_cmp(&other.upper).is_eq()
    }
}
impl<T> Eq for Ranked<T> {}
impl<T> PartialOrd for Ranked<T> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl<T> Ord for Ranked<T> {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.upper.total_cmp(&other.upper)
    }
}

/// A sub-triangle: its corners in the triangle's barycentrics, with its upper bound.
type Cell = Ranked<[[f64; 3]; 3]>;

/// Rank of `(l0, l1, ·)` among the 3-indices of degree `m` in the storage order of
/// [`multi_index`] (λ_0 decreasing, then λ_1).
#[inline]
fn rank3(l0: usize, l1: usize, m: usize) -> usize {
    (m - l0) * (m - l0 + 1) / 2 + (m - l0 - l1)
}

/// Blossom of a triangular BB polynomial of degree `d ≤ 3` (coefficients `c`) at `args`
/// (`d` of them): de Casteljau in place on a stack buffer. In place is safe because step
/// `r` reads `λ + e_0` (rank `r` itself) and `λ + e_1`, `λ + e_2` (ranks above `r`) only.
fn tri_blossom(c: &[f64], d: usize, args: &[[f64; 3]]) -> f64 {
    let mut buf = [0.0; 10];
    buf[..c.len()].copy_from_slice(c);
    let mut m = d;
    for a in args {
        let mut r = 0;
        for l0 in (0..m).rev() {
            for l1 in (0..m - l0).rev() {
                buf[r] =
                    a[0] * buf[r] + a[1] * buf[rank3(l0, l1 + 1, m)] + a[2] * buf[rank3(l0, l1, m)];
                r += 1;
            }
        }
        m -= 1;
    }
    buf[0]
}

/// Least BB coefficient of each layer over the sub-triangle with `corners`: each coefficient
/// is the blossom of the layer at the corners (repeated as its multi-index says).
fn cell_minima(layers: &[BbPoly<f64, 3>; 4], corners: &[[f64; 3]; 3]) -> [f64; 4] {
    std::array::from_fn(|k| {
        let d = layers[k].degree();
        let mut least = f64::INFINITY;
        let mut args = [[0.0; 3]; 3];
        for mu in multi_index::iter::<3>(d) {
            let mut n = 0;
            for (v, &times) in mu.iter().enumerate() {
                for _ in 0..times {
                    args[n] = corners[v];
                    n += 1;
                }
            }
            least = least.min(tri_blossom(layers[k].coeffs(), d, &args[..d]));
        }
        least
    })
}

/// Upper bound of `b_min^(1)` over a cell from the least coefficients `m` of its layers.
///
/// Why it is an upper bound: by the convex-hull property each layer `B_k(q)` is at least its
/// least BB coefficient `m_k` on the cell. `b_min^(1) = min_t max{−3F_2(t)/t², −F_3(t)/t²}`
/// (β = 1) with `F_j(t) = Σ_{i≤j} b_i B_i^j(t)`, and for `t ∈ (0, 1]` every `B_i^j(t) ≥ 0`,
/// so both terms, their maximum and its minimum over t are non-increasing in every `b_i`:
/// `b_min^(1)(B(q)) ≤ b_min^(1)(m)` for every `q` in the cell. ([`lemma_2_3_b_min`] rounds
/// upwards, so the computed value is at least the exact one.) `b_min^(2)` is *not* monotone
/// (its feasible set `F_1 ≤ 0` grows as the coefficients fall), which is why the certified
/// bound is on `b_min^(1)`: any `b > b_min^(1)` satisfies Lemma 2.3 on its own.
///
/// Public as [`b_min_1_upper_from_minima`] for callers that hold the whole triangle's layer
/// coefficients already (its own BB coefficients are the root cell's minima).
fn cell_upper(m: [f64; 4]) -> f64 {
    if m[0] >= 0.0 {
        // b_0 ≥ 0 on the whole cell: every ray starts on or beyond the surface (t = 0).
        return f64::NEG_INFINITY;
    }
    match lemma_2_3_b_min(m, 1.0) {
        Ok(b) => b.b_min_1,
        // Only non-finite coefficients get here (b_0 < 0 and β = 1 are checked): no bound.
        Err(_) => f64::INFINITY,
    }
}

/// The bound the branch and bound of [`certified_triangle_b_min_below`] gives a cell from the
/// least BB coefficients `m[k]` of its layers `k = 0..3` (see there): `−∞` when `m[0] ≥ 0`,
/// else Lemma 2.3's `b_min^(1)` of `m`, rounded upwards, which bounds `b_min^(1)` from above
/// at every point of the cell; `+∞` for non-finite `m`. For the whole triangle `m` is each
/// layer's least coefficient, and this is the value at which
/// [`certified_triangle_b_min_below`] stops when it is `≤ enough`, bit for bit.
///
/// ```
/// use algesurf_bb::sheet::b_min_1_upper_from_minima;
/// assert_eq!(b_min_1_upper_from_minima([0.5, -1.0, -1.0, -1.0]), f64::NEG_INFINITY);
/// assert!(b_min_1_upper_from_minima([-1.0, -1.0, -1.0, -1.0]) > 0.0);
/// ```
pub fn b_min_1_upper_from_minima(m: [f64; 4]) -> f64 {
    cell_upper(m)
}

/// Certified maximum over a triangle of the Lemma 2.3 bound `b_min^(1)` of the shooting
/// polynomials `Σ_k B_k(q) B_k^3(t)` (β = 1, the lift `b t²` of an apex value), given the four
/// layer polynomials `B_k` (degrees 3, 2, 1, 0) in BB form over the triangle: Step 6 of §4.2 of
/// Xu–Huang–Bajaj 2001 "computed with a guaranteed bound". Where the true coefficients at a
/// point differ from the polynomial layers (a rational term), pass layers whose coefficients
/// are lower bounds of the true ones (the bound stays valid, see `cell_upper`) and let
/// `sample(q)` return the true coefficients at `q`.
///
/// Branch and bound: the cell with the largest upper bound is split at its edge midpoints
/// (BB subdivision, exact up to rounding) until that largest upper bound is within `gap` of the
/// largest sampled value (`upper − sampled ≤ gap`), or `max_cells` cells exist; either way
/// `upper` bounds `b_min^(1)` at every point of the triangle, and when the gap closed it is
/// within `gap` of the true maximum.
pub fn certified_triangle_b_min(
    layers: [BbPoly<f64, 3>; 4],
    sample: impl Fn([f64; 3]) -> [f64; 4],
    gap: f64,
    max_cells: usize,
) -> TriangleBound {
    certified_triangle_b_min_below(layers, sample, gap, max_cells, f64::NEG_INFINITY)
}

/// [`certified_triangle_b_min`] that also stops as soon as the bound is certified to be at
/// most `enough`: when the largest upper bound of the cells is `≤ enough`, `upper` (that
/// largest cell bound, or the sampled value if larger) is returned without closing the gap.
///
/// For a caller that only needs to know whether a value `v` already satisfies Lemma 2.3 with
/// a margin (`enough = v − margin`) this decides the common case with the fewest cells,
/// often the whole triangle alone: the result is then still a guaranteed upper bound of
/// `b_min^(1)` over the triangle, only possibly farther above the true maximum than `gap`.
/// Whenever the result is above `enough`, it is exactly what [`certified_triangle_b_min`]
/// returns (the search visits the same cells in the same order until that test fires).
pub fn certified_triangle_b_min_below(
    layers: [BbPoly<f64, 3>; 4],
    sample: impl Fn([f64; 3]) -> [f64; 4],
    gap: f64,
    max_cells: usize,
    enough: f64,
) -> TriangleBound {
    let eval_sample = |q: [f64; 3]| {
        let b = sample(q);
        if b[0] < 0.0 {
            lemma_2_3_b_min(b, 1.0).map_or(f64::NEG_INFINITY, |x| x.b_min_1)
        } else {
            f64::NEG_INFINITY
        }
    };
    let centroid = |c: &[[f64; 3]; 3]| {
        std::array::from_fn::<f64, 3, _>(|i| (c[0][i] + c[1][i] + c[2][i]) / 3.0)
    };
    if layers.iter().enumerate().any(|(k, l)| l.degree() != 3 - k) {
        // Layers of a cubic have degrees 3, 2, 1, 0; anything else has no bound here.
        return TriangleBound {
            upper: f64::INFINITY,
            sampled: f64::NEG_INFINITY,
            cells: 0,
        };
    }
    let whole = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let root = Cell {
        upper: cell_upper(cell_minima(&layers, &whole)),
        cell: whole,
    };
    if root.upper <= enough {
        // Decided by the whole triangle's coefficients: no sample needed.
        return TriangleBound {
            upper: root.upper,
            sampled: f64::NEG_INFINITY,
            cells: 1,
        };
    }
    let mut sampled = eval_sample(centroid(&root.cell));
    let mut cells = 1;
    let mut heap = std::collections::BinaryHeap::new();
    if root.upper > f64::NEG_INFINITY {
        heap.push(root);
    }
    while let Some(top) = heap.peek() {
        if top.upper - sampled <= gap || top.upper <= enough || cells + 3 > max_cells {
            break;
        }
        let c = heap.pop().expect("peeked").cell;
        let mid = |a: usize, b: usize| std::array::from_fn(|i| 0.5 * (c[a][i] + c[b][i]));
        let (m01, m02, m12) = (mid(0, 1), mid(0, 2), mid(1, 2));
        // The midpoint 4-split (the corner order of `BbPoly::midpoint_split`).
        let children = [
            [c[0], m01, m02],
            [m01, c[1], m12],
            [m02, m12, c[2]],
            [m12, m02, m01],
        ];
        for corners in children {
            sampled = sampled.max(eval_sample(centroid(&corners)));
            let upper = cell_upper(cell_minima(&layers, &corners));
            if upper > f64::NEG_INFINITY {
                heap.push(Cell {
                    upper,
                    cell: corners,
                });
            }
        }
        cells += 3;
    }
    TriangleBound {
        upper: heap
            .peek()
            .map_or(f64::NEG_INFINITY, |c| c.upper)
            .max(sampled),
        sampled,
        cells,
    }
}

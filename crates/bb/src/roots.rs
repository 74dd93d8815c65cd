//! Real roots on `[0, 1]` of univariate Bernstein–Bézier polynomials
//! `p(t) = Σ_{k=0}^{n} b_k B_k^n(t)`.
//!
//! Two solvers:
//!
//! * [`cubic`]: degree ≤ 3 in closed form by Cardano's formulas exactly as in §4.4 of
//!   Xu–Huang–Bajaj 2001 ("Rational A-patches"), including the paper's root choice for the
//!   shooting polynomial ([`shooting_root`], the hot path of A-patch tessellation) and the full
//!   root set ([`cubic_roots`]); every root is polished by safeguarded Newton steps.
//! * [`subdivision`]: any degree up to [`MAX_DEGREE`] by Bernstein subdivision with guaranteed
//!   isolation through the variation-diminishing property ([`find_roots`]).
//!
//! # What "a root" means in floating point
//! Coefficients carry rounding errors, so a double root can show up as two close simple roots,
//! as a pair of complex roots, or as a near-miss. The solvers work with an explicit bound `E`
//! on the absolute error of every coefficient, `E = ε_rel · max_k |b_k|` for the input (see
//! [`RootOptions`]) plus the proven growth of every later step. A coefficient is *certain* when
//! `|c| > E`: its sign cannot be changed by any perturbation within the bound. The roots
//! reported are those of the polynomial perturbed within that bound (backward stability):
//!
//! * a root with [`Root::multiplicity`] 1 is certified simple: on an interval around it the
//!   certain coefficients show exactly one sign change for every admissible perturbation;
//! * a root with multiplicity `m > 1` is a *cluster*: an interval on which the polynomial is
//!   within its rounding bound of zero, on which the m-th derivative is certified nonzero (so by
//!   Rolle's theorem it holds at most m roots counted with multiplicity). It is a multiple
//!   root, or several roots closer than rounding can separate, or a "touching" near-root.
//!
//! ```
//! use algesurf_bb::BbPoly;
//! use algesurf_bb::roots::find_roots_of;
//! // (t − 1/4)² (t − 3/4) in Bernstein form: a double root and a simple root.
//! let p = BbPoly::univariate(&[-3.0 / 64.0, 19.0 / 192.0, -11.0 / 64.0, 9.0 / 64.0])?;
//! let roots = find_roots_of(&p)?;
//! assert_eq!(roots.len(), 2);
//! assert!((roots[0].t - 0.25).abs() < 1e-7 && roots[0].multiplicity == 2);
//! assert!((roots[1].t - 0.75).abs() < 1e-14 && roots[1].is_simple());
//! # Ok::<(), algesurf_bb::BbError>(())
//! ```

pub mod cubic;
mod fastmath;
pub mod subdivision;

pub use cubic::{
    Branch, CardanoCubic, ShootingRoot, cubic_root_estimates, cubic_roots, cubic_roots_closed_form,
    shooting_root,
};
pub use subdivision::{find_roots, find_roots_of, find_roots_with};

use crate::BbError;
use crate::extremes::max_abs;
use crate::multi_index::binomial;

/// Highest degree the root finders accept. Subdivision works for any degree; the cap keeps the
/// work buffers on the stack and the binomial coefficients used in deflation exact
/// (C(32, 16) < 2^53).
pub const MAX_DEGREE: usize = 32;

/// Unit roundoff of f64, `u = ε/2 = 2^-53`: `fl(a ∘ b) = (a ∘ b)(1 + δ)`, `|δ| ≤ u`.
pub(crate) const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// A real root on `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Root {
    /// The parameter `t ∈ [0, 1]`.
    pub t: f64,
    /// 1 for a certified simple root; for `m > 1` an upper bound on the number of roots
    /// (counted with multiplicity) that rounding cannot separate at `t`: m for an m-fold root.
    pub multiplicity: usize,
}

impl Root {
    /// Whether the root is certified simple.
    #[inline]
    pub fn is_simple(&self) -> bool {
        self.multiplicity == 1
    }
}

/// Options of the root finders.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RootOptions {
    /// Bound on the absolute error of each input coefficient, relative to the largest
    /// coefficient magnitude: `E_0 = relative_coefficient_error · max_k |b_k|`.
    ///
    /// Why this scale: coefficients are nearly always computed (a blossom, a restriction to a
    /// segment, a product of factors), and an O(n)-operation computation from data of the
    /// magnitude of the result has an error of a few `n u` times that magnitude. The default,
    /// [`RootOptions::default`], is `16 (n + 1) u` (u = 2^-53), which covers that case with a
    /// safety factor of 16. Raise it when the coefficients come from a computation with
    /// cancellation (their error is then relative to the cancelled terms, not to the result).
    pub relative_coefficient_error: f64,
}

impl RootOptions {
    /// The default options for a polynomial of degree `n`.
    pub fn for_degree(n: usize) -> Self {
        RootOptions {
            relative_coefficient_error: 16.0 * (n as f64 + 1.0) * UNIT_ROUNDOFF,
        }
    }
}

impl Default for RootOptions {
    /// The options for degree 9 (`relative_coefficient_error = 160 u ≈ 1.8e-14`); prefer
    /// [`RootOptions::for_degree`].
    fn default() -> Self {
        RootOptions::for_degree(9)
    }
}

/// Checks the coefficient slice: non-empty, degree ≤ [`MAX_DEGREE`], finite, not all zero.
/// Returns the largest magnitude.
pub(crate) fn validate(b: &[f64]) -> Result<f64, BbError> {
    if b.is_empty() {
        return Err(BbError::InvalidArgument(
            "a polynomial needs at least one coefficient".into(),
        ));
    }
    if b.len() > MAX_DEGREE + 1 {
        return Err(BbError::Degree(format!(
            "root finding supports degree ≤ {MAX_DEGREE}, got {}",
            b.len() - 1
        )));
    }
    if b.iter().any(|x| !x.is_finite()) {
        return Err(BbError::NonFinite {
            what: "polynomial coefficient",
        });
    }
    let m = max_abs(b);
    if m == 0.0 {
        return Err(BbError::InvalidArgument(
            "the zero polynomial vanishes everywhere: its roots are not isolated".into(),
        ));
    }
    Ok(m)
}

/// De Casteljau evaluation of `p` and `p'` at `t` (any degree ≤ [`MAX_DEGREE`]).
///
/// `p' = n (c_1 − c_0)` where `c_0, c_1` are the two values of the last-but-one level
/// (Farin 1990, §4.3). Every step is a convex combination for `t ∈ [0, 1]`, so the absolute
/// error of `p` is at most `2 n u max|b|` plus the propagated coefficient errors.
pub(crate) fn eval_with_derivative(b: &[f64], t: f64) -> (f64, f64) {
    let n = b.len() - 1;
    if n == 0 {
        return (b[0], 0.0);
    }
    if let &[b0, b1, b2, b3] = b {
        // The cubic unrolled (the root estimates of every split face's sheet bound call this
        // a few million times on the bunny): the same operations in the same order as the
        // loop below, so the same bits.
        let s = 1.0 - t;
        let (w0, w1, w2) = (s * b0 + t * b1, s * b1 + t * b2, s * b2 + t * b3);
        let (w0, w1) = (s * w0 + t * w1, s * w1 + t * w2);
        return (s * w0 + t * w1, 3.0 * (w1 - w0));
    }
    let mut w = [0.0f64; MAX_DEGREE + 1];
    w[..=n].copy_from_slice(b);
    let s = 1.0 - t;
    for level in (1..n).rev() {
        for i in 0..=level {
            w[i] = s * w[i] + t * w[i + 1];
        }
    }
    let value = s * w[0] + t * w[1];
    (value, n as f64 * (w[1] - w[0]))
}

/// Value of `p` at `t` by de Casteljau.
pub(crate) fn eval(b: &[f64], t: f64) -> f64 {
    eval_with_derivative(b, t).0
}

/// Splits the Bernstein coefficients of `b` (on `[lo, hi]`) at the local parameter `r`: the
/// coefficients on the left and right pieces (de Casteljau subdivision, Farin 1990, §4.6).
/// Each level is a convex combination, so each new coefficient has an absolute rounding
/// error of at most `3 u max|b|` per level (two products and a sum), `3 n u max|b|` in all.
pub(crate) fn split(b: &[f64], r: f64, left: &mut [f64], right: &mut [f64]) {
    let n = b.len() - 1;
    let mut w = [0.0f64; MAX_DEGREE + 1];
    w[..=n].copy_from_slice(b);
    let s = 1.0 - r;
    left[0] = w[0];
    right[n] = w[n];
    for level in 1..=n {
        for i in 0..=n - level {
            w[i] = s * w[i] + r * w[i + 1];
        }
        left[level] = w[0];
        right[n - level] = w[n - level];
    }
}

/// The coefficients of `b` restricted to `[a, c] ⊂ [0, 1]` (two subdivisions).
pub(crate) fn restrict(b: &[f64], a: f64, c: f64) -> Vec<f64> {
    let n = b.len() - 1;
    let mut left = [0.0; MAX_DEGREE + 1];
    let mut right = [0.0; MAX_DEGREE + 1];
    // First cut at c: keep [0, c]; then cut that at a / c: keep the right part.
    split(b, c, &mut left[..=n], &mut right[..=n]);
    let first: Vec<f64> = left[..=n].to_vec();
    if c > 0.0 {
        split(&first, a / c, &mut left[..=n], &mut right[..=n]);
        right[..=n].to_vec()
    } else {
        first
    }
}

/// Bernstein coefficients of the k-th derivative: `n!/(n−k)! Δ^k b` (Farin 1990, (4.19)).
pub(crate) fn derivative_coeffs(b: &[f64], k: usize) -> Vec<f64> {
    let mut d = b.to_vec();
    for _ in 0..k {
        if d.len() <= 1 {
            return vec![0.0];
        }
        let m = (d.len() - 1) as f64;
        d = d.windows(2).map(|w| m * (w[1] - w[0])).collect();
    }
    d
}

/// The roots at t = 0 and t = 1 (with their multiplicities, from [`end_multiplicities`]) and
/// the interior polynomial left after dividing them out ([`deflate`]), with its coefficient
/// error bounds: the common first step of every root finder here.
pub(crate) fn split_end_roots(bn: &[f64], e0: f64) -> (Vec<Root>, Vec<f64>, Vec<f64>) {
    let (m0, m1) = end_multiplicities(bn, e0);
    let mut roots = Vec::new();
    if m0 > 0 {
        roots.push(Root {
            t: 0.0,
            multiplicity: m0,
        });
    }
    if m1 > 0 {
        roots.push(Root {
            t: 1.0,
            multiplicity: m1,
        });
    }
    let (q, qe) = deflate(bn, e0, m0, m1);
    (roots, q, qe)
}

/// Removes `m0` roots at t = 0 and `m1` at t = 1: with `t^k B_j^{n−k} =
/// (C(n−k, j)/C(n, j+k)) B_{j+k}^n`, dividing `p` by `t^{m0} (1−t)^{m1}` maps the coefficient
/// `b_{j+m0}` to `b_{j+m0} C(n, j+m0) / C(n−m0, j)` and similarly at the other end. The
/// factors are positive, so signs are kept; the returned `growth` is the largest factor (the
/// deflated coefficient errors are at most `growth` times the input ones, plus 2u relative for
/// the product and the quotient). Returns the coefficients and their error bounds, given the
/// absolute error bound `e0` of the input coefficients: `(e0 + 2u|b|) · factor` (the factor is a
/// quotient of exact integers, rounded once, then multiplied once).
pub(crate) fn deflate(b: &[f64], e0: f64, m0: usize, m1: usize) -> (Vec<f64>, Vec<f64>) {
    let n = b.len() - 1;
    let n1 = n - m0 - m1;
    let mut out = Vec::with_capacity(n1 + 1);
    let mut err = Vec::with_capacity(n1 + 1);
    for j in 0..=n1 {
        // t^{m0} (1−t)^{m1} B_j^{n1} = C(n1, j) / C(n, j + m0) · B_{j+m0}^n.
        let f = binomial(n, j + m0) as f64 / binomial(n1, j) as f64;
        let x = b[j + m0];
        out.push(x * f);
        err.push((e0 + 2.0 * UNIT_ROUNDOFF * x.abs()) * f);
    }
    (out, err)
}

/// Roots at the ends of `[0, 1]` from the end coefficients: `p(0) = b_0`, and after zeroing
/// `b_0, …, b_{k−1}` the k-th derivative at 0 is a positive multiple of `b_k`, so the number of
/// leading coefficients within the error bound `e0` is the multiplicity of the root at 0 of a
/// polynomial within `e0` of the input (backward stable). Same at 1 with the trailing ones.
/// The largest coefficient is certain (`e0 < max|b|`), so the two scans never overlap.
pub(crate) fn end_multiplicities(b: &[f64], e0: f64) -> (usize, usize) {
    let n = b.len() - 1;
    // `2u|x|` allows for the rounding of the deflation factor applied later (see `deflate`),
    // so that every coefficient kept is certain after deflation too.
    let small = |x: &&f64| x.abs() <= e0 + 2.0 * UNIT_ROUNDOFF * x.abs();
    let m0 = b.iter().take_while(small).count().min(n);
    let m1 = b.iter().rev().take_while(small).count().min(n - m0);
    (m0, m1)
}

/// Safeguarded Newton–bisection (Numerical Recipes' `rtsafe`) for the single root of the
/// Bernstein polynomial `c` in local `u ∈ [0, 1]`, given `c_0 · c_n < 0`. Newton steps are taken
/// only while they stay strictly inside the current bracket and at least halve the previous
/// step; otherwise the bracket is bisected, so the bracket shrinks by at least half every two
/// iterations and the loop ends. `resolution(u)` is the smallest meaningful step at `u`; the
/// loop also ends once `|p(u)|` is below the rounding bound of its evaluation.
pub(crate) fn bracketed_root(c: &[f64], resolution: impl Fn(f64) -> f64) -> f64 {
    let n = c.len() - 1;
    let f_lo = c[0];
    // De Casteljau's rounding error bound at any u ∈ [0, 1] (see `eval_with_derivative`): once
    // |f| is below it, the sign of f — and so any further step — is noise.
    let noise = 2.0 * n as f64 * UNIT_ROUNDOFF * max_abs(c);
    let (mut a, mut b) = (0.0f64, 1.0f64);
    // Start at the zero of the chord (regula falsi), inside (0, 1) because c_0 c_n < 0.
    let mut u = (c[0] / (c[0] - c[n])).clamp(0.0, 1.0);
    let mut prev_step = 1.0f64;
    for _ in 0..200 {
        let (f, df) = eval_with_derivative(c, u);
        if f.abs() <= noise {
            return u;
        }
        if (f < 0.0) == (f_lo < 0.0) {
            a = u;
        } else {
            b = u;
        }
        let newton = u - f / df;
        let step;
        if df != 0.0 && newton > a && newton < b && (newton - u).abs() <= 0.5 * prev_step {
            step = (newton - u).abs();
            u = newton;
        } else {
            let mid = 0.5 * (a + b);
            step = (mid - u).abs();
            u = mid;
        }
        prev_step = step.max(f64::MIN_POSITIVE);
        if step <= resolution(u) || b - a <= resolution(u) {
            break;
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unrolled cubic in `eval_with_derivative` gives the bits of the general de Casteljau
    /// loop (written out here as the function had it), on cubics of mixed signs and scales.
    #[test]
    fn unrolled_cubic_is_the_general_loop_bit_for_bit() {
        let general = |b: &[f64; 4], t: f64| {
            let mut w = *b;
            let s = 1.0 - t;
            for level in (1..3).rev() {
                for i in 0..=level {
                    w[i] = s * w[i] + t * w[i + 1];
                }
            }
            (s * w[0] + t * w[1], 3.0 * (w[1] - w[0]))
        };
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let scale = 10f64.powi((next() * 12.0) as i32 - 6);
            let b = [0; 4].map(|_| (next() - 0.5) * scale);
            let t = next();
            let (v, d) = eval_with_derivative(&b, t);
            let (gv, gd) = general(&b, t);
            assert_eq!(
                (v.to_bits(), d.to_bits()),
                (gv.to_bits(), gd.to_bits()),
                "{b:?} at {t}"
            );
        }
    }

    #[test]
    fn deflation_divides_exactly() {
        // p = t (1 − t) (2 − t)·… : build t·(1−t)·q with q = (1, 3) and compare values.
        let q = [1.0, 3.0];
        // t (1 − t) q(t) in degree 3: multiply by B_1^2 / 2 … check by values instead.
        let p: Vec<f64> = {
            let f = |t: f64| t * (1.0 - t) * ((1.0 - t) + 3.0 * t);
            // Interpolate at 4 points through the Bernstein basis via blossom-free conversion:
            // coefficients of t(1−t)((1−t)+3t) = B_1^3/3 + B_2^3 (3/3) … computed directly.
            let c = [0.0, 1.0 / 3.0, 1.0, 0.0];
            for t in [0.1, 0.4, 0.9] {
                assert!((eval(&c, t) - f(t)).abs() < 1e-15);
            }
            c.to_vec()
        };
        let (d, _) = deflate(&p, 0.0, 1, 1);
        assert_eq!(d.len(), 2);
        assert!((d[0] - q[0]).abs() < 1e-15 && (d[1] - q[1]).abs() < 1e-15);
    }

    #[test]
    fn split_reproduces_values() {
        let b = [1.0, -2.0, 0.5, 3.0, -1.0];
        let mut l = [0.0; 5];
        let mut r = [0.0; 5];
        split(&b, 0.3, &mut l, &mut r);
        for u in [0.0, 0.2, 0.7, 1.0] {
            assert!((eval(&l, u) - eval(&b, 0.3 * u)).abs() < 1e-14);
            assert!((eval(&r, u) - eval(&b, 0.3 + 0.7 * u)).abs() < 1e-14);
        }
        let c = restrict(&b, 0.2, 0.6);
        for u in [0.0, 0.5, 1.0] {
            assert!((eval(&c, u) - eval(&b, 0.2 + 0.4 * u)).abs() < 1e-14);
        }
    }
}

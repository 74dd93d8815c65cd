//! Roots of any degree by Bernstein subdivision with guaranteed isolation.
//!
//! The variation-diminishing property (Farin 1990, §4.8; Lane–Riesenfeld 1981): the number of
//! roots of `p` in the open interval `(lo, hi)`, counted with multiplicity, is at most the number
//! `V` of sign changes of its Bernstein coefficients on that interval, and has the parity of
//! `V`. So `V = 0` excludes roots and `V = 1` proves exactly one simple root. Subdividing
//! converges the coefficients to the values of `p` (quadratically in the interval width), so
//! every interval eventually has `V ≤ 1` — except near multiple roots and clusters, where
//! rounding keeps the coefficients within their error bound of zero; those intervals are
//! collected, merged and classified (see the [module docs](super)).
//!
//! Algorithm (all bounds proven in the comments):
//! 1. normalise by `M = max|b_k|` (one rounding per coefficient);
//! 2. roots at 0 and 1 from the end coefficients (`end_multiplicities` in `roots`) and exact
//!    deflation (`deflate` in `roots`);
//! 3. subdivide `[0, 1]` with an explicit stack; each interval carries its coefficients and a
//!    per-coefficient error bound. Classify by the sign changes that *any* admissible
//!    perturbation can produce: `V_max = 0` → no root, `V_min = V_max = 1` → one simple root,
//!    refined by safeguarded Newton–bisection to full precision; all coefficients uncertain (or
//!    the width at the resolution of f64) → cluster; otherwise split;
//! 4. merge touching cluster intervals; the multiplicity estimate of a cluster is the least k
//!    whose k-th derivative is certified nonzero on it, and its location is the root of the
//!    (k−1)-th derivative there (a simple root, hence well conditioned).

use super::{
    MAX_DEGREE, Root, RootOptions, UNIT_ROUNDOFF as U, bracketed_root, derivative_coeffs, eval,
    restrict, split, split_end_roots, validate,
};
use crate::{BbError, BbPoly};

/// Upper bound on the number of intervals examined. Isolation needs O(n · log(1/separation))
/// intervals; a double root adds about two intervals per level down to width √u, so real
/// inputs use a few hundred. The cap only guarantees termination on adversarial input (the
/// pending intervals then become clusters, which is still a correct, if coarse, answer).
const MAX_INTERVALS: usize = 20_000;

/// Intervals narrower than 2^-32 that are still undecided become clusters. Two simple roots
/// at distance d of the normalised polynomial (max|b| = 1) differ from a double root by a
/// perturbation of about `c d²/4` with `c = |p''|/2 ≤ n(n−1)·2`, which rounding (at least
/// `E ≥ u`) hides unless `d ≥ 2√(u/(n(n−1)·2)) ≥ 3e-10` for n ≤ 32; 2^-32 ≈ 2.3e-10 is below
/// that, so no resolvable pair is merged, and the descent along the edges of a cluster stops
/// some 20 levels earlier than at the ulp scale. A cluster that is really one simple root of
/// tiny slope is still classified as simple (its derivative is certified nonzero).
const MIN_WIDTH: f64 = 1.0 / 4294967296.0;

/// Split ratios tried in order: the midpoint first; the others avoid splitting exactly at a
/// root (where the new end coefficient, the value there, would be uncertain on both sides and
/// never resolve). Dyadic, so `1 − r` is exact.
const SPLIT_RATIOS: [f64; 5] = [0.5, 0.4375, 0.5625, 0.375, 0.625];

/// All real roots of `Σ b_k B_k^n(t)` in `[0, 1]`, sorted, with default options
/// ([`RootOptions::for_degree`]).
///
/// Errors: empty input, degree above [`super::MAX_DEGREE`], a non-finite coefficient
/// ([`BbError::NonFinite`]), or the zero polynomial.
///
/// ```
/// use algesurf_bb::roots::find_roots;
/// // Coefficients 1, −2, 1 are the polynomial 6t² − 6t + 1, with roots (3 ∓ √3)/6.
/// let r = find_roots(&[1.0, -2.0, 1.0])?;
/// let s = 3f64.sqrt();
/// assert!((r[0].t - (3.0 - s) / 6.0).abs() < 1e-15 && (r[1].t - (3.0 + s) / 6.0).abs() < 1e-15);
/// assert!(r.iter().all(|x| x.is_simple()));
/// assert!(find_roots(&[f64::NAN, 1.0]).is_err());
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
pub fn find_roots(b: &[f64]) -> Result<Vec<Root>, BbError> {
    find_roots_with(b, &RootOptions::for_degree(b.len().saturating_sub(1)))
}

/// [`find_roots`] for a [`BbPoly<f64, 2>`].
pub fn find_roots_of(p: &BbPoly<f64, 2>) -> Result<Vec<Root>, BbError> {
    find_roots(p.coeffs())
}

struct Interval {
    lo: f64,
    hi: f64,
    c: [f64; MAX_DEGREE + 1],
    e: [f64; MAX_DEGREE + 1],
}

/// [`find_roots`] with explicit options.
pub fn find_roots_with(b: &[f64], opts: &RootOptions) -> Result<Vec<Root>, BbError> {
    let m = validate(b)?;
    if !(opts.relative_coefficient_error.is_finite() && opts.relative_coefficient_error >= 0.0) {
        return Err(BbError::InvalidArgument(
            "relative_coefficient_error must be finite and non-negative".into(),
        ));
    }
    // Normalised coefficients: one division each, relative error u; the largest becomes ±1.
    let bn: Vec<f64> = b.iter().map(|x| x / m).collect();
    let e0 = opts.relative_coefficient_error + U;
    let (mut roots, q, qe) = split_end_roots(&bn, e0);
    if q.len() > 1 {
        interior_roots(&q, &qe, &mut roots);
    }
    roots.sort_by(|a, b| a.t.total_cmp(&b.t));
    Ok(roots)
}

/// Sign-change counts of a coefficient sequence under every perturbation within `e`:
/// `(all_uncertain, v_min, v_max)`. `v_min` ignores the uncertain coefficients (a zero is
/// skipped by the sign-change count, and giving it a sign can only add changes); `v_max`
/// lets each uncertain coefficient take whichever sign (or zero) maximises the count, by a
/// three-state dynamic program over the last nonzero sign.
fn sign_changes(c: &[f64], e: &[f64]) -> (bool, usize, usize) {
    const NONE: i64 = i64::MIN / 4;
    // best[0]: no sign yet, best[1]: last +, best[2]: last −.
    let mut best = [0i64, NONE, NONE];
    let mut last_certain = 0i8;
    let mut v_min = 0;
    let mut any_certain = false;
    for (&x, &err) in c.iter().zip(e) {
        let certain = x.abs() > err;
        let (can_pos, can_neg) = if certain {
            (x > 0.0, x < 0.0)
        } else {
            (true, true)
        };
        let mut next = best;
        if certain {
            // A certain coefficient cannot be skipped.
            next = [NONE, NONE, NONE];
            any_certain = true;
            let s = if x > 0.0 { 1i8 } else { -1i8 };
            if last_certain != 0 && s != last_certain {
                v_min += 1;
            }
            last_certain = s;
        }
        if can_pos {
            next[1] = next[1].max(best[0]).max(best[1]).max(best[2] + 1);
        }
        if can_neg {
            next[2] = next[2].max(best[0]).max(best[2]).max(best[1] + 1);
        }
        best = next;
    }
    let v_max = best.iter().copied().max().unwrap_or(0).max(0) as usize;
    (!any_certain, v_min, v_max)
}

fn interior_roots(q: &[f64], qe: &[f64], roots: &mut Vec<Root>) {
    let n = q.len() - 1;
    let mut first = Interval {
        lo: 0.0,
        hi: 1.0,
        c: [0.0; MAX_DEGREE + 1],
        e: [0.0; MAX_DEGREE + 1],
    };
    first.c[..=n].copy_from_slice(q);
    first.e[..=n].copy_from_slice(qe);
    let mut stack = vec![first];
    let mut clusters: Vec<(f64, f64)> = Vec::new();
    let mut examined = 0;
    while let Some(iv) = stack.pop() {
        examined += 1;
        let c = &iv.c[..=n];
        let e = &iv.e[..=n];
        let width = iv.hi - iv.lo;
        if examined > MAX_INTERVALS {
            clusters.push((iv.lo, iv.hi));
            continue;
        }
        let (all_uncertain, v_min, v_max) = sign_changes(c, e);
        if all_uncertain {
            clusters.push((iv.lo, iv.hi));
            continue;
        }
        if v_max == 0 {
            continue;
        }
        if v_min == 1 && v_max == 1 {
            // Exactly one simple root for every admissible perturbation; then c_0 and c_n are
            // certain with opposite signs (an uncertain end could add a change), so the
            // bracket is valid.
            let (lo, w) = (iv.lo, width);
            // Stop when a step is below the spacing of doubles at t (2u|t|), in local units.
            let u = bracketed_root(c, |u| 2.0 * U * (lo + u * w).max(f64::MIN_POSITIVE) / w);
            roots.push(Root {
                t: (lo + u * w).clamp(iv.lo, iv.hi),
                multiplicity: 1,
            });
            continue;
        }
        // Below this width nothing is left to resolve: either the endpoints are a few ulps
        // apart, or the interval is under MIN_WIDTH (see there).
        if width <= (16.0 * U * iv.hi).max(MIN_WIDTH) {
            clusters.push((iv.lo, iv.hi));
            continue;
        }
        let cmax = c.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let emax = e.iter().fold(0.0f64, |a, x| a.max(*x));
        // Rounding added by one subdivision: n levels of convex combinations, each at most
        // 3u max|c| (see `split`).
        let added = 3.0 * n as f64 * U * cmax;
        let r = SPLIT_RATIOS
            .iter()
            .copied()
            .find(|&r| eval(c, r).abs() > emax + added)
            .unwrap_or(0.5);
        let mut left = Interval {
            lo: iv.lo,
            hi: iv.lo + r * width,
            c: [0.0; MAX_DEGREE + 1],
            e: [0.0; MAX_DEGREE + 1],
        };
        let mut right = Interval {
            lo: left.hi,
            hi: iv.hi,
            c: [0.0; MAX_DEGREE + 1],
            e: [0.0; MAX_DEGREE + 1],
        };
        split(c, r, &mut left.c[..=n], &mut right.c[..=n]);
        // Errors propagate through the same convex combinations (exactly a split of the
        // error vector), plus the new rounding; the factor (1 + 4nu) covers the rounding of
        // this bookkeeping itself.
        split(e, r, &mut left.e[..=n], &mut right.e[..=n]);
        let grow = 1.0 + 4.0 * n as f64 * U;
        for x in left.e[..=n].iter_mut().chain(right.e[..=n].iter_mut()) {
            *x = *x * grow + added;
        }
        stack.push(right);
        stack.push(left);
    }
    // Merge cluster intervals that touch (split points are shared exactly).
    clusters.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64)> = Vec::new();
    for (a, b) in clusters {
        match merged.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    let qmax = q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let qerr = qe.iter().fold(0.0f64, |a, x| a.max(*x));
    for (a, b) in merged {
        roots.push(classify_cluster(q, qmax, qerr, a, b));
    }
}

/// Multiplicity estimate and location of the cluster `[a, b]` of `q` (see the module docs).
fn classify_cluster(q: &[f64], qmax: f64, qerr: f64, a: f64, b: f64) -> Root {
    let n = q.len() - 1;
    let mut mult = n;
    let mut falling = 1.0;
    for k in 1..=n {
        falling *= (n - k + 1) as f64;
        let d = derivative_coeffs(q, k);
        // Error of n!/(n−k)! Δ^k q: each difference at most doubles the coefficient errors
        // and adds one rounding (≤ u · 2^j max|q| at level j), so ≤ 2^k (qerr + k u qmax)
        // before the exact-integer factor, which adds one more rounding (u relative).
        let pow2 = (1u64 << k.min(60)) as f64;
        let mut bound = falling * pow2 * (qerr + k as f64 * U * qmax) * (1.0 + 2.0 * U);
        let r = restrict(&d, a, b);
        let dmax = crate::extremes::max_abs(&d);
        // Two subdivisions of degree n − k: 2 · 3 (n − k) u max|d| (see `split`).
        bound += 6.0 * (n - k) as f64 * U * dmax;
        let pos = r.iter().all(|&x| x > bound);
        let neg = r.iter().all(|&x| x < -bound);
        if pos || neg {
            mult = k;
            break;
        }
    }
    // Location: the root of q^{(mult−1)} in [a, b] when it changes sign there (simple, since
    // q^{(mult)} has no root there), else the point of least |q| among the ends and the middle.
    let g = restrict(&derivative_coeffs(q, mult - 1), a, b);
    let w = b - a;
    let gl = g.len() - 1;
    let t = if g[0] != 0.0 && g[gl] != 0.0 && (g[0] < 0.0) != (g[gl] < 0.0) && w > 0.0 {
        let u = bracketed_root(&g, |u| 2.0 * U * (a + u * w).max(f64::MIN_POSITIVE) / w);
        (a + u * w).clamp(a, b)
    } else {
        [a, 0.5 * (a + b), b]
            .into_iter()
            .min_by(|x, y| eval(q, *x).abs().total_cmp(&eval(q, *y).abs()))
            .unwrap_or(a)
    };
    Root {
        t,
        multiplicity: mult,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_change_bounds() {
        let e = [0.1; 5];
        assert_eq!(sign_changes(&[1.0, 1.0, 1.0], &e[..3]), (false, 0, 0));
        assert_eq!(sign_changes(&[1.0, 0.0, 1.0], &e[..3]), (false, 0, 2));
        assert_eq!(sign_changes(&[-1.0, 0.05, 1.0], &e[..3]), (false, 1, 1));
        assert_eq!(sign_changes(&[0.0, 0.05, -0.01], &e[..3]), (true, 0, 2));
        assert_eq!(
            sign_changes(&[1.0, -1.0, 1.0, -1.0], &e[..4]),
            (false, 3, 3)
        );
    }

    #[test]
    fn double_root_in_the_middle() {
        // (t − 1/2)² = ¼ B0 − ¼ B1 + ¼ B2.
        let r = find_roots(&[0.25, -0.25, 0.25]).unwrap();
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].multiplicity, 2);
        assert!((r[0].t - 0.5).abs() < 1e-12);
    }
}

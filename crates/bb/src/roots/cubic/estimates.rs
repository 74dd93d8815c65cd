//! Root estimates without a certificate: [`cubic_root_estimates`].

use super::{CardanoCubic, DEGENERATE_A, cubic_roots};
use crate::roots::{UNIT_ROUNDOFF as U, eval_with_derivative};

/// Points of `[0, 1]` near every real root of the Bernstein cubic `coeffs` in `[0, 1)`, possibly
/// with others: for bounds that take a minimum over candidate points and stay valid at *any*
/// point (Lemma 2.3's `b_min`, [`crate::sheet::lemma_2_3_b_min`]), where a certified root set
/// ([`cubic_roots`]) costs its verification for nothing. No allocation.
///
/// Cardano in `s = t/(1 − t)` (written in whichever of t or 1 − t makes `|a| ≥ |d|`, as
/// [`super::cubic_roots_closed_form`] does; the cube roots and `cos(θ/3)` by the fast path of
/// [`super::shooting_root`]), every real branch `x` with `s = x − b/a ≥ 0` mapped to
/// `t = s/(1 + s)`, then up to four Newton steps on `coeffs`, each kept only while it stays in
/// `[0, 1]` and lowers `|p(t)|`. Where `Δ ≥ 0` the real part `−x₁/2` of the complex pair is a
/// candidate too: it is the double root when `Δ = 0`, and so covers a near-double root whose
/// computed `Δ` came out positive. Where `|a| < 2^-20 Σ|b_k|` after that choice (roots near
/// both ends, where the shift cancels too many bits) the candidates are [`cubic_roots`]'s.
/// An identically zero cubic has none.
///
/// ```
/// use algesurf_bb::roots::cubic_root_estimates;
/// // (t − 1/2)(t − 1/4)(t − 3/4): three simple roots.
/// let (t, n) = cubic_root_estimates([-3.0 / 32.0, 13.0 / 96.0, -13.0 / 96.0, 3.0 / 32.0]);
/// let mut t = t[..n].to_vec();
/// t.sort_by(f64::total_cmp);
/// assert_eq!(n, 3);
/// for (got, want) in t.iter().zip([0.25, 0.5, 0.75]) {
///     assert!((got - want).abs() < 1e-15);
/// }
/// ```
pub fn cubic_root_estimates(coeffs: [f64; 4]) -> ([f64; 3], usize) {
    let mut out = ([0.0; 3], 0usize);
    let sum = coeffs.iter().map(|x| x.abs()).sum::<f64>();
    if sum == 0.0 || !sum.is_finite() {
        return out;
    }
    let reversed = coeffs[3].abs() < coeffs[0].abs();
    let c = if reversed {
        [coeffs[3], coeffs[2], coeffs[1], coeffs[0]]
    } else {
        coeffs
    };
    let cardano = (c[3].abs() >= DEGENERATE_A * sum)
        .then(|| CardanoCubic::new(c))
        .flatten();
    let Some(cub) = cardano else {
        // Rare: both ends near zero. The certified set, as many as fit (a cubic has ≤ 3).
        if let Ok(roots) = cubic_roots(&coeffs) {
            for r in roots.iter().take(3) {
                out.0[out.1] = r.t;
                out.1 += 1;
            }
        }
        return out;
    };
    // The fast branches (cube roots and cos(θ/3) to ~6e-10 relative, no libm trigonometry):
    // the Newton steps below take them to full precision.
    let branches = if cub.delta < 0.0 {
        cub.branches_fast_delta_negative()
    } else {
        let x1 = cub.x1_fast();
        [x1, -0.5 * x1, f64::NAN]
    };
    for x in branches {
        // A root at s = 0 (t at the end) can come out a few ulps of the shift below 0.
        let s = x - cub.shift;
        // (NaN fails `is_finite`, so a NaN branch is skipped too.)
        if !s.is_finite() || s < -16.0 * U * (x.abs() + cub.shift.abs()) {
            continue;
        }
        let s = s.max(0.0);
        let t0 = s / (1.0 + s);
        let t0 = if reversed { 1.0 - t0 } else { t0 };
        out.0[out.1] = newton_estimate(&coeffs, t0);
        out.1 += 1;
    }
    out
}

/// Up to four Newton steps from `t0` on the Bernstein polynomial `c`, each kept only while it
/// stays in `[0, 1]` and lowers `|p|` (no bracket: the result is an estimate, see
/// [`cubic_root_estimates`]).
fn newton_estimate(c: &[f64; 4], t0: f64) -> f64 {
    let (mut t, (mut f, mut df)) = (t0, eval_with_derivative(c, t0));
    for _ in 0..4 {
        if f == 0.0 || df == 0.0 {
            break;
        }
        let next = t - f / df;
        if !(0.0..=1.0).contains(&next) {
            break;
        }
        let (fn_, dfn) = eval_with_derivative(c, next);
        if fn_.abs() >= f.abs() {
            break;
        }
        (t, f, df) = (next, fn_, dfn);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every root the certified solver finds in `[0, 1)` has an estimate next to it: within
    /// 1e-12 for a simple root, within 1e-6 for a multiple one (where `p` is flat, so Newton
    /// stops early); on a grid of cubics with roots anywhere, near both ends and double.
    #[test]
    fn root_estimates_cover_the_certified_roots() {
        let mut checked = [0usize; 2];
        let mut cubics = Vec::new();
        for i in 0..30 {
            for j in 0..30 {
                for k in 0..5 {
                    cubics.push([
                        -1.0 + 0.07 * i as f64,
                        -2.0 + 0.13 * j as f64,
                        1.5 - 0.6 * k as f64,
                        0.3 - 0.02 * (i + j) as f64,
                    ]);
                }
            }
        }
        // Products of linear factors: double roots, roots at and near the ends.
        let from_roots = |r: [f64; 3]| {
            // (t − r0)(t − r1)(t − r2) in Bernstein form, from its values' blossom.
            let e = [r[0] + r[1] + r[2], r[0] * r[1] + r[0] * r[2] + r[1] * r[2]];
            let m = [-r[0] * r[1] * r[2], e[1], -e[0], 1.0];
            [
                m[0],
                m[0] + m[1] / 3.0,
                m[0] + 2.0 * m[1] / 3.0 + m[2] / 3.0,
                m[0] + m[1] + m[2] + m[3],
            ]
        };
        for r in [
            [0.3, 0.3, 0.8],
            [0.5, 0.5, 0.5],
            [1e-9, 0.4, 0.6],
            [0.2, 0.999_999, 1.3],
            [1e-7, 1.0 - 1e-7, 0.5],
            [0.0, 0.25, 2.0],
            [-0.5, 0.7, 0.7],
        ] {
            cubics.push(from_roots(r));
        }
        for b in cubics {
            let (est, n) = cubic_root_estimates(b);
            assert!(n <= 3);
            for root in cubic_roots(&b).unwrap().iter().filter(|r| r.t < 1.0) {
                let tol = if root.is_simple() { 1e-12 } else { 1e-6 };
                let near = est[..n].iter().any(|t| (t - root.t).abs() <= tol);
                assert!(near, "{b:?}: root {root:?}, estimates {:?}", &est[..n]);
                checked[usize::from(!root.is_simple())] += 1;
            }
            for t in &est[..n] {
                assert!(
                    (0.0..=1.0).contains(t),
                    "{b:?}: estimate {t} outside [0, 1]"
                );
            }
        }
        assert!(checked[0] > 1000 && checked[1] >= 3, "{checked:?}");
    }
}

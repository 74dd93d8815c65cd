//! Fast evaluation of the two transcendental pieces of Cardano's formulas for the hot path
//! ([`super::shooting_root`]): the real (inverse) cube root and `cos(θ/3)` for `cos θ = z`.
//!
//! Both only have to start the Newton polish of the shooting root: with quadratic convergence a
//! relative error of 3e-12 in the Cardano root becomes rounding level after one Newton step on
//! the cubic, and the polish keeps iterating (up to its step limit) until Newton's own error
//! estimate is below half an ulp. The reference formulas with `f64::cbrt`, `atan2` and `cos`
//! are [`super::CardanoCubic::x1`] and [`super::CardanoCubic::branches`]; the unit tests
//! compare both paths.

/// `x^{-1/3}` for `x > 0`, to a relative error below 1e-15 (a few ulps) for normal `x`.
///
/// Division-free, so that the cube roots of (4.18) cost only multiplications: `∛x = x r²` and
/// `1/∛x = r`. Start: subtracting a third of the bit pattern from `0x553F…` gives the exponent
/// `−e/3` (the mantissa bits act as a piecewise-linear log2) with the offset that minimises
/// the relative error over all binades: ≤ 3.7%. Then four Newton steps for `r^{-3} = x`,
/// `r ← r (4 − x r³)/3`, each mapping the relative error e to `−2e² − e³`:
/// 3.7e-2 → 2.8e-3 → 1.6e-5 → 5.1e-10 → 5e-19 (then rounding). Subnormal, infinite or NaN
/// inputs use `f64::cbrt`.
#[inline]
pub(crate) fn inv_cbrt(x: f64) -> f64 {
    if !(x >= f64::MIN_POSITIVE && x < f64::MAX) {
        return 1.0 / x.cbrt();
    }
    let mut r = f64::from_bits(0x553F_0000_0000_0000 - x.to_bits() / 3);
    for _ in 0..4 {
        r *= (4.0 - x * (r * r * r)) * (1.0 / 3.0);
    }
    r
}

/// `cos(arccos(z)/3)` for `z ∈ [−1, 1]` to a relative error below 3e-12: the value of
/// `cos(θ/3)` in (4.21) with `cos θ = z`, `θ ∈ [0, π]`.
///
/// It is the root in `[1/2, 1]` of the triple-angle equation `4c³ − 3c = z`. For
/// `z ≥ −1/2` (`c ≥ cos(2π/9) ≈ 0.766`) the derivative `12c² − 3 ≥ 4.04` keeps Newton well
/// conditioned: start from the cubic interpolant at Chebyshev nodes on `[−1/2, 1]` (max error
/// 6.4e-4) and take two Newton steps; Newton's error `e ↦ |f''/2f'| e²` with
/// `|f''/2f'| = 12c/(12c² − 3) ≤ 2.3` on this range gives 6.4e-4 → 9.4e-7 → 2.1e-12 (and
/// ≤ 4e-13 for z ≥ 0, the Corollary's case q < 0, where the factor is ≤ 1.3). Below −1/2 (towards the double root of the triple-angle
/// equation at z = −1, i.e. Δ → 0 with q > 0) use `acos` and `cos`.
#[inline]
pub(crate) fn cos_third_of_arccos(z: f64) -> f64 {
    let z = z.clamp(-1.0, 1.0);
    if z < -0.5 {
        return (z.acos() / 3.0).cos();
    }
    let mut c = 0.866_111_114_630_817
        + z * (0.168_866_077_852_108_4 + z * (-0.051_567_707_115_040_405 + z * 0.016_835_254_606_466_45));
    for _ in 0..2 {
        let c2 = c * c;
        c -= (c * (4.0 * c2 - 3.0) - z) / (12.0 * c2 - 3.0);
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inv_cbrt_matches_libm() {
        let mut worst: f64 = 0.0;
        for k in -3000..=3000 {
            let x = 10f64.powf(k as f64 / 10.0) * 1.234_567;
            let exact = 1.0 / x.cbrt();
            worst = worst.max((inv_cbrt(x) - exact).abs() / exact);
        }
        // A few ulps: the last Newton step's own rounding (≈ 4 operations) plus libm's.
        assert!(worst < 8.0 * f64::EPSILON, "worst relative error {worst:e}");
        assert_eq!(inv_cbrt(8.0e-310), 1.0 / 8.0e-310f64.cbrt());
        assert!(inv_cbrt(f64::NAN).is_nan());
    }

    #[test]
    fn cos_third_matches_libm() {
        let mut worst: f64 = 0.0;
        for k in 0..=200_000 {
            let z = -1.0 + 2.0 * k as f64 / 200_000.0;
            let exact = (z.acos() / 3.0).cos();
            worst = worst.max((cos_third_of_arccos(z) - exact).abs() / exact);
        }
        assert!(worst < 3e-12, "worst relative error {worst:e}");
    }
}

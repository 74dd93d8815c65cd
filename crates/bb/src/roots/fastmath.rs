//! Fast evaluation of the two transcendental pieces of Cardano's formulas for the hot path
//! ([`super::shooting_root`]): the real (inverse) cube root and `cos(θ/3)` for `cos θ = z`.
//!
//! Both only have to start the Newton polish of the shooting root: with quadratic convergence a
//! relative error of 6e-10 in the Cardano root becomes rounding level after one Newton step on
//! the cubic (6e-10² ≪ u), and the polish keeps iterating (up to its step limit) until Newton's
//! own error estimate is below half an ulp. The reference formulas with `f64::cbrt`, `atan2` and `cos`
//! are [`super::CardanoCubic::x1`] and [`super::CardanoCubic::branches`]; the unit tests
//! compare both paths.

/// `x^{-1/3}` for `x > 0`, to a relative error below 6e-10 for normal `x`.
///
/// Division-free, so that the cube roots of (4.18) cost only multiplications: `∛x = x r²` and
/// `1/∛x = r`. Start: subtracting a third of the bit pattern from `0x553F…` gives the exponent
/// `−e/3` (the mantissa bits act as a piecewise-linear log2) with the offset that minimises
/// the relative error over all binades: ≤ 3.7%. Then three Newton steps for `r^{-3} = x`,
/// `r ← r (4 − x r³)/3`, each mapping the relative error e to `−2e² − e³`:
/// 3.7e-2 → 2.8e-3 → 1.6e-5 → 5.1e-10. A fourth step would reach rounding level; the Newton
/// polish of the root does that work instead, on the quantity that matters. Subnormal,
/// infinite or NaN inputs use `f64::cbrt`.
#[inline(always)]
pub(crate) fn inv_cbrt(x: f64) -> f64 {
    if !(f64::MIN_POSITIVE..f64::MAX).contains(&x) {
        return 1.0 / x.cbrt();
    }
    let mut r = f64::from_bits(0x553F_0000_0000_0000 - x.to_bits() / 3);
    for _ in 0..3 {
        // The same step `r (4 − x r³)/3`, associated for latency: `x r`, `r²` and `r/3` are
        // independent products, so the chain is three multiplications and one subtraction
        // instead of five (each regrouping changes only the rounding, a few ulps, far below
        // the 5.1e-10 truncation error of the third step).
        r = (r * (1.0 / 3.0)) * (4.0 - (x * r) * (r * r));
    }
    r
}

/// `cos(arccos(z)/3)` for `z ∈ [−1, 1]` to a relative error below 3e-12 (below 1e-12 for
/// `z ≥ 0`): the value of `cos(θ/3)` in (4.21) with `cos θ = z`, `θ ∈ [0, π]`.
///
/// It is the root in `[1/2, 1]` of the triple-angle equation `f(c) = 4c³ − 3c − z = 0`, and
/// Newton's error map is `e ↦ |f''/2f'| e²` with `|f''/2f'| = 12c/(12c² − 3)`.
/// * `z ∈ [0, 1]` (the Corollary's case q < 0): start from the degree-5 interpolant at
///   Chebyshev nodes on `[0, 1]` (max relative error 7.6e-7; `c ≥ √3/2` so the factor is
///   ≤ 1.3) and take one Newton step: ≤ 7.5e-13.
/// * `z ∈ [−1/2, 0)`: the cubic interpolant on `[−1/2, 1]` (6.4e-4) and two steps with the
///   factor ≤ 2.3 (`c ≥ cos(2π/9)`): 6.4e-4 → 9.4e-7 → 2.1e-12.
/// * below −1/2 (towards the double root of the triple-angle equation at z = −1, i.e.
///   Δ → 0 with q > 0): `acos` and `cos`.
#[inline(always)]
pub(crate) fn cos_third_of_arccos(z: f64) -> f64 {
    let z = z.clamp(-1.0, 1.0);
    let newton = |c: f64| {
        let c2 = c * c;
        c - (c * (4.0 * c2 - 3.0) - z) / (12.0 * c2 - 3.0)
    };
    if z >= 0.0 {
        // Estrin's scheme: three independent pairs, combined with z² and z⁴.
        let z2 = z * z;
        let c = (0.866_026_061_058_833_2 + 0.166_618_856_515_035_25 * z)
            + z2 * (-0.047_525_013_932_433_87 + 0.021_899_627_345_142_326 * z)
            + (z2 * z2) * (-0.008_966_451_200_155_465 + 0.001_947_301_610_415_895_8 * z);
        return newton(c);
    }
    if z < -0.5 {
        return (z.acos() / 3.0).cos();
    }
    let c = 0.866_111_114_630_817
        + z * (0.168_866_077_852_108_4
            + z * (-0.051_567_707_115_040_405 + z * 0.016_835_254_606_466_45));
    newton(newton(c))
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
        // The documented bound 5.1e-10 plus rounding.
        assert!(worst < 5.2e-10, "worst relative error {worst:e}");
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
        let mut worst_pos: f64 = 0.0;
        for k in 0..=100_000 {
            let z = k as f64 / 100_000.0;
            let exact = (z.acos() / 3.0).cos();
            worst_pos = worst_pos.max((cos_third_of_arccos(z) - exact).abs() / exact);
        }
        assert!(
            worst_pos < 1e-12,
            "worst relative error for z ≥ 0: {worst_pos:e}"
        );
    }
}

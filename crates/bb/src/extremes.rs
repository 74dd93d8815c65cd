//! Minimum and maximum of a running extreme in one comparison each.
//!
//! `f64::min(a, b)` and `f64::max(a, b)` answer the other operand when one is NaN. On x86-64
//! they compile to `minsd`/`maxsd`, which answer `b < a ? b : a` (`b > a ? b : a`), followed by
//! six instructions that replace the answer by `b` when `a` is NaN. Where `a` cannot be NaN
//! that replacement never fires, and one comparison gives the same value: [`min_not_nan`] and
//! [`max_not_nan`] are `f64::min`/`max` bit for bit on x86-64 whenever `a` is not NaN,
//! whatever `b` is (a NaN `b` leaves `a` either way; for `0.0` against `-0.0` both answer `a`).
//! On other targets `f64::min` may answer either zero for `0.0` against `-0.0`, so there the
//! values agree up to the sign of a zero, which no comparison tells apart.
//!
//! The typical use is a running extreme started at `±∞` (or at a value known to be a number):
//! `lo = min_not_nan(lo, x)` never makes `lo` NaN, so it stays in the case above for every `x`.
//! In the hull's overlap test and the sheet bounds' branch and bound these loops run hundreds
//! of millions of times on the Stanford bunny. Every use in algesurf is such a running extreme
//! (started at `±∞` or `0`), or says at its place why its first operand is not NaN.
//!
//! ```
//! use algesurf_bb::extremes::{max_not_nan, min_not_nan};
//! let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
//! for x in [3.0, f64::NAN, -1.0, 2.0] {
//!     lo = min_not_nan(lo, x);
//!     hi = max_not_nan(hi, x);
//! }
//! assert_eq!((lo, hi), (-1.0, 3.0)); // the NaN is skipped, as by f64::min/max
//! ```

/// `a.min(b)` for an `a` that is not NaN, as one comparison (see the [module](self) docs).
/// A NaN `a` is answered as it is (where `f64::min` answers `b`); no panic either way.
#[inline(always)]
pub fn min_not_nan(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// `a.max(b)` for an `a` that is not NaN, as one comparison (see the [module](self) docs).
/// A NaN `a` is answered as it is (where `f64::max` answers `b`); no panic either way.
#[inline(always)]
pub fn max_not_nan(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// The largest magnitude `|x|` of `values`, `0.0` when there are none; a NaN is skipped, as
/// by `f64::max`. A running extreme from 0 in one comparison per value ([`max_not_nan`]): the
/// scale of relative tolerances in the root finders, the sheet bounds, the rays and the split
/// faces' fits.
///
/// ```
/// use algesurf_bb::extremes::max_abs;
/// assert_eq!(max_abs(&[1.0, -3.0, f64::NAN, 2.0]), 3.0);
/// assert_eq!(max_abs(&[]), 0.0);
/// ```
#[inline]
pub fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, x| max_not_nan(m, x.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f64::min`/`max` bit for bit whenever the first operand is not NaN: signed zeros both
    /// ways round, infinities, subnormals and NaN second operands.
    #[test]
    fn not_nan_extremes_are_the_std_ones() {
        let xs = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            5e-324,
            -5e-324,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
        ];
        // `f64::min` may answer either zero for `0.0` against `-0.0` (x86-64's `minsd` gives
        // the first operand, aarch64's `fminnm` the negative one): the bits are compared where
        // the extremes were measured (x86-64), the values everywhere.
        let same = |x: f64, y: f64| {
            if cfg!(target_arch = "x86_64") {
                x.to_bits() == y.to_bits()
            } else {
                x == y || (x.is_nan() && y.is_nan())
            }
        };
        for a in xs.into_iter().filter(|a| !a.is_nan()) {
            for b in xs {
                assert!(same(min_not_nan(a, b), a.min(b)), "min {a} {b}");
                assert!(same(max_not_nan(a, b), a.max(b)), "max {a} {b}");
            }
        }
        // A NaN first operand stays (the one case where they differ), without a panic.
        assert!(min_not_nan(f64::NAN, 1.0).is_nan() && max_not_nan(f64::NAN, 1.0).is_nan());
        // The largest magnitude is `f64::max`'s fold from 0, bit for bit (magnitudes have no
        // negative zero), for every prefix of the values, NaNs and infinities included.
        for k in 0..=xs.len() {
            let std = xs[..k].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert_eq!(max_abs(&xs[..k]).to_bits(), std.to_bits(), "{:?}", &xs[..k]);
        }
    }
}

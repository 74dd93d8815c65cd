//! Decimal formatting of coordinates for the text writers.

use std::fmt::Write;

/// Appends `x` as the shortest decimal that reads back to the same `f64` (or `f32` when
/// `single`), using exponent notation for very large or very small magnitudes.
pub(crate) fn push(out: &mut String, x: f64, single: bool) {
    if single {
        let y = x as f32;
        let a = y.abs();
        if a != 0.0 && !(1e-5..1e16).contains(&a) && a.is_finite() {
            let _ = write!(out, "{y:e}");
        } else {
            let _ = write!(out, "{y}");
        }
    } else {
        let a = x.abs();
        if a != 0.0 && !(1e-5..1e16).contains(&a) && a.is_finite() {
            let _ = write!(out, "{x:e}");
        } else {
            let _ = write!(out, "{x}");
        }
    }
}

/// Appends three numbers separated by spaces.
pub(crate) fn push3(out: &mut String, v: glam::DVec3, single: bool) {
    push(out, v.x, single);
    out.push(' ');
    push(out, v.y, single);
    out.push(' ');
    push(out, v.z, single);
}

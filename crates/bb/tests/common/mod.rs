//! Generators shared by the property tests: random polynomials and well-shaped simplices.
#![allow(dead_code)]

use algesurf_bb::multi_index::count;
use algesurf_bb::{BbPoly, Simplex};
use glam::DVec3;
use proptest::prelude::*;

/// A point in [-1, 1]^3.
pub fn point() -> impl Strategy<Value = DVec3> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// A tetrahedron with vertices in [-1,1]^3 whose relative measure is at least 0.05
/// (well-shaped enough that finite differences are meaningful).
pub fn tetrahedron() -> impl Strategy<Value = Simplex<4>> {
    [point(), point(), point(), point()].prop_filter_map("well-shaped tetrahedron", |v| {
        Simplex::<4>::new(v)
            .ok()
            .filter(|t| t.relative_measure() > 0.05)
    })
}

/// A scalar BB polynomial of the given degree in N variables, coefficients in [-1, 1].
pub fn poly<const N: usize>(degree: usize) -> impl Strategy<Value = BbPoly<f64, N>> {
    proptest::collection::vec(-1.0..1.0f64, count::<N>(degree))
        .prop_map(move |c| BbPoly::new(degree, c).unwrap())
}

/// Barycentric coordinates of a point inside the simplex (all ≥ 0, summing to 1).
pub fn inside<const N: usize>() -> impl Strategy<Value = [f64; N]> {
    proptest::collection::vec(0.01..1.0f64, N).prop_map(|w| {
        let s: f64 = w.iter().sum();
        let mut t = [0.0; N];
        for i in 0..N {
            t[i] = w[i] / s;
        }
        t
    })
}

/// Relative difference |a − b| / scale.
pub fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale.max(f64::MIN_POSITIVE)
}

//! The local quadric fit is exact on quadric data: the basis of the default free parameter.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use algesurf_apatch::Quadric;
use glam::{DMat3, DVec3};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn quadric_fit_is_exact_on_ellipsoid_data(
        axes in (0.5..3.0f64, 0.5..3.0f64, 0.5..3.0f64),
        centre in (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64),
        angles in proptest::collection::vec((0.0..std::f64::consts::TAU, 0.2..2.9f64), 7),
        spread in 0.05..0.5f64,
        x in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
    ) {
        let c = DVec3::new(centre.0, centre.1, centre.2);
        let a = DMat3::from_diagonal(DVec3::new(1.0 / (axes.0 * axes.0), 1.0 / (axes.1 * axes.1), 1.0 / (axes.2 * axes.2)));
        let q = |p: DVec3| (p - c).dot(a * (p - c)) - 1.0;
        let g = |p: DVec3| a * (p - c) * 2.0;
        // A neighbourhood: points near one direction on the ellipsoid.
        let (t0, f0) = angles[0];
        let samples: Vec<(DVec3, DVec3)> = angles.iter().map(|&(t, f)| {
            let (t, f) = (t0 + spread * (t - std::f64::consts::PI) / std::f64::consts::PI, f0 + spread * (f - 1.5) / 1.5);
            let d = DVec3::new(f.sin() * t.cos() * axes.0, f.sin() * t.sin() * axes.1, f.cos() * axes.2);
            let p = c + d;
            (p, g(p))
        }).collect();
        let fit = Quadric::fit(&samples).unwrap();
        let y = c + DVec3::new(x.0, x.1, x.2) * 3.0;
        let scale = g(y).length().max(1.0) * 3.0;
        prop_assert!((fit.value(y) - q(y)).abs() < 1e-8 * scale, "{} vs {}", fit.value(y), q(y));
    }
}

#[test]
fn coplanar_data_add_no_square_of_the_plane() {
    // Three points of the plane z = 1 with normal gradients: the least-norm fit is the plane
    // itself (Q = z − 1), not Q + c(z − 1)².
    let s = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ]
    .map(|p| (p, DVec3::Z));
    let fit = Quadric::fit(&s).unwrap();
    for p in [
        DVec3::new(0.3, 0.2, 1.0),
        DVec3::new(0.3, 0.2, 3.0),
        DVec3::new(-2.0, 5.0, -1.0),
    ] {
        assert!(
            (fit.value(p) - (p.z - 1.0)).abs() < 1e-9,
            "{p}: {}",
            fit.value(p)
        );
    }
}

//! Claims of §4 of Xu–Huang–Bajaj 2001 about the face cubic, measured.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use algesurf_apatch::{FaceCubic, VertexData};
use glam::DVec3;
use proptest::prelude::*;

/// Apex over the centroid at height `h` (along the face normal of the face in order).
fn apex(p: [DVec3; 3], h: f64) -> DVec3 {
    let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
    (p[0] + p[1] + p[2]) / 3.0 + n * h
}

fn sphere_point(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(phi.sin() * theta.cos(), phi.sin() * theta.sin(), phi.cos())
}

/// A small outward-oriented triangle on the unit sphere around the given direction.
fn sphere_face(theta: f64, phi: f64, size: f64) -> [DVec3; 3] {
    let a = sphere_point(theta, phi);
    let b = sphere_point(theta + size, phi + 0.3 * size);
    let c = sphere_point(theta + 0.4 * size, phi + size);
    // Orient so that the face normal points away from the origin.
    if (b - a).cross(c - a).dot(a + b + c) > 0.0 {
        [a, b, c]
    } else {
        [a, c, b]
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Theorem 4.2: with vertex data from the quadric Q = (|x|² − 1)/2 (gradients N = x, the
    /// unit normals) and mid-edge gradients from (N_b + N_c)/2 = ∇Q(m), the face cubic is
    /// F = Q + [f_0003 − Q(u)] τ_3² for every f_0003, and the rational terms vanish.
    #[test]
    fn face_cubic_reproduces_the_sphere_family(
        theta in 0.0..6.0f64, phi in 0.3..2.8f64, size in 0.1..0.6f64, h in 0.05..0.5f64,
        lift in -0.2..0.2f64, w in proptest::collection::vec(0.0..1.0f64, 4),
    ) {
        let p = sphere_face(theta, phi, size);
        let u = apex(p, h);
        let q = |x: DVec3| 0.5 * (x.length_squared() - 1.0);
        let v = p.map(|x| VertexData { position: x, gradient: x });
        let mids = [(p[1] + p[2]) * 0.5, (p[2] + p[0]) * 0.5, (p[0] + p[1]) * 0.5];
        let f = FaceCubic::new(v, u, mids, q(u) + lift).unwrap();
        prop_assert!(f.rational().iter().all(|r| r.abs() < 1e-13), "{:?}", f.rational());
        prop_assert!(f.fit_residual() < 1e-12);
        let s: f64 = w.iter().sum();
        let tau = [w[0] / s, w[1] / s, w[2] / s, w[3] / s];
        let x = f.tetrahedron().point(tau);
        let expected = q(x) + lift * tau[3] * tau[3];
        prop_assert!((f.value(tau) - expected).abs() < 1e-12, "{} vs {}", f.value(tau), expected);
        let (_, g) = f.value_gradient(x);
        let tet = f.tetrahedron();
        let expected_g = x + tet.barycentric_gradients()[3] * (2.0 * lift * tau[3]);
        prop_assert!((g - expected_g).length() < 1e-11);
    }

    /// Steps 1–4 measured on arbitrary (non-quadric) data: F(p_a) = 0, ∇F(p_a) = N_a, and at
    /// each edge midpoint the transversal gradient equals that of the mid-edge gradient.
    #[test]
    fn face_cubic_interpolates_vertex_and_mid_edge_data(
        theta in 0.0..6.0f64, phi in 0.3..2.8f64, size in 0.2..0.8f64, h in 0.2..0.6f64,
        tilt in proptest::collection::vec(-0.3..0.3f64, 9), f0003 in 0.0..1.0f64,
    ) {
        let p = sphere_face(theta, phi, size);
        let u = apex(p, h);
        let grads: Vec<DVec3> = (0..3).map(|a| p[a] + DVec3::new(tilt[3 * a], tilt[3 * a + 1], tilt[3 * a + 2])).collect();
        let v = [0, 1, 2].map(|a| VertexData { position: p[a], gradient: grads[a] });
        let mids = [0, 1, 2].map(|a| (grads[(a + 1) % 3] + grads[(a + 2) % 3]) * 0.5);
        let f = FaceCubic::new(v, u, mids, f0003).unwrap();
        // Gradients are recovered through the barycentric gradients, which amplify coefficient
        // rounding by the condition number κ = max|∇τ_i| · diameter of the tetrahedron.
        let tet = f.tetrahedron();
        let diam = (0..4).flat_map(|i| (0..4).map(move |j| (i, j))).map(|(i, j)| tet.vertex(i).distance(tet.vertex(j))).fold(0.0, f64::max);
        let kappa = tet.barycentric_gradients().iter().map(|g| g.length()).fold(0.0, f64::max) * diam;
        for a in 0..3 {
            let (val, g) = f.value_gradient(p[a]);
            prop_assert!(val.abs() < 1e-14);
            prop_assert!((g - grads[a]).length() < 1e-14 * kappa * grads[a].length().max(1.0), "vertex {a}: {} vs {} (κ = {kappa})", g, grads[a]);
            // Mid-edge transversal gradient: compare in the two directions perpendicular to
            // the edge. Evaluate slightly inside: the rational blend is direction-dependent
            // exactly on the edge, its limit from inside the face is what C1 sees.
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let m = (p[b] + p[c]) * 0.5;
            let e = (p[c] - p[b]).normalize();
            let (_, gm) = f.value_gradient(m + (p[a] - m) * 1e-9);
            for d in [p[a] - m, u - m] {
                let d_perp = d - e * d.dot(e);
                let err = (gm - mids[a]).dot(d_perp.normalize());
                prop_assert!(err.abs() < 1e-7, "edge {a}: {err}");
            }
        }
    }
}

//! C1 joins between face and edge tetrahedra (§4.2 Steps 7–9 of Xu–Huang–Bajaj 2001),
//! measured on the paper's Fig. 6 configuration and on random perturbations of it.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use algesurf_apatch::{EdgeCubic, FaceCubic, VertexData};
use glam::DVec3;
use proptest::prelude::*;

/// Apex over the centroid, high enough that (u − p_l)ᵀ N_l > 0 for the three vertices (the
/// condition of §3.1 that makes the coefficients next to the vertices toward u positive).
fn apex(p: [DVec3; 3], n: [DVec3; 3], margin: f64) -> DVec3 {
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
    let t = (0..3)
        .map(|l| (p[l] - c).dot(n[l]) / nf.dot(n[l]))
        .fold(0.0f64, f64::max);
    c + nf * (t + margin)
}

struct Config {
    faces: [FaceCubic; 2],
    edge: EdgeCubic,
    pi: DVec3,
    pj: DVec3,
}

/// Two triangles [p1 p2 p3] and [p2 p1 p4] sharing the edge p1p2 (Fig. 6 with the given
/// normals; gradients are the unit normals).
fn config(p: [DVec3; 4], n: [DVec3; 4], f0003: [f64; 2]) -> Config {
    let n = n.map(|v| v.normalize());
    let tri = [[0usize, 1, 2], [1, 0, 3]];
    let faces = [0, 1].map(|f| {
        let t = tri[f];
        let pts = t.map(|i| p[i]);
        let nrm = t.map(|i| n[i]);
        let v = t.map(|i| VertexData {
            position: p[i],
            gradient: n[i],
        });
        let mids = [0, 1, 2].map(|a| (nrm[(a + 1) % 3] + nrm[(a + 2) % 3]) * 0.5);
        FaceCubic::new(v, apex(pts, nrm, 0.5), mids, f0003[f]).unwrap()
    });
    let edge = EdgeCubic::new(p[0], p[1], &faces[0], &faces[1]).unwrap();
    Config {
        faces,
        edge,
        pi: p[0],
        pj: p[1],
    }
}

fn fig6() -> ([DVec3; 4], [DVec3; 4]) {
    (
        [
            DVec3::new(-2.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 4.0, -1.0),
            DVec3::new(0.0, -4.0, -1.0),
        ],
        [
            DVec3::new(-1.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::new(0.0, -1.0, 1.0),
        ],
    )
}

/// Max value and gradient mismatch between the edge cubic and face `f` over points of their
/// common face [p_i p_j u_f], relative to the gradient size there.
fn join_mismatch(c: &Config, f: usize, samples: &[[f64; 3]]) -> (f64, f64) {
    let u = c.faces[f].tetrahedron().vertex(3);
    let mut worst = (0.0f64, 0.0f64);
    for w in samples {
        let x = c.pi * w[0] + c.pj * w[1] + u * w[2];
        let (fv, fg) = c.faces[f].value_gradient(x);
        let (ev, eg) = c.edge.value_gradient(x);
        let scale = fg.length().max(eg.length()).max(1e-300);
        worst.0 = worst.0.max((fv - ev).abs() / scale);
        worst.1 = worst.1.max((fg - eg).length() / scale);
    }
    worst
}

fn samples() -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    for i in 0..=6 {
        for j in 0..=(6 - i) {
            let k = 6 - i - j;
            // Skip the mesh edge itself (τ0 = τ3 = 0), where the rational blend is singular
            // but vanishes to second order; it is covered by the interior points' limit.
            if k == 0 {
                continue;
            }
            v.push([i as f64 / 6.0, j as f64 / 6.0, k as f64 / 6.0]);
        }
    }
    v
}

#[test]
fn fig6_face_and_edge_cubics_join_c1() {
    let (p, n) = fig6();
    let c = config(p, n, [2.0, 2.0]);
    assert!(
        c.edge.overlap_mismatch() < 1e-13,
        "overlap {}",
        c.edge.overlap_mismatch()
    );
    for f in 0..2 {
        let (dv, dg) = join_mismatch(&c, f, &samples());
        assert!(
            dv < 1e-12 && dg < 1e-10,
            "face {f}: value {dv:e}, gradient {dg:e}"
        );
    }
}

#[test]
fn perturbing_one_edge_coefficient_breaks_the_measured_join() {
    // The measurement above can fail: an edge cubic built against a face cubic whose
    // mid-edge gradient differs no longer joins C1.
    let (p, n) = fig6();
    let c = config(p, n, [2.0, 2.0]);
    let mut n2 = n;
    n2[2] = DVec3::new(0.0, 1.2, 1.0);
    let other = config(p, n2, [2.0, 2.0]);
    let mixed = Config {
        faces: [c.faces[0].clone(), c.faces[1].clone()],
        edge: EdgeCubic::new(p[0], p[1], &other.faces[0], &c.faces[1]).unwrap(),
        pi: p[0],
        pj: p[1],
    };
    let (_, dg) = join_mismatch(&mixed, 0, &samples());
    assert!(dg > 1e-3, "gradient mismatch {dg:e} should be visible");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn perturbed_fig6_joins_c1(
        tilt in proptest::collection::vec(-0.25..0.25f64, 12),
        free in (0.5..4.0f64, 0.5..4.0f64),
    ) {
        let (p, n) = fig6();
        let n = [0, 1, 2, 3].map(|i| n[i] + DVec3::new(tilt[3 * i], tilt[3 * i + 1], tilt[3 * i + 2]));
        let c = config(p, n, [free.0, free.1]);
        prop_assert!(c.edge.overlap_mismatch() < 1e-12, "overlap {}", c.edge.overlap_mismatch());
        for f in 0..2 {
            let (dv, dg) = join_mismatch(&c, f, &samples());
            prop_assert!(dv < 1e-12 && dg < 1e-10, "face {f}: value {dv:e}, gradient {dg:e}");
        }
        // Shooting polynomials agree with direct evaluation along their rays.
        for (x, y, t) in [(0.3, 0.6, 0.4), (0.8, 0.1, 0.7), (0.5, 0.5, 0.2)] {
            let s = c.edge.shooting_polynomial(x, y);
            let b = [(1.0 - t) * (1.0 - t) * (1.0 - t), 3.0 * t * (1.0 - t) * (1.0 - t), 3.0 * t * t * (1.0 - t), t * t * t];
            let via_shoot: f64 = (0..4).map(|i| s[i] * b[i]).sum();
            let a = [0.0, x, 1.0 - x, 0.0];
            let e = [1.0 - y, 0.0, 0.0, y];
            let tau: [f64; 4] = std::array::from_fn(|i| (1.0 - t) * a[i] + t * e[i]);
            prop_assert!((via_shoot - c.edge.value(tau)).abs() < 1e-12);
            let q = [0.2, 0.3 + 0.1 * x, 0.5 - 0.1 * x];
            let sf = c.faces[0].shooting_polynomial(q);
            let tau_f = [(1.0 - t) * q[0], (1.0 - t) * q[1], (1.0 - t) * q[2], t];
            let via_face: f64 = (0..4).map(|i| sf[i] * b[i]).sum();
            prop_assert!((via_face - c.faces[0].value(tau_f)).abs() < 1e-12);
        }
    }
}

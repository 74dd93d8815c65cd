//! The split (nonconvex) face: hard constraints hold, C1 across every internal facet, and
//! quadric data are reproduced exactly.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use algesurf_apatch::examples::WorkedExample;
use algesurf_apatch::{Quadric, SplitFace, VertexData};
use algesurf_bb::Tetrahedron;
use glam::DVec3;
use proptest::prelude::*;

fn face_normal(p: [DVec3; 3]) -> DVec3 {
    (p[1] - p[0]).cross(p[2] - p[0]).normalize()
}

fn build(p: [DVec3; 3], grads: [DVec3; 3], q: &Quadric, h: f64, f: [f64; 2]) -> SplitFace {
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let n = face_normal(p);
    let v = [0, 1, 2].map(|a| VertexData {
        position: p[a],
        gradient: grads[a],
    });
    let mids = [0, 1, 2].map(|a| (grads[(a + 1) % 3] + grads[(a + 2) % 3]) * 0.5);
    SplitFace::new(v, &[c + n * h, c - n * h], mids, q, &f).unwrap()
}

/// Worst value/gradient mismatch between the pieces on either side of every internal facet,
/// sampled on a grid of each facet, relative to the gradient size.
fn internal_c1_mismatch(s: &SplitFace) -> (f64, f64) {
    let mut pieces: Vec<(&Tetrahedron, &algesurf_bb::BbPoly<f64, 4>)> = Vec::new();
    for side in &s.sides {
        for a in 0..3 {
            pieces.push((&side.tets[a], &side.polys[a]));
        }
    }
    let mut worst = (0.0f64, 0.0f64);
    for i in 0..pieces.len() {
        for j in i + 1..pieces.len() {
            let (ta, pa) = pieces[i];
            let (tb, pb) = pieces[j];
            let shared: Vec<DVec3> = (0..4)
                .map(|k| ta.vertex(k))
                .filter(|x| (0..4).any(|m| tb.vertex(m) == *x))
                .collect();
            if shared.len() != 3 {
                continue;
            }
            for u in 0..=5 {
                for w in 0..=(5 - u) {
                    let bary = [u as f64 / 5.0, w as f64 / 5.0, (5 - u - w) as f64 / 5.0];
                    let x = shared[0] * bary[0] + shared[1] * bary[1] + shared[2] * bary[2];
                    let (ga, gb) = (pa.gradient_at(ta, x), pb.gradient_at(tb, x));
                    let scale = ga.length().max(gb.length()).max(1e-300);
                    worst.0 = worst
                        .0
                        .max((pa.value_at(ta, x) - pb.value_at(tb, x)).abs() / scale);
                    worst.1 = worst.1.max((ga - gb).length() / scale);
                }
            }
        }
    }
    worst
}

#[test]
fn split_face_reproduces_the_sphere_on_both_sides() {
    let p = [
        DVec3::new(1.0, 0.1, 0.2),
        DVec3::new(0.2, 1.0, 0.1),
        DVec3::new(0.1, 0.2, 1.0),
    ]
    .map(|x| x.normalize());
    let q = Quadric {
        a: glam::DMat3::IDENTITY * 0.5,
        b: DVec3::ZERO,
        c: -0.5,
    };
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let n = face_normal(p);
    let (u, v) = (c + n * 0.3, c - n * 0.3);
    let s = build(p, p, &q, 0.3, [q.value(u), q.value(v)]);
    assert!(s.constraint_residual < 1e-12, "{}", s.constraint_residual);
    for side in &s.sides {
        for a in 0..3 {
            for w in [
                [0.25, 0.25, 0.25, 0.25],
                [0.1, 0.5, 0.3, 0.1],
                [0.6, 0.1, 0.1, 0.2],
            ] {
                let x = side.tets[a].point(w);
                assert!((side.polys[a].eval(w) - q.value(x)).abs() < 1e-12);
            }
        }
    }
}

/// Face [p1 p2 p3] of Fig. 9 (`WorkedExample::Fig9`: n1 = n2 = (1,0,1), n3 = (0,−1,1.5)),
/// which is nonconvex: its positions and unit normals.
fn fig9_face() -> ([DVec3; 3], [DVec3; 3]) {
    let (mesh, normals) = WorkedExample::Fig9.mesh_and_normals();
    let tri = mesh.triangles()[0];
    (
        tri.map(|v| mesh.positions()[v as usize]),
        tri.map(|v| normals[v as usize]),
    )
}

/// Fig. 9 of the paper: face [p1 p2 p3] is nonconvex.
#[test]
fn fig9_split_face_is_c1_across_every_internal_facet() {
    let (p, g) = fig9_face();
    let samples: Vec<(DVec3, DVec3)> = (0..3).map(|i| (p[i], g[i])).collect();
    let q = Quadric::fit(&samples).unwrap();
    let s = build(p, g, &q, 1.0, [1.0, -1.0]);
    assert!(s.constraint_residual < 1e-10, "{}", s.constraint_residual);
    let (dv, dg) = internal_c1_mismatch(&s);
    assert!(dv < 1e-12 && dg < 1e-10, "value {dv:e}, gradient {dg:e}");
}

#[test]
fn a_perturbed_split_face_is_measurably_not_c1() {
    let (p, g) = fig9_face();
    let q = Quadric::fit(&(0..3).map(|i| (p[i], g[i])).collect::<Vec<_>>()).unwrap();
    let mut s = build(p, g, &q, 1.0, [1.0, -1.0]);
    let c = s.sides[0].polys[0].coeff([1, 0, 1, 1]);
    s.sides[0].polys[0].set([1, 0, 1, 1], c + 1e-3);
    assert!(internal_c1_mismatch(&s).1 > 1e-5);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn random_split_faces_are_c1_and_interpolate(
        tilt in proptest::collection::vec(-0.6..0.6f64, 9),
        h in (0.3..1.5f64, 0.3..1.5f64),
        f in (0.1..2.0f64, -2.0..-0.1f64),
    ) {
        let p = [DVec3::new(-2.0, 0.0, 0.0), DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 4.0, -1.0)];
        let g = [0, 1, 2].map(|i| (DVec3::Z + DVec3::new(tilt[3 * i], tilt[3 * i + 1], tilt[3 * i + 2])).normalize());
        let q = Quadric::fit(&(0..3).map(|i| (p[i], g[i])).collect::<Vec<_>>()).unwrap();
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let n = face_normal(p);
        let vd = [0, 1, 2].map(|a| VertexData { position: p[a], gradient: g[a] });
        let mids = [0, 1, 2].map(|a| (g[(a + 1) % 3] + g[(a + 2) % 3]) * 0.5);
        let s = SplitFace::new(vd, &[c + n * h.0, c - n * h.1], mids, &q, &[f.0, f.1]).unwrap();
        prop_assert!(s.constraint_residual < 1e-10, "{}", s.constraint_residual);
        let (dv, dg) = internal_c1_mismatch(&s);
        prop_assert!(dv < 1e-12 && dg < 1e-9, "value {dv:e}, gradient {dg:e}");
        // Interpolation at the mesh vertices, from every piece that contains them.
        for side in &s.sides {
            for a in 0..3 {
                for local in 0..2 {
                    let x = side.tets[a].vertex(local);
                    let i = (0..3).find(|&i| p[i] == x).unwrap();
                    // Exactly on the coefficient (Step 1) ...
                    let corner = if local == 0 { [3, 0, 0, 0] } else { [0, 3, 0, 0] };
                    prop_assert!(side.polys[a].coeff(corner).abs() < 1e-13 * g[i].length());
                    // ... and evaluated at the Cartesian vertex, where converting to barycentric
                    // coordinates amplifies rounding by κ = max|∇τ|·diameter of the (flat)
                    // sub-tetrahedron: |F| ≤ 1e-14 · κ · diameter · |N|.
                    let t = &side.tets[a];
                    let diam = (0..4).flat_map(|i| (0..4).map(move |j| (i, j))).map(|(i, j)| t.vertex(i).distance(t.vertex(j))).fold(0.0, f64::max);
                    let kappa = t.barycentric_gradients().iter().map(|v| v.length()).fold(0.0, f64::max) * diam;
                    let val = side.polys[a].value_at(t, x);
                    prop_assert!(val.abs() < 1e-14 * kappa * diam * g[i].length(), "value {val:e} at vertex {i} (κ = {kappa})");
                    let ge = (side.polys[a].gradient_at(t, x) - g[i]).length();
                    prop_assert!(ge < 1e-14 * kappa * g[i].length(), "gradient error {ge:e}, κ = {kappa}");
                }
            }
        }
    }
}

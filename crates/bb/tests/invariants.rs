//! Property tests of the BB algebra: the invariants every later layer relies on.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

mod common;

use algesurf_bb::multi_index::{self, count, rank, unrank};
use algesurf_bb::{BbPoly, PowerPoly, continuity};
use common::*;
use glam::{DMat3, DVec3};
use proptest::prelude::*;

#[test]
fn rank_unrank_round_trip_up_to_degree_9() {
    fn check<const N: usize>() {
        for n in 0..=9 {
            let all: Vec<_> = multi_index::iter::<N>(n).collect();
            assert_eq!(all.len(), count::<N>(n));
            for (r, l) in all.iter().enumerate() {
                assert_eq!(multi_index::degree(l), n);
                assert_eq!(rank(l), r, "rank of {l:?}");
                assert_eq!(unrank::<N>(n, r), *l);
            }
            assert!(multi_index::checked_unrank::<N>(n, all.len()).is_none());
        }
    }
    check::<2>();
    check::<3>();
    check::<4>();
}

#[test]
fn storage_order_is_reverse_lexicographic() {
    let v: Vec<_> = multi_index::iter::<3>(2).collect();
    assert_eq!(
        v,
        vec![
            [2, 0, 0],
            [1, 1, 0],
            [1, 0, 1],
            [0, 2, 0],
            [0, 1, 1],
            [0, 0, 2]
        ]
    );
    let layer: Vec<_> = multi_index::layer::<4>(3, 3, 1).collect();
    assert_eq!(layer.len(), count::<3>(2));
    assert!(layer.iter().all(|l| l[3] == 1));
}

#[test]
fn coefficient_count_is_checked() {
    assert!(BbPoly::<f64, 4>::new(3, vec![0.0; 19]).is_err());
    assert!(BbPoly::<f64, 4>::new(3, vec![0.0; 20]).is_ok());
}

/// Pascal's triangle by additions, in `u128` while the entries fit (`None` beyond): the
/// oracle for the binomials, independent of their multiplicative formula.
fn pascal(rows: usize) -> Vec<Vec<Option<u128>>> {
    let mut t: Vec<Vec<Option<u128>>> = vec![vec![Some(1)]];
    for a in 1..=rows {
        let prev = &t[a - 1];
        let row = (0..=a)
            .map(|b| {
                let left = if b == 0 { Some(0) } else { prev[b - 1] };
                let right = prev.get(b).copied().unwrap_or(Some(0));
                left?.checked_add(right?)
            })
            .collect();
        t.push(row);
    }
    t
}

#[test]
fn binomials_are_exact_wherever_they_fit() {
    let u = f64::EPSILON / 2.0;
    for (a, row) in pascal(160).iter().enumerate() {
        for (b, exact) in row.iter().enumerate() {
            let int = multi_index::binomial(a, b);
            let float = multi_index::binomial_f64(a, b);
            match exact {
                Some(e) if *e <= usize::MAX as u128 => {
                    assert_eq!(int as u128, *e, "C({a}, {b})");
                }
                _ => assert_eq!(int, usize::MAX, "C({a}, {b}) saturates"),
            }
            match exact {
                // Every product of the formula fits in u128: rounded once.
                Some(e) if a <= 125 => assert_eq!(float, *e as f64, "C({a}, {b}) as f64"),
                Some(e) => {
                    let rel = (float / *e as f64 - 1.0).abs();
                    assert!(
                        rel <= 2.0 * b.min(a - b) as f64 * u + u,
                        "C({a}, {b}): {rel:e}"
                    );
                }
                None => assert!(float > 2f64.powi(127), "C({a}, {b}) = {float:e}"),
            }
        }
        assert_eq!(multi_index::binomial(a, a + 1), 0);
        assert_eq!(multi_index::binomial_f64(a, a + 1), 0.0);
    }
    assert_eq!(multi_index::binomial_f64(1030, 515), f64::INFINITY);
    assert_eq!(count::<4>(usize::MAX), usize::MAX);
}

#[test]
fn products_of_high_degree_curves_are_pointwise() {
    // The products' weights C(μ)C(ν)/C(λ) are ratios of multinomials, which an integer
    // product overflowed from degree 64 on (garbage in release builds, a panic in debug ones).
    for n in [10usize, 63, 64, 65, 80, 127, 200, 400] {
        let (n1, n2) = (n / 2, n - n / 2);
        let one = BbPoly::<f64, 2>::constant(n1, 1.0).mul_scalar_poly(&BbPoly::constant(n2, 1.0));
        let worst = one
            .coeffs()
            .iter()
            .map(|c| (c - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-13,
            "degree {n}: 1 · 1 has a coefficient off by {worst:e}"
        );
        let a = BbPoly::<f64, 2>::from_fn(n1, |l| ((l[0] * 7 + 3) % 11) as f64 / 11.0 - 0.3);
        let b = BbPoly::<f64, 2>::from_fn(n2, |l| ((l[1] * 5 + 1) % 13) as f64 / 13.0 - 0.4);
        let ab = a.mul_scalar_poly(&b);
        for t in [0.0, 0.125, 0.3, 0.5, 0.77, 1.0] {
            let tau = [1.0 - t, t];
            let (pa, pb, pab) = (a.eval(tau), b.eval(tau), ab.eval(tau));
            // The coefficients are below 1 in size, so the products' are too: an absolute
            // bound with the degree's rounding errors.
            assert!(
                (pab - pa * pb).abs() <= 1e-12,
                "degree {n} at t = {t}: {pab} vs {}",
                pa * pb
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn evaluation_equals_blossom_on_the_diagonal(p in poly::<4>(5), tau in inside::<4>()) {
        let s = p.max_coeff_norm();
        prop_assert!(rel(p.eval(tau), p.blossom(&[tau; 5]).unwrap(), s) < 1e-14);
    }

    #[test]
    fn fast_evaluator_matches_de_casteljau(p in poly::<4>(3), q in poly::<3>(9), t4 in inside::<4>(), t3 in inside::<3>()) {
        prop_assert!(rel(p.evaluator().eval(t4), p.eval(t4), p.max_coeff_norm()) < 1e-13);
        prop_assert!(rel(q.evaluator().eval(t3), q.eval(t3), q.max_coeff_norm()) < 1e-13);
    }

    #[test]
    fn blossom_is_symmetric_and_multiaffine(p in poly::<3>(3), a in inside::<3>(), b in inside::<3>(), c in inside::<3>(), w in 0.0..1.0f64) {
        let s = p.max_coeff_norm();
        let abc = p.blossom(&[a, b, c]).unwrap();
        prop_assert!(rel(abc, p.blossom(&[c, a, b]).unwrap(), s) < 1e-14);
        let mix: [f64; 3] = std::array::from_fn(|i| (1.0 - w) * a[i] + w * b[i]);
        let lhs = p.blossom(&[mix, b, c]).unwrap();
        let rhs = (1.0 - w) * abc + w * p.blossom(&[b, b, c]).unwrap();
        prop_assert!(rel(lhs, rhs, s) < 1e-14);
    }

    #[test]
    fn degree_elevation_preserves_values(p in poly::<4>(3), k in 1usize..4, tau in inside::<4>()) {
        let e = p.elevate(k);
        prop_assert_eq!(e.degree(), 3 + k);
        prop_assert!(rel(e.eval(tau), p.eval(tau), p.max_coeff_norm()) < 1e-12);
    }

    #[test]
    fn subdivision_preserves_values(p in poly::<4>(4), split in inside::<4>(), sub in inside::<4>()) {
        // Point with sub-simplex coordinates `sub` in piece i: Σ_k sub_k w_k with w_i = split.
        for (i, piece) in p.subdivide(split).iter().enumerate() {
            let mut tau = [0.0; 4];
            for k in 0..4 {
                let w = if k == i { split } else { std::array::from_fn(|m| f64::from(u8::from(m == k))) };
                for m in 0..4 { tau[m] += sub[k] * w[m]; }
            }
            prop_assert!(rel(piece.eval(sub), p.eval(tau), p.max_coeff_norm()) < 1e-12);
        }
    }

    #[test]
    fn midpoint_split_preserves_values(p in poly::<3>(5), sub in inside::<3>()) {
        let corners = [
            [[1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 0.5]],
            [[0.5, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.5, 0.5]],
            [[0.5, 0.0, 0.5], [0.0, 0.5, 0.5], [0.0, 0.0, 1.0]],
            [[0.0, 0.5, 0.5], [0.5, 0.0, 0.5], [0.5, 0.5, 0.0]],
        ];
        for (piece, w) in p.midpoint_split().iter().zip(corners) {
            let tau: [f64; 3] = std::array::from_fn(|m| (0..3).map(|k| sub[k] * w[k][m]).sum());
            prop_assert!(rel(piece.eval(sub), p.eval(tau), p.max_coeff_norm()) < 1e-12);
        }
    }

    #[test]
    fn gradient_and_hessian_match_central_differences(p in poly::<4>(4), tet in tetrahedron(), tau in inside::<4>()) {
        let x = tet.point(tau);
        let h = 1e-5;
        let g = p.gradient_at(&tet, x);
        let hess = p.hessian_at(&tet, x);
        // Scales: |∂τ| ≤ G := max |∇τ_i|, so |∇p| ≤ n G max|b| and |∇²p| ≤ n(n−1) G² max|b|.
        let gmax = tet.barycentric_gradients().iter().map(|v| v.length()).fold(0.0, f64::max);
        let s1 = 4.0 * gmax * p.max_coeff_norm();
        let s2 = 12.0 * gmax * gmax * p.max_coeff_norm();
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let fd = (p.value_at(&tet, x + axis * h) - p.value_at(&tet, x - axis * h)) / (2.0 * h);
            prop_assert!(rel(g.dot(axis), fd, s1) < 1e-7, "gradient {} vs {}", g.dot(axis), fd);
            let fdg = (p.gradient_at(&tet, x + axis * h) - p.gradient_at(&tet, x - axis * h)) / (2.0 * h);
            prop_assert!((hess * axis - fdg).length() / s2 < 1e-7);
        }
        prop_assert!((hess - hess.transpose()).abs().to_cols_array().iter().all(|v| *v < 1e-10 * s2));
    }

    #[test]
    fn directional_derivatives_match_finite_differences(p in poly::<3>(5), tau in inside::<3>(), d in (-1.0..1.0f64, -1.0..1.0f64)) {
        let dir = [d.0, d.1, -d.0 - d.1];
        let h = 1e-5;
        let at = |s: f64| p.eval(std::array::from_fn(|i| tau[i] + s * dir[i]));
        let fd1 = (at(h) - at(-h)) / (2.0 * h);
        let fd2 = (at(h) - 2.0 * at(0.0) + at(-h)) / (h * h);
        let s = 25.0 * p.max_coeff_norm();
        prop_assert!(rel(p.directional_derivative(tau, &[dir]), fd1, s) < 1e-8);
        prop_assert!(rel(p.derivative(dir).eval(tau), fd1, s) < 1e-8);
        prop_assert!(rel(p.directional_derivative(tau, &[dir, dir]), fd2, 20.0 * s) < 1e-4);
    }

    #[test]
    fn cr_facet_formulas_give_cr_joins(
        p in poly::<4>(5), q0 in poly::<4>(5), tet in tetrahedron(),
        far in (0.2..1.5f64), offs in (-0.4..0.4f64, -0.4..0.4f64), j in 0usize..4, r in 0usize..3,
        on_facet in inside::<3>(),
    ) {
        // Opposite vertex: beyond facet j (β_j = −far < 0), so T' really is a neighbour.
        let mut beta = [0.0; 4];
        let others: Vec<usize> = (0..4).filter(|&i| i != j).collect();
        beta[j] = -far;
        beta[others[0]] = (1.0 + far) / 3.0 + offs.0;
        beta[others[1]] = (1.0 + far) / 3.0 + offs.1;
        beta[others[2]] = 1.0 + far - beta[others[0]] - beta[others[1]];
        let w = tet.point(beta);
        let mut verts = *tet.vertices();
        verts[j] = w;
        let Ok(tet2) = algesurf_bb::Tetrahedron::new(verts) else { return Ok(()) };
        let mut q = q0.clone();
        continuity::impose_cr(&p, &mut q, j, beta, r).unwrap();

        // The residual function says C^r.
        let res = continuity::cr_residual(&p, &q, j, beta, r).unwrap();
        prop_assert!(res.iter().all(|&x| x < 1e-12), "{res:?}");

        // And pointwise: value / gradient / Hessian agree at a random facet point.
        let mut tau = [0.0; 4];
        for (k, &i) in others.iter().enumerate() { tau[i] = on_facet[k]; }
        let x = tet.point(tau);
        let g = tet.barycentric_gradients().iter().chain(tet2.barycentric_gradients()).map(|v| v.length()).fold(0.0, f64::max);
        let c = p.max_coeff_norm().max(q.max_coeff_norm());
        prop_assert!(rel(p.value_at(&tet, x), q.value_at(&tet2, x), c) < 1e-9);
        if r >= 1 {
            let d = (p.gradient_at(&tet, x) - q.gradient_at(&tet2, x)).length();
            prop_assert!(d / (5.0 * g * c) < 1e-9, "gradient mismatch {d}");
        }
        if r >= 2 {
            let d: DMat3 = p.hessian_at(&tet, x) - q.hessian_at(&tet2, x);
            let m = d.to_cols_array().iter().fold(0.0f64, |a, v| a.max(v.abs()));
            prop_assert!(m / (20.0 * g * g * c) < 1e-9, "Hessian mismatch {m}");
        }

        // Perturbing one coefficient of layer r makes the residual clearly nonzero.
        let victim = multi_index::layer::<4>(5, j, r).nth(1).unwrap();
        let mut bad = q.clone();
        bad.set(victim, q.coeff(victim) + 1e-3 * c);
        let res_bad = continuity::cr_residual(&p, &bad, j, beta, r).unwrap();
        prop_assert!(res_bad[r] > 5e-4, "{res_bad:?}");
    }

    #[test]
    fn vertex_formulas_reproduce_the_coefficients(p in poly::<4>(4), tet in tetrahedron(), i in 0usize..4) {
        let v = tet.vertex(i);
        let coeffs = continuity::vertex_coefficients(
            tet.vertices(), 4, i, p.value_at(&tet, v), p.gradient_at(&tet, v), Some(p.hessian_at(&tet, v)),
        ).unwrap();
        prop_assert_eq!(coeffs.len(), 1 + 3 + 6);
        for (l, c) in coeffs {
            prop_assert!(rel(c, p.coeff(l), p.max_coeff_norm()) < 1e-9, "{l:?}: {c} vs {}", p.coeff(l));
        }
    }

    #[test]
    fn products_and_sums_are_pointwise(a in poly::<4>(2), b in poly::<4>(3), tau in inside::<4>()) {
        let s = a.max_coeff_norm() * b.max_coeff_norm();
        prop_assert!(rel(b.mul_scalar_poly(&a).eval(tau), a.eval(tau) * b.eval(tau), s) < 1e-13);
        let sum = a.add_poly(&b);
        prop_assert!(rel(sum.eval(tau), a.eval(tau) + b.eval(tau), a.max_coeff_norm() + b.max_coeff_norm()) < 1e-13);
    }

    #[test]
    fn monomial_round_trips(p in poly::<4>(4), tet in tetrahedron(), tau in inside::<4>()) {
        let s = p.max_coeff_norm();
        let local = p.to_power();
        let back = BbPoly::from_power(&local, 4).unwrap();
        for (x, y) in back.coeffs().iter().zip(p.coeffs()) {
            prop_assert!(rel(*x, *y, s) < 1e-12);
        }
        prop_assert!(rel(local.eval(&[tau[1], tau[2], tau[3]]), p.eval(tau), s) < 1e-12);
        let cart = p.to_cartesian(&tet);
        let x = tet.point(tau);
        prop_assert!(rel(cart.eval(&x.to_array()), p.eval(tau), s) < 1e-9);
        let again = BbPoly::from_cartesian(&tet, &cart, 4).unwrap();
        for (x, y) in again.coeffs().iter().zip(p.coeffs()) {
            prop_assert!(rel(*x, *y, s) < 1e-8);
        }
    }

    #[test]
    fn layers_reassemble_the_shooting_polynomial(p in poly::<4>(3), q in inside::<3>(), t in 0.0..1.0f64, j in 0usize..4) {
        // (4.8): p((1−t) q + t v_j) = Σ_s B_s(q) B_s^3(t).
        let layers = p.layers::<3>(j).unwrap();
        let mut tau = [0.0; 4];
        let mut k = 0;
        for (i, x) in tau.iter_mut().enumerate() {
            if i == j { *x = t } else { *x = (1.0 - t) * q[k]; k += 1; }
        }
        let bern = [(1.0 - t).powi(3), 3.0 * t * (1.0 - t).powi(2), 3.0 * t * t * (1.0 - t), t.powi(3)];
        let sum: f64 = layers.iter().enumerate().map(|(s, l)| l.eval(q) * bern[s]).sum();
        prop_assert!(rel(sum, p.eval(tau), p.max_coeff_norm()) < 1e-13);
        // And restrict_to_segment gives the same univariate polynomial.
        let mut a = [0.0; 4];
        let mut k = 0;
        for (i, x) in a.iter_mut().enumerate() { if i != j { *x = q[k]; k += 1; } }
        let mut b = [0.0; 4];
        b[j] = 1.0;
        let shoot = p.restrict_to_segment(a, b);
        prop_assert!(rel(shoot.eval_t(t), p.eval(tau), p.max_coeff_norm()) < 1e-13);
        for s in 0..=3 {
            prop_assert!(rel(shoot.coeffs()[s], layers[s].eval(q), p.max_coeff_norm()) < 1e-13);
        }
    }
}

#[test]
fn sphere_from_cartesian_vanishes_on_the_sphere() {
    let mut s = PowerPoly::<4>::zero(2);
    for e in [[2, 0, 0], [0, 2, 0], [0, 0, 2]] {
        s.set(&e, 1.0).unwrap();
    }
    s.set(&[0, 0, 0], -1.0).unwrap();
    let tet = algesurf_bb::Tetrahedron::new([
        DVec3::new(-2.0, -2.0, -2.0),
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(0.0, 3.0, 0.0),
        DVec3::new(0.0, 0.0, 3.0),
    ])
    .unwrap();
    let f = BbPoly::from_cartesian(&tet, &s, 2).unwrap();
    for k in 0..50 {
        let th = k as f64 * 0.37;
        let ph = k as f64 * 0.11;
        let x = DVec3::new(th.cos() * ph.sin(), th.sin() * ph.sin(), ph.cos());
        assert!(f.value_at(&tet, x).abs() < 1e-13);
        assert!((f.gradient_at(&tet, x) - 2.0 * x).length() < 1e-12);
    }
}

#[test]
fn degenerate_and_non_finite_simplices_are_rejected() {
    use algesurf_bb::{BbError, Tetrahedron, Triangle};
    let flat = Tetrahedron::new([DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.3, 0.3, 1e-12)]);
    assert!(matches!(flat, Err(BbError::DegenerateSimplex { .. })));
    let nan = Triangle::new([DVec3::ZERO, DVec3::X, DVec3::new(f64::NAN, 0.0, 0.0)]);
    assert!(matches!(nan, Err(BbError::NonFinite { .. })));
    // Scale invariance: a tiny but well-shaped tetrahedron is fine.
    let tiny = Tetrahedron::new([
        DVec3::ZERO,
        DVec3::X * 1e-9,
        DVec3::Y * 1e-9,
        DVec3::Z * 1e-9,
    ]);
    assert!(tiny.is_ok());
}

/// `2^e`, exactly, for the normal exponents.
fn power_of_two(e: i32) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

#[test]
fn simplices_scale_exactly_over_the_whole_range_of_f64() {
    use algesurf_bb::{BbError, Segment, Simplex, Tetrahedron, Triangle};
    // Scaling a simplex by 2^e scales its barycentric gradients by 2^-e and leaves its
    // barycentric coordinates and relative measure as they were, bit for bit, wherever the
    // scaled coordinates are normal numbers: here (smallest coordinate 2^-4) from 2^-1018 to
    // 2^1018, the end of the supported range (beyond 2^±240 the construction works on a scaled copy, where the
    // products of four lengths in its closed forms would leave f64's range). A shape with no
    // symmetry, off the origin, so that every dual has rounding in its last bits.
    let base = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.125, -0.375),
        DVec3::new(0.3125, 1.25, 0.0625),
        DVec3::new(-0.1875, 0.4375, 0.9375),
    ];
    let p = DVec3::new(0.3, 0.2, 0.1);
    fn same<const N: usize>(
        a: &Simplex<N>,
        b: &Simplex<N>,
        e: i32,
        p: DVec3,
    ) -> Result<(), String> {
        let s = power_of_two(-e);
        for (da, db) in a
            .barycentric_gradients()
            .iter()
            .zip(b.barycentric_gradients())
        {
            if *da * s != *db {
                return Err(format!("2^{e}: gradient {db} is not {da} · 2^{}", -e));
            }
        }
        if a.relative_measure() != b.relative_measure() {
            return Err(format!("2^{e}: relative measure changed"));
        }
        if a.barycentric(p) != b.barycentric(p * power_of_two(e)) {
            return Err(format!("2^{e}: barycentric coordinates changed"));
        }
        Ok(())
    }
    let tet = Tetrahedron::new(base).unwrap();
    let tri = Triangle::new([base[0], base[1], base[2]]).unwrap();
    let seg = Segment::new([base[0], base[1]]).unwrap();
    for e in (-1018..=1018)
        .step_by(7)
        .chain([-1018, -241, -240, 240, 241, 1018])
    {
        let k = power_of_two(e);
        let at = |i: usize| base[i] * k;
        same(
            &tet,
            &Tetrahedron::new([at(0), at(1), at(2), at(3)]).unwrap(),
            e,
            p,
        )
        .unwrap();
        same(&tri, &Triangle::new([at(0), at(1), at(2)]).unwrap(), e, p).unwrap();
        same(&seg, &Segment::new([at(0), at(1)]).unwrap(), e, p).unwrap();
    }
    // Translated far from the origin, a huge simplex keeps its shape (not bit for bit: the
    // vertices' translation rounds).
    let far = DVec3::splat(1e300);
    let small = Tetrahedron::new(base.map(|v| far + v * 1e299)).unwrap();
    let tau = small.barycentric(small.point([0.25; 4]));
    assert!(tau.iter().all(|t| (t - 0.25).abs() < 1e-12), "{tau:?}");
    // Beyond the range the error says so instead of calling the simplex degenerate.
    for k in [power_of_two(-1022) / 4.0, f64::MAX / 2.0] {
        let err = Tetrahedron::new(base.map(|v| v * k)).unwrap_err();
        assert!(
            matches!(&err, BbError::InvalidArgument(m) if m.contains("range")),
            "{err}"
        );
    }
    // Vertices whose differences overflow.
    let err = Segment::new([DVec3::splat(-f64::MAX), DVec3::splat(f64::MAX)]).unwrap_err();
    assert!(
        matches!(&err, BbError::InvalidArgument(m) if m.contains("range")),
        "{err}"
    );
}

#[test]
fn facet_continuation_rejects_a_flat_neighbour() {
    let p = BbPoly::<f64, 4>::zero(3);
    assert!(continuity::continuation(&p, 0, [0.0, 0.5, 0.25, 0.25]).is_err());
    assert!(continuity::continuation(&p, 7, [0.0, 0.5, 0.25, 0.25]).is_err());
    assert!(continuity::continuation(&p, 0, [-1.0, 0.5, 0.25, 0.25]).is_err()); // sums to 0
}

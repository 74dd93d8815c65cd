//! B-spline, tensor-product and mixed (triangle × interval) bases.

use algesurf_bb::BbPoly;
use algesurf_bb::bspline::{BSplineCurve, KnotVector};
use algesurf_bb::multi_index;
use algesurf_bb::tensor::{PrismBb, TensorBb2, TensorBb3, bernstein};
use glam::DVec3;
use proptest::prelude::*;

/// Random valid knot vectors: degree 0..=5, interior knots with repetitions up to p.
fn knot_vector() -> impl Strategy<Value = KnotVector> {
    (
        0usize..=5,
        prop::collection::vec((0.0f64..1.0, 1usize..=3), 0..6),
        any::<bool>(),
    )
        .prop_map(|(p, interior, clamped)| {
            let mut knots = Vec::new();
            if clamped {
                knots.extend(std::iter::repeat_n(0.0, p + 1));
            } else {
                knots.extend((0..=p).map(|i| -0.1 * (p - i) as f64));
            }
            let mut inner: Vec<(f64, usize)> = interior;
            inner.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (u, mult) in inner {
                if u > 0.0 && u < 1.0 {
                    knots.extend(std::iter::repeat_n(u, mult.min(p.max(1))));
                }
            }
            if clamped {
                knots.extend(std::iter::repeat_n(1.0, p + 1));
            } else {
                knots.extend((0..=p).map(|i| 1.0 + 0.1 * i as f64));
            }
            KnotVector::new(p, knots).expect("valid by construction")
        })
}

proptest! {
    #[test]
    fn partition_of_unity_and_non_negativity(kv in knot_vector(), x in 0.0f64..=1.0) {
        let (lo, hi) = kv.domain();
        let t = lo + x * (hi - lo);
        let (span, n) = kv.basis(t).unwrap();
        prop_assert_eq!(n.len(), kv.degree() + 1);
        prop_assert!(span >= kv.degree() && span < kv.num_basis());
        prop_assert!(kv.knots()[span] <= t && (t < kv.knots()[span + 1] || t == hi));
        // Each value is a sum of non-negative terms: non-negative exactly; the sum is 1 up
        // to p rounding errors per level.
        prop_assert!(n.iter().all(|v| *v >= 0.0), "{:?}", n);
        let sum: f64 = n.iter().sum();
        prop_assert!((sum - 1.0).abs() <= 4.0 * (kv.degree() as f64 + 1.0) * f64::EPSILON, "{}", sum);
        // Derivatives of the partition of unity vanish.
        let (_, d) = kv.basis_derivatives(t, 2).unwrap();
        prop_assert_eq!(&d[0], &n);
        let scale: f64 = d[1].iter().map(|v| v.abs()).sum::<f64>() + 1.0;
        prop_assert!(d[1].iter().sum::<f64>().abs() <= 1e-12 * scale);
    }

    /// Derivatives against central differences of the basis. Inside a span the basis
    /// functions are polynomials, so the central difference of the (k−1)-th derivative has
    /// truncation error `h²/6 |N^{(k+2)}(ξ)|` for some ξ in the stencil (bounded by the largest
    /// of the three sampled values plus 10%, as N^{(k+2)} is a polynomial of low degree that
    /// barely moves over 2h = 2e-4 of the span), plus the rounding of the two values divided by
    /// 2h (O(p²ε) relative to the row's magnitude, bounded here by 64(p+1)²ε).
    #[test]
    fn derivatives_match_central_differences(kv in knot_vector(), x in 0.05f64..0.95) {
        let p = kv.degree();
        let (lo, hi) = kv.domain();
        let t = lo + x * (hi - lo);
        let span = kv.find_span(t).unwrap();
        let (a, b) = (kv.knots()[span], kv.knots()[span + 1]);
        let h = 1e-4 * (b - a);
        prop_assume!(t - a > 2.0 * h && b - t > 2.0 * h);
        let order = p + 3;
        let (_, d) = kv.basis_derivatives(t, order).unwrap();
        let (_, dp) = kv.basis_derivatives(t + h, order).unwrap();
        let (_, dm) = kv.basis_derivatives(t - h, order).unwrap();
        for k in 1..=p {
            for r in 0..=p {
                let fd = (dp[k - 1][r] - dm[k - 1][r]) / (2.0 * h);
                let third = d[k + 2][r].abs().max(dp[k + 2][r].abs()).max(dm[k + 2][r].abs());
                let size: f64 = d[k - 1].iter().map(|v| v.abs()).sum::<f64>();
                let tol = 1.1 * h * h / 6.0 * third
                    + 64.0 * ((p + 1) * (p + 1)) as f64 * f64::EPSILON * size / h;
                prop_assert!((fd - d[k][r]).abs() <= tol, "k={} r={} fd={} d={} tol={}", k, r, fd, d[k][r], tol);
            }
        }
        // Above the degree: zero.
        prop_assert!(d[p + 1].iter().all(|v| *v == 0.0));
    }

    #[test]
    fn bezier_knots_reproduce_bernstein(p in 0usize..=9, t in 0.0f64..=1.0) {
        let kv = KnotVector::bezier(p);
        let (span, n) = kv.basis(t).unwrap();
        prop_assert_eq!(span, p);
        for (i, v) in n.iter().enumerate() {
            prop_assert!((v - bernstein(p, i, t)).abs() <= 1e-14, "i={} {} vs {}", i, v, bernstein(p, i, t));
        }
        // And the curve equals the univariate BB polynomial with the same coefficients.
        let c: Vec<f64> = (0..=p).map(|i| ((i * 7) % 5) as f64 - 2.0).collect();
        let curve = BSplineCurve::new(kv, c.clone()).unwrap();
        let bb = BbPoly::univariate(&c).unwrap();
        prop_assert!((curve.eval(t).unwrap() - bb.eval_t(t)).abs() <= 1e-13);
        if p >= 1 {
            let d = bb.derivative([-1.0, 1.0]).eval_t(t);
            prop_assert!((curve.derivative(t, 1).unwrap() - d).abs() <= 1e-12 * (1.0 + d.abs()));
        }
    }
}

#[test]
fn uniform_cubic_at_knots_is_one_six_four_one() {
    let kv = KnotVector::uniform(3, 8).unwrap();
    assert_eq!(kv.num_basis(), 11);
    for k in 0..8 {
        let t = k as f64 / 8.0;
        let (span, n) = kv.basis(t).unwrap();
        assert_eq!(span, k + 3);
        let expect = [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0];
        for (v, e) in n.iter().zip(expect) {
            assert!((v - e).abs() < 1e-15, "t={t}: {n:?}");
        }
        // Derivatives at a knot: (−1/2, 0, 1/2, 0)/h and (1, −2, 1, 0)/h², h = 1/8.
        let (_, d) = kv.basis_derivatives(t, 2).unwrap();
        for (v, e) in d[1].iter().zip([-4.0, 0.0, 4.0, 0.0]) {
            assert!((v - e).abs() < 1e-12, "{d:?}");
        }
        for (v, e) in d[2].iter().zip([64.0, -128.0, 64.0, 0.0]) {
            assert!((v - e).abs() < 1e-10, "{d:?}");
        }
    }
    // The right end uses the last span.
    assert_eq!(kv.find_span(1.0).unwrap(), 10);
}

#[test]
fn knot_vector_validation_and_curve_errors() {
    assert!(KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0]).is_err()); // too few
    assert!(KnotVector::new(1, vec![0.0, 1.0, 0.5, 2.0]).is_err()); // decreasing
    assert!(KnotVector::new(1, vec![0.0, f64::NAN, 1.0, 2.0]).is_err());
    assert!(KnotVector::new(1, vec![0.0, 0.5, 0.5, 0.5, 1.0]).is_err()); // multiplicity 3 > 2
    assert!(KnotVector::new(1, vec![0.0, 1.0, 1.0, 1.0]).is_err()); // empty domain... and mult
    assert!(KnotVector::new(2, vec![0.0, 0.0, 1.0, 1.0, 1.0, 1.0]).is_err());
    assert!(KnotVector::uniform(3, 0).is_err());
    let kv = KnotVector::clamped_uniform(2, 3).unwrap();
    assert!(kv.find_span(-0.1).is_err() && kv.find_span(f64::NAN).is_err());
    assert!(BSplineCurve::new(kv.clone(), vec![0.0; 4]).is_err());
    let c = BSplineCurve::new(
        kv,
        vec![DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE, DVec3::ZERO],
    )
    .unwrap();
    assert_eq!(c.eval(0.0).unwrap(), DVec3::X);
    assert_eq!(c.eval(1.0).unwrap(), DVec3::ZERO);
    assert!(c.eval(1.5).is_err());
    // Curve derivative vs central difference, DVec3 coefficients.
    let (t, h) = (0.4, 1e-5);
    let fd = (c.eval(t + h).unwrap() - c.eval(t - h).unwrap()) / (2.0 * h);
    assert!((c.derivative(t, 1).unwrap() - fd).length() < 1e-8);
}

// ---------------------------------------------------------------------------------------------
// Tensor products and the mixed basis.

fn coeff_vec(n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..1.0, n)
}

proptest! {
    #[test]
    fn tensor2_direct_sum_partition_and_derivatives(
        n1 in 0usize..=5, n2 in 0usize..=5, seed in coeff_vec(36), x in 0.0f64..=1.0, y in 0.0f64..=1.0,
    ) {
        let p = TensorBb2::from_fn([n1, n2], |[i, j]| seed[(i * 6 + j) % seed.len()]);
        // Direct sum of coefficients times basis functions.
        let mut direct = 0.0;
        let mut unity = 0.0;
        for i in 0..=n1 {
            for j in 0..=n2 {
                let b = TensorBb2::<f64>::basis([n1, n2], [i, j], [x, y]);
                prop_assert!(b >= 0.0);
                unity += b;
                direct += p.get([i, j]).unwrap() * b;
            }
        }
        prop_assert!((unity - 1.0).abs() <= 1e-14);
        prop_assert!((p.eval([x, y]) - direct).abs() <= 1e-13);
        // Partials vs central differences: truncation h²/6 |f'''| with
        // |f'''| ≤ n(n−1)(n−2) · 8 max|w| ≤ 480 (third differences of coefficients in [−1, 1],
        // Farin 1990 (4.19)), plus rounding ~ 4ε Σ|w B| / h.
        let h = 1e-5;
        let fd_tol = h * h / 6.0 * 480.0 + 4.0 * f64::EPSILON * 36.0 / h;
        for axis in 0..2 {
            let d = p.derivative(axis).unwrap();
            let mut a = [x, y];
            let mut b = [x, y];
            a[axis] += h;
            b[axis] -= h;
            let fd = (p.eval(a) - p.eval(b)) / (2.0 * h);
            prop_assert!((d.eval([x, y]) - fd).abs() <= fd_tol, "{} vs {}", d.eval([x, y]), fd);
        }
        // Elevation preserves values.
        for axis in 0..2 {
            let e = p.elevate(axis, 2).unwrap();
            prop_assert_eq!(e.degrees()[axis], p.degrees()[axis] + 2);
            prop_assert!((e.eval([x, y]) - p.eval([x, y])).abs() <= 1e-13);
        }
    }

    #[test]
    fn tensor3_direct_sum_and_derivatives(
        n in prop::array::uniform3(0usize..=3), seed in coeff_vec(64), x in prop::array::uniform3(0.0f64..=1.0),
    ) {
        let p = TensorBb3::from_fn(n, |[i, j, k]| DVec3::new(
            seed[(i * 16 + j * 4 + k) % seed.len()],
            seed[(i + j * 16 + k * 4) % seed.len()],
            seed[(i * 4 + j + k * 16) % seed.len()],
        ));
        let mut direct = DVec3::ZERO;
        for i in 0..=n[0] {
            for j in 0..=n[1] {
                for k in 0..=n[2] {
                    direct += p.get([i, j, k]).unwrap() * TensorBb3::<DVec3>::basis(n, [i, j, k], x);
                }
            }
        }
        prop_assert!((p.eval(x) - direct).length() <= 1e-13);
        // Degree ≤ 3 per direction: |f'''| ≤ 3·2·1 · 8 per component (as above).
        let h = 1e-5;
        let fd_tol = 3f64.sqrt() * (h * h / 6.0 * 48.0 + 4.0 * f64::EPSILON * 64.0 / h);
        for axis in 0..3 {
            let d = p.derivative(axis).unwrap();
            let mut a = x;
            let mut b = x;
            a[axis] += h;
            b[axis] -= h;
            let fd = (p.eval(a) - p.eval(b)) / (2.0 * h);
            prop_assert!((d.eval(x) - fd).length() <= fd_tol);
            let e = p.elevate(axis, 1).unwrap();
            prop_assert!((e.eval(x) - p.eval(x)).length() <= 1e-13);
        }
        prop_assert!(p.derivative(3).is_err() && p.elevate(5, 1).is_err());
    }

    #[test]
    fn prism_direct_sum_partition_and_derivatives(
        n in 0usize..=4, m in 0usize..=4, seed in coeff_vec(40),
        w in prop::array::uniform3(0.01f64..1.0), t in 0.0f64..=1.0,
    ) {
        let s: f64 = w.iter().sum();
        let tau = w.map(|v| v / s);
        let mut i = 0;
        let p = PrismBb::from_fn(n, m, |_, _| { i += 1; seed[i % seed.len()] });
        let mut direct = 0.0;
        let mut unity = 0.0;
        for (r, lambda) in multi_index::iter::<3>(n).enumerate() {
            for l in 0..=m {
                let b = PrismBb::<f64>::basis(n, m, lambda, l, tau, t);
                prop_assert!(b >= 0.0);
                unity += b;
                direct += p.coeffs()[r * (m + 1) + l] * b;
            }
        }
        prop_assert!((unity - 1.0).abs() <= 1e-13);
        prop_assert!((p.eval(tau, t) - direct).abs() <= 1e-13);
        // ∂/∂t and a triangle direction vs central differences: degree ≤ 4, coefficients in
        // [−1, 1]; with Σ|d_i| = 2 a third directional derivative is at most
        // 4·3·2 · 2³ · max|w| = 192 (blossom bound), the same for t.
        let h = 1e-5;
        let fd_tol = h * h / 6.0 * 192.0 + 4.0 * f64::EPSILON * 8.0 / h;
        let fd_t = (p.eval(tau, t + h) - p.eval(tau, t - h)) / (2.0 * h);
        prop_assert!((p.derivative_t().eval(tau, t) - fd_t).abs() <= fd_tol);
        let d = [1.0, -0.5, -0.5];
        let plus = [tau[0] + h * d[0], tau[1] + h * d[1], tau[2] + h * d[2]];
        let minus = [tau[0] - h * d[0], tau[1] - h * d[1], tau[2] - h * d[2]];
        let fd_d = (p.eval(plus, t) - p.eval(minus, t)) / (2.0 * h);
        prop_assert!((p.derivative_tau(d).eval(tau, t) - fd_d).abs() <= fd_tol);
        // Elevation in either factor preserves values.
        prop_assert!((p.elevate_t(2).eval(tau, t) - p.eval(tau, t)).abs() <= 1e-13);
        prop_assert!((p.elevate_tau(2).eval(tau, t) - p.eval(tau, t)).abs() <= 1e-13);
        // The layers are the BB polynomials of the prism's faces t = 0 and t = 1.
        prop_assert!((p.layer(0).unwrap().eval(tau) - p.eval(tau, 0.0)).abs() <= 1e-14);
        prop_assert!((p.layer(m).unwrap().eval(tau) - p.eval(tau, 1.0)).abs() <= 1e-14);
    }
}

#[test]
fn construction_errors() {
    assert!(TensorBb2::<f64>::new([1, 1], vec![0.0; 3]).is_err());
    assert!(TensorBb2::<f64>::new([1, 1], vec![0.0; 4]).is_ok());
    assert!(PrismBb::<f64>::new(2, 1, vec![0.0; 11]).is_err());
    assert!(PrismBb::<f64>::new(2, 1, vec![0.0; 12]).is_ok());
    let p = PrismBb::<f64>::new(2, 1, vec![1.0; 12]).unwrap();
    assert!(p.layer(2).is_none());
    assert_eq!(p.derivative_t().degrees(), (2, 0));
    assert_eq!(p.derivative_t().derivative_t().coeffs(), &[0.0; 6]);
}

//! Root finding on [0, 1]: polynomials built from known roots, the closed form against the
//! subdivision solver, and the §4.4 root choice along a path.

use algesurf_bb::BbPoly;
use algesurf_bb::roots::{
    Branch, CardanoCubic, MAX_DEGREE, Root, RootOptions, cubic_roots, cubic_roots_closed_form,
    find_roots, find_roots_of, shooting_root,
};
use proptest::prelude::*;

/// A factor `(t − r)^m` of a test polynomial.
#[derive(Clone, Copy, Debug)]
struct Factor {
    r: f64,
    m: usize,
}

/// `scale · Π (t − r_i)^{m_i} · (extra)`, built by Bernstein products (`mul_scalar_poly`),
/// the way user code builds polynomials. `extra` is a factor without roots in [0, 1].
fn build(factors: &[Factor], extra: &[f64], scale: f64) -> BbPoly<f64, 2> {
    let mut p = BbPoly::univariate(&[scale]).unwrap();
    for f in factors {
        let lin = BbPoly::univariate(&[-f.r, 1.0 - f.r]).unwrap();
        for _ in 0..f.m {
            p = p.mul_scalar_poly(&lin);
        }
    }
    p.mul_scalar_poly(&BbPoly::univariate(extra).unwrap())
}

/// Value of the exact product at t (for the conditioning of each root).
fn exact_value(factors: &[Factor], extra: &[f64], scale: f64, skip: usize, t: f64) -> f64 {
    let e = BbPoly::univariate(extra).unwrap().eval_t(t);
    let mut v = scale * e;
    for (i, f) in factors.iter().enumerate() {
        if i != skip {
            v *= (t - f.r).powi(f.m as i32);
        }
    }
    v
}

/// The expected accuracy of an m-fold root r: a coefficient perturbation of size E moves it by
/// at most about `(E / |p^{(m)}(r)/m!|)^{1/m}` (the first term of the Taylor expansion at r).
/// E is the solver's documented coefficient error bound plus the de Casteljau rounding; the
/// factor 4 covers the second-order terms.
fn expected_accuracy(
    p: &BbPoly<f64, 2>,
    factors: &[Factor],
    extra: &[f64],
    scale: f64,
    i: usize,
) -> f64 {
    let n = p.degree();
    let e = (RootOptions::for_degree(n).relative_coefficient_error + 4.0 * n as f64 * f64::EPSILON)
        * p.max_coeff_norm();
    let f = factors[i];
    let taylor = exact_value(factors, extra, scale, i, f.r).abs();
    4.0 * (e / taylor).powf(1.0 / f.m as f64) + 4.0 * f64::EPSILON
}

fn check_recovers(factors: &[Factor], extra: &[f64], scale: f64) -> Result<(), TestCaseError> {
    let p = build(factors, extra, scale);
    let roots = find_roots_of(&p).unwrap();
    let mut sorted: Vec<(usize, Factor)> = factors.iter().copied().enumerate().collect();
    sorted.sort_by(|a, b| a.1.r.total_cmp(&b.1.r));
    prop_assert_eq!(
        roots.len(),
        factors.len(),
        "roots {:?} of {:?} (factors {:?})",
        roots,
        p.coeffs(),
        factors
    );
    for (root, (i, f)) in roots.iter().zip(&sorted) {
        let tol = expected_accuracy(&p, factors, extra, scale, *i);
        prop_assert!(
            (root.t - f.r).abs() <= tol,
            "root {:?} vs {:?}: error {:e} > {:e}",
            root,
            f,
            (root.t - f.r).abs(),
            tol
        );
        prop_assert_eq!(root.multiplicity, f.m, "root {:?} vs {:?}", root, f);
    }
    Ok(())
}

/// Well-separated roots (gap ≥ 0.05) in [0, 1], some at 0 and 1, multiplicities 1..=3, total
/// degree ≤ `max_degree` with a root-free extra factor.
fn factor_set(max_degree: usize) -> impl Strategy<Value = (Vec<Factor>, Vec<f64>, f64)> {
    (
        prop::collection::vec((0usize..20, 1usize..=3), 1..=4),
        prop_oneof![
            Just(vec![1.0]),
            Just(vec![1.0]),
            (0.2f64..2.0, 0.2f64..2.0).prop_map(|(a, b)| vec![a, b]),
            (0.5f64..2.0, -0.2f64..0.2, 0.5f64..2.0).prop_map(|(a, b, c)| vec![a, b, c]),
        ],
        prop_oneof![Just(1.0), -1e3f64..-1e-3, 1e-3f64..1e3],
    )
        .prop_map(move |(raw, extra, scale)| {
            let mut slots: Vec<usize> = Vec::new();
            let mut factors = Vec::new();
            let mut degree = extra.len() - 1;
            for (slot, m) in raw {
                // Slots 0..=19 on a grid of 1/19: roots at least 1/19 ≈ 0.053 apart, with
                // slot 0 → t = 0 and slot 19 → t = 1 exactly.
                if slots.contains(&slot) || degree + m > max_degree {
                    continue;
                }
                slots.push(slot);
                degree += m;
                factors.push(Factor {
                    r: slot as f64 / 19.0,
                    m,
                });
            }
            if factors.is_empty() {
                // The extra factor alone could exceed the degree: keep one simple root.
                return (vec![Factor { r: 0.5, m: 1 }], vec![1.0], scale);
            }
            (factors, extra, scale)
        })
}

proptest! {
    #[test]
    fn recovers_roots_with_multiplicities((factors, extra, scale) in factor_set(9)) {
        check_recovers(&factors, &extra, scale)?;
    }

    #[test]
    fn closed_form_agrees_with_subdivision(
        coeffs in prop::collection::vec(-1.0f64..1.0, 2..=4),
    ) {
        let closed = cubic_roots_closed_form(&coeffs).unwrap();
        let sub = find_roots(&coeffs).unwrap();
        let closed = closed.expect("closed form verified");
        prop_assert_eq!(closed.len(), sub.len(), "{:?}: {:?} vs {:?}", coeffs, closed, sub);
        for (a, b) in closed.iter().zip(&sub) {
            prop_assert_eq!(a.multiplicity, b.multiplicity);
            // Both are polished to the conditioning of the root: compare through the residual
            // scale |p(t)| / |p'(t)|, bounded by the coefficient error over the slope.
            let p = BbPoly::univariate(&coeffs).unwrap();
            let slope = p.derivative([-1.0, 1.0]).eval_t(a.t).abs();
            let tol = 1e-13 * p.max_coeff_norm() / slope.max(1e-300) + 1e-15;
            prop_assert!((a.t - b.t).abs() <= tol, "{:?}: {:?} vs {:?}", coeffs, a, b);
        }
    }

    #[test]
    fn closed_form_recovers_built_cubics((factors, extra, scale) in factor_set(3)) {
        let p = build(&factors, &extra, scale);
        prop_assert!(p.degree() <= 3);
        let closed = cubic_roots_closed_form(p.coeffs()).unwrap().expect("verified");
        let sub = find_roots_of(&p).unwrap();
        prop_assert_eq!(closed.len(), sub.len());
        for (a, b) in closed.iter().zip(&sub) {
            prop_assert_eq!(a.multiplicity, b.multiplicity);
        }
        check_recovers(&factors, &extra, scale)?;
    }

    /// The shooting root is the smallest root in [0, 1) that the subdivision solver finds.
    #[test]
    fn shooting_root_is_the_smallest_root(b in prop::array::uniform4(-1.0f64..1.0)) {
        let sub = find_roots(&b).unwrap();
        let expected = sub.iter().find(|r| r.t < 1.0);
        let got = shooting_root(b).unwrap();
        match (got, expected) {
            (None, None) => {}
            (Some(g), Some(e)) => {
                let p = BbPoly::univariate(&b).unwrap();
                let slope = p.derivative([-1.0, 1.0]).eval_t(e.t).abs();
                // Simple roots: agreement to the conditioning; multiple: to its square root.
                let tol = if e.is_simple() {
                    1e-13 / slope.max(1e-300) + 1e-15
                } else {
                    1e-6
                };
                prop_assert!((g.t - e.t).abs() <= tol, "{:?}: {:?} vs {:?}", b, g, e);
            }
            (g, e) => prop_assert!(false, "{:?}: shooting {:?} vs subdivision {:?}", b, g, e),
        }
    }

    /// In the Corollary's setting (ab > 0, ad < 0) the branch is always x₁.
    #[test]
    fn corollary_setting_uses_x1(
        d in -1.0f64..-1e-3, c in -2.0f64..2.0, b in 1e-3f64..2.0, a in 1e-3f64..2.0,
    ) {
        let r = shooting_root([d, c, b, a]).unwrap().expect("one positive root by Descartes");
        prop_assert_eq!(r.branch, Branch::X1);
        let p = BbPoly::univariate(&[d, c, b, a]).unwrap();
        prop_assert!(p.eval_t(r.t).abs() <= 8.0 * f64::EPSILON * 2.0);
    }

    #[test]
    fn never_panics(b in prop::collection::vec(prop_oneof![
        -1e3f64..1e3, Just(0.0), Just(f64::NAN), Just(f64::INFINITY), Just(1e-300), Just(1e300)
    ], 0..12)) {
        let r = find_roots(&b);
        if b.is_empty() || b.iter().any(|x| !x.is_finite()) || b.iter().all(|x| *x == 0.0) {
            prop_assert!(r.is_err());
        } else {
            let r = r.unwrap();
            prop_assert!(r.windows(2).all(|w| w[0].t <= w[1].t));
            prop_assert!(r.iter().all(|x| (0.0..=1.0).contains(&x.t) && x.multiplicity >= 1));
        }
        if b.len() == 4 {
            let s = shooting_root([b[0], b[1], b[2], b[3]]);
            prop_assert_eq!(s.is_err(), b.iter().any(|x| !x.is_finite()));
        }
    }
}

#[test]
fn double_triple_and_end_roots() {
    let f = |r: f64, m: usize| Factor { r, m };
    for (factors, extra) in [
        (vec![f(0.3, 2), f(0.7, 1)], vec![1.0]),
        (vec![f(0.5, 3)], vec![1.0, 2.0]),
        (vec![f(0.0, 2), f(1.0, 3), f(0.4, 1)], vec![1.0]),
        (
            vec![f(0.0, 1), f(0.25, 2), f(0.75, 2), f(1.0, 1)],
            vec![1.0, -0.5, 1.0],
        ),
        (vec![f(0.1, 3), f(0.9, 3)], vec![1.0]),
        (vec![f(0.2, 1), f(0.45, 4)], vec![1.0]),
    ] {
        check_recovers(&factors, &extra, 1.0).unwrap();
    }
}

#[test]
fn clusters_below_rounding_become_one_multiple_root() {
    // Two roots 1e-10 apart: p ≈ (t − r)², whose minimum −(5e-11)² is far below the rounding
    // level, so no computation in f64 can separate them: one cluster of multiplicity 2.
    let p = build(
        &[
            Factor { r: 0.3, m: 1 },
            Factor {
                r: 0.3 + 1e-10,
                m: 1,
            },
            Factor { r: 0.8, m: 1 },
        ],
        &[1.0],
        1.0,
    );
    let r = find_roots_of(&p).unwrap();
    assert_eq!(r.len(), 2, "{r:?}");
    assert_eq!(r[0].multiplicity, 2);
    assert!((r[0].t - 0.3).abs() < 1e-7);
    assert!(r[1].is_simple() && (r[1].t - 0.8).abs() < 1e-14);
    // Three roots 1e-3 apart are resolved: simple, each to full precision.
    let c = [0.5, 0.501, 0.502];
    let p = build(&c.map(|r| Factor { r, m: 1 }), &[1.0], 1.0);
    let r = find_roots_of(&p).unwrap();
    assert_eq!(r.len(), 3, "{r:?}");
    for (x, e) in r.iter().zip(c) {
        assert!(x.is_simple());
        // Conditioning: |p'(r)| ≈ 2e-6 against coefficient errors ~1e-16 ⇒ ~1e-10.
        assert!((x.t - e).abs() < 1e-9, "{x:?} vs {e}");
    }
}

#[test]
fn touching_root_without_sign_change_is_found() {
    // (t − 0.6)² + 1e-18 never vanishes, but lies within rounding of a double root: the
    // coefficient hull touches zero and p' vanishes there.
    let p = build(&[Factor { r: 0.6, m: 2 }], &[1.0], 1.0);
    let c: Vec<f64> = p.coeffs().iter().map(|x| x + 1e-18).collect();
    let r = find_roots(&c).unwrap();
    assert_eq!(r.len(), 1);
    assert_eq!(r[0].multiplicity, 2);
    assert!((r[0].t - 0.6).abs() < 1e-12, "{r:?}");
    // Lifted clearly above rounding: no root at all.
    let c: Vec<f64> = p.coeffs().iter().map(|x| x + 1e-9).collect();
    assert!(find_roots(&c).unwrap().is_empty());
}

#[test]
fn high_degree_and_errors() {
    // Degree 9 Wilkinson-like: roots k/10, k = 1..9, all simple.
    let factors: Vec<Factor> = (1..10)
        .map(|k| Factor {
            r: k as f64 / 10.0,
            m: 1,
        })
        .collect();
    check_recovers(&factors, &[1.0], 1.0).unwrap();
    // Degree 20.
    let factors: Vec<Factor> = (0..20)
        .map(|k| Factor {
            r: (k as f64 + 0.5) / 20.0,
            m: 1,
        })
        .collect();
    check_recovers(&factors, &[1.0], 1.0).unwrap();
    assert!(find_roots(&[]).is_err());
    assert!(find_roots(&[0.0, 0.0]).is_err());
    assert!(find_roots(&[1.0, f64::NAN]).is_err());
    assert!(find_roots(&vec![1.0; MAX_DEGREE + 2]).is_err());
    assert!(cubic_roots(&[1.0; 5]).is_err());
    assert!(shooting_root([f64::NAN, 1.0, 1.0, 1.0]).is_err());
    assert_eq!(find_roots(&[2.0]).unwrap(), Vec::<Root>::new());
    // Constant zero at an end only: b = (0, 1) is t, a simple root at 0.
    assert_eq!(
        find_roots(&[0.0, 1.0]).unwrap(),
        vec![Root {
            t: 0.0,
            multiplicity: 1
        }]
    );
}

#[test]
fn shooting_root_degenerate_leading_coefficients() {
    // a = 0: s-quadratic 3b s² + 3c s + d. With d = −1, c = 0, b = 1/3: s = 1 ⇒ t = 1/2.
    let r = shooting_root([-1.0, 0.0, 1.0 / 3.0, 0.0]).unwrap().unwrap();
    assert_eq!(r.branch, Branch::Quadratic);
    assert!((r.t - 0.5).abs() < 1e-15);
    // a = b = 0: linear 3c s + d: s = 1/3 ⇒ t = 1/4 for c = 1, d = −1.
    let r = shooting_root([-1.0, 1.0, 0.0, 0.0]).unwrap().unwrap();
    assert_eq!(r.branch, Branch::Linear);
    assert!((r.t - 0.25).abs() < 1e-15);
    // Tiny a with the only root near t = 1: found by the fallback.
    let r = shooting_root([-1.0, -1.0, -1.0, 1e-9]).unwrap().unwrap();
    assert_eq!(r.branch, Branch::Subdivision);
    let p = BbPoly::univariate(&[-1.0, -1.0, -1.0, 1e-9]).unwrap();
    assert!(p.eval_t(r.t).abs() < 1e-15 && r.t < 1.0 && r.t > 0.999_999);
    // Tiny a with a quadratic root: polished on the full cubic.
    let b = [-1.0, 0.0, 1.0 / 3.0, 1e-8];
    let r = shooting_root(b).unwrap().unwrap();
    assert!(BbPoly::univariate(&b).unwrap().eval_t(r.t).abs() < 4e-16);
    // b_0 = 0 ⇒ t = 0; no root in [0, 1).
    assert_eq!(
        shooting_root([0.0, 1.0, 2.0, 3.0]).unwrap().unwrap().branch,
        Branch::Origin
    );
    assert!(shooting_root([1.0, 2.0, 3.0, 4.0]).unwrap().is_none());
    assert!(shooting_root([-1.0, -2.0, -3.0, 0.0]).unwrap().is_none());
}

/// The §4.4 Corollary: along a path with ab > 0 (and ad < 0), the chosen root — x₁ — varies
/// continuously, including where the discriminant changes sign (one real root ↔ three).
#[test]
fn shooting_root_is_continuous_along_a_path_where_ab_positive() {
    // d = −1, a = 1, b = 1 fixed; c from 2 down to −3 passes Δ > 0 → Δ < 0.
    let steps = 20_000;
    let mut prev: Option<f64> = None;
    let mut saw_pos = false;
    let mut saw_neg = false;
    let mut max_jump: f64 = 0.0;
    for k in 0..=steps {
        let c = 2.0 - 5.0 * k as f64 / steps as f64;
        let b = [-1.0, c, 1.0, 1.0];
        let cc = CardanoCubic::new(b).unwrap();
        saw_pos |= cc.delta > 0.0;
        saw_neg |= cc.delta < 0.0;
        let r = shooting_root(b).unwrap().unwrap();
        assert_eq!(r.branch, Branch::X1);
        // It is the smallest root in [0, 1).
        let sub = find_roots(&b).unwrap();
        assert!((sub[0].t - r.t).abs() < 1e-12, "c = {c}: {r:?} vs {sub:?}");
        if let Some(p) = prev {
            max_jump = max_jump.max((r.t - p).abs());
        }
        prev = Some(r.t);
    }
    assert!(saw_pos && saw_neg, "the path must cross Δ = 0");
    // Lipschitz along the path: |dt/dc| = |∂p/∂c| / |p'| ≤ 3/ min|p'| — bounded here, so a
    // jump bigger than 100 steps' worth would be a branch switch.
    assert!(max_jump < 100.0 * 5.0 / steps as f64, "max jump {max_jump}");
    // Without the paper's rule the branches do switch: the smallest non-negative s among the
    // three x_j is x₁ only sometimes; x₂ and x₃ are real on the Δ < 0 part of this path and
    // are discontinuous at Δ = 0 as functions of the formula (they are complex for Δ > 0).
}

#[test]
fn corollary_fails_without_ab_positive_but_general_rule_still_smallest() {
    // a > 0 > b: two positive s-roots possible; the smallest is not x₁ (the largest root).
    let b = [1.0, -2.0, -0.5, 1.0];
    let r = shooting_root(b).unwrap().unwrap();
    assert_ne!(r.branch, Branch::X1);
    let sub = find_roots(&b).unwrap();
    assert!((sub[0].t - r.t).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Lemma 2.3 (Xu–Huang–Bajaj 2001) and Theorem 2.1 (Bajaj–Chen–Xu 1994).

mod sheets {
    use super::*;
    use algesurf_bb::sheet::{LiftCase, edge_lifting_beta, j_patch_level, lemma_2_3_b_min};

    fn lifted(b: [f64; 4], beta: f64, x: f64) -> [f64; 4] {
        // β t² = β (B_2^3/3 + B_3^3).
        [b[0], b[1], b[2] + beta * x / 3.0, b[3] + beta * x]
    }

    /// `max{g_2, g_3}` and `g_3` of the Lemma, evaluated directly (monomials), for grid checks.
    fn g(b: [f64; 4], beta: f64, t: f64) -> (f64, f64, f64) {
        let s = 1.0 - t;
        let f1 = b[0] * s + b[1] * t;
        let f2 = b[0] * s * s + 2.0 * b[1] * s * t + b[2] * t * t;
        let f3 = BbPoly::univariate(&b).unwrap().eval_t(t);
        (-3.0 * f2 / (beta * t * t), -f3 / (beta * t * t), f1)
    }

    proptest! {
        #[test]
        fn above_b_min_the_smallest_root_is_simple(
            b0 in -2.0f64..-0.01, b1 in -3.0f64..3.0, b2 in -3.0f64..3.0, b3 in -3.0f64..3.0,
            beta in 0.1f64..3.0, lift in prop_oneof![Just(1e-6), Just(1e-3), Just(1.0)],
        ) {
            let b = [b0, b1, b2, b3];
            let bound = lemma_2_3_b_min(b, beta).unwrap();
            prop_assert!(bound.b_min.is_finite() && bound.t_min > 0.0 && bound.t_min <= 1.0);
            let x = bound.b_min + lift * (1.0 + bound.b_min.abs());
            let roots = find_roots(&lifted(b, beta, x)).unwrap();
            if let Some(first) = roots.iter().find(|r| r.t < 1.0) {
                prop_assert!(first.is_simple(), "b = {:?}, β = {}, bound {:?}: {:?}", b, beta, bound, roots);
                prop_assert!(first.t <= bound.t_min, "the proof puts the root in (0, t_min]");
            }
            // The proof's certificate: on [0, t_min] the coefficients change sign exactly once.
            let p = BbPoly::univariate(&lifted(b, beta, x)).unwrap();
            let left = p.reparametrize(&[[1.0, 0.0], [1.0 - bound.t_min, bound.t_min]]);
            let c = left.coeffs();
            // Coefficients within rounding of zero are skipped, as zeros are in the sign-change
            // count (in case 2, t_min is the zero of F_1, so that coefficient is 0 up to
            // rounding); 64ε of the largest covers the few operations of the subdivision.
            let cmax = c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let signs: Vec<bool> = c
                .iter()
                .filter(|v| v.abs() > 64.0 * f64::EPSILON * cmax)
                .map(|v| *v > 0.0)
                .collect();
            let changes = signs.windows(2).filter(|w| w[0] != w[1]).count();
            prop_assert_eq!(changes, 1, "certificate coefficients {:?}", c);
            // The minimum is found, not merely bounded: no grid point does better.
            for k in 1..=2000 {
                let t = k as f64 / 2000.0;
                let (g2, g3, f1) = g(b, beta, t);
                let slack = 1e-9 * (1.0 + g2.abs().max(g3.abs()));
                prop_assert!(bound.b_min_1 <= g2.max(g3) + slack, "t = {}: {:?}", t, bound);
                if f1 <= 0.0 {
                    prop_assert!(bound.b_min_2 <= g3 + slack, "t = {}: {:?}", t, bound);
                }
            }
        }
    }

    /// The bound is tight: b = (−1, −1, 4, −2), β = 1 has g_3(t) = 1/t² − 15 + 16t with its
    /// minimum −3 at t = 1/2 and F_1 ≤ 0 on [0, 1], so b_min = −3 (case 2), and at b = b_min the
    /// smallest root is the double root t = 1/2; just above it is simple, just below there is
    /// no root in [0, 1] at all.
    #[test]
    fn the_bound_is_tight_where_g3_has_an_interior_minimum() {
        let b = [-1.0, -1.0, 4.0, -2.0];
        let bound = lemma_2_3_b_min(b, 1.0).unwrap();
        assert_eq!(bound.case, LiftCase::Two);
        assert!((bound.b_min + 3.0).abs() < 1e-13, "{bound:?}");
        assert!((bound.t_min - 0.5).abs() < 1e-15);
        assert!(bound.b_min >= -3.0, "rounded upwards");
        let at = find_roots(&lifted(b, 1.0, bound.b_min)).unwrap();
        assert_eq!(at[0].multiplicity, 2, "{at:?}");
        assert!((at[0].t - 0.5).abs() < 1e-7);
        let above = find_roots(&lifted(b, 1.0, bound.b_min + 1e-3)).unwrap();
        assert!(above[0].is_simple() && above[0].t < 0.5);
        let below = find_roots(&lifted(b, 1.0, bound.b_min - 1e-3)).unwrap();
        assert!(below.iter().all(|r| r.t >= 1.0), "{below:?}");
    }

    #[test]
    fn lemma_rejects_bad_input_and_edge_beta_is_positive() {
        assert!(lemma_2_3_b_min([0.0, 1.0, 1.0, 1.0], 1.0).is_err());
        assert!(lemma_2_3_b_min([-1.0, 1.0, 1.0, 1.0], 0.0).is_err());
        assert!(lemma_2_3_b_min([-1.0, f64::NAN, 1.0, 1.0], 1.0).is_err());
        // β(y) = 1 at both ends; with ν₁, μ₄ ≥ 0 it is ≥ min(1, …) > 0 inside.
        assert_eq!(edge_lifting_beta(0.3, 0.7, 0.0), 1.0);
        assert_eq!(edge_lifting_beta(0.3, 0.7, 1.0), 1.0);
        // At y = 1/2: 1/8 + (2/3)(0.3)(3/8) + (2/3)(0.7)(3/8) + 1/8 + 1/4 = 0.75.
        assert!((edge_lifting_beta(0.3, 0.7, 0.5) - 0.75).abs() < 1e-15);
    }

    /// A tetrahedral polynomial of degree `m` whose layers along vertex `j` have the signs of
    /// Theorem 2.1 with `k = 1`: layer 0 positive, layer 1 mixed, the rest non-positive.
    fn j_patch_poly(m: usize, j: usize, seed: &[f64]) -> BbPoly<f64, 4> {
        let mut i = 0;
        BbPoly::from_fn(m, |l| {
            i += 1;
            let r = seed[i % seed.len()];
            match l[j] {
                0 => 0.1 + r.abs(),
                1 => r,
                // Some zeros inside the negative layers; the vertex coefficient stays negative
                // so that some layer above k is not all zero.
                s if s < m && i % 5 == 0 => 0.0,
                _ => -(0.05 + r.abs()),
            }
        })
    }

    proptest! {
        #[test]
        fn theorem_2_1_rays_from_vertex_j_meet_the_patch_once(
            m in 2usize..=5, j in 0usize..4,
            seed in prop::collection::vec(-1.0f64..1.0, 8..30),
            q in prop::array::uniform4(0.01f64..1.0),
        ) {
            let f = j_patch_poly(m, j, &seed);
            prop_assert_eq!(j_patch_level(&f, j).unwrap(), Some(1));
            // A point of the open face opposite j, and the segment from it to vertex j.
            let mut face = q;
            face[j] = 0.0;
            let sum: f64 = face.iter().sum();
            let face = face.map(|x| x / sum);
            let mut vj = [0.0; 4];
            vj[j] = 1.0;
            let ray = f.restrict_to_segment(face, vj);
            let roots = find_roots_of(&ray).unwrap();
            let interior: Vec<_> = roots.iter().filter(|r| r.t > 0.0 && r.t < 1.0).collect();
            prop_assert_eq!(interior.len(), 1, "{:?}", roots);
            prop_assert!(interior[0].is_simple());
        }
    }

    #[test]
    fn theorem_2_1_fails_where_rays_meet_three_times() {
        // Constant layers 1, −2, 2, −1 along vertex 3: every ray's polynomial has coefficients
        // (1, −2, 2, −1), which has three roots in (0, 1) (one at 1/2 by the antisymmetry
        // p(1 − t) = −p(t)).
        let f = BbPoly::<f64, 4>::from_fn(3, |l| [1.0, -2.0, 2.0, -1.0][l[3]]);
        assert_eq!(j_patch_level(&f, 3).unwrap(), None);
        let ray = f.restrict_to_segment([0.2, 0.3, 0.5, 0.0], [0.0, 0.0, 0.0, 1.0]);
        let roots = find_roots_of(&ray).unwrap();
        assert_eq!(roots.len(), 3, "{roots:?}");
        assert!(roots.iter().all(|r| r.is_simple()));
        // Along another vertex the condition can hold: layers in λ_0 mix the four values.
        assert!(j_patch_level(&f, 7).is_err());
        // Satisfied with k = 2 (layer 2 of mixed signs, layer 3 negative), and not with k = 1.
        let g = BbPoly::<f64, 4>::from_fn(4, |l| match l[0] {
            2 => {
                if l[1] % 2 == 0 {
                    0.3
                } else {
                    -0.3
                }
            }
            s => [1.0, 0.5, 0.0, -1.0, 0.0][s],
        });
        assert_eq!(j_patch_level(&g, 0).unwrap(), Some(2));
        // All-zero layer 0 fails the "Σ b_λ > 0" part.
        let h = BbPoly::<f64, 4>::from_fn(3, |l| [0.0, 1.0, -1.0, -1.0][l[1]]);
        assert_eq!(j_patch_level(&h, 1).unwrap(), None);
    }
}

/// A ray that starts a hair off the surface (b₀ = −2.5e-34 against coefficients ~5e-3, seen on
/// the fandisk) still has its root near t = 0; Cardano's shift cannot resolve it, the
/// near-origin branch must.
#[test]
fn shooting_root_just_above_the_origin() {
    use algesurf_bb::roots::shooting_root;
    for d in [-2.527783052008247e-34, -1e-20, -1e-15, -1e-12] {
        let c = [
            d,
            0.0046949808268929305,
            0.009404879277733747,
            0.014130528525466701,
        ];
        let r = shooting_root(c).unwrap().expect("a root near 0");
        let expected = -d / (3.0 * c[1]);
        // Within rounding of the true root: below 8ε·scale, b₀ is noise and t = 0 (1e-14 in t
        // covers that); above it the root is resolved to 1e-6 relative.
        assert!(
            r.t >= 0.0 && (r.t - expected).abs() <= 1e-6 * expected.abs() + 1e-14,
            "d = {d}: t = {}",
            r.t
        );
    }
}

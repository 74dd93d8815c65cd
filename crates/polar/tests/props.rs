//! Property tests of algesurf-polar: random control nets over random non-degenerate frames.

use algesurf_polar::{
    AffineFrame, CornerStar, IntervalFrame, PolarCurve, PolarError, PolarLabel, PolarPatch,
    continuity::{self, SharedEdge},
    corner_star_residual,
};
use glam::{DAffine2, DMat2, DVec2, DVec3};
use proptest::prelude::*;
use std::collections::HashMap;

// ---------------------------------------------------------------- strategies and helpers

fn v2() -> impl Strategy<Value = DVec2> {
    (-5.0..5.0f64, -5.0..5.0f64).prop_map(|(x, y)| DVec2::new(x, y))
}

fn v3() -> impl Strategy<Value = DVec3> {
    (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// A random frame with relative area ≥ 0.05 (well-conditioned enough for 1e-12 checks).
fn frame() -> impl Strategy<Value = AffineFrame> {
    (v2(), v2(), v2()).prop_filter_map("degenerate frame", |(r, s, t)| {
        AffineFrame::new(r, s, t)
            .ok()
            .filter(|f| f.relative_area() >= 0.05)
    })
}

fn patch(degrees: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = PolarPatch> {
    (frame(), degrees).prop_flat_map(|(f, n)| {
        let count = (n + 1) * (n + 2) / 2;
        prop::collection::vec(v3(), count).prop_map(move |pts| PolarPatch::new(f, n, pts).unwrap())
    })
}

/// Barycentric coordinates with every entry ≥ `lo` (a point inside the triangle).
fn inside(lo: f64) -> impl Strategy<Value = [f64; 3]> {
    (0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64).prop_map(move |(a, b, c)| {
        let s = a + b + c + 1e-9;
        let w = [a / s, b / s, c / s];
        let k = 1.0 - 3.0 * lo;
        [lo + k * w[0], lo + k * w[1], lo + k * w[2]]
    })
}

fn scale(p: &PolarPatch) -> f64 {
    p.bb().max_coeff_norm().max(1.0)
}

/// The condition scale of evaluating `p` at `a`: `Σ |b_λ| B_λ(|τ|)` (de Casteljau's forward
/// error is bounded by n ε times this).
fn cond(p: &PolarPatch, a: DVec2) -> f64 {
    p.bb()
        .map(|b| b.length())
        .eval(p.frame().barycentric(a).map(f64::abs))
}

/// The growth `(max_i Σ_j |τ_j(g_i)|)^n` of the coefficients' error bound under a change of
/// frame from `p`'s frame to `g`.
fn growth(p: &PolarPatch, g: &AffineFrame) -> f64 {
    g.points()
        .iter()
        .map(|x| {
            p.frame()
                .barycentric(*x)
                .iter()
                .map(|c| c.abs())
                .sum::<f64>()
        })
        .fold(1.0, f64::max)
        .powi(p.degree() as i32)
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

/// The polar form of the monomial `x^a y^b` written in degree m ≥ a + b: the average, over all
/// ways of choosing a arguments for x and b for y among the m, of the product of coordinates.
fn monomial_blossom(a: usize, b: usize, args: &[DVec2]) -> f64 {
    let m = args.len();
    let mut sum = 0.0;
    let mut count = 0usize;
    for code in 0..3usize.pow(m as u32) {
        let mut c = code;
        let (mut na, mut nb, mut prod) = (0, 0, 1.0);
        for arg in args {
            match c % 3 {
                0 => {
                    na += 1;
                    prod *= arg.x;
                }
                1 => {
                    nb += 1;
                    prod *= arg.y;
                }
                _ => {}
            }
            c /= 3;
        }
        if na == a && nb == b {
            sum += prod;
            count += 1;
        }
    }
    sum / count as f64
}

/// A polynomial surface F(x, y) = Σ c_ab x^a y^b of total degree ≤ m, with its polar form.
#[derive(Clone, Debug)]
struct Monomial {
    m: usize,
    terms: Vec<(usize, usize, DVec3)>,
}

impl Monomial {
    fn eval(&self, p: DVec2) -> DVec3 {
        self.terms
            .iter()
            .map(|&(a, b, c)| c * (p.x.powi(a as i32) * p.y.powi(b as i32)))
            .sum()
    }
    fn blossom(&self, args: &[DVec2]) -> DVec3 {
        self.terms
            .iter()
            .map(|&(a, b, c)| c * monomial_blossom(a, b, args))
            .sum()
    }
    /// The control net over `frame` straight from the polar form (Lemma 2.7.1).
    fn patch(&self, frame: AffineFrame) -> PolarPatch {
        PolarPatch::from_fn(frame, self.m, |l| {
            let args: Vec<DVec2> = [(frame.r(), l.i), (frame.s(), l.j), (frame.t(), l.k)]
                .iter()
                .flat_map(|&(p, k)| std::iter::repeat_n(p, k))
                .collect();
            self.blossom(&args)
        })
    }
}

fn monomial(degrees: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = Monomial> {
    degrees.prop_flat_map(|m| {
        let exps: Vec<(usize, usize)> = (0..=m)
            .flat_map(|a| (0..=m - a).map(move |b| (a, b)))
            .collect();
        prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), exps.len()).prop_map(
            move |cs| Monomial {
                m,
                terms: exps
                    .iter()
                    .zip(cs)
                    .map(|(&(a, b), (x, y, z))| (a, b, DVec3::new(x, y, z)))
                    .collect(),
            },
        )
    })
}

/// A vertex q across the edge (r, s) from p, with Δqrs reasonably shaped.
fn opposite(r: DVec2, s: DVec2, p: DVec2, mu: f64, nu: f64) -> Option<DVec2> {
    let e = s - r;
    let mut n = e.perp();
    if n.dot(p - r) > 0.0 {
        n = -n;
    }
    let q = r + e * mu + n * nu;
    AffineFrame::new(q, r, s)
        .ok()
        .filter(|f| f.relative_area() >= 0.05)
        .map(|_| q)
}

/// A random frame for the neighbour: the points q, r, s in the order given by `perm`.
fn permuted(points: [DVec2; 3], perm: usize) -> AffineFrame {
    const PERMS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let p = PERMS[perm % 6];
    AffineFrame::new(points[p[0]], points[p[1]], points[p[2]]).unwrap()
}

/// An adjacent pair: A random over (r, s, p) from `base`, B's frame over (q, r, s) permuted.
fn adjacent_frames() -> impl Strategy<Value = (AffineFrame, AffineFrame)> {
    (frame(), -0.2..1.2f64, 0.3..1.5f64, 0..6usize).prop_filter_map(
        "bad neighbour",
        |(fa, mu, nu, perm)| {
            let [r, s, p] = fa.points();
            let q = opposite(r, s, p, mu, nu)?;
            Some((fa, permuted([q, r, s], perm)))
        },
    )
}

fn random_net(f: AffineFrame, n: usize, seed: &[DVec3]) -> PolarPatch {
    let count = (n + 1) * (n + 2) / 2;
    PolarPatch::new(f, n, seed.iter().cycle().take(count).copied().collect()).unwrap()
}

// ---------------------------------------------------------------- properties

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn blossom_diagonal_is_evaluation(p in patch(0..=6), w in inside(-0.2)) {
        let a = p.frame().point(w);
        let diag = p.blossom(&vec![a; p.degree()]).unwrap();
        prop_assert!(close(diag, p.eval(a), 1e-12 * scale(&p)));
    }

    #[test]
    fn blossom_is_symmetric_and_multiaffine(
        p in patch(1..=5), pts in prop::collection::vec(v2(), 6), b in v2(), alpha in -1.0..2.0f64,
    ) {
        let n = p.degree();
        let args = &pts[..n];
        let f = p.blossom(args).unwrap();
        let mut rev = args.to_vec();
        rev.reverse();
        let tol = 1e-10 * scale(&p) * 100f64.powi(n as i32) / p.frame().relative_area();
        prop_assert!(close(f, p.blossom(&rev).unwrap(), tol));
        // Affine in the first argument.
        let mut mixed = args.to_vec();
        mixed[0] = args[0] * alpha + b * (1.0 - alpha);
        let mut with_b = args.to_vec();
        with_b[0] = b;
        let lhs = p.blossom(&mixed).unwrap();
        let rhs = f * alpha + p.blossom(&with_b).unwrap() * (1.0 - alpha);
        prop_assert!(close(lhs, rhs, tol));
    }

    #[test]
    fn control_points_are_polar_values_of_the_surface(
        mono in monomial(0..=3), f in frame(), pts in prop::collection::vec(v2(), 3), w in inside(0.0),
    ) {
        // Lemma 2.7.1: the net f(r^i s^j t^k) defines the surface and its polar form everywhere.
        let p = mono.patch(f);
        let a = f.point(w);
        // Relative to the sizes involved: the monomial terms and the control net.
        let size = |x: DVec2| mono.terms.iter().map(|&(i, j, c)| c.length() * (x.x.abs().powi(i as i32) * x.y.abs().powi(j as i32))).sum::<f64>();
        prop_assert!(close(p.eval(a), mono.eval(a), 1e-12 * (size(a) + cond(&p, a))));
        let args = &pts[..mono.m];
        let reach = args.iter().map(|x| f.barycentric(*x).iter().map(|c| c.abs()).sum::<f64>()).fold(1.0, f64::max);
        let big = args.iter().map(|x| x.abs().max_element()).fold(1.0, f64::max);
        let tol = 1e-12 * (scale(&p) * reach.powi(mono.m as i32) + size(DVec2::splat(big)));
        prop_assert!(close(p.blossom(args).unwrap(), mono.blossom(args), tol));
    }

    #[test]
    fn change_of_frame_leaves_the_surface_unchanged(p in patch(0..=5), g in frame(), w in inside(0.0)) {
        // Any frame, however far: relative 1e-12 of the problem's own scale (the de Casteljau
        // error bounds of the change of frame and of the two evaluations).
        let q = p.reparametrize(g);
        let a = p.frame().point(w);
        let n = p.degree() as i32;
        let reach: f64 = g.barycentric(a).iter().map(|c| c.abs()).sum();
        let tol = 1e-12
            * (cond(&p, a) + cond(&q, a) + scale(&p) * growth(&p, &g) * reach.powi(n));
        prop_assert!(close(q.eval(a), p.eval(a), tol), "{} vs {}", (q.eval(a) - p.eval(a)).length(), tol);
    }

    #[test]
    fn change_to_a_nearby_frame_is_exact_to_1e_12(
        p in patch(0..=6), noise in prop::collection::vec(-0.3..0.3f64, 6), w in inside(0.0),
    ) {
        // Each vertex of g moves by up to 0.3 in the barycentric coordinates of p's frame.
        let moved = |i: usize| {
            let mut b = [0.0; 3];
            b[i] = 1.0;
            b[(i + 1) % 3] += noise[2 * i];
            b[(i + 2) % 3] += noise[2 * i + 1];
            b[i] -= noise[2 * i] + noise[2 * i + 1];
            p.frame().point(b)
        };
        let g = AffineFrame::new(moved(0), moved(1), moved(2));
        prop_assume!(g.is_ok());
        let g = g.unwrap();
        let q = p.reparametrize(g);
        let sc = scale(&p).max(scale(&q));
        // Points of the new triangle (which lies near the old one).
        {
            let a = g.point(w);
            prop_assert!(close(q.eval(a), p.eval(a), 1e-12 * sc), "{}", (q.eval(a) - p.eval(a)).length() / sc);
            // Derivatives and normals are those of the same surface too.
            let u = DVec2::new(0.3, -0.7);
            prop_assert!(close(q.derivative(a, u), p.derivative(a, u), 1e-11 * sc * 6.0 / p.frame().diameter() / p.frame().relative_area()));
            if let (Ok(x), Ok(y)) = (q.normal(a), p.normal(a)) {
                prop_assert!((x - y).length() < 1e-6 || p.partials(a)[0].cross(p.partials(a)[1]).length() < 1e-3 * sc * sc);
            }
        }
        // And back: the original net (up to the growth of extrapolating q's net to p's frame).
        let back = q.reparametrize(*p.frame());
        for (x, y) in back.control_points().iter().zip(p.control_points()) {
            prop_assert!(close(*x, *y, 1e-12 * sc * growth(&q, p.frame()) * 10.0));
        }
    }

    #[test]
    fn lemma_5_3_3_reparameterisation_keeps_control_points(
        p in patch(0..=5), m in (0.0..6.3f64, 0.5..3.0f64, 0.5..3.0f64, -2.0..2.0f64, any::<bool>()), t in v2(), w in inside(0.0),
    ) {
        // ρ = rotation · (scale + shear), possibly orientation reversing.
        let sign = if m.4 { -1.0 } else { 1.0 };
        let lin = DMat2::from_angle(m.0) * DMat2::from_cols(DVec2::new(m.1, 0.0), DVec2::new(m.3, sign * m.2));
        let rho = DAffine2::from_mat2_translation(lin, t);
        let moved = p.transform_domain(rho).unwrap();
        prop_assert_eq!(moved.control_points(), p.control_points());
        // F' = F ∘ ρ⁻¹: F'(ρ(a)) = F(a).
        let a = p.frame().point(w);
        prop_assert!(close(moved.eval(rho.transform_point2(a)), p.eval(a), 1e-12 * scale(&p)));
        // Equivalently: the net of F' over ρ(Δrst) is the net of F over Δrst (thesis (5.1)).
        let direct = PolarPatch::from_fn(*moved.frame(), p.degree(), |l| {
            let args: Vec<DVec2> = [(p.frame().r(), l.i), (p.frame().s(), l.j), (p.frame().t(), l.k)]
                .iter()
                .flat_map(|&(x, k)| std::iter::repeat_n(x, k))
                .collect();
            p.blossom(&args).unwrap()
        });
        for (x, y) in direct.control_points().iter().zip(p.control_points()) {
            prop_assert!(close(*x, *y, 1e-12 * scale(&p)));
        }
    }

    #[test]
    fn three_split_preserves_values(p in patch(0..=6), at in inside(0.05), w in inside(0.0)) {
        let a = p.frame().point(at);
        let subs = p.subdivide_at(a).unwrap();
        // Frames Δast, Δrat, Δrsa.
        let [r, s, t] = p.frame().points();
        prop_assert_eq!(subs[0].frame().points(), [a, s, t]);
        prop_assert_eq!(subs[1].frame().points(), [r, a, t]);
        prop_assert_eq!(subs[2].frame().points(), [r, s, a]);
        for sub in &subs {
            // A point of the sub-triangle, and the shared corner a.
            let x = sub.frame().point(w);
            prop_assert!(close(sub.eval(x), p.eval(x), 1e-12 * scale(&p)));
            prop_assert!(close(sub.eval(a), p.eval(a), 1e-12 * scale(&p)));
        }
    }

    #[test]
    fn four_split_preserves_values(p in patch(0..=6), w in inside(0.0)) {
        let kids = p.split4();
        let [r, s, t] = p.frame().points();
        let (ma, mb, mc) = ((s + t) / 2.0, (r + t) / 2.0, (r + s) / 2.0);
        prop_assert_eq!(kids[0].frame().points(), [r, mc, mb]);
        prop_assert_eq!(kids[1].frame().points(), [mc, s, ma]);
        prop_assert_eq!(kids[2].frame().points(), [mb, ma, t]);
        prop_assert_eq!(kids[3].frame().points(), [ma, mb, mc]);
        for kid in &kids {
            let x = kid.frame().point(w);
            prop_assert!(close(kid.eval(x), p.eval(x), 1e-12 * scale(&p)));
            // Recursion: the split of a split.
            let grand = &kid.split4()[3];
            let y = grand.frame().point(w);
            prop_assert!(close(grand.eval(y), p.eval(y), 1e-12 * scale(&p)));
        }
    }

    #[test]
    fn elevation_preserves_values_and_symmetrises_the_blossom(
        p in patch(0..=5), k in 1..3usize, pts in prop::collection::vec(inside(0.0), 6), w in inside(-0.1),
    ) {
        let e = p.elevate(k);
        prop_assert_eq!(e.degree(), p.degree() + k);
        let a = p.frame().point(w);
        prop_assert!(close(e.eval(a), p.eval(a), 1e-12 * scale(&p)));
        // f̂(a_1..a_{n+1}) = (1/(n+1)) Σ_i f(a_1..â_i..a_{n+1}) (inside the frame).
        let e1 = p.elevate(1);
        let n1 = p.degree() + 1;
        let args: Vec<DVec2> = pts.iter().take(n1).map(|w| p.frame().point(*w)).collect();
        let mut avg = DVec3::ZERO;
        for i in 0..n1 {
            let mut rest = args.clone();
            rest.remove(i);
            avg += p.blossom(&rest).unwrap() / n1 as f64;
        }
        prop_assert!(close(e1.blossom(&args).unwrap(), avg, 1e-12 * scale(&p)));
    }

    #[test]
    fn derivatives_match_central_differences(
        p in patch(1..=5), w in inside(0.1), u in v2(), v in v2(),
    ) {
        prop_assume!(u.length() > 0.1 && v.length() > 0.1);
        let a = p.frame().point(w);
        // Central differences with one Richardson step (error O(h⁴)).
        let h = 1e-4 * p.frame().diameter();
        let rich = |g: &dyn Fn(f64) -> DVec3| {
            let c = |h: f64| (g(h) - g(-h)) / (2.0 * h);
            (c(h / 2.0) * 4.0 - c(h)) / 3.0
        };
        let d_scale = scale(&p) * (p.degree() as f64 / p.frame().diameter()).powi(2)
            * u.length().max(1.0) * v.length().max(1.0) / p.frame().relative_area().powi(2);
        let fd1 = rich(&|t| p.eval(a + u * t));
        prop_assert!(close(p.derivative(a, u), fd1, 1e-6 * d_scale), "first: {:?} vs {:?}", p.derivative(a, u), fd1);
        let fd2 = rich(&|t| p.derivative(a + u * t, v));
        prop_assert!(close(p.second_derivative(a, u, v), fd2, 1e-6 * d_scale), "second: {} vs scale {}", (p.second_derivative(a, u, v) - fd2).length(), d_scale);
        // Symmetry of second derivatives and the partials.
        prop_assert!(close(p.second_derivative(a, u, v), p.second_derivative(a, v, u), 1e-9 * d_scale));
        let [fx, fy] = p.partials(a);
        prop_assert!(close(p.derivative(a, u), fx * u.x + fy * u.y, 1e-9 * d_scale));
        // The unit normal is orthogonal to both partials.
        if let Ok(nrm) = p.normal(a) {
            prop_assert!((nrm.length() - 1.0).abs() < 1e-12);
            prop_assert!(nrm.dot(fx).abs() <= 1e-9 * fx.length().max(1e-300) + 1e-12 * d_scale);
            prop_assert!(nrm.dot(fy).abs() <= 1e-9 * fy.length().max(1e-300) + 1e-12 * d_scale);
        }
    }

    #[test]
    fn curves(
        pts in prop::collection::vec(v3(), 1..8), r in -5.0..5.0f64, len in 0.5..5.0f64,
        g in (-5.0..5.0f64, 0.5..5.0f64), t in 0.0..1.0f64, cut in 0.1..0.9f64,
    ) {
        let n = pts.len() - 1;
        let frame = IntervalFrame::new(r, r + len).unwrap();
        let c = PolarCurve::new(frame, n, pts.clone()).unwrap();
        let sc = c.bb().max_coeff_norm().max(1.0);
        let u = r + t * len;
        prop_assert!(close(c.blossom(&vec![u; n]).unwrap(), c.eval(u), 1e-12 * sc));
        // Other frame.
        let g = IntervalFrame::new(g.0, g.0 + g.1).unwrap();
        let other = c.reparametrize(g);
        let reach = g.barycentric(u).iter().map(|x| x.abs()).sum::<f64>();
        let grow = [g.r(), g.s()].iter().map(|&x| frame.barycentric(x).iter().map(|y| y.abs()).sum::<f64>()).fold(1.0, f64::max);
        let ccond = |k: &PolarCurve, x: f64| k.bb().map(|b| b.length()).eval(k.frame().barycentric(x).map(f64::abs));
        let tol = 1e-12 * (ccond(&c, u) + ccond(&other, u) + sc * (grow * reach).powi(n as i32));
        prop_assert!(close(other.eval(u), c.eval(u), tol));
        // Subdivision.
        let [left, right] = c.subdivide_at(r + cut * len).unwrap();
        prop_assert_eq!(left.frame().s(), r + cut * len);
        let piece = if t <= cut { &left } else { &right };
        prop_assert!(close(piece.eval(u), c.eval(u), 1e-12 * sc));
        // Elevation.
        prop_assert!(close(c.elevate(2).eval(u), c.eval(u), 1e-12 * sc));
        // Derivative against central differences.
        if n >= 1 {
            let h = 1e-5 * len;
            let fd = (c.eval(u + h) - c.eval(u - h)) / (2.0 * h);
            let ds = sc * (n as f64 / len).powi(2);
            prop_assert!(close(c.derivative(u, 1), fd, 1e-6 * ds));
        }
        // Lemma 5.3.3 for curves.
        let moved = c.transform_domain(-2.0, 1.0).unwrap();
        prop_assert!(close(moved.eval(-2.0 * u + 1.0), c.eval(u), 1e-12 * sc));
    }

    #[test]
    fn boundary_curve_is_the_restriction(p in patch(0..=5), t in 0.0..1.0f64) {
        let [r, s, _] = p.frame().points();
        let c = p.restrict_to_segment(r, s);
        prop_assert!(close(c.eval(t), p.eval(r + (s - r) * t), 1e-12 * scale(&p)));
        // Its control points are the patch's f(r^i s^j) (the C^0 data of (3.4)).
        let n = p.degree();
        for j in 0..=n {
            prop_assert!(close(c.control_points()[j], p.control_point(PolarLabel::new(n - j, j, 0)).unwrap(), 1e-12 * scale(&p)));
        }
    }

    #[test]
    fn imposed_c1_join_is_c1(
        (fa, fb) in adjacent_frames(), n in 1..=5usize,
        na in prop::collection::vec(v3(), 21), nb in prop::collection::vec(v3(), 21),
        u in 0.0..1.0f64, which in 0..21usize,
    ) {
        let a = random_net(fa, n, &na);
        let b = random_net(fb, n, &nb);
        let joined = continuity::impose_continuity(&a, &b, 1).unwrap();
        prop_assert!(continuity::c0_residual(&a, &joined).unwrap() < 1e-12);
        prop_assert!(continuity::c1_residual(&a, &joined).unwrap() < 1e-12);
        prop_assert!(continuity::derivative_jump(&a, &joined, 1, u).unwrap() < 1e-10);
        // Across-edge derivative by hand, at a random edge point.
        let edge = SharedEdge::between(a.frame(), joined.frame()).unwrap();
        let x = edge.point(u);
        let cross = (edge.s - edge.r).perp();
        let jump = (a.derivative(x, cross) - joined.derivative(x, cross)).length();
        prop_assert!(jump <= 1e-10 * scale(&a).max(scale(&joined)) * n as f64 * cross.length() / (edge.s - edge.r).length().min(1.0) * 100.0);
        // Rows h ≥ 2 of B are kept.
        let q = edge.b_index[2];
        for ((l, x), y) in joined.net().zip(b.control_points()) {
            if l.multi_index()[q] >= 2 {
                prop_assert_eq!(x, *y);
            }
        }
        // Perturbing one control point of the rows h ≤ 1 breaks the conditions clearly.
        let rows: Vec<PolarLabel> = joined.net().map(|(l, _)| l).filter(|l| l.multi_index()[q] <= 1).collect();
        let l = rows[which % rows.len()];
        let mut bad = joined.clone();
        let size = a.net_size().max(joined.net_size());
        bad.set_control_point(l, joined.control_point(l).unwrap() + DVec3::new(0.0, 0.0, 0.01 * size)).unwrap();
        prop_assert!(continuity::c1_residual(&a, &bad).unwrap() > 1e-3);
        prop_assert!(continuity::derivative_jump(&a, &bad, 1, u).unwrap() > 1e-9
            || continuity::derivative_jump(&a, &bad, 1, 0.5 * u + 0.25).unwrap() > 1e-9);
    }

    #[test]
    fn imposed_c2_join_is_c2((fa, fb) in adjacent_frames(), n in 2..=5usize,
        na in prop::collection::vec(v3(), 21), nb in prop::collection::vec(v3(), 21), u in 0.0..1.0f64,
    ) {
        let a = random_net(fa, n, &na);
        let b = random_net(fb, n, &nb);
        let joined = continuity::impose_continuity(&a, &b, 2).unwrap();
        prop_assert!(continuity::c2_residual(&a, &joined).unwrap() < 1e-12);
        prop_assert!(continuity::derivative_jump(&a, &joined, 2, u).unwrap() < 1e-10);
        // A random neighbour is not even C^0 (a clearly nonzero residual).
        prop_assert!(continuity::c0_residual(&a, &b).unwrap() > 1e-3);
    }

    #[test]
    fn diamond_rule_holds_for_one_polynomial_on_two_triangles(
        mono in monomial(2..=3), (fa, fb) in adjacent_frames(),
    ) {
        // Two nets built independently from ONE polynomial surface's polar form: C^∞.
        let a = mono.patch(fa);
        let b = mono.patch(fb);
        let edge = SharedEdge::between(&fa, &fb).unwrap();
        let diamonds = continuity::c1_diamonds(&a, &b).unwrap();
        prop_assert_eq!(diamonds.len(), mono.m);
        for d in &diamonds {
            prop_assert!(continuity::diamond_residual(edge.diamond(), *d).unwrap() < 1e-9);
            let apex = continuity::diamond_apex(edge.p, edge.r, edge.s, edge.q, d[0], d[1], d[2]).unwrap();
            prop_assert!(close(apex, d[3], 1e-9 * (1.0 + d[0].length())));
        }
        for k in 0..=mono.m {
            prop_assert!(continuity::continuity_residual(&a, &b, k).unwrap() < 1e-9);
        }
        // A perturbed apex violates the rule.
        let mut d = diamonds[0];
        let diag = d.iter().fold(DVec3::splat(f64::NEG_INFINITY), |m, x| m.max(*x))
            - d.iter().fold(DVec3::splat(f64::INFINITY), |m, x| m.min(*x));
        d[3] += DVec3::X * (0.05 * diag.length());
        let res = continuity::diamond_residual(edge.diamond(), d).unwrap();
        prop_assert!(res > 1e-3, "res {} d {:?} dom {:?}", res, d, edge.diamond());
    }

    #[test]
    fn tessellation_is_watertight(p in patch(0..=4), level in 0..5u32) {
        let (verts, tris) = p.tessellate(level);
        let m = 1usize << level;
        prop_assert_eq!(verts.len(), (m + 1) * (m + 2) / 2);
        prop_assert_eq!(tris.len(), m * m);
        // Vertices are surface points at the grid's domain points.
        for (v, x) in verts.iter().zip(p.tessellation_domain_points(level)) {
            prop_assert!(close(*v, p.eval(x), 1e-12 * scale(&p)));
        }
        // Every interior edge in exactly two triangles, with opposite directions; 3m boundary edges.
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &tris {
            prop_assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
            for e in 0..3 {
                let (x, y) = (t[e], t[(e + 1) % 3]);
                *edges.entry((x.min(y), x.max(y))).or_default() += if x < y { 1 } else { -1 };
            }
        }
        let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &tris {
            for e in 0..3 {
                let (x, y) = (t[e], t[(e + 1) % 3]);
                *uses.entry((x.min(y), x.max(y))).or_default() += 1;
            }
        }
        let boundary = uses.values().filter(|&&c| c == 1).count();
        prop_assert!(uses.values().all(|&c| c == 1 || c == 2));
        prop_assert_eq!(boundary, 3 * m);
        for (e, c) in &uses {
            if *c == 2 {
                prop_assert_eq!(edges[e], 0, "consistently oriented");
            }
        }
        // Euler characteristic of a disc.
        prop_assert_eq!(verts.len() as i64 - uses.len() as i64 + tris.len() as i64, 1);
        // Orientation follows the frame: domain triangles have the frame's sign of area.
        let dom = p.tessellation_domain_points(level);
        let sign = p.frame().signed_area().signum();
        for t in &tris {
            let (x, y, z) = (dom[t[0] as usize], dom[t[1] as usize], dom[t[2] as usize]);
            prop_assert_eq!((y - x).perp_dot(z - x).signum(), sign);
        }
    }

    #[test]
    fn corner_star_lemma_3_3_2(
        c in v2(), n_tri in 2..6usize, angles in prop::collection::vec(0.3..1.2f64, 6),
        radii in prop::collection::vec(0.5..2.0f64, 7), deg in 1..=4usize,
        seed in prop::collection::vec(v3(), 15), which in 0..3usize,
    ) {
        // A fan of n_tri triangles T_i = (v_1, v_{i+1}, v_{i+2}) around v_1 = c (incomplete star).
        let mut theta = 0.0;
        let mut ring = vec![c + DVec2::new(radii[0], 0.0)];
        for i in 0..n_tri {
            theta += angles[i];
            ring.push(c + DVec2::from_angle(theta) * radii[i + 1]);
        }
        prop_assume!(theta < 2.0 * std::f64::consts::PI - 0.3);
        let frames: Vec<AffineFrame> = (0..n_tri)
            .map(|i| AffineFrame::new(c, ring[i], ring[i + 1]).unwrap())
            .collect();
        // First patch random; each next one C^1 to the previous (Lemma 3.3.2's hypothesis).
        let mut patches = vec![random_net(frames[0], deg, &seed)];
        for f in &frames[1..] {
            let prev = patches.last().unwrap();
            let fresh = random_net(*f, deg, &seed[3..]);
            patches.push(continuity::impose_continuity(prev, &fresh, 1).unwrap());
        }
        prop_assert!(corner_star_residual(c, &patches).unwrap() < 1e-11);
        // The star is determined by any three points over affinely independent domain points.
        let star = CornerStar::of_patch(&patches[0], 0).unwrap();
        let last = n_tri;
        let three = CornerStar::from_three(c, deg, [ring[0], ring[last / 2 + 1].lerp(ring[last], 0.0), ring[last]],
            [star.star_point(ring[0]), star.star_point(ring[last / 2 + 1]), star.star_point(ring[last])]);
        if let Ok(three) = three {
            for v in &ring {
                prop_assert!(close(three.star_point(*v), star.star_point(*v), 1e-9 * scale(&patches[0])));
            }
        }
        // The constructor from the vertex point and two tangent directions agrees with the
        // patch's derivatives at the vertex.
        let p0 = &patches[0];
        let [fx, fy] = p0.partials(c);
        let from_t = CornerStar::from_tangents(c, deg, p0.eval(c), fx, fy).unwrap();
        for v in &ring {
            prop_assert!(close(from_t.star_point(*v), star.star_point(*v), 1e-10 * scale(p0) * deg as f64));
        }
        // Imposing a prescribed star makes every patch agree with it; perturbing breaks it.
        let target = CornerStar::from_corner(c, deg, seed[7], (ring[0], seed[8]), (ring[1], seed[9])).unwrap();
        let mut fresh: Vec<PolarPatch> = frames.iter().map(|f| random_net(*f, deg, &seed[5..])).collect();
        for p in &mut fresh {
            target.apply(p).unwrap();
            prop_assert!(target.residual(p).unwrap() < 1e-12);
        }
        prop_assert!(corner_star_residual(c, &fresh).unwrap() < 1e-12);
        let mut l = [0; 3];
        l[0] = deg - 1;
        l[1 + which % 2] += 1;
        let bad_label = if which == 2 { PolarLabel::corner(deg, 0) } else { PolarLabel::from_multi_index(l) };
        let k = fresh.len() - 1;
        let old = fresh[k].control_point(bad_label).unwrap();
        let size = fresh[k].net_size();
        fresh[k].set_control_point(bad_label, old + DVec3::X * 0.05 * size).unwrap();
        prop_assert!(corner_star_residual(c, &fresh).unwrap() > 1e-3);
    }
}

// ---------------------------------------------------------------- plain tests

#[test]
fn degenerate_inputs_are_typed_errors() {
    let z = DVec2::ZERO;
    assert!(matches!(
        AffineFrame::new(z, DVec2::X, DVec2::X * 3.0),
        Err(PolarError::DegenerateFrame { .. })
    ));
    assert!(matches!(
        AffineFrame::new(z, DVec2::X, DVec2::new(f64::NAN, 0.0)),
        Err(PolarError::NonFinite { .. })
    ));
    assert!(matches!(
        IntervalFrame::new(1.0, 1.0),
        Err(PolarError::DegenerateInterval { .. })
    ));
    let p = PolarPatch::from_fn(AffineFrame::unit(), 2, |l| {
        DVec3::new(l.i as f64, l.j as f64, 0.0)
    });
    assert!(matches!(
        p.blossom(&[z]),
        Err(PolarError::ArgumentCount {
            degree: 2,
            found: 1
        })
    ));
    assert!(matches!(
        PolarPatch::new(AffineFrame::unit(), 2, vec![DVec3::ZERO; 5]),
        Err(PolarError::Bb(_))
    ));
    // Subdividing at a point on an edge gives a flat sub-frame.
    assert!(matches!(
        p.subdivide_at(DVec2::new(0.5, 0.0)),
        Err(PolarError::DegenerateFrame { .. })
    ));
    // Continuity needs adjacent frames of equal degree.
    let far = AffineFrame::new(
        DVec2::new(5.0, 5.0),
        DVec2::new(6.0, 5.0),
        DVec2::new(5.0, 6.0),
    )
    .unwrap();
    let q = PolarPatch::from_fn(far, 2, |_| DVec3::ZERO);
    assert!(matches!(
        continuity::c1_residual(&p, &q),
        Err(PolarError::NotAdjacent(_))
    ));
    let overlapping = AffineFrame::new(z, DVec2::X, DVec2::new(0.5, 0.5)).unwrap();
    let o = PolarPatch::from_fn(overlapping, 2, |_| DVec3::ZERO);
    assert!(matches!(
        continuity::c0_residual(&p, &o),
        Err(PolarError::NotAdjacent(_))
    ));
    let nb = AffineFrame::new(DVec2::new(1.0, 1.0), DVec2::X, DVec2::Y).unwrap();
    let cubic = PolarPatch::from_fn(nb, 3, |_| DVec3::ZERO);
    assert!(matches!(
        continuity::c0_residual(&p, &cubic),
        Err(PolarError::DegreeMismatch { left: 2, right: 3 })
    ));
    // Collinear diamonds cannot propagate.
    assert!(matches!(
        continuity::diamond_apex(
            z,
            DVec2::X,
            DVec2::X * 2.0,
            DVec2::Y,
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y
        ),
        Err(PolarError::DegenerateFrame { .. })
    ));
    // A star needs a vertex of the patch.
    let star = CornerStar::from_tangents(DVec2::new(0.3, 0.3), 2, DVec3::ZERO, DVec3::X, DVec3::Y)
        .unwrap();
    let mut pp = p.clone();
    assert!(matches!(
        star.apply(&mut pp),
        Err(PolarError::NotAVertex { .. })
    ));
}

#[test]
fn singular_normals_are_reported() {
    // A patch whose net lies on a line: F_x × F_y = 0 everywhere.
    let line = PolarPatch::from_fn(AffineFrame::unit(), 3, |l| {
        DVec3::X * (l.i * l.i + l.j) as f64
    });
    assert!(matches!(
        line.normal(DVec2::new(0.2, 0.3)),
        Err(PolarError::SingularNormal { .. })
    ));
    // The cone-like degenerate corner: all star points of r equal the corner.
    let mut cone = PolarPatch::from_fn(AffineFrame::unit(), 2, |l| {
        DVec3::new(l.j as f64, l.k as f64, (l.j * l.k) as f64)
    });
    for l in [
        PolarLabel::new(2, 0, 0),
        PolarLabel::new(1, 1, 0),
        PolarLabel::new(1, 0, 1),
    ] {
        cone.set_control_point(l, DVec3::ZERO).unwrap();
    }
    assert!(cone.normal(DVec2::ZERO).is_err());
    assert!(cone.normal(DVec2::new(0.3, 0.3)).is_ok());
    // A plane: normal is ±z and frame independent.
    let plane = PolarPatch::from_fn(AffineFrame::unit(), 2, |l| {
        DVec3::new(l.j as f64, l.k as f64, 0.0) / 2.0
    });
    let nrm = plane.normal(DVec2::new(0.2, 0.2)).unwrap();
    assert!((nrm - DVec3::Z).length() < 1e-15);
    let flipped = plane.reparametrize(AffineFrame::new(DVec2::ZERO, DVec2::Y, DVec2::X).unwrap());
    assert!((flipped.normal(DVec2::new(0.2, 0.2)).unwrap() - DVec3::Z).length() < 1e-15);
}

#[test]
fn normal_jump_of_a_c1_join_vanishes() {
    let fa = AffineFrame::new(DVec2::ZERO, DVec2::X, DVec2::Y).unwrap();
    let fb = AffineFrame::new(DVec2::new(1.2, 0.9), DVec2::Y, DVec2::X).unwrap();
    let a = PolarPatch::from_fn(fa, 3, |l| {
        DVec3::new(
            l.j as f64,
            l.k as f64,
            ((l.i + 1) * (l.j + 2) % 5) as f64 / 4.0,
        ) / 3.0
    });
    let b0 = PolarPatch::from_fn(fb, 3, |_| DVec3::ZERO);
    let b = continuity::impose_continuity(&a, &b0, 1).unwrap();
    for u in [0.1, 0.5, 0.9] {
        assert!(continuity::normal_jump(&a, &b, u).unwrap() < 1e-12);
    }
    let c0 = continuity::impose_continuity(&a, &b0, 0).unwrap();
    assert!(continuity::normal_jump(&a, &c0, 0.5).unwrap() > 1e-3);
}

#[test]
fn thesis_table_2_2_enneper_net_reproduces_the_surface() {
    // Enneper's surface (u − u³/3 + uv², v − v³/3 + u²v, u² − v²) (thesis §2.7, Table 2.2);
    // its net is listed w.r.t. the frame r = (1, 0), s = (0, 1), t = (0, 0) of the (u, v) plane.
    let frame = AffineFrame::new(DVec2::X, DVec2::Y, DVec2::ZERO).unwrap();
    let enneper = |p: DVec2| {
        let (u, v) = (p.x, p.y);
        DVec3::new(
            u - u * u * u / 3.0 + u * v * v,
            v - v * v * v / 3.0 + u * u * v,
            u * u - v * v,
        )
    };
    let table = [
        ((3, 0, 0), DVec3::new(2.0 / 3.0, 0.0, 1.0)),
        ((2, 0, 1), DVec3::new(2.0 / 3.0, 0.0, 1.0 / 3.0)),
        ((2, 1, 0), DVec3::new(2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0)),
        ((1, 0, 2), DVec3::new(1.0 / 3.0, 0.0, 0.0)),
        ((1, 1, 1), DVec3::new(1.0 / 3.0, 1.0 / 3.0, 0.0)),
        ((1, 2, 0), DVec3::new(2.0 / 3.0, 2.0 / 3.0, -1.0 / 3.0)),
        ((0, 0, 3), DVec3::ZERO),
        ((0, 1, 2), DVec3::new(0.0, 1.0 / 3.0, 0.0)),
        ((0, 2, 1), DVec3::new(0.0, 2.0 / 3.0, -1.0 / 3.0)),
        ((0, 3, 0), DVec3::new(0.0, 2.0 / 3.0, -1.0)),
    ];
    let mut p = PolarPatch::from_fn(frame, 3, |_| DVec3::ZERO);
    for ((i, j, k), b) in table {
        p.set_control_point(PolarLabel::new(i, j, k), b).unwrap();
    }
    for x in [
        DVec2::new(0.2, 0.3),
        DVec2::new(0.5, 0.1),
        DVec2::new(0.0, 0.9),
    ] {
        assert!((p.eval(x) - enneper(x)).length() < 1e-14, "{x}");
    }
}

#[test]
fn labels_follow_storage_order() {
    let labels: Vec<String> = PolarLabel::all(2).map(|l| l.to_string()).collect();
    assert_eq!(
        labels,
        ["f(r^2)", "f(r s)", "f(r t)", "f(s^2)", "f(s t)", "f(t^2)"]
    );
    let p = PolarPatch::from_fn(AffineFrame::unit(), 4, |l| {
        DVec3::new(l.i as f64, l.j as f64, l.k as f64)
    });
    for (l, b) in p.net() {
        assert_eq!(b, DVec3::new(l.i as f64, l.j as f64, l.k as f64));
        assert_eq!(p.control_points()[l.rank()], b);
    }
}

#[test]
fn tessellation_of_a_linear_patch_is_its_domain() {
    let frame = AffineFrame::new(
        DVec2::new(1.0, 1.0),
        DVec2::new(3.0, 1.5),
        DVec2::new(0.0, 4.0),
    )
    .unwrap();
    let p = PolarPatch::from_fn(frame, 1, |l| {
        frame
            .point([l.i as f64, l.j as f64, l.k as f64])
            .extend(0.0)
    });
    let (verts, tris) = p.tessellate(2);
    assert_eq!(tris.len(), 16);
    for (v, x) in verts.iter().zip(p.tessellation_domain_points(2)) {
        assert!((*v - x.extend(0.0)).length() < 1e-14);
    }
}

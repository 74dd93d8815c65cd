//! Closed-form roots of BB polynomials of degree ≤ 3 by Cardano's formulas, as in §4.4 of
//! Xu–Huang–Bajaj 2001, "Rational A-patches".
//!
//! The paper writes the shooting polynomial as
//! `d B_0^3(t) + c B_1^3(t) + b B_2^3(t) + a B_3^3(t) = (1 − t)^3 (d + 3cs + 3bs² + as³)` with
//! `s = t/(1 − t) ∈ [0, ∞)` for `t ∈ [0, 1)`. So in this module's `[f64; 4]` arguments
//! (`b_0, b_1, b_2, b_3`, the crate's storage order) `d = b_0`, `c = b_1`, `b = b_2`, `a = b_3`.
//! With `s = x − b/a` the cubic in s becomes `x³ + px + q = 0`,
//! `p = 3(ac − b²)/a²`, `q = (2b³ − 3abc + a²d)/a³`, with discriminant
//! `Δ = (q/2)² + (p/3)³` and roots x₁, x₂, x₃ by (4.18)–(4.21) ([`CardanoCubic`]).
//!
//! Root choice ("Result" and "Corollary" of §4.4): the cube root (4.21) with arguments in
//! `(−π, π]` makes x₁ real, and x₁ is the required (smallest in `[0, 1)`) root wherever `Δ ≥ 0`.
//! When `ab > 0` the paper shows one branch serves the whole parameter region, and it is x₁.
//! We make that checkable: if also `a d < 0` (in the paper `d = F(q) < 0` and the lifted
//! `a = f_0003 > 0`), the coefficients of `d + 3cs + 3bs² + as³` have exactly one sign change
//! whatever the sign of c, so by Descartes' rule of signs there is exactly one positive root;
//! it is the largest real root, and for `Δ < 0` x₁ = 2ρ cos(θ/3) with θ ∈ (0, π) is the
//! largest of the three. So [`shooting_root`] uses x₁ alone there — a continuous function of
//! the coefficients, since (4.21) is discontinuous only at `Δ = 0, q > 0`, which the proof of
//! the Corollary excludes (x₁ ≥ b/a > 0 forces q < 0). Elsewhere it takes the smallest
//! non-negative s among the real branches.

use super::{
    Root, RootOptions, UNIT_ROUNDOFF as U, eval_with_derivative, fastmath, find_roots,
    split_end_roots, validate,
};
use crate::BbError;

mod estimates;
pub use estimates::cubic_root_estimates;

/// Which formula produced a [`ShootingRoot`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Branch {
    /// `b_0 = 0`: the root is t = 0.
    Origin,
    /// Degenerate leading coefficients: the s-polynomial was linear (`a ≈ 0`, `b ≈ 0`).
    Linear,
    /// Degenerate leading coefficient: the s-polynomial was quadratic (`a ≈ 0`).
    Quadratic,
    /// x₁ of (4.18).
    X1,
    /// x₂ of (4.19).
    X2,
    /// x₃ of (4.20).
    X3,
    /// The degenerate case needed the general solver (a root within `2^-20` of t = 1).
    Subdivision,
}

/// The smallest root in `[0, 1)` of a cubic shooting polynomial and the formula it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShootingRoot {
    /// The root `t ∈ [0, 1)`.
    pub t: f64,
    /// The branch of Cardano's formulas (or the degenerate case) that gave it.
    pub branch: Branch,
}

/// The depressed cubic `x³ + px + q` of §4.4 for the Bernstein coefficients `[d, c, b, a]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CardanoCubic {
    /// `b/a`: `s = x − b/a`.
    pub shift: f64,
    /// `p = 3(ac − b²)/a²`.
    pub p: f64,
    /// `q = (2b³ − 3abc + a²d)/a³`.
    pub q: f64,
    /// `Δ = (q/2)² + (p/3)³`.
    pub delta: f64,
}

impl CardanoCubic {
    /// The depressed form of `Σ b_k B_k^3(t)` (`b = [d, c, b, a]`), or `None` when `a = 0` or a
    /// value is not finite. Computed through `β = b/a`, `γ = c/a`, `δ = d/a`:
    /// `p = 3(γ − β²)`, `q = β(2β² − 3γ) + δ` (the same expressions divided out).
    ///
    /// ```
    /// use algesurf_bb::roots::CardanoCubic;
    /// // (t − 1/2)(t − 1/4)(t − 3/4) has three real roots: Δ < 0.
    /// let c = CardanoCubic::new([-3.0 / 32.0, 13.0 / 96.0, -13.0 / 96.0, 3.0 / 32.0]).unwrap();
    /// assert!(c.delta < 0.0);
    /// let s: Vec<f64> = c.real_branches().iter().map(|x| x - c.shift).collect();
    /// // s = t/(1 − t) = 3, 1/3, 1 for t = 3/4, 1/4, 1/2: x₁ is the largest, x₂ the smallest.
    /// assert!((s[0] - 3.0).abs() < 1e-14 && (s[1] - 1.0 / 3.0).abs() < 1e-14);
    /// assert!((s[2] - 1.0).abs() < 1e-14);
    /// ```
    #[inline(always)]
    pub fn new(coeffs: [f64; 4]) -> Option<Self> {
        let [d, c, b, a] = coeffs;
        if a == 0.0 || !(a.is_finite() && b.is_finite() && c.is_finite() && d.is_finite()) {
            return None;
        }
        Self::new_finite(coeffs)
    }

    /// [`Self::new`] for coefficients already known finite with `a ≠ 0` (the hot path of
    /// [`shooting_root`] has checked both), skipping those checks; the overflow check on
    /// `p`, `q`, `Δ` stays.
    #[inline(always)]
    fn new_finite(coeffs: [f64; 4]) -> Option<Self> {
        let [d, c, b, a] = coeffs;
        // One division, then products: β, γ, δ carry at most 2u relative error each.
        let inv = 1.0 / a;
        let (beta, gamma, delta0) = (b * inv, c * inv, d * inv);
        let p = 3.0 * (gamma - beta * beta);
        let q = beta * (2.0 * beta * beta - 3.0 * gamma) + delta0;
        let half_q = 0.5 * q;
        let third_p = gamma - beta * beta;
        let delta = half_q * half_q + third_p * third_p * third_p;
        let out = CardanoCubic {
            shift: beta,
            p,
            q,
            delta,
        };
        (p.is_finite() && q.is_finite() && delta.is_finite()).then_some(out)
    }

    /// x₁ of (4.18), always real. For `Δ ≥ 0`: `∛(−q/2 + √Δ) + ∛(−q/2 − √Δ)` with real cube
    /// roots, computed without cancellation as `u − p/(3u)` where `u` is the cube root of the
    /// term of larger magnitude (the two cube roots multiply to `∛(q²/4 − Δ) = −p/3`). For
    /// `Δ < 0`: by (4.21), `2ρ cos(θ/3)` with `ρ = √(−p/3)` and
    /// `θ = arg(−q/2 + i√(−Δ)) ∈ (0, π)`.
    #[inline]
    pub fn x1(&self) -> f64 {
        if self.delta >= 0.0 {
            let (u, v) = self.real_cube_roots();
            u + v
        } else {
            let (rho, theta) = self.polar();
            2.0 * rho * (theta / 3.0).cos()
        }
    }

    /// x₁ by the fast path of [`super::fastmath`] (relative error ≤ 6e-10 in each cube root against [`Self::x1`]; the polish does the rest):
    /// the same formula (4.18)/(4.21), with the real cube root by a division-free Newton iteration and
    /// `cos(θ/3)` from the triple-angle equation (`cos θ = (−q/2)/ρ³`, since `|−q/2 + i√−Δ| = ρ³`).
    #[inline(always)]
    fn x1_fast(&self) -> f64 {
        if self.delta >= 0.0 {
            let sq = self.delta.sqrt();
            let h = -0.5 * self.q;
            let big = if h >= 0.0 { h + sq } else { h - sq };
            if big == 0.0 {
                // q = Δ = 0 ⇒ p = 0: the triple root x = 0.
                return 0.0;
            }
            // r = 1/∛big (sign included), ∛big = big r², and the other cube root is
            // −p/(3∛big) = −(p/3) r.
            let r = fastmath::inv_cbrt(big.abs()).copysign(big);
            big * r * r - (self.p * (1.0 / 3.0)) * r
        } else {
            let (rho, z) = self.rho_cos_theta();
            2.0 * rho * fastmath::cos_third_of_arccos(z)
        }
    }

    /// `(ρ, cos θ)` for `Δ < 0`: `ρ = √(−p/3)`, `cos θ = (−q/2)/ρ³`.
    #[inline(always)]
    fn rho_cos_theta(&self) -> (f64, f64) {
        // m = −p/3 by a multiplication (one more rounding than the division: the start only
        // needs ~1e-9). cos θ = (−q/2)/ρ³ = (−q/2) ρ/m² (ρ² = m): 1/m² is formed while the
        // square root runs, instead of a division after it.
        let m = (-self.p * (1.0 / 3.0)).max(0.0);
        let inv_m2 = 1.0 / (m * m);
        let rho = m.sqrt();
        let z = -0.5 * self.q * inv_m2 * rho;
        // m = 0 (or m² underflowing): z would be 0·∞ or ∞; take θ = 0 as before.
        let z = if inv_m2.is_finite() { z } else { 1.0 };
        (rho, z)
    }

    /// x₁, x₂, x₃ for `Δ < 0` by the fast path: with `c = cos(θ/3)` and `s = sin(θ/3) =
    /// √(1 − c²) ≥ 0` (θ/3 ∈ (0, π/3)), `2ρ cos(θ/3 ± 2π/3) = ρ(−c ∓ √3 s)`.
    #[inline]
    fn branches_fast_delta_negative(&self) -> [f64; 3] {
        let (rho, z) = self.rho_cos_theta();
        let c = fastmath::cos_third_of_arccos(z);
        let s = (1.0 - c * c).max(0.0).sqrt() * 3f64.sqrt();
        [2.0 * rho * c, rho * (-c - s), rho * (-c + s)]
    }

    /// `(u, v) = (∛(−q/2 ± √Δ))` for `Δ ≥ 0` (real cube roots), the larger-magnitude term first.
    #[inline]
    fn real_cube_roots(&self) -> (f64, f64) {
        let sq = self.delta.max(0.0).sqrt();
        let h = -0.5 * self.q;
        // |h| + √Δ: no cancellation; sign of h (either sign when h = 0).
        let big = if h >= 0.0 { h + sq } else { h - sq };
        let u = big.cbrt();
        if u == 0.0 {
            return (0.0, 0.0);
        }
        (u, -self.p / (3.0 * u))
    }

    /// `(ρ, θ)` of (4.21) for `Δ < 0`.
    #[inline]
    fn polar(&self) -> (f64, f64) {
        let rho = (-self.p / 3.0).max(0.0).sqrt();
        let theta = (-self.delta).sqrt().atan2(-0.5 * self.q);
        (rho, theta)
    }

    /// The three values x₁, x₂, x₃ of (4.18)–(4.20) as complex numbers `(re, im)`, with
    /// `ω = (−1 + i√3)/2` and the cube roots of (4.21).
    pub fn branches(&self) -> [(f64, f64); 3] {
        if self.delta >= 0.0 {
            // x₂ = ωu + ω²v = −(u+v)/2 + i(√3/2)(u − v), x₃ its conjugate. `real_cube_roots`
            // returns the larger term first; (4.19) has u for −q/2 + √Δ.
            let (big, small) = self.real_cube_roots();
            let (u, v) = if -0.5 * self.q >= 0.0 {
                (big, small)
            } else {
                (small, big)
            };
            let re = -0.5 * (u + v);
            let im = 0.5 * 3f64.sqrt() * (u - v);
            [(u + v, 0.0), (re, im), (re, -im)]
        } else {
            let [x1, x2, x3] = self.real_branches_delta_negative();
            [(x1, 0.0), (x2, 0.0), (x3, 0.0)]
        }
    }

    /// For `Δ < 0`: `u = ρ e^{iθ/3}`, `v = ū`, so x₂ = ωu + ω²v = 2ρ cos(θ/3 + 2π/3) and
    /// x₃ = ω²u + ωv = 2ρ cos(θ/3 − 2π/3).
    fn real_branches_delta_negative(&self) -> [f64; 3] {
        let (rho, theta) = self.polar();
        let third = theta / 3.0;
        let w = 2.0 * std::f64::consts::FRAC_PI_3;
        [
            2.0 * rho * third.cos(),
            2.0 * rho * (third + w).cos(),
            2.0 * rho * (third - w).cos(),
        ]
    }

    /// The real values among x₁, x₂, x₃ (in that order): one when `Δ > 0`, three otherwise
    /// (with x₂ = x₃ when `Δ = 0`).
    pub fn real_branches(&self) -> Vec<f64> {
        if self.delta > 0.0 {
            vec![self.x1()]
        } else if self.delta == 0.0 {
            // Δ = 0: u = v = ∛(−q/2), x₁ = 2u, x₂ = x₃ = −u.
            let x1 = self.x1();
            vec![x1, -0.5 * x1, -0.5 * x1]
        } else {
            self.real_branches_delta_negative().to_vec()
        }
    }
}

/// Below this relative size (`|a| ≤ 2^-20 Σ|b_k|`) the leading coefficient is treated as zero
/// and the s-polynomial as quadratic ("a = 0"). Why this scale: Cardano's shift
/// `s = x − b/a` cancels about `log2|b/a|` bits, so for `|a/b| ≥ 2^-20` the start is accurate
/// to ~2^-33 and two Newton steps reach full precision; below it, dropping `a` moves the
/// quadratic's roots by O(a/b) ≤ 2^-20 relative, which Newton on the full cubic (three
/// steps) removes. The root that `a` adds near `t = 1` (at `1 − t ≈ |a/(3b)|`) is recovered
/// separately when the quadratic has none.
const DEGENERATE_A: f64 = 1.0 / 1048576.0;

/// Maximum Newton steps of the polish (quadratic convergence from ≥ 2^-33 relative error
/// needs two; the third covers the degenerate start).
const NEWTON_STEPS: usize = 4;

/// The smallest root in `[0, 1)` of the cubic shooting polynomial `Σ b_k B_k^3(t)` (§4.4 of
/// Xu–Huang–Bajaj 2001), with the paper's branch choice (see the [module docs](self)), polished
/// by safeguarded Newton steps. `Ok(None)` when there is no root in `[0, 1)`.
///
/// Errors: a non-finite coefficient, or the zero polynomial.
///
/// ```
/// use algesurf_bb::roots::{Branch, shooting_root};
/// // b_0 < 0 < b_2, b_3 (the lifted shooting polynomial): x₁ by the Corollary.
/// let r = shooting_root([-1.0, 0.5, 2.0, 3.0])?.unwrap();
/// assert_eq!(r.branch, Branch::X1);
/// let p = |t: f64| -(1.0 - t).powi(3) + 1.5 * t * (1.0 - t).powi(2) + 6.0 * t * t * (1.0 - t) + 3.0 * t.powi(3);
/// assert!(p(r.t).abs() < 1e-15);
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
#[inline]
pub fn shooting_root(coeffs: [f64; 4]) -> Result<Option<ShootingRoot>, BbError> {
    let [d, c, b, a] = coeffs;
    if !(d.is_finite() && c.is_finite() && b.is_finite() && a.is_finite()) {
        return Err(BbError::NonFinite {
            what: "shooting polynomial coefficient",
        });
    }
    if d == 0.0 {
        return Ok(Some(ShootingRoot {
            t: 0.0,
            branch: Branch::Origin,
        }));
    }
    let scale = d.abs() + c.abs() + b.abs() + a.abs();
    // A ray starting within rounding of the surface: `d` is below the error with which it was
    // computed from coefficients of size `scale`, so t = 0 to working precision.
    if d.abs() <= 8.0 * f64::EPSILON * scale {
        return Ok(Some(ShootingRoot {
            t: 0.0,
            branch: Branch::Origin,
        }));
    }
    // A root just above s = 0: with d·c < 0 and |d| ≤ 2^-27 |c| the s-polynomial
    // g(s) = d + 3cs + 3bs² + as³ is monotone on [0, 2|d/3c|] (its quadratic and cubic terms
    // are O(s²) ≤ 2^-27 of the linear one there) with one root near −d/(3c). Cardano cannot
    // resolve it: the shift x₁ − b/a cancels to an absolute error of ~ε, larger than the root
    // (a ray from a point of F ≈ 1e-34 returned no root). Newton from −d/(3c) converges
    // quadratically.
    if d * c < 0.0 && d.abs() <= c.abs() / 134_217_728.0 {
        let mut s = -d / (3.0 * c);
        for _ in 0..3 {
            let g = d + s * (3.0 * c + s * (3.0 * b + s * a));
            let dg = 3.0 * c + s * (6.0 * b + 3.0 * s * a);
            s -= g / dg;
        }
        return Ok(Some(ShootingRoot {
            t: s / (1.0 + s),
            branch: Branch::Linear,
        }));
    }
    let (s, branch) = if a.abs() <= DEGENERATE_A * scale {
        match degenerate_s(d, c, b, scale) {
            Some(found) => found,
            None => return degenerate_near_one(coeffs),
        }
    } else {
        // `new` only fails for a = 0 or overflow; the latter is out of range for a cubic
        // whose coefficients are finite and |a| ≥ 2^-20 scale, so fall back defensively.
        // Finite (checked on entry) and a ≠ 0 (|a| > 2^-20 scale ≥ 0 here).
        let Some(cc) = CardanoCubic::new_finite(coeffs) else {
            return degenerate_near_one(coeffs);
        };
        match cardano_smallest_s(&cc, a, b, d) {
            Some(found) => found,
            None => return Ok(None),
        }
    };
    let t = polish_t(&coeffs, s);
    if t >= 1.0 || t.is_nan() {
        // s beyond 2^53: the root is t = 1 to working precision, outside [0, 1).
        return Ok(None);
    }
    Ok(Some(ShootingRoot { t, branch }))
}

/// The §4.4 branch choice: x₁ alone in the Corollary's case, else the smallest admissible s.
#[inline(always)]
fn cardano_smallest_s(cc: &CardanoCubic, a: f64, b: f64, d: f64) -> Option<(f64, Branch)> {
    // Rounding of s = x − b/a: a few ulps of |x| + |b/a| (x carries the error of cbrt/cos and
    // of p, q, which are O(u) relative to |b/a|² and |b/a|³); roots at t ≈ 0 may come out at
    // slightly negative s and are clamped to 0, then polished.
    let tol = |x: f64| 16.0 * U * (x.abs() + cc.shift.abs());
    if a * b > 0.0 && a * d < 0.0 {
        let x = cc.x1_fast();
        let s = x - cc.shift;
        return (s >= -tol(x)).then_some((s.max(0.0), Branch::X1));
    }
    let mut best: Option<(f64, Branch)> = None;
    let mut consider = |x: f64, br: Branch| {
        let s = x - cc.shift;
        if s >= -tol(x) && best.is_none_or(|(bs, _)| s.max(0.0) < bs) {
            best = Some((s.max(0.0), br));
        }
    };
    if cc.delta > 0.0 {
        consider(cc.x1_fast(), Branch::X1);
    } else {
        let [x1, x2, x3] = if cc.delta == 0.0 {
            let x1 = cc.x1_fast();
            [x1, -0.5 * x1, -0.5 * x1]
        } else {
            cc.branches_fast_delta_negative()
        };
        consider(x1, Branch::X1);
        consider(x2, Branch::X2);
        consider(x3, Branch::X3);
    }
    best
}

/// "a = 0": the smallest root s ≥ 0 of `3b s² + 3c s + d` (or of `3c s + d` when b is
/// negligible at the same scale). The quadratic uses the cancellation-free form
/// `s = k/(3b)`, `s' = d/k` with `k = −(3c + sign(c)√D)/2`, `D = 9c² − 12bd`.
fn degenerate_s(d: f64, c: f64, b: f64, scale: f64) -> Option<(f64, Branch)> {
    if b.abs() <= DEGENERATE_A * scale {
        let s = -d / (3.0 * c);
        return (s.is_finite() && s >= 0.0).then_some((s, Branch::Linear));
    }
    let (qa, qb, qc) = (3.0 * b, 3.0 * c, d);
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return None;
    }
    let k = -0.5 * (qb + disc.sqrt().copysign(qb));
    let mut best: Option<f64> = None;
    for s in [k / qa, qc / k] {
        if s.is_finite() && s >= 0.0 && best.is_none_or(|bs| s < bs) {
            best = Some(s);
        }
    }
    best.map(|s| (s, Branch::Quadratic))
}

/// The degenerate case without a quadratic root: any root in `[0, 1)` lies within the
/// `O(|a/b|)` neighbourhood of t = 1 that the dropped `a` creates; the general solver finds it.
#[cold]
fn degenerate_near_one(coeffs: [f64; 4]) -> Result<Option<ShootingRoot>, BbError> {
    let roots = find_roots(&coeffs)?;
    Ok(roots.iter().find(|r| r.t < 1.0).map(|r| ShootingRoot {
        t: r.t,
        branch: Branch::Subdivision,
    }))
}

/// Safeguarded Newton polish of a root `s ≥ 0` of the paper's s-polynomial
/// `P(s) = d + 3cs + 3bs² + as³ = p(t)/(1 − t)³`. The bracket `[lo, hi]` starts as `[0, ∞)`
/// and is narrowed by the sign of P at each iterate (the smallest positive root separates the
/// sign of `P(0) = b_0` from the opposite sign); a step that would leave the bracket, or that
/// is not finite, ends the polish with the current iterate.
///
/// Working in s keeps the single division `t = s/(1 + s)` off the iteration. Horner's rule in
/// s is as well conditioned as de Casteljau in t: its error bound `γ_6 Σ_k C(3,k)|b_k| s^k`
/// is `(1 − t)^{-3}` times de Casteljau's `γ_6 Σ_k |b_k| B_k^3(t)`, and the scale
/// `(1 − t)^{-3}` divides out of Newton's step.
///
/// Stopping rule: after a Newton step `h = P/P'` the error of the new iterate is
/// `|P''/(2P')| h² (1 + O(h))` (Taylor expansion at the root; Kantorovich), so the polish stops
/// as soon as that estimate is below half an ulp of s, `u s` — usually after one step, since
/// the Cardano start is accurate to ~1e-9. (Relative accuracy in s carries over to t:
/// `dt/t = ds/(s(1 + s)) ≤ ds/s`.)
#[inline(always)]
fn polish_s(b: &[f64; 4], s0: f64) -> f64 {
    let [d, c, bb, a] = *b;
    let (c3, b3) = (3.0 * c, 3.0 * bb);
    let neg0 = d < 0.0;
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    let mut s = s0;
    for _ in 0..NEWTON_STEPS {
        let f = d + s * (c3 + s * (b3 + s * a));
        let df = c3 + s * (2.0 * b3 + s * (3.0 * a));
        let d2f = 2.0 * b3 + s * (6.0 * a);
        if f == 0.0 {
            break;
        }
        if (f < 0.0) == neg0 {
            lo = s;
        } else {
            hi = s;
        }
        let h = f / df;
        let next = s - h;
        if !(next >= lo && next <= hi) {
            break;
        }
        s = next;
        if (d2f * h * h).abs() <= 2.0 * U * (df * s).abs() {
            break;
        }
    }
    s
}

/// [`polish_s`] followed by `t = s/(1 + s)`, with the common case — one Newton step that passes
/// the stopping rule — done with a single division instead of two.
///
/// With `f = P(s₀)`, `f' = P'(s₀)` the Newton iterate is `s₁ = s₀ − f/f'`, and
/// `t₁ = s₁/(1 + s₁) = N/(N + f')` with `N = s₀f' − f = s₁f'` (multiply numerator and
/// denominator by `f'`). The checks of [`polish_s`]'s first iteration are rewritten without
/// the quotient `h = f/f'` by multiplying through by `f'` or `f'²` (signs are preserved):
/// * bracket, `s₀` below the root (`sign f = sign b_0`): `s₁ ≥ s₀` ⇔ `h ≤ 0` ⇔ `f f' ≤ 0`;
///   above it: `0 ≤ s₁ ≤ s₀` ⇔ `f f' ≥ 0` and `N f' ≥ 0`;
/// * stopping rule `|P''| h² ≤ 2u|f' s₁|` ⇔ `|P''| f² ≤ 2u f'² |N|`. An overflowed or
///   underflowed right side is rejected (`is_normal`); an underflowed left side is below the
///   normal right side, so the comparison stays right, and an overflowed one fails it.
///
/// Error bound of the result: the stopping rule bounds the error of `s₁` by `u s₁` (see
/// [`polish_s`]; Newton's error after one step is `|P''/(2P')| h² (1 + O(h))`). So a Cardano
/// start with relative error `e` in `s` needs only `|P''/(2P')| e² s ≤ u`, e.g. `e ≤ 1e-8`
/// when `|P'' s/(2P')| ≤ 1`, which holds for simple roots away from a double root; any start
/// that misses the bound falls through to the full loop of [`polish_s`], so the accuracy is
/// the same as before and only the common case is cheaper. Rounding of `t₁`: we also require
/// `|f| ≤ |s₀f'|/2`, i.e. `|h| ≤ s₀/2` (or `s₀ = 0`, where `N = −f` is exact), so that
/// `N = s₀f' − f` does not cancel: its rounding error is `u(|s₀f'| + |f|) + u|N| ≤ 4u|N|`;
/// `N + f' = f'(s₁ + 1)` adds terms of one sign (`s₁ ≥ 0`) and the quotient one more
/// rounding, so `t₁` is within `≈ 10u` relative, as `s₁/(1 + s₁)` after [`polish_s`] (the
/// rounding of `s₁` plus two).
#[inline(always)]
fn polish_t(b: &[f64; 4], s0: f64) -> f64 {
    let [d, c, bb, a] = *b;
    let (c3, b3) = (3.0 * c, 3.0 * bb);
    // Estrin's scheme instead of Horner's (shorter dependency chain: `s²` and the two
    // linear halves are independent). Each term `C(3,k) b_k s^k` passes through at most five
    // roundings, so the error bound `γ_6 Σ_k C(3,k)|b_k| s^k` of [`polish_s`] still holds.
    let s2 = s0 * s0;
    let f = (d + s0 * c3) + s2 * (b3 + s0 * a);
    let df = (c3 + s0 * (2.0 * b3)) + s2 * (3.0 * a);
    let d2f = 2.0 * b3 + s0 * (6.0 * a);
    let n = s0 * df - f;
    let below = (f < 0.0) == (d < 0.0);
    let fdf = f * df;
    let bracket_ok = if below {
        fdf <= 0.0
    } else {
        fdf >= 0.0 && n * df >= 0.0
    };
    let rhs = 2.0 * U * (df * df) * n.abs();
    let converged = (d2f * f * f).abs() <= rhs && rhs.is_normal();
    let no_cancel = s0 == 0.0 || f.abs() <= 0.5 * (s0 * df).abs();
    if f != 0.0 && bracket_ok && converged && no_cancel {
        return n / (n + df);
    }
    let s = polish_s(b, s0);
    s / (1.0 + s)
}

/// All real roots in `[0, 1]` of `Σ b_k B_k^n(t)` for `n ≤ 3` (1 to 4 coefficients), sorted,
/// with multiplicities, by the closed forms of [`cubic_roots_closed_form`]; when its
/// verification fails it falls back to [`find_roots`].
///
/// ```
/// use algesurf_bb::roots::cubic_roots;
/// // (t − 1/2)²(t − 1) has Bernstein coefficients −1/4, 1/6, −1/12, 0.
/// let r = cubic_roots(&[-0.25, 1.0 / 6.0, -1.0 / 12.0, 0.0])?;
/// assert_eq!(r.len(), 2);
/// assert!((r[0].t - 0.5).abs() < 1e-8 && r[0].multiplicity == 2);
/// assert!(r[1].t == 1.0 && r[1].multiplicity == 1);
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
pub fn cubic_roots(coeffs: &[f64]) -> Result<Vec<Root>, BbError> {
    match cubic_roots_closed_form(coeffs)? {
        Some(r) => Ok(r),
        None => find_roots(coeffs),
    }
}

/// The closed-form root set of a BB polynomial of degree ≤ 3 on `[0, 1]`, or `Ok(None)` when
/// the result fails its verification (then use [`find_roots`]).
///
/// Steps: roots at t = 0 and 1 and exact deflation as in [`find_roots`] (same error model,
/// [`RootOptions::for_degree`]); then the linear root, the quadratic by the cancellation-free
/// formula in `s = t/(1−t)`, or the cubic by Cardano (§4.4), written in whichever of t or
/// 1 − t makes `|a| ≥ |d|` (the shift b/a then cancels least). Multiple roots are recognised
/// from the discriminant within its first-order perturbation bound (`Δ ≈ 0`: a double root
/// x₂ = x₃; also `p ≈ q ≈ 0`: a triple root) and located as the simple root of the first or
/// second derivative. Every root is polished by Newton steps inside a bracket; the result is
/// rejected when a polished root leaves `[0, 1]`, two roots collapse, or a residual exceeds
/// the rounding bound.
pub fn cubic_roots_closed_form(coeffs: &[f64]) -> Result<Option<Vec<Root>>, BbError> {
    let m = validate(coeffs)?;
    let n = coeffs.len() - 1;
    if n > 3 {
        return Err(BbError::Degree(format!(
            "closed-form roots need degree ≤ 3, got {n}"
        )));
    }
    let bn: Vec<f64> = coeffs.iter().map(|x| x / m).collect();
    let e0 = RootOptions::for_degree(n).relative_coefficient_error + U;
    let (roots, q, qe) = split_end_roots(&bn, e0);
    let emax = qe.iter().fold(0.0f64, |a, x| a.max(*x));
    let interior = match q.len() - 1 {
        0 => Vec::new(),
        1 => linear_roots(q[0], q[1]),
        2 => quadratic_roots(&q, &qe),
        _ => {
            let reversed = q[3].abs() < q[0].abs();
            let c = if reversed {
                [q[3], q[2], q[1], q[0]]
            } else {
                [q[0], q[1], q[2], q[3]]
            };
            let mut r = cubic_interior(&c, emax);
            if reversed {
                for x in &mut r {
                    x.t = 1.0 - x.t;
                }
            }
            r
        }
    };
    // Verification: inside [0, 1], residual within the rounding bound of the deflated
    // polynomial (its coefficient errors plus de Casteljau's 2nu max|q|), with a factor 64 of
    // slack for the perturbation a multiple root absorbs; simple roots pairwise distinct.
    let qmax = q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let bound = 64.0 * (emax + 2.0 * q.len() as f64 * U * qmax);
    for r in &interior {
        if !(r.t >= 0.0 && r.t <= 1.0) || super::eval(&q, r.t).abs() > bound {
            return Ok(None);
        }
    }
    let mut all: Vec<Root> = roots.into_iter().chain(interior).collect();
    all.sort_by(|a, b| a.t.total_cmp(&b.t));
    if all.windows(2).any(|w| w[0].t == w[1].t) {
        return Ok(None);
    }
    Ok(Some(all))
}

fn linear_roots(q0: f64, q1: f64) -> Vec<Root> {
    // q0 (1 − t) + q1 t = 0 at t = q0/(q0 − q1): one rounding in the difference (no
    // cancellation, the signs differ) and one in the quotient.
    if (q0 < 0.0) != (q1 < 0.0) {
        vec![Root {
            t: q0 / (q0 - q1),
            multiplicity: 1,
        }]
    } else {
        Vec::new()
    }
}

/// Roots in (0, 1) of `q0 B_0^2 + q1 B_1^2 + q2 B_2^2 = (1−t)² (q0 + 2q1 s + q2 s²)`.
fn quadratic_roots(q: &[f64], qe: &[f64]) -> Vec<Root> {
    let (q0, q1, q2) = (q[0], q[1], q[2]);
    let disc = q1 * q1 - q0 * q2;
    // First-order perturbation bound of the discriminant under coefficient errors qe, plus the
    // rounding of its own evaluation (2u of each product, u for the difference).
    let disc_err = 2.0 * q1.abs() * qe[1]
        + q0.abs() * qe[2]
        + q2.abs() * qe[0]
        + 3.0 * U * (q1 * q1 + (q0 * q2).abs());
    let polish_q = |t: f64| newton_bracketed(q, t);
    if disc.abs() <= disc_err {
        // Double root: the zero of q' = 2[(q1 − q0)(1 − t) + (q2 − q1) t], exact formula.
        let den = q0 - 2.0 * q1 + q2;
        let t = (q0 - q1) / den;
        return if den != 0.0 && t > 0.0 && t < 1.0 {
            vec![Root { t, multiplicity: 2 }]
        } else {
            Vec::new()
        };
    }
    if disc < 0.0 {
        return Vec::new();
    }
    let k = -(q1 + disc.sqrt().copysign(q1));
    let mut out = Vec::new();
    for s in [k / q2, q0 / k] {
        if s.is_finite() && s > 0.0 {
            out.push(Root {
                t: polish_q(s / (1.0 + s)),
                multiplicity: 1,
            });
        }
    }
    out
}

/// Interior roots of a cubic with certain, nonzero end coefficients and `|b_3| ≥ |b_0|`.
fn cubic_interior(c: &[f64; 4], emax: f64) -> Vec<Root> {
    let [d, cc, _, a] = *c;
    let Some(cub) = CardanoCubic::new(*c) else {
        return Vec::new();
    };
    // First-order perturbation bounds of β, γ, δ (= b/a, c/a, d/a) when each coefficient moves
    // by emax, plus their rounding (2u relative), then of p, q and Δ through their formulas,
    // each with the rounding of its own evaluation.
    let beta = cub.shift;
    let (gamma, delta0) = (cc / a, d / a);
    // (β, γ, δ are recomputed here only for the bounds; `new` formed them with 2u error.)
    let ea = emax / a.abs();
    let db = (1.0 + beta.abs()) * ea + 2.0 * U * beta.abs();
    let dg = (1.0 + gamma.abs()) * ea + 2.0 * U * gamma.abs();
    let dd = (1.0 + delta0.abs()) * ea + 2.0 * U * delta0.abs();
    let dp = 3.0 * dg + 6.0 * beta.abs() * db + 4.0 * U * (3.0 * gamma.abs() + 3.0 * beta * beta);
    let dq = (6.0 * beta * beta + 3.0 * gamma.abs()) * db
        + 3.0 * beta.abs() * dg
        + dd
        + 6.0 * U * (2.0 * beta.abs().powi(3) + 3.0 * (beta * gamma).abs() + delta0.abs());
    let (p, q) = (cub.p, cub.q);
    let dd_delta = 0.5 * q.abs() * dq
        + p * p / 9.0 * dp
        + 0.25 * dq * dq
        + (p.abs() + dp) * dp * dp / 9.0
        + 4.0 * U * (0.25 * q * q + p.abs().powi(3) / 27.0);
    let mut xs: Vec<(f64, usize)> = Vec::with_capacity(3);
    if p.abs() <= dp && q.abs() <= dq {
        xs.push((0.0, 3));
    } else if cub.delta.abs() <= dd_delta {
        // Δ = 0: u = v = ∛(−q/2): x₁ = 2u simple, x₂ = x₃ = −u double.
        let u = (-0.5 * q).cbrt();
        xs.push((2.0 * u, 1));
        xs.push((-u, 2));
    } else if cub.delta > 0.0 {
        xs.push((cub.x1(), 1));
    } else {
        for x in cub.real_branches_delta_negative() {
            xs.push((x, 1));
        }
    }
    let mut out = Vec::new();
    for (x, mult) in xs {
        let s = x - beta;
        let tol = 16.0 * U * (x.abs() + beta.abs());
        if s <= -tol || s.is_nan() {
            continue;
        }
        let t0 = (s.max(0.0)) / (1.0 + s.max(0.0));
        let t = match mult {
            1 => newton_bracketed(c, t0),
            2 => newton_bracketed(&super::derivative_coeffs(c, 1), t0),
            _ => {
                // The zero of q'' (linear): exact formula as for the linear case.
                let d2 = super::derivative_coeffs(c, 2);
                let den = d2[0] - d2[1];
                if den != 0.0 { d2[0] / den } else { t0 }
            }
        };
        if t > 0.0 && t < 1.0 {
            out.push(Root {
                t,
                multiplicity: mult,
            });
        }
    }
    out
}

/// Newton polish of a simple root of `c` near `t0`, safeguarded by a bracket around `t0`: the
/// bracket is grown geometrically from `t0` until `c` changes sign over it (within [0, 1]); if
/// it does, Newton–bisection ([`super::bracketed_root`]) runs on the bracket, else `t0` is kept.
fn newton_bracketed(c: &[f64], t0: f64) -> f64 {
    let f0 = eval_with_derivative(c, t0).0;
    if f0 == 0.0 {
        return t0;
    }
    // Start with a half-width of 2^-30 (Cardano's start is at least that accurate away from
    // the degenerate cases) and double it up to the whole interval.
    let mut h = (t0.abs().max(1e-300) * 1e-9).max(1e-300);
    while h < 1.0 {
        let lo = (t0 - h).max(0.0);
        let hi = (t0 + h).min(1.0);
        let (flo, fhi) = (super::eval(c, lo), super::eval(c, hi));
        if (flo < 0.0) != (fhi < 0.0) && flo != 0.0 && fhi != 0.0 {
            let local = super::restrict(c, lo, hi);
            let w = hi - lo;
            let u = super::bracketed_root(&local, |u| {
                2.0 * U * (lo + u * w).max(f64::MIN_POSITIVE) / w
            });
            return (lo + u * w).clamp(lo, hi);
        }
        if flo == 0.0 {
            return lo;
        }
        if fhi == 0.0 {
            return hi;
        }
        if lo == 0.0 && hi == 1.0 {
            break;
        }
        h *= 8.0;
    }
    t0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fused one-division polish agrees with the full loop followed by `s/(1 + s)` to a
    /// few ulps, from starts perturbed by 1e-9 relative (the Cardano fast path's accuracy).
    #[test]
    fn fused_polish_matches_loop() {
        for k in 0..64 {
            let x = (k * 37 % 64) as f64 / 64.0;
            let y = (k * 11 % 64) as f64 / 64.0;
            let b = [-0.2 - x, 2.0 * y - 1.5, 0.1 + x * y, 0.5 + y];
            let t0 = shooting_root(b).unwrap().unwrap().t;
            let exact = polish_s(&b, t0 / (1.0 - t0));
            for e in [-1e-9, 0.0, 1e-9] {
                let t = polish_t(&b, exact * (1.0 + e));
                let reference = exact / (1.0 + exact);
                assert!(
                    (t - reference).abs() <= 16.0 * U * reference,
                    "{b:?}: {t} {reference}"
                );
            }
        }
    }

    /// The fast path against the reference formulas, on a grid of cubics covering Δ of both
    /// signs and q of both signs.
    #[test]
    fn fast_branches_match_reference() {
        let mut checked = [0usize; 2];
        for i in 0..40 {
            for j in 0..40 {
                for k in 0..6 {
                    let b = [
                        -1.0 + 0.05 * i as f64,
                        -2.0 + 0.1 * j as f64,
                        -1.0 + 0.4 * k as f64,
                        0.7 + 0.01 * i as f64,
                    ];
                    let Some(cc) = CardanoCubic::new(b) else {
                        continue;
                    };
                    if cc.delta > 0.0 {
                        // r = 1/∛big to 5.2e-10 relative: u = big r² carries twice that and
                        // v = −(p/3) r once (plus rounding).
                        let (u, v) = cc.real_cube_roots();
                        let bound = 5.2e-10 * (2.0 * u.abs() + v.abs()) + 1e-15;
                        assert!((cc.x1_fast() - cc.x1()).abs() <= bound, "{b:?}");
                        checked[0] += 1;
                    } else if cc.delta < 0.0 {
                        let fast = cc.branches_fast_delta_negative();
                        let reference = cc.real_branches_delta_negative();
                        let rho = (-cc.p / 3.0).sqrt();
                        for (f, r) in fast.iter().zip(reference) {
                            // cos(θ/3) to 3e-12 relative; sin(θ/3) = √(1 − c²) amplifies an
                            // error δ of c by c/s, bounded via √(2δ) when s is tiny.
                            assert!((f - r).abs() <= 2.0 * rho * 3e-6 + 1e-15, "{b:?}");
                        }
                        assert!((fast[0] - reference[0]).abs() <= 2.0 * rho * 3e-12 + 1e-15);
                        checked[1] += 1;
                    }
                }
            }
        }
        assert!(checked[0] > 100 && checked[1] > 100, "{checked:?}");
    }
}

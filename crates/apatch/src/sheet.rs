//! Single-sheet lower bounds for the free parameters: Step 6 of §4.2 of Xu–Huang–Bajaj 2001
//! with Lemma 2.3.
//!
//! Along a ray from a face point `q` (where `F(q) = b_0 < 0`) to the apex, the shooting
//! polynomial is `G(t) + b t²` with `G = Σ b_i B_i^3`, `b_3 = 0`, and `b` the value of F at the
//! apex (the layer-2 coefficients carry `b/3` by (4.14), the apex `b`, and
//! `t² = B_2^3/3 + B_3^3`). Lemma 2.3: if for some `t ∈ (0, 1]` both
//! `F_2(t) + b t²/3 > 0` and `F_3(t) + b t² > 0`, the Bézier coefficients of the shooting
//! polynomial over `[0, t]` change sign once, so its smallest root in `[0, 1)` is simple. The
//! least such `b` is `b_min(q) = min{b_min^(1), b_min^(2)}` of the lemma (
//! per ray this is `algesurf_bb::sheet::lemma_2_3_b_min`, computed from critical points and
//! rounded upwards, i.e. certified).
//!
//! The maximum over the face is taken over a barycentric grid; every ray of the tessellation is
//! then checked for a simple root (`Tessellation::multiple_roots`, `missed_rays`), so a point
//! between grid samples that needed more shows up as a measured failure, not silently.

use algesurf_bb::sheet::lemma_2_3_b_min;

/// `max_q b_min(q)` over a triangular grid of `level` subdivisions of a face (barycentric
/// points `(i, j, k)/level`, all of them, corners included: there `b_0 = 0` and they are
/// skipped), given the base shooting coefficients at each point. `−∞` when no point has
/// `b_0 < 0`.
pub fn face_bound(level: usize, base: impl Fn([f64; 3]) -> [f64; 4]) -> f64 {
    let mut worst = f64::NEG_INFINITY;
    for i in 0..=level {
        for j in 0..=(level - i) {
            let k = level - i - j;
            let q = [i as f64, j as f64, k as f64].map(|x| x / level as f64);
            let b = base(q);
            // Lemma 2.3 needs b_0 < 0; where b_0 ≥ 0 the ray starts on the surface (t = 0).
            if b[0] < 0.0
                && let Ok(bound) = lemma_2_3_b_min(b, 1.0)
            {
                worst = worst.max(bound.b_min);
            }
        }
    }
    worst
}

/// Lemma 2.3 for a general lift: the least `b` such that the smallest root in `[0, 1)` of
/// `base + b·lift` is certified simple, where `lift = (0, 0, c_2, c_3)` with `c_2, c_3 ≥ 0`
/// (raising an apex value by b adds b·τ_apex² to the pieces, which reaches a ray only through
/// its layers 2 and 3). Over `[0, t]` the coefficients are `b_0`, `F_1(t)`,
/// `F_2(t) + b c_2 t²`, `F_3(t) + b (3 c_2 t²(1 − t) + c_3 t³)`: one sign change (so one simple
/// root, the smallest) once the last two are positive. `None` when `b_0 ≥ 0` or the lift has
/// another shape.
pub fn lifted_b_min(base: [f64; 4], lift: [f64; 4]) -> Option<f64> {
    let [b0, b1, b2, b3] = base;
    let [l0, l1, c2, c3] = lift;
    let scale = lift.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // The lift's layers 0 and 1 vanish exactly in exact arithmetic; 1e-12 of its size allows
    // for the rounding of the blossoms that produce it.
    if b0 >= 0.0
        || l0.abs() > 1e-12 * scale
        || l1.abs() > 1e-12 * scale
        || c2 < 0.0
        || c3 < 0.0
        || scale == 0.0
    {
        return None;
    }
    let phi = |t: f64| {
        let s = 1.0 - t;
        let f2 = b0 * s * s + 2.0 * b1 * t * s + b2 * t * t;
        let f3 = b0 * s * s * s + 3.0 * b1 * t * s * s + 3.0 * b2 * t * t * s + b3 * t * t * t;
        let w2 = c2 * t * t;
        let w3 = 3.0 * c2 * t * t * s + c3 * t * t * t;
        let need2 = if w2 > 0.0 {
            -f2 / w2
        } else if f2 > 0.0 {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        };
        let need3 = if w3 > 0.0 {
            -f3 / w3
        } else if f3 > 0.0 {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        };
        need2.max(need3)
    };
    const SAMPLES: usize = 64;
    let mut best = f64::INFINITY;
    let mut best_k = SAMPLES;
    for k in 1..=SAMPLES {
        let v = phi(k as f64 / SAMPLES as f64);
        if v < best {
            best = v;
            best_k = k;
        }
    }
    if !best.is_finite() {
        return if best < 0.0 {
            Some(f64::NEG_INFINITY)
        } else {
            None
        };
    }
    let (mut lo, mut hi) = (
        (best_k as f64 - 1.0).max(0.5) / SAMPLES as f64,
        ((best_k + 1) as f64 / SAMPLES as f64).min(1.0),
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..40 {
        let a = hi - g * (hi - lo);
        let c = lo + g * (hi - lo);
        if phi(a) < phi(c) {
            hi = c;
        } else {
            lo = a;
        }
    }
    Some(best.min(phi(0.5 * (lo + hi))))
}

//! Single-sheet lower bounds for the free parameters: Step 6 of §4.2 of Xu–Huang–Bajaj 2001
//! with Lemma 2.3.
//!
//! Along a ray from a face point `q` (where `F(q) = b_0 < 0`) to the apex, the shooting
//! polynomial is `G(t) + b t²` with `G = Σ b_i B_i^3`, `b_3 = 0`, and `b` the value of F at the
//! apex (the layer-2 coefficients carry `b/3` by (4.14), the apex `b`, and
//! `t² = B_2^3/3 + B_3^3`). Lemma 2.3: if for some `t ∈ (0, 1]` both
//! `F_2(t) + b t²/3 > 0` and `F_3(t) + b t² > 0`, the Bézier coefficients of the shooting
//! polynomial over `[0, t]` change sign once, so its smallest root in `[0, 1)` is simple. The
//! least such `b` is `b_min(q) = min_t max{−3F_2(t)/t², −F_3(t)/t²}` (`b_min^(1)` of the lemma;
//! dropping `b_min^(2)` only makes the bound more conservative).

/// `b_min^(1)` of Lemma 2.3 for the shooting polynomial with coefficients
/// `[b_0, b_1, b_2, 0]` (the part that does not depend on the apex value), or `None` when
/// `b_0 ≥ 0` (the ray starts on the surface; its root is t = 0).
///
/// The minimum over t is taken on 64 samples and refined by golden-section search in the
/// bracket around the best sample; the function of t is continuous on (0, 1] and tends to +∞
/// or −∞ as t → 0 depending on the sign of `b_1`, so the samples find its basin.
pub fn lemma_2_3_b_min(b: [f64; 4]) -> Option<f64> {
    let [b0, b1, b2, b3] = b;
    if b0 >= 0.0 {
        return None;
    }
    let phi = |t: f64| {
        let s = 1.0 - t;
        let f2 = b0 * s * s + 2.0 * b1 * t * s + b2 * t * t;
        let f3 = b0 * s * s * s + 3.0 * b1 * t * s * s + 3.0 * b2 * t * t * s + b3 * t * t * t;
        (-3.0 * f2 / (t * t)).max(-f3 / (t * t))
    };
    const SAMPLES: usize = 64;
    let (mut best_k, mut best) = (SAMPLES, phi(1.0));
    for k in 1..SAMPLES {
        let v = phi(k as f64 / SAMPLES as f64);
        if v < best {
            best = v;
            best_k = k;
        }
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
            if let Some(b) = lemma_2_3_b_min(base(q)) {
                worst = worst.max(b);
            }
        }
    }
    worst
}

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
//! Over a face (convex faces and each sub-triangle of a split face) the maximum is certified:
//! [`certified_face_bound`] bounds Lemma 2.3's `b_min^(1)` from above at every point of the face
//! by BB subdivision (branch and bound on the layer polynomials' coefficient hulls), within
//! [`CERTIFIED_GAP`] of the best sampled value. Over an edge tetrahedron the rays (4.9) form an
//! `(x, y)` square and the lift of the apex values varies over it; the same branch and bound
//! on the tensor-product coefficients ([`algesurf_bb::sheet::square`]) certifies that bound
//! too (`surface::edge_need`). Every ray of the tessellation is still checked for a simple root
//! (`Tessellation::multiple_roots`, `missed_rays`) as a measurement. [`face_bound`] is the grid
//! maximum, kept for comparison.

use algesurf_bb::BbPoly;
use algesurf_bb::extremes::{max_abs, min_not_nan};
use algesurf_bb::sheet::{
    b_min_1_upper_from_minima, certified_triangle_b_min_below, lemma_2_3_b_min,
};

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
    lifted_b_min_above(base, lift, f64::NEG_INFINITY)
}

/// [`lifted_b_min`] for a caller that only needs values above `floor`: returns as soon as
/// some `t` certifies a value `≤ floor` (that value, attained at an actual `t`, so the least
/// `b` is at most it). Every result above `floor` is exactly [`lifted_b_min`]'s (the same
/// samples and golden-section steps run). Step 6 on an edge only asks whether a ray needs
/// more than the largest increment found so far (or more than `−margin`), so most rays stop
/// at the first sample, `t = 1`.
pub fn lifted_b_min_above(base: [f64; 4], lift: [f64; 4], floor: f64) -> Option<f64> {
    let [b0, b1, b2, b3] = base;
    let [l0, l1, c2, c3] = lift;
    let scale = max_abs(&lift);
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
    // t = 1 first: the usual minimiser on the edges' rays, and a value ≤ floor settles it.
    let at_end = phi(1.0);
    if at_end <= floor {
        return Some(at_end);
    }
    let mut best = f64::INFINITY;
    let mut best_k = SAMPLES;
    for k in 1..=SAMPLES {
        let v = phi(k as f64 / SAMPLES as f64);
        if v <= floor {
            return Some(v);
        }
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

/// Gap of the certified face bound, relative to the face's coefficient scale
/// (`max |∇F| · longest edge`): half the default [`crate::SurfaceOptions::sheet_margin`], so
/// the certified bound overshoots the true maximum by less than the margin kept above it
/// (1e-3 needed up to 1024 cells on some torus faces, 5e-3 at most ~140).
pub const CERTIFIED_GAP: f64 = 5e-3;

/// Cells of the subdivision of one face before [`certified_face_bound`] stops refining (the
/// result is an upper bound either way; this only caps the work on faces where the maximum is
/// approached at a corner, where `b_0 → 0`).
pub const CERTIFIED_MAX_CELLS: usize = 256;

/// Certified Step 6 bound over the face `[q_0 q_1 q_2]` of a piece `poly` (apex last) for
/// `sign · F` (sign +1 on the positive side): an upper bound, valid at every point of the face,
/// of Lemma 2.3's `b_min^(1)` of the base shooting polynomials (apex value `apex_value` removed
/// as in (4.14)), within [`CERTIFIED_GAP`]` · scale` of the largest value sampled (see
/// [`algesurf_bb::sheet::certified_triangle_b_min`] for why it is an upper bound). `rational`:
/// the values `r_a` of the blend of (4.1) for a convex face; the face term
/// `6 τ0τ1τ2 · blend` is at least `min_a (sign r_a) · B_111(τ)` because the blend is a convex
/// combination of the `r_a` on the face, so that is added to the layer-0 coefficient at
/// `(1,1,1)` to keep the layers below the true coefficients. `base(q)` gives the true base
/// coefficients of `sign · F` at the face point `q`. `−∞` when no ray starts where `b_0 < 0`.
///
/// `enough`: the search stops as soon as the bound is certified `≤ enough` (see
/// [`certified_triangle_b_min_below`]). Construction passes `sign·value − margin` for the
/// apex value it would keep: a bound at or below that leaves the value unchanged, so the
/// free parameters and F are exactly those the gap-closing search gives, while the reported
/// bound of such a face is only certified, not within the gap of the true maximum. Pass
/// `−∞` for the bound within the gap everywhere.
pub fn certified_face_bound(
    poly: &BbPoly<f64, 4>,
    apex_value: f64,
    sign: f64,
    rational: Option<[f64; 3]>,
    scale: f64,
    enough: f64,
    base: impl Fn([f64; 3]) -> [f64; 4],
) -> f64 {
    // (4.14): layer 2 carries f/3, the apex f; remove them like `without_apex`.
    let off = [0.0, 0.0, apex_value / 3.0, apex_value];
    let low = rational.map(|r| r.iter().map(|x| sign * x).fold(f64::INFINITY, min_not_nan));
    // The whole face first, without building its layers: the root cell's minima are the
    // layers' least coefficients (the blossom at the triangle's own corners is exact), so
    // this is bit for bit the value at which `certified_triangle_b_min_below` would stop at
    // the root — as it does for 339,642 of the bunny's 339,854 face bounds.
    if poly.degree() == 3 {
        let mut minima = [f64::INFINITY; 4];
        for (&l, &c) in crate::cubic::INDICES3.iter().zip(poly.coeffs()) {
            let k = l[3];
            let mut v = sign * (c - off[k]);
            if let (Some(low), [1, 1, 1, 0]) = (low, l) {
                v += low;
            }
            minima[k] = minima[k].min(v);
        }
        let upper = b_min_1_upper_from_minima(minima);
        if upper <= enough {
            return upper;
        }
    }
    certified_triangle_b_min_below(
        base_layers(poly, off, sign, low),
        base,
        CERTIFIED_GAP * scale,
        CERTIFIED_MAX_CELLS,
        enough,
    )
    .upper
}

/// The layers (w.r.t. the apex, vertex 3) of `sign · (poly − off)`, `off[k]` taken off layer
/// `k`, with `low` (the rational face term's least blend value, already signed) added to the
/// layer-0 coefficient at `(1, 1, 1)`: the base layers [`certified_face_bound`] bounds.
fn base_layers(
    poly: &BbPoly<f64, 4>,
    off: [f64; 4],
    sign: f64,
    low: Option<f64>,
) -> [BbPoly<f64, 3>; 4] {
    let layers = poly.layers::<3>(3).expect("vertex 3 of a tetrahedron");
    let mut layers: [BbPoly<f64, 3>; 4] =
        std::array::from_fn(|k| layers[k].map(|c| sign * (c - off[k])));
    if let Some(low) = low {
        let c = layers[0].coeff([1, 1, 1]);
        layers[0].set([1, 1, 1], c + low);
    }
    layers
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The whole-face shortcut of `certified_face_bound` returns bit for bit what the branch
    /// and bound returns when it stops at the root (`enough = +∞`), with and without a
    /// rational term, on both sides.
    #[test]
    fn whole_face_shortcut_is_the_root_cell_bound() {
        let mut rng = algesurf_mesh::test_rng::Lcg(99);
        let mut next = || rng.centred();
        let mut decided = 0;
        for case in 0..200 {
            let poly = BbPoly::from_fn(3, |l| next() - if l[3] == 0 { 0.3 } else { 0.0 });
            let (apex, sign) = (next(), if case % 2 == 0 { 1.0 } else { -1.0 });
            let rational = (case % 3 == 0).then(|| [next(), next(), next()]);
            let fast =
                certified_face_bound(&poly, apex, sign, rational, 1.0, f64::INFINITY, |_| {
                    [0.0; 4]
                });
            let off = [0.0, 0.0, apex / 3.0, apex];
            let low = rational.map(|r| r.iter().map(|x| sign * x).fold(f64::INFINITY, f64::min));
            let slow = certified_triangle_b_min_below(
                base_layers(&poly, off, sign, low),
                |_| [0.0; 4],
                1.0,
                256,
                f64::INFINITY,
            );
            assert_eq!(fast.to_bits(), slow.upper.to_bits(), "case {case}");
            decided += fast.is_finite() as usize;
        }
        assert!(decided > 50, "too few finite bounds to compare: {decided}");
    }

    #[test]
    fn lifted_b_min_above_is_exact_above_the_floor_and_certified_below_it() {
        let lift = [0.0, 0.0, 0.4, 1.0];
        for base in [
            [-1.0, 0.3, -0.8, -0.2],
            [-0.5, -0.4, 0.2, 0.9],
            [-2.0, 1.5, -1.0, 0.3],
        ] {
            let exact = lifted_b_min(base, lift).unwrap();
            for floor in [exact - 1.0, exact - 1e-9, exact, exact + 1e-9, exact + 1.0] {
                let got = lifted_b_min_above(base, lift, floor).unwrap();
                if got > floor {
                    assert_eq!(got.to_bits(), exact.to_bits(), "{base:?}, floor {floor}");
                } else {
                    // A value at some t: the least b is at most it.
                    assert!(got >= exact, "{got} below the minimum {exact}");
                }
                if exact > floor {
                    assert_eq!(got.to_bits(), exact.to_bits(), "{base:?}, floor {floor}");
                }
            }
        }
        // b_0 ≥ 0: no bound, whatever the floor.
        assert_eq!(lifted_b_min_above([0.1, 0.0, 0.0, 0.0], lift, 0.0), None);
    }
}

//! Certified Step 6 bound over a square of rays: the edge A-patches of Xu–Huang–Bajaj 2001.
//!
//! An edge A-patch (4.7) is swept by the rays from `q = x p_i + (1 − x) p_j` on the mesh edge
//! to `u = y u_k + (1 − y) u_l` on the apex segment, `(x, y) ∈ [0, 1]²`. Along each ray the
//! function is a cubic `Σ b_k(x, y) B_k^3(t)` (4.9), and raising the two faces' apex values by
//! `b` adds `b (0, 0, c_2(x, y), c_3(x, y))` with `c_2, c_3 ≥ 0` (their `τ_apex²`, continued C1
//! into the edge tetrahedron). Each `b_k` and `c_k` is a polynomial of degree at most 3 in `x`
//! and in `y` (a blossom of the cubic in `3 − k` copies of `q` and `k` of `u`, plus the edge
//! term of (4.3), cubic in `y`), so they are exact in the tensor-product Bernstein basis of
//! bidegree (3, 3), and their BB coefficients over any sub-rectangle bound them there
//! (convex-hull property). [`certified_square_lift_bound`] turns those bounds into a guaranteed
//! upper bound of Lemma 2.3's `b_min^(1)` — the least `b` for which some `t` has both lifted
//! de Casteljau coefficients positive — at every ray of the square, by branch and bound.

use super::Ranked;
use crate::extremes::{max_not_nan, min_not_nan};

/// Bernstein coefficients `c[i][j]` of a polynomial of bidegree (3, 3) on `[0, 1]²`:
/// `Σ c[i][j] B_i^3(x) B_j^3(y)`.
pub type Tensor3 = [[f64; 4]; 4];

/// Interpolates a polynomial of bidegree at most (3, 3) from its values `v[a][b]` at
/// `(x, y) = (a/3, b/3)`: exact for such polynomials (up to rounding of a few ulps of the
/// values' size), which is how callers get [`Tensor3`] coefficients of functions they can only
/// evaluate.
///
/// ```
/// use algesurf_bb::sheet::square::{interpolate_tensor3, tensor3_value};
/// let f = |x: f64, y: f64| 1.0 + x * x * y - 2.0 * y * y * y * x;
/// let v = std::array::from_fn(|a| std::array::from_fn(|b| f(a as f64 / 3.0, b as f64 / 3.0)));
/// let c = interpolate_tensor3(&v);
/// assert!((tensor3_value(&c, 0.3, 0.8) - f(0.3, 0.8)).abs() < 1e-14);
/// ```
pub fn interpolate_tensor3(v: &Tensor3) -> Tensor3 {
    // The Bernstein collocation matrix at 0, ⅓, ⅔, 1 inverted by hand: c_0 = v_0, c_3 = v_3,
    // c_1 = (−5v_0 + 18v_1 − 9v_2 + 2v_3)/6, c_2 = (2v_0 − 9v_1 + 18v_2 − 5v_3)/6.
    let solve = |w: [f64; 4]| -> [f64; 4] {
        [
            w[0],
            (-5.0 * w[0] + 18.0 * w[1] - 9.0 * w[2] + 2.0 * w[3]) / 6.0,
            (2.0 * w[0] - 9.0 * w[1] + 18.0 * w[2] - 5.0 * w[3]) / 6.0,
            w[3],
        ]
    };
    // Along y for each x node, then along x for each y index.
    let rows: [[f64; 4]; 4] = std::array::from_fn(|a| solve(v[a]));
    let mut c = [[0.0; 4]; 4];
    for j in 0..4 {
        let col = solve([rows[0][j], rows[1][j], rows[2][j], rows[3][j]]);
        for i in 0..4 {
            c[i][j] = col[i];
        }
    }
    c
}

/// The value of a [`Tensor3`] at `(x, y)` (de Casteljau in each variable).
pub fn tensor3_value(c: &Tensor3, x: f64, y: f64) -> f64 {
    let row: [f64; 4] = std::array::from_fn(|i| casteljau(c[i], y));
    casteljau(row, x)
}

fn casteljau(mut b: [f64; 4], t: f64) -> f64 {
    for m in (1..4).rev() {
        for k in 0..m {
            b[k] = (1.0 - t) * b[k] + t * b[k + 1];
        }
    }
    b[0]
}

/// BB coefficients of a cubic (coefficients `b` on `[0, 1]`) over `[lo, hi]`: the blossom at
/// `(lo^{3−i}, hi^i)` for coefficient `i`.
fn restrict1(b: [f64; 4], lo: f64, hi: f64) -> [f64; 4] {
    std::array::from_fn(|i| {
        let mut w = b;
        let mut m = 3;
        for step in 0..3 {
            let t = if step < 3 - i { lo } else { hi };
            for k in 0..m {
                w[k] = (1.0 - t) * w[k] + t * w[k + 1];
            }
            m -= 1;
        }
        w[0]
    })
}

/// Least and largest BB coefficient of `c` over the rectangle `[x0, x1] × [y0, y1]`: bounds of
/// the polynomial there (convex-hull property).
fn range_over(c: &Tensor3, x: [f64; 2], y: [f64; 2]) -> (f64, f64) {
    // The whole square (the branch and bound's root cell, where most edges' bounds are
    // decided): every de Casteljau step of the restriction has t = 0 or t = 1, which returns
    // one of its two finite inputs exactly (`1·a + 0·b`, `0·a + 1·b`; only the sign of a zero
    // can differ, and no comparison below tells them apart), so the coefficients are `c`'s.
    if x == [0.0, 1.0] && y == [0.0, 1.0] && c.iter().flatten().all(|v| v.is_finite()) {
        return c
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                // Running extremes from ±∞: never NaN.
                (min_not_nan(lo, v), max_not_nan(hi, v))
            });
    }
    restricted_range(c, x, y)
}

/// [`range_over`] by restricting `c` to the rectangle (the general path).
fn restricted_range(c: &Tensor3, x: [f64; 2], y: [f64; 2]) -> (f64, f64) {
    let rows: [[f64; 4]; 4] = std::array::from_fn(|i| restrict1(c[i], y[0], y[1]));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for j in 0..4 {
        for v in restrict1([rows[0][j], rows[1][j], rows[2][j], rows[3][j]], x[0], x[1]) {
            // Running extremes from ±∞ (a NaN `v` is skipped, as by `f64::min`).
            lo = min_not_nan(lo, v);
            hi = max_not_nan(hi, v);
        }
    }
    (lo, hi)
}

/// Upper bound of Lemma 2.3's `b_min^(1)` for every ray whose base coefficients are at least
/// `m` (`m[0] < 0`) and whose lift has `c_2 ∈ [l2.0, l2.1]`, `c_3 ∈ [l3.0, l3.1]`, both `≥ 0`
/// (for a lift that may be negative see the first branch).
///
/// For one `t ∈ (0, 1]` the lifted coefficients over `[0, t]` are `F_2(t) + b c_2 t²` and
/// `F_3(t) + b (3c_2 t²(1 − t) + c_3 t³)`, with `F_j(t) = Σ_{i≤j} b_i B_i^j(t)` non-decreasing in
/// every `b_i`. Both are positive once `b > −F_j/w_j`; with `F_j ≥ F_j(m)` and the weight `w_j`
/// in its interval, `−F_j/w_j ≤ −F_j(m)/w_min` when `F_j(m) < 0` and `≤ −F_j(m)/w_max` (≤ 0)
/// otherwise. So every `t` gives an upper bound of `b_min^(1)`, and the least over the sampled
/// `t` is one. `F_j(m)` is lowered by its evaluation error bound `8u Σ|m_i|` first.
///
/// `enough`: return the first sampled bound that is `≤ enough` (from `t = 1` down, where the
/// edges' rays usually have their least need), not the least of them; it is an upper bound
/// all the same. Otherwise the least of all the samples, exactly as with `enough = −∞` (the
/// minimum does not depend on their order). The bunny's edges took 154.6 k cell bounds for
/// 145.8 k squares, nearly all decided by the whole square's cell, each after all 32 samples
/// (~2.7 k instructions, 419 M in all, `callgrind`).
fn cell_upper(m: [f64; 4], l2: (f64, f64), l3: (f64, f64), enough: f64) -> f64 {
    if m[0] >= 0.0 {
        return f64::NEG_INFINITY;
    }
    if m.iter().any(|x| !x.is_finite()) {
        return f64::INFINITY;
    }
    if !(l2.0 >= 0.0 && l3.0 >= 0.0) {
        // The lift may be negative here (an apex far outside its neighbour's tetrahedron in
        // the continuation's coordinates): raising the apex values may lower these rays, so
        // no increment helps. They are fine if they satisfy Lemma 2.3 already — a need below
        // 0 for the positive lift t² (`c_2 = ⅓`, `c_3 = 1`) says some t has both coefficients
        // positive at b = 0 — and then ask for nothing; otherwise the cell has no bound.
        let own = cell_upper(m, (1.0 / 3.0, 1.0 / 3.0), (1.0, 1.0), f64::NEG_INFINITY);
        return if own < 0.0 {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        };
    }
    let err = 8.0 * f64::EPSILON * m.iter().map(|x| x.abs()).sum::<f64>();
    let part = |f: f64, wmin: f64, wmax: f64| -> f64 {
        if f < 0.0 {
            if wmin > 0.0 { -f / wmin } else { f64::INFINITY }
        } else if wmax > 0.0 {
            -f / wmax
        } else {
            // f ≥ 0 with a zero weight: that coefficient is already nonnegative for every b;
            // 0 keeps the bound valid (the other coefficient decides).
            0.0
        }
    };
    const SAMPLES: usize = 32;
    // The division's rounding: one more relative ulp upwards.
    let rounded_up = |b: f64| b + b.abs() * 2.0 * f64::EPSILON;
    let mut best = f64::INFINITY;
    for k in (1..=SAMPLES).rev() {
        let t = k as f64 / SAMPLES as f64;
        let s = 1.0 - t;
        let f2 = m[0] * s * s + 2.0 * m[1] * t * s + m[2] * t * t - err;
        let f3 =
            m[0] * s * s * s + 3.0 * m[1] * t * s * s + 3.0 * m[2] * t * t * s + m[3] * t * t * t
                - err;
        let (w2min, w2max) = (l2.0 * t * t, l2.1 * t * t);
        let w3 = |c2: f64, c3: f64| 3.0 * c2 * t * t * s + c3 * t * t * t;
        let v = part(f2, w2min, w2max).max(part(f3, w3(l2.0, l3.0), w3(l2.1, l3.1)));
        if rounded_up(v) <= enough {
            return rounded_up(v);
        }
        best = best.min(v);
    }
    rounded_up(best)
}

/// The result of [`certified_square_lift_bound`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SquareBound {
    /// Guaranteed upper bound of `b_min^(1)` over every ray of the square with `b_0 < 0`
    /// (`−∞` when there is none; `+∞` when some cell has a lift that may be negative and rays
    /// that do not already satisfy Lemma 2.3). Rays whose lift may be negative and that
    /// satisfy the lemma at the current coefficients count as needing nothing: they are
    /// certified at `b = 0` only, as raising the apex values may lower them.
    pub upper: f64,
    /// The largest value `sample` returned at a cell centre: a lower bound of the true maximum.
    pub sampled: f64,
    /// The centre of the cell that holds `upper` when the search stopped (where to look when
    /// it is `+∞`).
    pub worst: [f64; 2],
    /// Cells the square was subdivided into.
    pub cells: usize,
}

/// A sub-rectangle `x × y` of the square, with its upper bound.
type Cell = Ranked<([f64; 2], [f64; 2])>;

fn centre(c: &Cell) -> [f64; 2] {
    let (x, y) = c.cell;
    [0.5 * (x[0] + x[1]), 0.5 * (y[0] + y[1])]
}

/// Certified maximum over the square `[0, 1]²` of rays of Lemma 2.3's `b_min^(1)` for the
/// base coefficients `base[k]` and the lift `(0, 0, lift[0], lift[1])` (see the module docs):
/// Step 6 of §4.2 for an edge A-patch "computed with a guaranteed bound". `sample(x, y)` gives
/// the exact need of one ray (`−∞` when it needs nothing), for the lower end of the gap.
///
/// Branch and bound like [`super::certified_triangle_b_min_below`]: the cell with the largest
/// upper bound is split into four until that bound is within `gap` of the largest sampled
/// value, is `≤ enough`, or `max_cells` cells exist; `upper` bounds `b_min^(1)` at every ray
/// either way. Above `enough` the result is exactly that of `enough = −∞` (the same cells are
/// split in the same order); at or below it, it is only certified, as a cell's bound then
/// stops at its first sample below `enough`.
///
/// ```
/// use algesurf_bb::sheet::square::{Tensor3, certified_square_lift_bound};
/// // b = (−1, 0.5, −2, −1) on every ray, lifted by the apex's t² (c₂ = ⅓, c₃ = 1).
/// let constant = |v: f64| -> Tensor3 { [[v; 4]; 4] };
/// let base = [constant(-1.0), constant(0.5), constant(-2.0), constant(-1.0)];
/// let lift = [constant(1.0 / 3.0), constant(1.0)];
/// let exact = algesurf_bb::sheet::lemma_2_3_b_min([-1.0, 0.5, -2.0, -1.0], 1.0)?.b_min_1;
/// let b = certified_square_lift_bound(&base, &lift, |_, _| exact, 1e-3, 64, f64::NEG_INFINITY);
/// assert!(b.upper >= exact && b.upper <= exact + 0.05);
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
pub fn certified_square_lift_bound(
    base: &[Tensor3; 4],
    lift: &[Tensor3; 2],
    sample: impl Fn(f64, f64) -> f64,
    gap: f64,
    max_cells: usize,
    enough: f64,
) -> SquareBound {
    let bound = |x: [f64; 2], y: [f64; 2]| -> f64 {
        let m: [f64; 4] = std::array::from_fn(|k| range_over(&base[k], x, y).0);
        cell_upper(
            m,
            range_over(&lift[0], x, y),
            range_over(&lift[1], x, y),
            enough,
        )
    };
    let root = Cell {
        upper: bound([0.0, 1.0], [0.0, 1.0]),
        cell: ([0.0, 1.0], [0.0, 1.0]),
    };
    let mut worst = centre(&root);
    if root.upper <= enough {
        return SquareBound {
            upper: root.upper,
            sampled: f64::NEG_INFINITY,
            worst,
            cells: 1,
        };
    }
    let [cx, cy] = centre(&root);
    let mut sampled = sample(cx, cy);
    let mut cells = 1;
    let mut heap = std::collections::BinaryHeap::new();
    if root.upper > f64::NEG_INFINITY {
        heap.push(root);
    }
    while let Some(top) = heap.peek() {
        worst = centre(top);
        let closed = top.upper.is_finite() && top.upper - sampled <= gap;
        if closed || top.upper <= enough || cells + 3 > max_cells {
            break;
        }
        let c = heap.pop().expect("peeked");
        let [mx, my] = centre(&c);
        let (cx, cy) = c.cell;
        for (x, y) in [
            ([cx[0], mx], [cy[0], my]),
            ([mx, cx[1]], [cy[0], my]),
            ([cx[0], mx], [my, cy[1]]),
            ([mx, cx[1]], [my, cy[1]]),
        ] {
            let child = Cell {
                upper: bound(x, y),
                cell: (x, y),
            };
            let [sx, sy] = centre(&child);
            sampled = sampled.max(sample(sx, sy));
            if child.upper > f64::NEG_INFINITY {
                heap.push(child);
            }
        }
        cells += 3;
    }
    SquareBound {
        upper: heap
            .peek()
            .map_or(f64::NEG_INFINITY, |c| c.upper)
            .max(sampled),
        sampled,
        worst,
        cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sheet::lemma_2_3_b_min;

    /// A tiny deterministic generator (no external crates in unit tests).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn restriction_reproduces_the_polynomial_on_the_sub_rectangle() {
        let mut r = Lcg(3);
        let c: Tensor3 = std::array::from_fn(|_| std::array::from_fn(|_| r.next() - 0.5));
        let (x, y) = ([0.2, 0.7], [0.1, 0.45]);
        let rows: [[f64; 4]; 4] = std::array::from_fn(|i| restrict1(c[i], y[0], y[1]));
        let mut sub = [[0.0; 4]; 4];
        for j in 0..4 {
            let col = restrict1([rows[0][j], rows[1][j], rows[2][j], rows[3][j]], x[0], x[1]);
            for i in 0..4 {
                sub[i][j] = col[i];
            }
        }
        for (s, t) in [(0.0, 0.0), (0.3, 0.9), (1.0, 0.5), (0.6, 1.0)] {
            let want = tensor3_value(&c, x[0] + s * (x[1] - x[0]), y[0] + t * (y[1] - y[0]));
            assert!((tensor3_value(&sub, s, t) - want).abs() < 1e-14);
        }
        let (lo, hi) = range_over(&c, x, y);
        for k in 0..50 {
            let (s, t) = (k as f64 / 49.0, r.next());
            let v = tensor3_value(&c, x[0] + s * (x[1] - x[0]), y[0] + t * (y[1] - y[0]));
            assert!(lo <= v && v <= hi);
        }
    }

    /// On the whole square the range is the coefficients' own, which is what the restriction
    /// gives there, value for value (zeros of either sign included in the draws).
    #[test]
    fn whole_square_range_is_the_restrictions() {
        let mut r = Lcg(5);
        for case in 0..200 {
            let c: Tensor3 = std::array::from_fn(|_| {
                std::array::from_fn(|_| match (r.next() * 8.0) as u32 {
                    0 => 0.0,
                    1 => -0.0,
                    _ => (r.next() - 0.5) * 10f64.powi(case % 7 - 3),
                })
            });
            let (lo, hi) = restricted_range(&c, [0.0, 1.0], [0.0, 1.0]);
            let fast = range_over(&c, [0.0, 1.0], [0.0, 1.0]);
            assert!(
                fast.0 == lo && fast.1 == hi,
                "case {case}: {fast:?} vs {:?}",
                (lo, hi)
            );
        }
    }

    /// Random base and lift tensors: layer 0 in `[−low − 1, −low]` (rays start below the
    /// surface), layers 1–3 in `[−shift, 2 − shift]`, the lift's `c_2`, `c_3` positive.
    fn random_square(r: &mut Lcg, low: f64, shift: f64) -> ([Tensor3; 4], [Tensor3; 2]) {
        let base = std::array::from_fn(|k| {
            std::array::from_fn(|_| {
                std::array::from_fn(|_| match k {
                    0 => -low - r.next(),
                    _ => 2.0 * r.next() - shift,
                })
            })
        });
        let lift = std::array::from_fn(|k| {
            std::array::from_fn(|_| {
                std::array::from_fn(|_| if k == 0 { 0.1 } else { 0.5 } + r.next())
            })
        });
        (base, lift)
    }

    /// The need of the ray `(x, y)` for a general lift by a scan of `steps` values of t (slow,
    /// tests only): a lower bound of the least need, as the search's samples must be.
    fn scanned_need(base: &[Tensor3; 4], lift: &[Tensor3; 2], x: f64, y: f64, steps: u32) -> f64 {
        let b: [f64; 4] = std::array::from_fn(|k| tensor3_value(&base[k], x, y));
        let (c2, c3) = (tensor3_value(&lift[0], x, y), tensor3_value(&lift[1], x, y));
        let mut best = f64::INFINITY;
        for k in 1..=steps {
            let t = f64::from(k) / f64::from(steps);
            let s = 1.0 - t;
            let f2 = b[0] * s * s + 2.0 * b[1] * t * s + b[2] * t * t;
            let f3 = b[0] * s * s * s
                + 3.0 * b[1] * t * s * s
                + 3.0 * b[2] * t * t * s
                + b[3] * t * t * t;
            let w2 = c2 * t * t;
            let w3 = 3.0 * c2 * t * t * s + c3 * t * t * t;
            best = best.min((-f2 / w2).max(-f3 / w3));
        }
        best
    }

    /// Against every ray of a fine grid: the certified bound is at least each ray's exact
    /// `b_min^(1)` (the lift varying over the square as an edge's does).
    #[test]
    fn certified_bound_is_above_every_sampled_ray() {
        let mut r = Lcg(11);
        for _ in 0..20 {
            let (base, lift) = random_square(&mut r, 0.2, 1.2);
            let need = |x: f64, y: f64| scanned_need(&base, &lift, x, y, 4000);
            let b = certified_square_lift_bound(&base, &lift, need, 1e-2, 256, f64::NEG_INFINITY);
            for i in 0..=24 {
                for j in 0..=24 {
                    let v = need(i as f64 / 24.0, j as f64 / 24.0);
                    assert!(b.upper >= v - 1e-9, "bound {} below ray need {v}", b.upper);
                }
            }
            assert!(b.upper.is_finite() && b.sampled <= b.upper);
        }
        // The β = 1 lift agrees with Lemma 2.3 on a constant square.
        let constant = |v: f64| -> Tensor3 { [[v; 4]; 4] };
        let coeffs = [-1.0, 0.3, -0.5, -0.2];
        let exact = lemma_2_3_b_min(coeffs, 1.0).unwrap().b_min_1;
        let b = certified_square_lift_bound(
            &coeffs.map(constant),
            &[constant(1.0 / 3.0), constant(1.0)],
            |_, _| exact,
            1e-4,
            16,
            f64::NEG_INFINITY,
        );
        assert!(
            b.upper >= exact && b.upper <= exact + 0.05,
            "{} vs {exact}",
            b.upper
        );
    }

    /// With `enough`, a bound above it is bit for bit the bound without (the same cells in the
    /// same order), a bound at or below it is so without too, and every result bounds the
    /// sampled needs: on random squares whose bounds fall on both sides of each `enough`.
    #[test]
    fn enough_changes_only_bounds_below_it() {
        let mut r = Lcg(17);
        let mut below = 0;
        let mut above = 0;
        for _ in 0..30 {
            let (base, lift) = random_square(&mut r, 0.05, 0.9);
            let need = |x: f64, y: f64| scanned_need(&base, &lift, x, y, 1000);
            let full = certified_square_lift_bound(&base, &lift, need, 1e-3, 64, f64::NEG_INFINITY);
            for enough in [
                full.upper - 0.5,
                full.upper - 1e-12,
                full.upper,
                full.upper + 0.5,
            ] {
                let got = certified_square_lift_bound(&base, &lift, need, 1e-3, 64, enough);
                assert_eq!(got.upper > enough, full.upper > enough, "enough {enough}");
                if got.upper > enough {
                    assert_eq!(got.upper.to_bits(), full.upper.to_bits());
                    above += 1;
                } else {
                    assert!(got.upper >= got.sampled);
                    below += 1;
                }
            }
        }
        assert!(below > 25 && above > 25, "below {below}, above {above}");
    }

    #[test]
    fn a_negative_lift_gives_no_bound() {
        let constant = |v: f64| -> Tensor3 { [[v; 4]; 4] };
        let base = [-1.0, 0.0, -1.0, -1.0].map(constant);
        let b = certified_square_lift_bound(
            &base,
            &[constant(-0.1), constant(1.0)],
            |_, _| f64::INFINITY,
            1e-3,
            16,
            f64::NEG_INFINITY,
        );
        assert_eq!(b.upper, f64::INFINITY);
    }
}

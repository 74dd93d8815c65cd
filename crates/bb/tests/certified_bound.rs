//! Claims of the certified Step 6 bound over a triangle (`certified_triangle_b_min`): it is an
//! upper bound of Lemma 2.3's `b_min^(1)` at every point, within the requested gap of the
//! sampled maximum, and it finds maxima a fixed grid misses.

use algesurf_bb::BbPoly;
use algesurf_bb::sheet::{
    certified_triangle_b_min, certified_triangle_b_min_below, lemma_2_3_b_min,
};

/// Quadratic `c + k Σ_i (q_i − s_i)²` in BB form over the triangle (homogenised with Σ q = 1:
/// the coefficient of `B_{e_j+e_k}` is the symmetric matrix entry `A_jk`).
fn bowl(c: f64, k: f64, s: [f64; 3]) -> BbPoly<f64, 3> {
    let d = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    let a = |j: usize, l: usize| {
        c + k
            * (0..3)
                .map(|i| (d(i, j) - s[i]) * (d(i, l) - s[i]))
                .sum::<f64>()
    };
    BbPoly::from_fn(2, |m| {
        let idx: Vec<usize> = (0..3).flat_map(|i| std::iter::repeat_n(i, m[i])).collect();
        a(idx[0], idx[1])
    })
}

fn layers_eval(layers: &[BbPoly<f64, 3>; 4], q: [f64; 3]) -> [f64; 4] {
    std::array::from_fn(|k| layers[k].eval(q))
}

fn b_min_1(b: [f64; 4]) -> f64 {
    if b[0] < 0.0 {
        lemma_2_3_b_min(b, 1.0).unwrap().b_min_1
    } else {
        f64::NEG_INFINITY
    }
}

fn grid_max(layers: &[BbPoly<f64, 3>; 4], level: usize) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for i in 0..=level {
        for j in 0..=(level - i) {
            let q = [i, j, level - i - j].map(|x| x as f64 / level as f64);
            best = best.max(b_min_1(layers_eval(layers, q)));
        }
    }
    best
}

/// b_0 < 0 inside, the layer-1 bowl has its minimum (so b_min^(1) its maximum) at `s`.
fn bowl_layers(s: [f64; 3]) -> [BbPoly<f64, 3>; 4] {
    [
        BbPoly::constant(3, -1.0),
        bowl(-2.0, 40.0, s),
        BbPoly::constant(1, 0.5),
        BbPoly::constant(0, 0.0),
    ]
}

#[test]
fn the_certified_bound_is_above_every_dense_sample_and_within_the_gap() {
    let wavy: [BbPoly<f64, 3>; 4] = std::array::from_fn(|k| {
        BbPoly::from_fn(3 - k, |m| {
            let x = (m[0] * 3 + m[1] * 5 + k * 7) as f64;
            if k == 0 {
                -1.0 + 0.5 * x.sin()
            } else {
                x.cos()
            }
        })
    });
    for layers in [bowl_layers([0.37, 0.41, 0.22]), wavy] {
        let gap = 1e-3;
        let b = certified_triangle_b_min(layers.clone(), |q| layers_eval(&layers, q), gap, 1 << 16);
        let dense = grid_max(&layers, 120);
        assert!(b.upper >= dense, "bound {} below a sample {dense}", b.upper);
        assert!(b.upper - b.sampled <= gap, "gap not closed: {b:?}");
        assert!(
            b.sampled <= dense + gap,
            "sampled {} vs dense {dense}",
            b.sampled
        );
        println!("{b:?}, dense max {dense}");
    }
}

#[test]
fn a_grid_misses_an_off_grid_maximum_that_the_certified_bound_covers() {
    let s = [0.37, 0.41, 0.22];
    let layers = bowl_layers(s);
    let at_peak = b_min_1(layers_eval(&layers, s));
    let grid = grid_max(&layers, 8);
    assert!(
        grid < at_peak - 1e-3,
        "the level-8 grid should miss the peak: {grid} vs {at_peak}"
    );
    let b = certified_triangle_b_min(layers.clone(), |q| layers_eval(&layers, q), 1e-4, 1 << 16);
    assert!(b.upper >= at_peak, "{b:?} below the peak {at_peak}");
    assert!(
        b.upper <= at_peak + 1e-4,
        "{b:?} not within the gap of {at_peak}"
    );
}

#[test]
fn stopping_below_a_level_keeps_the_bound_guaranteed_and_is_exact_above_it() {
    let layers = bowl_layers([0.37, 0.41, 0.22]);
    let eval = |q: [f64; 3]| layers_eval(&layers, q);
    let gap = 1e-4;
    let full = certified_triangle_b_min(layers.clone(), eval, gap, 1 << 16);
    let dense = grid_max(&layers, 120);
    // Far above the bound: decided by the whole triangle.
    let root = certified_triangle_b_min_below(layers.clone(), eval, gap, 1 << 16, 1e6);
    assert_eq!(root.cells, 1, "{root:?}");
    assert!(
        root.upper >= full.upper && root.upper <= 1e6,
        "{root:?} vs {full:?}"
    );
    // Between the true maximum and the root bound: stops early, still above every sample.
    let mid = 0.5 * (full.upper + root.upper);
    let early = certified_triangle_b_min_below(layers.clone(), eval, gap, 1 << 16, mid);
    assert!(
        early.upper <= mid && early.upper >= dense,
        "{early:?}, dense {dense}"
    );
    assert!(early.cells <= full.cells, "{early:?} vs {full:?}");
    // Below the true maximum the level never fires: the same search, the same result.
    let below = certified_triangle_b_min_below(layers.clone(), eval, gap, 1 << 16, dense - 1.0);
    assert_eq!(below, full);
}

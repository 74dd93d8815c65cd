//! Evaluation benchmarks of the BB algebra (issue targets: trivariate cubic ≤ 40 ns/eval).
//! Run: `cargo bench -p algesurf-benches --bench bb` (or `cargo xtask bench bb`).

use algesurf::bb::BbPoly;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

fn sample(degree: usize) -> BbPoly<f64, 4> {
    BbPoly::from_fn(degree, |l| {
        ((l[0] * 7 + l[1] * 3 + l[2] * 5 + l[3] * 11) % 13) as f64 / 13.0 - 0.5
    })
}

/// 64 points spread inside the tetrahedron, so branch prediction sees varied input.
fn points() -> Vec<[f64; 4]> {
    (0..64)
        .map(|k| {
            let a = 0.05 + 0.9 * ((k * 37 % 64) as f64 / 64.0);
            let b = (1.0 - a) * ((k * 11 % 64) as f64 / 64.0);
            let c = (1.0 - a - b) * ((k * 23 % 64) as f64 / 64.0);
            [a, b, c, 1.0 - a - b - c]
        })
        .collect()
}

#[divan::bench(args = [3, 5])]
fn trivariate_fast_eval(bencher: Bencher, degree: usize) {
    let p = sample(degree).evaluator();
    let pts = points();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        p.eval(black_box(pts[i]))
    });
}

#[divan::bench(args = [3, 5])]
fn trivariate_de_casteljau(bencher: Bencher, degree: usize) {
    let p = sample(degree);
    let pts = points();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        p.eval(black_box(pts[i]))
    });
}

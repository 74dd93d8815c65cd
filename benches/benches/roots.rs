//! Root-finding benchmarks (issue target: smallest cubic root in [0, 1] ≤ 60 ns/solve).
//! Run: `cargo bench -p algesurf-benches --bench roots`.

use algesurf::bb::BbPoly;
use algesurf::bb::roots::{cubic_roots, find_roots, shooting_root};
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

/// 64 lifted shooting polynomials (b_0 < 0 < b_2, b_3: the Corollary's case, as in A-patch
/// tessellation), with b_1 of both signs so both Δ > 0 and Δ < 0 occur.
fn lifted_cubics() -> Vec<[f64; 4]> {
    (0..64)
        .map(|k| {
            let x = (k * 37 % 64) as f64 / 64.0;
            let y = (k * 11 % 64) as f64 / 64.0;
            [-0.2 - x, 2.0 * y - 1.5, 0.1 + x * y, 0.5 + y]
        })
        .collect()
}

/// 64 general cubics with coefficients of mixed signs (up to three roots in [0, 1]).
fn general_cubics() -> Vec<[f64; 4]> {
    (0..64)
        .map(|k| {
            let f = |m: usize| ((k * m % 97) as f64 / 97.0) * 2.0 - 1.0;
            [f(13), f(29), f(53), f(71)]
        })
        .collect()
}

#[divan::bench]
fn shooting_root_lifted(bencher: Bencher) {
    let cs = lifted_cubics();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        shooting_root(black_box(cs[i]))
    });
}

#[divan::bench]
fn shooting_root_general(bencher: Bencher) {
    let cs = general_cubics();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        shooting_root(black_box(cs[i]))
    });
}

#[divan::bench]
fn cubic_all_roots_closed_form(bencher: Bencher) {
    let cs = general_cubics();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        cubic_roots(black_box(&cs[i]))
    });
}

#[divan::bench]
fn cubic_all_roots_subdivision(bencher: Bencher) {
    let cs = general_cubics();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        find_roots(black_box(&cs[i]))
    });
}

/// Degree 9 with nine simple roots in (0, 1) (the hardest isolation for subdivision), and
/// with a double root plus simple roots.
fn degree9(roots: &[(f64, usize)]) -> Vec<f64> {
    let mut p = BbPoly::univariate(&[1.0]).unwrap();
    for &(r, m) in roots {
        for _ in 0..m {
            p = p.mul_scalar_poly(&BbPoly::univariate(&[-r, 1.0 - r]).unwrap());
        }
    }
    p.into_coeffs()
}

#[divan::bench]
fn degree9_nine_simple_roots(bencher: Bencher) {
    let b = degree9(
        &(1..10)
            .map(|k| (k as f64 / 10.0 - 0.03, 1))
            .collect::<Vec<_>>(),
    );
    bencher.bench_local(|| find_roots(black_box(&b)));
}

#[divan::bench]
fn degree9_double_root_and_simple_roots(bencher: Bencher) {
    let b = degree9(&[(0.15, 1), (0.35, 2), (0.6, 1), (0.8, 1)]);
    let b: Vec<f64> = BbPoly::univariate(&b)
        .unwrap()
        .elevate(9 - (b.len() - 1))
        .into_coeffs();
    bencher.bench_local(|| find_roots(black_box(&b)));
}

#[divan::bench]
fn degree9_random_coefficients(bencher: Bencher) {
    let polys: Vec<Vec<f64>> = (0..64)
        .map(|k| {
            (0..10)
                .map(|j| (((k * 31 + j * 17) % 89) as f64 / 89.0) * 2.0 - 1.0)
                .collect()
        })
        .collect();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) & 63;
        find_roots(black_box(&polys[i]))
    });
}

//! Mesh pipeline benchmarks (issue targets: bunny load → validate → repair → normals under
//! 150 ms on the 2-core machine; BVH build, self-intersections and their self-join, and 1 M
//! closest-point queries).
//! Run: `cargo bench -p algesurf-benches --bench mesh`. Reads the bunny from
//! `ALGESURF_CORPUS` (default `../shared/data`; a relative path is taken from the workspace
//! root, as in the tests); without it, an icosphere of similar size
//! stands in and the output says so.

use algesurf::io;
use algesurf::mesh::{
    NormalMethod, RepairOptions, TriMesh, TriangleBvh, repair, validate, vertex_normals,
};
use divan::{Bencher, black_box};
use glam::DVec3;
use std::path::PathBuf;

fn main() {
    divan::main();
}

fn bunny_path() -> Option<PathBuf> {
    let given = std::env::var_os("ALGESURF_CORPUS").unwrap_or_else(|| "../shared/data".into());
    let dir = algesurf_mesh::test_corpus::resolve(std::path::Path::new(&given));
    let p = dir.join("stanford-bunny.obj");
    p.is_file().then_some(p)
}

/// The whole front end of `algesurf smooth`: read, validate, repair, adjacency, Loop normals.
#[divan::bench(sample_count = 20)]
fn bunny_load_to_normals(bencher: Bencher) {
    let Some(path) = bunny_path() else {
        eprintln!("bunny not found (set ALGESURF_CORPUS): benchmarking nothing");
        return;
    };
    bencher.bench(|| {
        let poly = io::read(&path).unwrap();
        let report = validate(&poly);
        let repaired = repair(&poly, &RepairOptions::default()).unwrap();
        let mesh = TriMesh::from_polygon_mesh(&repaired.mesh).unwrap();
        let n = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
        black_box((report, n))
    });
}

fn bunny_mesh() -> TriMesh {
    match bunny_path() {
        Some(p) => {
            let poly = io::read(&p).unwrap();
            TriMesh::from_polygon_mesh(&repair(&poly, &RepairOptions::default()).unwrap().mesh)
                .unwrap()
        }
        None => {
            eprintln!("bunny not found: using icosphere(6) instead");
            algesurf::mesh::shapes::icosphere(6)
        }
    }
}

#[divan::bench(sample_count = 20)]
fn bvh_build(bencher: Bencher) {
    let mesh = bunny_mesh();
    bencher.bench(|| black_box(TriangleBvh::new(&mesh)));
}

/// The bunny numbered in spatial order as `algesurf smooth` builds on it: the faces' Morton
/// order, the vertices by first use, and the renumbered mesh with its new topology
/// (`SpatialOrder::of` and `apply`).
#[divan::bench(sample_count = 20)]
fn spatial_order(bencher: Bencher) {
    use algesurf::mesh::spatial_order::SpatialOrder;
    let mesh = bunny_mesh();
    bencher.bench(|| {
        let order = SpatialOrder::of(&mesh);
        black_box(order.apply(&mesh).unwrap())
    });
}

/// The input's self-intersections (`algesurf smooth`'s crossing zone): the tree build and
/// one self-join over the faces' boxes, with the exact triangle test on every candidate pair.
#[divan::bench(sample_count = 20)]
fn self_intersections(bencher: Bencher) {
    let mesh = bunny_mesh();
    bencher.bench(|| black_box(algesurf::mesh::self_intersections(&mesh)));
}

/// The self-join alone over the faces' boxes of a built tree (every overlapping pair once).
#[divan::bench(sample_count = 20)]
fn overlapping_box_pairs(bencher: Bencher) {
    let mesh = bunny_mesh();
    let bvh = TriangleBvh::new(&mesh);
    bencher.bench(|| black_box(bvh.overlapping_box_pairs(|i, j| Some((i, j))).len()));
}

/// 1 M closest-point queries at points spread through the bounding box.
#[divan::bench(sample_count = 5)]
fn closest_point_1m_queries(bencher: Bencher) {
    let mesh = bunny_mesh();
    let bvh = TriangleBvh::new(&mesh);
    let bb = mesh.bounding_box();
    let pts: Vec<DVec3> = (0..1_000_000u64)
        .map(|k| {
            // Low-discrepancy (additive recurrence) points in the box.
            let f = |a: f64| (k as f64 * a).fract();
            bb.min
                + (bb.max - bb.min)
                    * DVec3::new(f(0.754_877_666), f(0.569_840_291), f(0.431_857_643))
        })
        .collect();
    bencher.bench(|| {
        let mut acc = 0.0;
        for p in &pts {
            acc += bvh.closest_point(*p).map_or(0.0, |c| c.distance);
        }
        black_box(acc)
    });
}

/// Butterfly limit normals of a mesh with two vertices of valence 256 (`shapes::bicone(256,
/// 0.05)`: two flat fans and a sharp rim, whose normals `--normals auto` takes from the
/// Butterfly surface): each rim vertex's cut-out holds a whole fan. The stencil of a
/// high-valence vertex through its ring's sums (`butterfly_ring`) made this quadratic in the
/// valence instead of cubic.
#[divan::bench(sample_count = 5)]
fn butterfly_normals_of_fans_of_valence_256(bencher: Bencher) {
    let mesh = algesurf::mesh::shapes::bicone(256, 0.05);
    bencher.bench_local(|| {
        vertex_normals(black_box(&mesh), NormalMethod::Butterfly).expect("normals")
    });
}

/// `(key, id)` pairs as the hull sorts them: `n` keys of `bits` random bits (63: Morton codes
/// of the bunny's 305 k hull tetrahedra; 32: its 208 k corners' edge keys), numbered in order.
fn keyed_pairs(n: usize, bits: u32) -> Vec<(u64, u32)> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    (0..n as u32)
        .map(|i| {
            // xorshift64: any well-spread keys do; the radix sort's cost depends only on how
            // many digits vary.
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s & ((1u64 << bits) - 1), i)
        })
        .collect()
}

const SORT_CASES: [(usize, u32); 2] = [(305_000, 63), (208_000, 32)];

/// Sorts copies of [`keyed_pairs`]`(n, bits)` by `sort`.
fn bench_sort(bencher: Bencher, (n, bits): (usize, u32), sort: fn(&mut Vec<(u64, u32)>)) {
    let pairs = keyed_pairs(n, bits);
    bencher
        .with_inputs(|| pairs.clone())
        .bench_local_values(|mut p| {
            sort(&mut p);
            p
        });
}

/// [`algesurf::mesh::radix::sort_pairs`] (the hull's edge keys and small trees' Morton
/// codes): a radix sort on 11-bit digits, in series.
#[divan::bench(args = SORT_CASES, sample_count = 20)]
fn sort_pairs_radix(bencher: Bencher, case: (usize, u32)) {
    bench_sort(bencher, case, algesurf::mesh::radix::sort_pairs);
}

/// The same pairs by `sort_unstable` (a comparison sort on one core), for scale.
#[divan::bench(args = SORT_CASES, sample_count = 20)]
fn sort_pairs_comparison(bencher: Bencher, case: (usize, u32)) {
    bench_sort(bencher, case, |p| p.sort_unstable());
}

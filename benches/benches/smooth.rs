//! A-patch surface benchmarks (issue targets: construction ≥ 200 k faces/s, tessellation
//! ≥ 10 M surface points/s, on the 2-core machine).
//! Run: `cargo bench -p algesurf-benches --bench smooth` (or `cargo xtask bench smooth`, which
//! also times the bunny against libigl's Loop subdivision).
//!
//! Meshes: `icosphere(3)` (1280 faces, all positive convex: one cubic per face) and a torus
//! of 24 × 12 segments (576 faces; its inner half is saddle-shaped, so many faces are
//! nonconvex and split into three cubics per side), both with Loop normals. Construction is
//! `ApatchSurface::new` (hull + function), counted in input faces; tessellation is
//! `ApatchSurface::tessellate(8, 8)`, counted in output vertices (each one a ray evaluated
//! once: a root of a shooting polynomial and a gradient).

use algesurf::apatch::{ApatchSurface, SurfaceOptions};
use algesurf::mesh::{NormalMethod, TriMesh, shapes, vertex_normals};
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use glam::DVec3;

fn main() {
    divan::main();
}

const MESHES: [&str; 2] = ["icosphere3", "torus24x12"];

fn mesh(name: &str) -> (TriMesh, Vec<DVec3>) {
    let m = match name {
        "icosphere3" => shapes::icosphere(3),
        "torus24x12" => shapes::torus(24, 12, 1.5, 0.6),
        _ => unreachable!("unknown mesh {name}"),
    };
    let n = vertex_normals(&m, NormalMethod::Loop).expect("Loop normals");
    (m, n)
}

#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn construction(bencher: Bencher, name: &str) {
    let (m, n) = mesh(name);
    let options = SurfaceOptions::default();
    bencher
        .counter(ItemsCount::new(m.face_count()))
        .bench_local(|| {
            ApatchSurface::new(black_box(&m), black_box(&n), &options).expect("surface")
        });
}

#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn tessellation(bencher: Bencher, name: &str) {
    let (m, n) = mesh(name);
    let surface = ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface");
    let points = surface
        .tessellate(8, 8)
        .expect("tessellation")
        .positions
        .len();
    bencher
        .counter(ItemsCount::new(points))
        .bench_local(|| black_box(&surface).tessellate(8, 8).expect("tessellation"));
}

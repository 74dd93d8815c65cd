//! The check battery of `algesurf_inspect::check` (interpolation, C1 across every interior
//! facet at level 6, normal agreement, topology, margins) on the A-patch surfaces of the smooth
//! benchmark's meshes, counted in interior facets measured.
//! Run: `cargo bench -p algesurf-benches --bench check`.

use algesurf::apatch::{ApatchSurface, SurfaceOptions};
use algesurf::inspect::check::{ApatchView, CheckOptions, check, continuity};
use algesurf::mesh::{NormalMethod, shapes, vertex_normals};
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

const MESHES: [&str; 2] = ["icosphere3", "torus24x12"];

fn surface(name: &str) -> ApatchSurface {
    let m = match name {
        "icosphere3" => shapes::icosphere(3),
        "torus24x12" => shapes::torus(24, 12, 1.5, 0.6),
        _ => unreachable!("unknown mesh {name}"),
    };
    let n = vertex_normals(&m, NormalMethod::Loop).expect("Loop normals");
    ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface")
}

/// The whole battery at the default options (tessellation resolution 4 included).
#[divan::bench(args = MESHES, sample_count = 10, sample_size = 1)]
fn battery(bencher: Bencher, name: &str) {
    let s = surface(name);
    let view = ApatchView::new(&s);
    let options = CheckOptions::default();
    let facets = continuity(&view, options.facet_level).facets.len();
    bencher
        .counter(ItemsCount::new(facets))
        .bench_local(|| check(black_box(&view), &options).expect("check"));
}

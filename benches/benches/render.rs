//! Renderer benchmarks (issue target: a ≥ 1 M triangle mesh to 1024×1024 in under 1 s on the
//! 2-core machine). Run: `cargo bench -p algesurf-benches --bench render`.
//!
//! The mesh is a level-8 icosphere (1 310 720 triangles, 655 362 vertices) with exact
//! normals, seen from the iso preset; the timed call is the whole `render` (checks, framing,
//! projection, binning, rasterisation, shading, resolve), not the PNG encoding, which is
//! timed separately.

use algesurf::inspect::render::{Mode, RenderMesh, RenderOptions, View, render};
use algesurf::mesh::shapes;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

fn sphere() -> RenderMesh {
    let s = shapes::icosphere(8);
    let mut m = RenderMesh::from(&s);
    m.normals = Some(s.positions().iter().map(|p| p.normalize()).collect());
    m
}

fn options(mode: Mode) -> RenderOptions {
    RenderOptions {
        mode,
        views: vec![View::Iso],
        size: (1024, 1024),
        ..RenderOptions::default()
    }
}

/// 1.3 M triangles to 1024×1024, 2×2 supersampling.
#[divan::bench(args = [Mode::Shaded, Mode::Isophotes, Mode::Patches], sample_count = 10)]
fn icosphere_1m_to_1024(bencher: Bencher, mode: Mode) {
    let mesh = sphere();
    assert!(mesh.triangles.len() >= 1_000_000);
    let o = options(mode);
    bencher.bench(|| render(black_box(&mesh), black_box(&o)).unwrap());
}

/// PNG encoding of the 1024×1024 shaded image.
#[divan::bench(sample_count = 10)]
fn encode_png_1024(bencher: Bencher) {
    let image = render(&sphere(), &options(Mode::Shaded)).unwrap();
    bencher.bench(|| black_box(&image).encode_png().unwrap());
}

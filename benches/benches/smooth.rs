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
use algesurf::hull::{Side, SimplicialHull};
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

/// Construction on a flat grid of 100 × 100 squares (20 k faces, every one zero-convex: a
/// planar patch, no tetrahedra, no fit), counted in faces: the cheapest faces there are. The
/// quadric fit once ran for them too (and went to the SVD, their neighbourhoods being
/// coplanar): 130.5 ms fastest here before, 33.0 ms after.
#[divan::bench(sample_count = 10, sample_size = 1)]
fn construction_flat_grid(bencher: Bencher) {
    let m = shapes::grid(100, 100);
    let n = vertex_normals(&m, NormalMethod::Loop).expect("Loop normals");
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
    bench_tessellate_8x8(bencher, &surface);
}

/// Times `surface.tessellate(8, 8)`, counting its points.
fn bench_tessellate_8x8(bencher: Bencher, surface: &ApatchSurface) {
    let points = surface
        .tessellate(8, 8)
        .expect("tessellation")
        .positions
        .len();
    bencher
        .counter(ItemsCount::new(points))
        .bench_local(|| black_box(surface).tessellate(8, 8).expect("tessellation"));
}

/// Corpus meshes for [`tessellation_corpus`], read from `$ALGESURF_CORPUS/NAME.obj` like the
/// CLI reads them (repair, Loop normals, default surface options).
const CORPUS: [&str; 3] = ["spot", "fandisk", "teapot"];

/// `$ALGESURF_CORPUS/NAME.obj`, repaired, with Loop normals; `None` (with a note naming the
/// bench) when `ALGESURF_CORPUS` is not set.
fn corpus_mesh(bench: &str, name: &str) -> Option<(TriMesh, Vec<DVec3>)> {
    let Some(dir) = std::env::var_os("ALGESURF_CORPUS") else {
        eprintln!("{bench}: set ALGESURF_CORPUS to the corpus directory");
        return None;
    };
    let path =
        algesurf_mesh::test_corpus::resolve(std::path::Path::new(&dir)).join(format!("{name}.obj"));
    let poly = algesurf::io::read(&path).expect("corpus mesh");
    let repaired =
        algesurf::mesh::repair(&poly, &algesurf::mesh::RepairOptions::default()).expect("repair");
    let m = TriMesh::from_polygon_mesh(&repaired.mesh).expect("triangle mesh");
    let n = vertex_normals(&m, NormalMethod::Loop).expect("Loop normals");
    Some((m, n))
}

/// [`corpus_mesh`] and its surface with default options.
fn corpus_surface(bench: &str, name: &str) -> Option<(TriMesh, ApatchSurface)> {
    let (m, n) = corpus_mesh(bench, name)?;
    let surface = ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface");
    Some((m, surface))
}

/// `tessellate(8, 8)` of a real mesh, the CLI's `smooth --resolution 8` stage: many more points
/// than fit in cache, split faces and edge patches in the proportions of scanned models. Skipped
/// (with a note) when `ALGESURF_CORPUS` is not set.
#[divan::bench(args = CORPUS, sample_count = 10, sample_size = 1)]
fn tessellation_corpus(bencher: Bencher, name: &str) {
    let Some((_, surface)) = corpus_surface("tessellation_corpus", name) else {
        return;
    };
    bench_tessellate_8x8(bencher, &surface);
}

/// The simplicial hull of the Stanford bunny (69 k faces) as `algesurf smooth` builds it: the
/// normals and options the surface's own hull was built with, face and edge tetrahedra, the
/// overlap check of every candidate pair (5.3 M), and the refinement rounds that resolve the
/// overlaps (4 on the bunny). Counted in input faces. Skipped without `ALGESURF_CORPUS`.
#[divan::bench(sample_count = 10, sample_size = 1)]
fn hull_bunny(bencher: Bencher) {
    let Some((m, surface)) = corpus_surface("hull_bunny", "stanford-bunny") else {
        return;
    };
    let hull = surface.hull();
    let normals = hull.normals()[..hull.input_vertex_count()].to_vec();
    let options = hull.options().clone();
    bencher
        .counter(ItemsCount::new(m.face_count()))
        .bench_local(|| {
            SimplicialHull::from_mesh(black_box(&m), black_box(&normals), &options).expect("hull")
        });
}

/// The overlap check alone (§3: every pair of the hull's tetrahedra whose boxes overlap,
/// decided exactly) on the bunny's final hull, counted in tetrahedra. Skipped without
/// `ALGESURF_CORPUS`.
#[divan::bench(sample_count = 10, sample_size = 1)]
fn hull_intersections_bunny(bencher: Bencher) {
    let Some((_, surface)) = corpus_surface("hull_intersections_bunny", "stanford-bunny") else {
        return;
    };
    let hull = surface.hull();
    bencher
        .counter(ItemsCount::new(hull.tetrahedra().len()))
        .bench_local(|| black_box(hull).intersections());
}

/// A surface, its `tessellate(8, 8)`, and a free parameter in the middle of the list with two
/// admissible values (its own and one further from its bound).
fn updatable(
    name: &str,
) -> (
    ApatchSurface,
    algesurf::apatch::Tessellation,
    usize,
    Side,
    [f64; 2],
) {
    let (m, n) = mesh(name);
    let surface = ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface");
    let tess = surface.tessellate(8, 8).expect("tessellation");
    let p = surface.free_parameters()[surface.free_parameters().len() / 2];
    let sign = if p.side == Side::Positive { 1.0 } else { -1.0 };
    (
        surface,
        tess,
        p.face,
        p.side,
        [p.value, p.value + sign * 0.5 * p.scale],
    )
}

/// §5.3 interactive update, re-tessellation part (target ≤ 50 µs): re-evaluate the rays of one
/// face's patches (the face and its same-side edge patches) at `tessellate(8, 8)` after a
/// parameter change, writing the points in place.
#[divan::bench(args = MESHES, sample_count = 50, sample_size = 20)]
fn retessellate_one_face(bencher: Bencher, name: &str) {
    let (mut surface, mut tess, face, side, values) = updatable(name);
    let up = surface
        .set_free_parameter(face, side, values[1])
        .expect("admissible");
    bencher.bench_local(|| {
        surface
            .retessellate_patches(black_box(&mut tess), &up)
            .expect("retessellation")
    });
}

/// §5.3 interactive update, whole: set one face's parameter (alternating between two
/// admissible values; includes rebuilding its edge cubics and re-checking their Step 6 bounds)
/// and re-tessellate its patches.
#[divan::bench(args = MESHES, sample_count = 50, sample_size = 20)]
fn set_and_retessellate_one_face(bencher: Bencher, name: &str) {
    let (mut surface, mut tess, face, side, values) = updatable(name);
    let mut k = 0;
    bencher.bench_local(|| {
        k += 1;
        let up = surface
            .set_free_parameter(face, side, values[k % 2])
            .expect("admissible");
        surface
            .retessellate_patches(black_box(&mut tess), &up)
            .expect("retessellation")
    });
}

/// `SplitFace::new` alone (the three-cubics-per-side construction of a nonconvex face, about
/// 40 % of the bunny's function stage) on nonconvex faces of a hull, in face order as
/// construction meets them: their corners, Loop normals, both apexes and the mid-edge
/// gradients the construction uses, with the plane through the face centroid as the quadric
/// and the plane's values at the apexes as the free parameters. Counted in split faces.
///
/// `torus24x12`: all 240 nonconvex faces of the torus. Its symmetry makes exact zeros that
/// vary from face to face, so 30 % of them record a new elimination plan (`constrained::plan`)
/// instead of replaying a kept one. `stanford-bunny` (needs `ALGESURF_CORPUS`): its first 4000
/// nonconvex faces, where 1.5 % do, as in a whole run.
#[divan::bench(args = ["torus24x12", "stanford-bunny"], sample_count = 30, sample_size = 3)]
fn split_face(bencher: Bencher, name: &str) {
    use algesurf::apatch::{Quadric, SplitFace, VertexData};
    use algesurf::hull::Convexity;
    // The hull a surface of the mesh is built in (normals conditioned as construction does).
    let surface = if name == "torus24x12" {
        let (m, n) = mesh(name);
        ApatchSurface::new(&m, &n, &SurfaceOptions::default()).expect("surface")
    } else {
        let Some((_, surface)) = corpus_surface("split_face", name) else {
            return;
        };
        surface
    };
    let hull = surface.hull();
    let inputs: Vec<_> = hull
        .faces()
        .iter()
        .filter(|f| f.convexity == Convexity::Nonconvex)
        .take(4000)
        .map(|f| {
            let v = f.vertices.map(|i| VertexData {
                position: hull.mesh().positions()[i as usize],
                gradient: hull.normals()[i as usize],
            });
            let g = v.map(|x| x.gradient);
            let mids = [0, 1, 2].map(|a| (g[(a + 1) % 3] + g[(a + 2) % 3]) * 0.5);
            let apexes = [f.u().expect("u"), f.v().expect("v")];
            let q = Quadric {
                a: glam::DMat3::ZERO,
                b: f.normal,
                c: -f.normal.dot(f.centroid),
            };
            let values = apexes.map(|a| q.value(a));
            (v, apexes, mids, q, values)
        })
        .collect();
    assert!(inputs.len() > 100, "{} split faces", inputs.len());
    bencher
        .counter(ItemsCount::new(inputs.len()))
        .bench_local(|| {
            for (v, apexes, mids, q, values) in &inputs {
                black_box(SplitFace::new(*v, apexes, *mids, q, values).expect("split face"));
            }
        });
}

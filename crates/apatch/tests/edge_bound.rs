//! Step 6 on the edge A-patches (§4.2, Lemma 2.3), certified: after construction every ray of
//! every edge tetrahedron — not only the rays of a grid or of the tessellation — already
//! satisfies Lemma 2.3 at the built apex values, measured here on a fine grid of rays.

use algesurf_apatch::{ApatchSurface, SurfaceOptions};
use algesurf_bb::sheet::lemma_2_3_b_min;
use algesurf_mesh::shapes::{bicone, icosphere, torus};
use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};

/// The largest `b_min^(1)` (lift `t²`) over a `k × k` grid of rays of every edge tetrahedron,
/// relative to the edge cubic's coefficient size: negative when every sampled ray's smallest
/// root is certified simple at the current coefficients.
fn worst_edge_ray(s: &ApatchSurface, k: usize) -> (f64, usize) {
    let mut worst = f64::NEG_INFINITY;
    let mut rays = 0;
    for slots in s.edges() {
        for (slot, cubic) in slots.iter().enumerate() {
            let Some(cubic) = cubic else { continue };
            let sign = if slot == 0 { 1.0 } else { -1.0 };
            let scale = cubic.polynomial().max_coeff_norm();
            for i in 1..k {
                for j in 0..=k {
                    let (x, y) = (i as f64 / k as f64, j as f64 / k as f64);
                    let c = cubic.shooting_polynomial(x, y).map(|v| sign * v);
                    // A ray starting on or beyond the surface has no root to certify here
                    // (on a two-sided edge it is the other side's ray).
                    if c[0] >= 0.0 {
                        continue;
                    }
                    rays += 1;
                    let b = lemma_2_3_b_min(c, 1.0).unwrap().b_min_1;
                    worst = worst.max(b / scale);
                }
            }
        }
    }
    (worst, rays)
}

#[test]
fn every_edge_ray_is_single_sheeted_at_the_built_apex_values() {
    let meshes: [(&str, TriMesh); 3] = [
        ("icosphere(1)", icosphere(1)),
        ("torus(16, 10)", torus(16, 10, 1.5, 0.5)),
        ("bicone(12, 0.1)", bicone(12, 0.1)),
    ];
    for (name, mesh) in meshes {
        let normals = vertex_normals(&mesh, NormalMethod::Loop).unwrap();
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
        let (worst, rays) = worst_edge_ray(&s, 40);
        println!("{name}: worst edge-ray b_min {worst:.3e} (relative) over {rays} rays");
        assert!(rays > 1000, "{name}: {rays} rays");
        assert!(worst < 0.0, "{name}: a ray needs {worst:e} more");
    }
}

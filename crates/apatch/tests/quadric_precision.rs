//! Quadric precision from *unit* normals (READING-NOTES; beyond the paper): with
//! [`GradientMagnitudes::QuadricConsistent`] the gradient magnitudes are recovered from local
//! quadric fits, so an ellipsoid and a hyperbolic paraboloid sampled with their unit normals
//! are reproduced, like the sphere. (With the default, `AsGiven`, exact gradients reproduce
//! them: `ellipsoid_is_recovered_from_its_gradients` in surface.rs.)

use algesurf_apatch::{ApatchSurface, GradientMagnitudes, SurfaceOptions};
use algesurf_mesh::TriMesh;
use algesurf_mesh::shapes::{grid, icosphere};
use glam::DVec3;

fn worst_ellipsoid_error(options: &SurfaceOptions) -> f64 {
    let sphere = icosphere(2);
    let axes = DVec3::new(1.5, 1.0, 0.7);
    let pos: Vec<DVec3> = sphere.positions().iter().map(|p| *p * axes).collect();
    let unit: Vec<DVec3> = pos
        .iter()
        .map(|p| (*p / (axes * axes)).normalize())
        .collect();
    let mesh = TriMesh::new(pos, sphere.triangles().to_vec()).unwrap();
    let s = ApatchSurface::new(&mesh, &unit, options).unwrap();
    let t = s.tessellate(6, 6).unwrap();
    assert!(t.missed_rays.is_empty() && t.multiple_roots.is_empty());
    t.positions
        .iter()
        .map(|p| ((*p / axes).length() - 1.0).abs())
        .fold(0.0, f64::max)
}

fn recovered() -> SurfaceOptions {
    SurfaceOptions {
        gradient_magnitudes: GradientMagnitudes::QuadricConsistent,
        ..SurfaceOptions::default()
    }
}

#[test]
fn ellipsoid_is_recovered_from_unit_normals_with_recovered_magnitudes() {
    let worst = worst_ellipsoid_error(&recovered());
    println!("recovered magnitudes: max |‖p/axes‖ − 1| = {worst:e}");
    assert!(worst <= 1e-10, "max |‖p/axes‖ − 1| = {worst:e}");
}

/// The finding that motivates the default: taking unit normals as gradients leaves the
/// ellipsoid (by far more than rounding).
#[test]
fn unit_normals_as_gradients_leave_the_ellipsoid() {
    let worst = worst_ellipsoid_error(&SurfaceOptions::default());
    println!("unit normals as gradients: max |‖p/axes‖ − 1| = {worst:e}");
    assert!(worst > 1e-4, "max |‖p/axes‖ − 1| = {worst:e}");
}

#[test]
fn hyperbolic_paraboloid_is_recovered_from_unit_normals() {
    // z = 0.3 (x² − y²) over [−1, 1]²: Q = 0.3 (x² − y²) − z.
    let g = grid(6, 6);
    let pos: Vec<DVec3> = g
        .positions()
        .iter()
        .map(|p| {
            let (x, y) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
            DVec3::new(x, y, 0.3 * (x * x - y * y))
        })
        .collect();
    let unit: Vec<DVec3> = pos
        .iter()
        .map(|p| DVec3::new(-0.6 * p.x, 0.6 * p.y, 1.0).normalize())
        .collect();
    let mesh = TriMesh::new(pos, g.triangles().to_vec()).unwrap();
    let s = ApatchSurface::new(&mesh, &unit, &recovered()).unwrap();
    let t = s.tessellate(6, 6).unwrap();
    assert!(t.missed_rays.is_empty() && t.multiple_roots.is_empty());
    let worst = t
        .positions
        .iter()
        .map(|p| (p.z - 0.3 * (p.x * p.x - p.y * p.y)).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-10, "max |z − 0.3(x² − y²)| = {worst:e}");
}

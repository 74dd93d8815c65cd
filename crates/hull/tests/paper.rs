//! The configurations of §6 (Figs. 6, 7, 9, 10) of Xu–Huang–Bajaj 2001.

mod common;

use algesurf_hull::{Convexity, HullOptions, SimplicialHull};
use common::{check_apex_properties, min_relative_measure};
use glam::DVec3;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// p1..p4 of §6 (p4 as given for the figure) and the triangles [p1 p2 p3] and [p1 p2 p4],
/// the latter written [p2 p1 p4] so that both are counter-clockwise seen from +z, the side all
/// the paper's normals point to.
fn build(p4: DVec3, n: [DVec3; 4]) -> SimplicialHull {
    let p = [v(-2., 0., 0.), v(2., 0., 0.), v(0., 4., -1.), p4];
    let n = n.map(|x| x.normalize());
    let hull = SimplicialHull::new(&p, &[[0, 1, 2], [1, 0, 3]], &n, &HullOptions::default()).unwrap();
    hull
}

fn classes(h: &SimplicialHull) -> (Convexity, Convexity, Convexity) {
    (h.faces()[0].convexity, h.faces()[1].convexity, h.edge_between(0, 1).unwrap().convexity)
}

#[test]
fn fig6_two_convex_faces() {
    let h = build(v(0., -4., -1.), [v(-1., 0., 1.), v(1., 0., 1.), v(0., 1., 1.), v(0., -1., 1.)]);
    use Convexity::*;
    assert_eq!(classes(&h), (PositiveConvex, PositiveConvex, PositiveConvex));
    check_apex_properties(&h);
    assert!(min_relative_measure(&h) > 1e-3);
    assert!(h.intersections().is_empty());
    assert!(h.refinements().is_empty());
}

#[test]
fn fig7_convex_and_nonconvex() {
    let h = build(v(0., -4., -1.), [v(-1., 0., 1.), v(1., 0., 1.), v(0., 1., 1.5), v(0., 1., 1.5)]);
    use Convexity::*;
    assert_eq!(classes(&h), (PositiveConvex, Nonconvex, PositiveConvex));
    check_apex_properties(&h);
    assert!(h.intersections().is_empty());
}

#[test]
fn fig9_two_nonconvex_faces() {
    let h = build(v(0., -4., -1.), [v(1., 0., 1.), v(1., 0., 1.), v(0., -1., 1.5), v(0., 1., 1.5)]);
    use Convexity::*;
    assert_eq!(classes(&h), (Nonconvex, Nonconvex, Nonconvex));
    check_apex_properties(&h);
    assert!(h.intersections().is_empty());
}

#[test]
fn fig10_nonconvex_and_zero() {
    let h = build(v(0., -4., 0.), [v(0., 0., 1.), v(0., 0., 1.), v(0., -1., 1.5), v(0., 0., 1.)]);
    use Convexity::*;
    assert_eq!(classes(&h), (Nonconvex, ZeroConvex, ZeroConvex));
    check_apex_properties(&h);
    assert!(h.intersections().is_empty());
}

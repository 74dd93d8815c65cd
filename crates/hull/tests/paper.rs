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
    SimplicialHull::new(&p, &[[0, 1, 2], [1, 0, 3]], &n, &HullOptions::default()).unwrap()
}

fn classes(h: &SimplicialHull) -> (Convexity, Convexity, Convexity) {
    (
        h.faces()[0].convexity,
        h.faces()[1].convexity,
        h.edge_between(0, 1).unwrap().convexity,
    )
}

#[test]
fn fig6_two_convex_faces() {
    let h = build(
        v(0., -4., -1.),
        [v(-1., 0., 1.), v(1., 0., 1.), v(0., 1., 1.), v(0., -1., 1.)],
    );
    use Convexity::*;
    assert_eq!(
        classes(&h),
        (PositiveConvex, PositiveConvex, PositiveConvex)
    );
    check_apex_properties(&h);
    assert!(min_relative_measure(&h) > 1e-3);
    assert!(h.intersections().is_empty());
    assert!(h.refinements().is_empty());
}

#[test]
fn fig7_convex_and_nonconvex() {
    let h = build(
        v(0., -4., -1.),
        [
            v(-1., 0., 1.),
            v(1., 0., 1.),
            v(0., 1., 1.5),
            v(0., 1., 1.5),
        ],
    );
    use Convexity::*;
    // The text: "[p1 p2 p3] is convex and face [p1 p2 p4] is nonconvex" -- with n4 = (0, 1, 1.5)
    // as printed, (p4 − p1)ᵀn4 = −5.5 < 0 < (p1 − p4)ᵀn1 = 3: edge [p1 p4] is nonconvex, so the
    // printed normal (no dropped sign) gives the stated classes. The common edge stays positive.
    assert_eq!(classes(&h), (PositiveConvex, Nonconvex, PositiveConvex));
    assert_eq!(h.edge_between(0, 3).unwrap().convexity, Nonconvex);
    let [f, g] = [&h.faces()[0], &h.faces()[1]];
    assert!(f.positive.is_some() && f.negative.is_none());
    assert!(g.positive.is_some() && g.negative.is_some());
    let e = h.edge_between(0, 1).unwrap();
    assert!(e.positive.is_some() && e.negative.is_none());
    check_apex_properties(&h);
    assert!(h.intersections().is_empty());
}

#[test]
fn fig9_two_nonconvex_faces() {
    let h = build(
        v(0., -4., -1.),
        [
            v(1., 0., 1.),
            v(1., 0., 1.),
            v(0., -1., 1.5),
            v(0., 1., 1.5),
        ],
    );
    use Convexity::*;
    assert_eq!(classes(&h), (Nonconvex, Nonconvex, Nonconvex));
    let e = h.edge_between(0, 1).unwrap();
    assert!(e.positive.is_some() && e.negative.is_some());
    assert_eq!(h.tetrahedra().len(), 6);
    assert!(min_relative_measure(&h) > 1e-3);
    check_apex_properties(&h);
    assert!(h.intersections().is_empty());
}

#[test]
fn fig10_nonconvex_and_zero() {
    let h = build(
        v(0., -4., 0.),
        [v(0., 0., 1.), v(0., 0., 1.), v(0., -1., 1.5), v(0., 0., 1.)],
    );
    use Convexity::*;
    assert_eq!(classes(&h), (Nonconvex, ZeroConvex, ZeroConvex));
    // The planar face carries no tetrahedra, the common (zero convex) edge no edge tetrahedra.
    let g = &h.faces()[1];
    assert!(g.positive.is_none() && g.negative.is_none() && g.parameters.is_none());
    assert_eq!(h.tetrahedra().len(), 2);
    check_apex_properties(&h);
    assert!(h.intersections().is_empty());
}

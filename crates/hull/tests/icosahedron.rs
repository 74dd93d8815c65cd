//! The icosahedron and icospheres with exact sphere normals: everything positive convex,
//! tetrahedra nondegenerate and interior-disjoint, the apex margins of §3.1 hold.

mod common;

use algesurf_hull::{Convexity, Element, HullError, HullOptions, Side, SimplicialHull};
use common::{
    brute_force_overlaps, check_apex_properties, icosahedron, icosphere, min_relative_measure,
};
use glam::DVec3;

/// Every face and every edge of the hull has convexity `c`.
fn assert_everything_is(hull: &SimplicialHull, c: Convexity) {
    assert!(
        hull.faces().iter().all(|f| f.convexity == c),
        "a face is not {c:?}"
    );
    assert!(
        hull.edges().iter().all(|e| e.convexity == c),
        "an edge is not {c:?}"
    );
}

#[test]
fn icosahedron_is_positive_convex_and_disjoint() {
    let (p, f) = icosahedron();
    let n = p.clone();
    let hull = SimplicialHull::new(&p, &f, &n, &HullOptions::default()).unwrap();
    assert_eq!(hull.faces().len(), 20);
    assert_eq!(hull.edges().len(), 30);
    assert!(hull.refinements().is_empty());
    assert!(
        hull.faces()
            .iter()
            .all(|f| f.convexity == Convexity::PositiveConvex)
    );
    assert!(
        hull.edges()
            .iter()
            .all(|e| e.convexity == Convexity::PositiveConvex && !e.is_boundary())
    );
    assert!(
        hull.faces()
            .iter()
            .all(|f| f.positive.is_some() && f.negative.is_none())
    );
    assert!(
        hull.edges()
            .iter()
            .all(|e| e.positive.is_some() && e.negative.is_none())
    );
    assert_eq!(hull.tetrahedra().len(), 50);
    assert!(hull.tetrahedra().iter().all(|t| t.side == Side::Positive));
    // Regular tetrahedra have 0.41; ours are well shaped.
    let m = min_relative_measure(&hull);
    assert!(m > 0.05, "min relative measure {m}");
    let margin = check_apex_properties(&hull);
    assert!(margin > 0.05, "apex margin {margin}");
    assert!(hull.intersections().is_empty());
    assert_eq!(brute_force_overlaps(&hull, 1e-9), 0);
    // Apexes lie outside the sphere, above their face, on the face's axis.
    for face in hull.faces() {
        let u = face.u().unwrap();
        assert!(u.length() > 1.0);
        assert!((u - face.centroid).cross(face.normal).length() < 1e-12);
        let t = face.parameters.unwrap();
        assert!(t.t_vertex.iter().all(|&x| x > 0.0));
        // By symmetry the nearest apex (the default) lies on the axis, where the nearest
        // feasible point is the paper's `c + t_max n_ijk` (to rounding).
        assert!((face.positive.unwrap().t - t.t_max).abs() <= 1e-12 * t.t_max);
    }
    assert_eq!(hull.face_map(), (0..20).collect::<Vec<u32>>().as_slice());
}

/// (4.15): μ and ν reproduce the apexes, and the face map / element ids are consistent.
#[test]
fn edge_tetrahedra_carry_4_15() {
    let (p, f) = icosahedron();
    let hull = SimplicialHull::new(&p, &f, &p, &HullOptions::default()).unwrap();
    let pos = hull.mesh().positions();
    for edge in hull.edges() {
        let et = edge.positive.unwrap();
        let [i, j] = edge.vertices;
        let (k, l) = (edge.k, edge.l.unwrap());
        let fk = &hull.faces()[edge.face_k as usize];
        let fl = &hull.faces()[edge.face_l.unwrap() as usize];
        // [p_i p_j p_k] runs i -> j, [p_i p_j p_l] runs j -> i.
        let runs = |t: [u32; 3], a: u32, b: u32| (0..3).any(|c| t[c] == a && t[(c + 1) % 3] == b);
        assert!(runs(fk.vertices, i, j) && runs(fl.vertices, j, i));
        assert!(fk.vertices.contains(&k) && fl.vertices.contains(&l));
        let (uk, ul) = (fk.u().unwrap(), fl.u().unwrap());
        assert_eq!(
            *et.tetrahedron.vertices(),
            [ul, pos[i as usize], pos[j as usize], uk]
        );
        let mu = et.mu;
        let back = mu[0] * pos[k as usize]
            + mu[1] * pos[i as usize]
            + mu[2] * pos[j as usize]
            + mu[3] * uk;
        assert!(back.distance(ul) < 1e-12);
        let nu = et.nu;
        let back = nu[0] * ul
            + nu[1] * pos[i as usize]
            + nu[2] * pos[j as usize]
            + nu[3] * pos[l as usize];
        assert!(back.distance(uk) < 1e-12);
        // u_ijl lies beyond the face [p_i p_j u_ijk] of the face tetrahedron: μ1 < 0.
        assert!(mu[0] < 0.0);
    }
    for t in hull.tetrahedra() {
        if let Element::Face(f) = t.element {
            assert_eq!(t.vertices[3], hull.faces()[f as usize].u().unwrap());
        }
    }
}

#[test]
fn icospheres_levels_1_to_3() {
    for level in 1..=3 {
        let (p, f) = icosphere(level);
        let hull = SimplicialHull::new(&p, &f, &p, &HullOptions::default()).unwrap();
        assert!(hull.refinements().is_empty(), "level {level}");
        assert_everything_is(&hull, Convexity::PositiveConvex);
        assert!(min_relative_measure(&hull) > 0.01);
        check_apex_properties(&hull);
        if level == 1 {
            assert_eq!(brute_force_overlaps(&hull, 1e-9), 0);
        }
    }
}

/// Turning the sphere inside out (reversed triangles, inward normals) makes everything
/// negative convex, with the mirror-image hull.
#[test]
fn inside_out_sphere_is_negative_convex() {
    let (p, f) = icosphere(1);
    let f: Vec<[u32; 3]> = f.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let n: Vec<DVec3> = p.iter().map(|&x| -x).collect();
    let hull = SimplicialHull::new(&p, &f, &n, &HullOptions::default()).unwrap();
    assert_everything_is(&hull, Convexity::NegativeConvex);
    assert!(
        hull.faces()
            .iter()
            .all(|f| f.positive.is_none() && f.v().unwrap().length() > 1.0)
    );
    assert!(hull.edges().iter().all(|e| e.negative.is_some()));
    check_apex_properties(&hull);
    assert!(hull.intersections().is_empty());
}

/// Scale invariance: scaling and translating the input scales the hull.
#[test]
fn hull_is_scale_and_translation_invariant() {
    let (p, f) = icosphere(1);
    let a = SimplicialHull::new(&p, &f, &p, &HullOptions::default()).unwrap();
    let q: Vec<DVec3> = p
        .iter()
        .map(|&x| 1e3 * x + DVec3::new(1e4, -2e4, 5e3))
        .collect();
    let b = SimplicialHull::new(&q, &f, &p, &HullOptions::default()).unwrap();
    for (fa, fb) in a.faces().iter().zip(b.faces()) {
        let (ua, ub) = (fa.u().unwrap(), fb.u().unwrap());
        let expect = 1e3 * ua + DVec3::new(1e4, -2e4, 5e3);
        assert!(expect.distance(ub) < 1e-9 * 1e3, "{expect} vs {ub}");
    }
    assert!(b.intersections().is_empty());
}

/// `tetrahedra()` lists every face's tetrahedra in face order (positive before negative),
/// then every edge's in edge order, on a mesh of several thousand elements (more than one of
/// the blocks it is written in) with faces and edges of every kind.
#[test]
fn tetrahedra_are_listed_in_element_order() {
    use algesurf_hull::HullTetrahedron;
    let (p, t, n) = common::height_field(48, common::wave(0.05, 3.0));
    let hull = SimplicialHull::new(&p, &t, &n, &HullOptions::default()).unwrap();
    let sides = |pos: Option<(Side, [DVec3; 4])>, neg: Option<(Side, [DVec3; 4])>| {
        [pos, neg].into_iter().flatten()
    };
    let mut want: Vec<HullTetrahedron> = Vec::new();
    for (f, face) in hull.faces().iter().enumerate() {
        let of = |t: &Option<algesurf_hull::FaceTetrahedron>| {
            t.as_ref().map(|t| (t.side, *t.tetrahedron.vertices()))
        };
        for (side, vertices) in sides(of(&face.positive), of(&face.negative)) {
            want.push(HullTetrahedron {
                element: Element::Face(f as u32),
                side,
                vertices,
            });
        }
    }
    for (e, edge) in hull.edges().iter().enumerate() {
        let of = |t: &Option<algesurf_hull::EdgeTetrahedron>| {
            t.as_ref().map(|t| (t.side, *t.tetrahedron.vertices()))
        };
        for (side, vertices) in sides(of(&edge.positive), of(&edge.negative)) {
            want.push(HullTetrahedron {
                element: Element::Edge(e as u32),
                side,
                vertices,
            });
        }
    }
    let negative = want.iter().filter(|t| t.side == Side::Negative).count();
    assert!(
        hull.faces().len() + hull.edges().len() > 2 * 4096 && negative > 100,
        "{} elements, {negative} negative tetrahedra",
        hull.faces().len() + hull.edges().len()
    );
    assert_eq!(hull.tetrahedra(), want);
}

/// Beyond `2^±252` (the largest coordinate) the hull's products of four lengths would leave
/// f64's range: such meshes are refused with `CoordinatesOutOfRange`, naming the coordinate
/// (the icosahedron at `2^260` failed with a zero face normal, "the normal of vertex 0 is not
/// on the positive side", and at `2^-270` with "degenerate (zero area)"). Within the range, at
/// both ends, the hull is the unit one's scaled, bit for bit.
#[test]
fn coordinates_beyond_the_range_are_refused_and_the_ends_of_the_range_build() {
    let (p, f) = icosphere(1);
    let unit = SimplicialHull::new(&p, &f, &p, &HullOptions::default()).unwrap();
    for k in [-252, 252] {
        let s = 2f64.powi(k);
        let q: Vec<DVec3> = p.iter().map(|&x| x * s).collect();
        let h = SimplicialHull::new(&q, &f, &p, &HullOptions::default()).unwrap();
        for (a, b) in unit.faces().iter().zip(h.faces()) {
            assert_eq!(a.u().unwrap() * s, b.u().unwrap(), "2^{k}");
            assert_eq!(a.v().map(|v| v * s), b.v(), "2^{k}");
        }
    }
    for k in [-260, -253, 253, 260] {
        let q: Vec<DVec3> = p.iter().map(|&x| x * 2f64.powi(k)).collect();
        let largest = q.iter().map(|x| x.abs().max_element()).fold(0.0, f64::max);
        assert_eq!(
            SimplicialHull::new(&q, &f, &p, &HullOptions::default()).err(),
            Some(HullError::CoordinatesOutOfRange { largest }),
            "2^{k}"
        );
    }
}

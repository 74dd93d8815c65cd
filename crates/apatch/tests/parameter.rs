//! Claims of the free-parameter API (§5.3 of Xu–Huang–Bajaj 2001): a change reaches exactly
//! the face and its same-side edge tetrahedra, keeps F C1 and single-sheeted, and the
//! incremental re-tessellation equals a full one bit for bit.

use algesurf_apatch::{
    ApatchSurface, FaceFunction, Retessellation, SurfaceOptions, Tessellation, UpdatedPatches,
};
use algesurf_hull::Side;
use algesurf_inspect::check::{ApatchView, CheckOptions, check};
use algesurf_mesh::shapes::{icosphere, torus};
use glam::DVec3;

fn sphere() -> ApatchSurface {
    let mesh = icosphere(1);
    let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
    ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap()
}

/// A torus: convex and split (nonconvex) faces, one- and two-sided edges.
fn torus_surface() -> ApatchSurface {
    torus_surface_with(&SurfaceOptions::default())
}

fn torus_surface_with(options: &SurfaceOptions) -> ApatchSurface {
    let mesh = torus(12, 8, 1.5, 0.6);
    let normals = algesurf_mesh::vertex_normals(&mesh, algesurf_mesh::NormalMethod::Loop).unwrap();
    ApatchSurface::new(&mesh, &normals, options).unwrap()
}

fn bits(p: &[DVec3]) -> Vec<[u64; 3]> {
    p.iter().map(|x| x.to_array().map(f64::to_bits)).collect()
}

fn assert_same(a: &Tessellation, b: &Tessellation) {
    assert_eq!(bits(&a.positions), bits(&b.positions), "positions");
    assert_eq!(bits(&a.normals), bits(&b.normals), "normals");
    assert_eq!(a.triangles, b.triangles, "triangles");
    assert_eq!(a.triangle_patch, b.triangle_patch, "patches");
    assert_eq!(a.missed_rays.len(), b.missed_rays.len(), "missed rays");
    assert_eq!(
        a.multiple_roots.len(),
        b.multiple_roots.len(),
        "multiple roots"
    );
    assert_eq!(a.layout, b.layout, "layout");
}

/// Coefficients of every piece, as bits, per face and per edge.
fn face_bits(s: &ApatchSurface, f: usize) -> Vec<u64> {
    match &s.faces()[f] {
        FaceFunction::Planar => Vec::new(),
        FaceFunction::Convex { cubic, .. } => {
            let mut v: Vec<u64> = cubic
                .polynomial()
                .coeffs()
                .iter()
                .map(|x| x.to_bits())
                .collect();
            v.extend(cubic.rational().map(f64::to_bits));
            v
        }
        FaceFunction::Split(split) => split
            .sides
            .iter()
            .flat_map(|side| side.polys.iter().flat_map(|p| p.coeffs().to_vec()))
            .map(f64::to_bits)
            .collect(),
    }
}

fn edge_bits(s: &ApatchSurface, e: usize) -> Vec<u64> {
    s.edges()[e]
        .iter()
        .flatten()
        .flat_map(|c| {
            let mut v: Vec<f64> = c.polynomial().coeffs().to_vec();
            v.extend(c.rational().iter().flatten());
            v
        })
        .map(f64::to_bits)
        .collect()
}

/// A value further from the bound than the current one (always admissible for the face; the
/// edges are re-checked by the setter).
fn raised(s: &ApatchSurface, face: usize, side: Side, factor: f64) -> f64 {
    let p = s.free_parameter(face, side).unwrap();
    p.bound + (p.value - p.bound) * factor
}

#[test]
fn an_update_changes_exactly_the_face_and_its_same_side_edge_tetrahedra() {
    for s0 in [sphere(), torus_surface()] {
        let params: Vec<_> = s0.free_parameters().to_vec();
        for p in params.iter().step_by(7) {
            let mut s = s0.clone();
            let value = raised(&s, p.face, p.side, 1.5);
            let up = s.set_free_parameter(p.face, p.side, value).unwrap();
            assert_eq!(up.faces, vec![p.face]);
            assert!(!up.edges.is_empty() && up.edges.len() <= 3);
            assert_eq!(s.free_parameter(p.face, p.side).unwrap().value, value);
            for f in 0..s.faces().len() {
                let same = face_bits(&s, f) == face_bits(&s0, f);
                assert_eq!(same, f != p.face, "face {f} after setting face {}", p.face);
            }
            let slot = if p.side == Side::Positive { 0 } else { 1 };
            for e in 0..s.edges().len() {
                if up.edges.contains(&e) {
                    // The other side's edge tetrahedron is untouched.
                    let other = |s: &ApatchSurface| {
                        s.edges()[e][1 - slot]
                            .as_ref()
                            .map(|c| c.polynomial().coeffs().to_vec())
                    };
                    assert_eq!(other(&s), other(&s0), "edge {e}, other side");
                    assert_ne!(
                        edge_bits(&s, e),
                        edge_bits(&s0, e),
                        "edge {e} did not change"
                    );
                } else {
                    assert_eq!(edge_bits(&s, e), edge_bits(&s0, e), "edge {e} changed");
                }
            }
        }
    }
}

#[test]
fn f_stays_c1_and_interpolating_after_updates() {
    let mut s = torus_surface();
    let params: Vec<_> = s.free_parameters().to_vec();
    for p in params.iter().step_by(5) {
        let value = raised(&s, p.face, p.side, 2.0);
        s.set_free_parameter(p.face, p.side, value).unwrap();
    }
    // The whole check battery (the construction tests' thresholds): C1 across every facet,
    // interpolation, normal agreement, simple roots, watertightness, parameter margins.
    let r = check(&ApatchView::new(&s), &CheckOptions::default()).unwrap();
    assert!(r.passed(), "\n{r}");
    let t = s.tessellate(6, 6).unwrap();
    assert!(t.missed_rays.is_empty() && t.multiple_roots.is_empty());
}

#[test]
fn incremental_retessellation_equals_a_full_tessellation_bit_for_bit() {
    for mut s in [sphere(), torus_surface()] {
        let mut t = s.tessellate(5, 3).unwrap();
        let params: Vec<_> = s.free_parameters().to_vec();
        let mut all = UpdatedPatches::default();
        for (k, p) in params.iter().step_by(3).enumerate() {
            let factor = if k % 2 == 0 { 1.7 } else { 0.6 };
            let value = raised(&s, p.face, p.side, factor);
            // Lowering may be rejected by an edge bound; either way the surface stays valid.
            if let Ok(up) = s.set_free_parameter(p.face, p.side, value) {
                let how = s.retessellate_patches(&mut t, &up).unwrap();
                assert!(matches!(how, Retessellation::Incremental { rays } if rays > 0));
                all.merge(&up);
            }
        }
        assert!(!all.faces.is_empty());
        assert_same(&t, &s.tessellate(5, 3).unwrap());
    }
}

#[test]
fn a_value_on_the_wrong_side_of_the_bound_is_rejected_naming_the_face() {
    let mut s = torus_surface();
    let before = s.tessellate(3, 3).unwrap();
    let p = s.free_parameters()[4];
    let err = s.set_free_parameter(p.face, p.side, p.bound).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains(&format!("face {}", p.face)), "{msg}");
    assert!(msg.contains("not admissible"), "{msg}");
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let msg = s
            .set_free_parameter(p.face, p.side, bad)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("must be a finite number"), "{bad}: {msg}");
    }
    // Nothing changed.
    assert_eq!(s.free_parameter(p.face, p.side).unwrap().value, p.value);
    assert_same(&before, &s.tessellate(3, 3).unwrap());
    // A face side without a tetrahedron has no parameter.
    let convex = s
        .faces()
        .iter()
        .position(|f| matches!(f, FaceFunction::Convex { .. }))
        .unwrap();
    let other = match &s.faces()[convex] {
        FaceFunction::Convex { side, .. } => match side {
            Side::Positive => Side::Negative,
            Side::Negative => Side::Positive,
        },
        _ => unreachable!(),
    };
    assert!(s.set_free_parameter(convex, other, 1.0).is_err());
}

#[test]
fn rejected_edge_bound_leaves_the_surface_unchanged() {
    // Lower every parameter to just beyond its face bound: on some face the edge tetrahedra
    // then need a raise (Step 6, edge bound), and that set must be refused atomically. The
    // face bounds must be tight for "just beyond" to come near the edges' needs.
    let s0 = torus_surface_with(&SurfaceOptions {
        tight_face_bounds: true,
        ..SurfaceOptions::default()
    });
    let mut rejected = 0;
    for p in s0.free_parameters() {
        let mut s = s0.clone();
        let value = raised(&s, p.face, p.side, 1e-6);
        match s.set_free_parameter(p.face, p.side, value) {
            Ok(_) => {}
            Err(e) => {
                assert!(e.to_string().contains("edge"), "{e}");
                for f in 0..s.faces().len() {
                    assert_eq!(face_bits(&s, f), face_bits(&s0, f));
                }
                for e in 0..s.edges().len() {
                    assert_eq!(edge_bits(&s, e), edge_bits(&s0, e));
                }
                rejected += 1;
            }
        }
    }
    println!(
        "{rejected} of {} near-bound values rejected by an edge bound",
        s0.free_parameters().len()
    );
    assert!(
        rejected > 0,
        "no near-bound value met an edge bound: the check went unexercised"
    );
}

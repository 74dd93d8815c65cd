use super::*;
use crate::geometry::triangle_area;
use crate::shapes::{self, CapTriangulation};
use crate::test_rng::Lcg;
use std::f64::consts::TAU;

/// Narrow strips split between any two flat regions (the command's second remeshing).
const SPLIT_EVERYWHERE: FlatRemeshOptions = FlatRemeshOptions {
    tolerance: DEFAULT_FLAT_TOLERANCE,
    skinny_angle_degrees: DEFAULT_SKINNY_ANGLE_DEGREES,
    min_angle_degrees: DEFAULT_REMESH_MIN_ANGLE_DEGREES,
    split_narrow_strips: Some(0.0),
};

/// The faces' smallest angles, in degrees.
fn angles_of(mesh: &TriMesh) -> Vec<f64> {
    let p = mesh.positions();
    mesh.triangles()
        .iter()
        .map(|t| {
            triangle_min_angle(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]).to_degrees()
        })
        .collect()
}

/// Faces with an angle below the default skinny limit.
fn skinny_count(mesh: &TriMesh) -> usize {
    angles_of(mesh)
        .into_iter()
        .filter(|&a| a < DEFAULT_SKINNY_ANGLE_DEGREES)
        .count()
}

fn area(mesh: &TriMesh) -> f64 {
    let p = mesh.positions();
    mesh.triangles()
        .iter()
        .map(|t| triangle_area(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]))
        .sum()
}

/// The directed boundary edges of `mesh` (each edge's direction as its one face has it).
fn directed_boundary(mesh: &TriMesh) -> Vec<[u32; 2]> {
    let directed: Vec<[u32; 2]> = mesh
        .triangles()
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .collect();
    let set: std::collections::HashSet<[u32; 2]> = directed.iter().copied().collect();
    let mut out: Vec<[u32; 2]> = directed
        .into_iter()
        .filter(|&[a, b]| !set.contains(&[b, a]))
        .collect();
    out.sort_unstable();
    out
}

/// A regular `n`-gon of radius 1 in the plane `z = 0`, triangulated as a fan from corner 0.
fn fan_disc(n: u32) -> TriMesh {
    let positions = (0..n)
        .map(|i| {
            let a = TAU * i as f64 / n as f64;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    TriMesh::new(positions, (1..n - 1).map(|i| [0, i, i + 1]).collect()).unwrap()
}

/// An annulus (radii 1 and 0.5, `n` segments each) triangulated as a strip, in the plane
/// through `o` spanned by `u` and `v`: a flat face with a hole.
fn annulus(n: u32, o: DVec3, u: DVec3, v: DVec3) -> TriMesh {
    let mut positions = Vec::new();
    for r in [1.0, 0.5] {
        for i in 0..n {
            let a = TAU * i as f64 / n as f64;
            positions.push(o + u * (r * a.cos()) + v * (r * a.sin()));
        }
    }
    let mut tris = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        tris.push([i, j, n + j]);
        tris.push([i, n + j, n + i]);
    }
    TriMesh::new(positions, tris).unwrap()
}

#[test]
fn fan_cap_of_a_disc_is_remeshed_without_thin_faces() {
    let fan = fan_disc(48);
    assert_eq!(skinny_count(&fan), 46);
    let out = remesh_flat_regions(&fan, &FlatRemeshOptions::default()).unwrap();
    assert_eq!(out.report.remeshed.len(), 1);
    let r = &out.report.remeshed[0];
    assert_eq!(r.faces, (0..46).collect::<Vec<u32>>());
    assert_eq!(r.skinny_after, 0);
    assert_eq!(skinny_count(&out.mesh), 0);
    assert!(
        (r.min_angle_before - 3.75).abs() < 1e-9,
        "{}",
        r.min_angle_before
    );
    assert!(r.min_angle_after > 20.0, "{}", r.min_angle_after);
    // Every corner kept, by id and position; new vertices inside the disc and on its plane.
    assert_eq!(&out.mesh.positions()[..48], fan.positions());
    assert_eq!(
        out.mesh.vertex_count(),
        48 + r.added_vertices as usize,
        "vertices appended"
    );
    for p in &out.mesh.positions()[48..] {
        assert_eq!(p.z.abs(), 0.0);
        assert!(p.length() < 1.0);
    }
    // The same boundary, edge for edge and direction, and the same area (the disc is open).
    assert_eq!(directed_boundary(&out.mesh), directed_boundary(&fan));
    assert!((area(&out.mesh) - area(&fan)).abs() <= 1e-12 * area(&fan));
    // Every face faces the way the fan did.
    for f in 0..out.mesh.face_count() {
        assert!(out.mesh.face_normal(f).z > 0.0);
    }
    assert_eq!(out.report.face_map.len(), out.mesh.face_count());
}

#[test]
fn puck_with_fan_caps_stays_a_closed_manifold_of_the_same_volume() {
    for n in [12, 48, 96, 256] {
        let puck = shapes::puck(n, 0.3, CapTriangulation::Fan);
        let out = remesh_flat_regions(&puck, &FlatRemeshOptions::default()).unwrap();
        let remeshed = &out.report.remeshed;
        // 12 segments: fans of 15° needles, not skinny; each of the side's rectangles
        // (0.52 × 0.3) is a flat region of two faces, not skinny either.
        if n == 12 {
            assert!(remeshed.is_empty(), "{remeshed:?}");
            assert!(out.report.skipped.is_empty());
            assert_eq!(out.mesh.triangles(), puck.triangles());
            continue;
        }
        assert_eq!(remeshed.len(), 2, "n = {n}: both caps");
        // From 96 segments on the side's rectangles are skinny too (0.065 × 0.3: 12.3°...
        // 0.0245 × 0.3: 4.7° at 256), and no triangulation of a rectangle does better.
        assert!(
            out.report
                .skipped
                .iter()
                .all(|s| s.reason == SkipReason::NoImprovement && s.faces.len() == 2),
            "{:?}",
            out.report.skipped
        );
        // The caps' skinny faces are gone; the side's stay.
        let before: usize = remeshed.iter().map(|r| r.skinny_before as usize).sum();
        assert_eq!(before, 2 * (n as usize - 2));
        assert_eq!(skinny_count(&out.mesh), skinny_count(&puck) - before);
        assert!(remeshed.iter().all(|r| r.skinny_after == 0), "{remeshed:?}");
        let topo = out.mesh.topology();
        assert!((0..topo.edge_count() as u32).all(|e| topo.edge_face_count(e) == 2));
        assert_eq!(out.mesh.euler_characteristic(), 2);
        let (v0, v1) = (puck.signed_volume(), out.mesh.signed_volume());
        assert!((v1 - v0).abs() <= 1e-12 * v0, "n = {n}: volume {v0} → {v1}");
        assert!(
            out.report
                .face_map
                .iter()
                .all(|&f| f < puck.face_count() as u32)
        );
    }
}

#[test]
fn regions_without_thin_faces_are_left_alone() {
    // An icosphere has no two coplanar faces; a grid is one flat region of right triangles
    // (45°); an annulus strip of 24 segments has angles of 14° and more.
    for mesh in [
        shapes::icosphere(2),
        shapes::grid(6, 4),
        annulus(24, DVec3::ZERO, DVec3::X, DVec3::Y),
    ] {
        let out = remesh_flat_regions(&mesh, &FlatRemeshOptions::default()).unwrap();
        assert!(!out.report.changed());
        assert!(out.report.skipped.is_empty());
        assert_eq!(out.mesh.positions(), mesh.positions());
        assert_eq!(out.mesh.triangles(), mesh.triangles());
    }
    assert!(flat_regions(&shapes::icosphere(2), 1e-6).is_empty());
    let grid = flat_regions(&shapes::grid(6, 4), 1e-6);
    assert_eq!(grid.len(), 1);
    assert_eq!(grid[0].faces.len(), 48);
}

#[test]
fn a_hole_in_a_flat_region_stays_a_hole() {
    // 256 segments: the strip's faces are skinny (2.8°), the ring is wide (0.5 against
    // edges of 0.0245), so refinement fills it without touching the hole. Tilted and moved
    // off the origin, so the frame's plane is not a coordinate plane.
    let (u, v) = (
        DVec3::new(1.0, 2.0, 0.5).normalize(),
        DVec3::new(-2.0, 1.0, 0.0).normalize(),
    );
    let v = (v - u * u.dot(v)).normalize();
    let ring = annulus(256, DVec3::new(10.0, -3.0, 7.0), u, v);
    assert_eq!(skinny_count(&ring), 512);
    let out = remesh_flat_regions(&ring, &FlatRemeshOptions::default()).unwrap();
    assert_eq!(out.report.remeshed.len(), 1);
    assert_eq!(skinny_count(&out.mesh), 0);
    assert_eq!(directed_boundary(&out.mesh), directed_boundary(&ring));
    let (a0, a1) = (area(&ring), area(&out.mesh));
    assert!((a1 - a0).abs() <= 1e-11 * a0, "{a0} → {a1}");
    // No vertex inside the hole, none off the plane.
    let n = u.cross(v);
    let o = DVec3::new(10.0, -3.0, 7.0);
    for p in &out.mesh.positions()[512..] {
        let d = *p - o;
        assert!(d.dot(n).abs() < 1e-12);
        let r = (d - n * d.dot(n)).length();
        assert!(r > 0.5 && r < 1.0, "{r}");
    }
    assert_eq!(out.mesh.components().len(), 1);
    assert_eq!(out.mesh.euler_characteristic(), 0, "an annulus");
}

#[test]
fn a_strip_narrower_than_its_edges_is_skipped_with_its_reason() {
    // Two triangles of a 2 × 0.02 rectangle: no point fits inside without coming closer to a
    // long edge than half its length, so the new triangulation is the old one. Its long
    // edges are the mesh's boundary, which is never split.
    let strip = TriMesh::new(
        vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 0.02, 0.0),
            DVec3::new(0.0, 0.02, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let out = remesh_flat_regions(&strip, &FlatRemeshOptions::default()).unwrap();
    assert!(!out.report.changed());
    assert_eq!(out.report.split_edges, 0);
    assert_eq!(
        out.report.skipped,
        vec![SkippedRegion {
            faces: vec![0, 1],
            reason: SkipReason::NoImprovement
        }]
    );
    assert_eq!(out.mesh.triangles(), strip.triangles());
}

#[test]
fn regions_do_not_depend_on_the_order_of_the_faces() {
    let puck = shapes::puck(64, 0.3, CapTriangulation::Fan);
    let base = remesh_flat_regions(&puck, &FlatRemeshOptions::default()).unwrap();
    let key = |m: &TriMesh, range: std::ops::Range<usize>| {
        let mut t: Vec<[u32; 3]> = m.triangles()[range]
            .iter()
            .map(|t| {
                let mut t = *t;
                t.sort_unstable();
                t
            })
            .collect();
        t.sort_unstable();
        t
    };
    let kept = puck.face_count() - 2 * 62;
    let mut rng = Lcg(7);
    for _ in 0..3 {
        let mut order: Vec<usize> = (0..puck.face_count()).collect();
        for i in (1..order.len()).rev() {
            order.swap(i, (rng.next() * (i + 1) as f64) as usize);
        }
        // Shuffled faces, each with its corners rotated.
        let tris: Vec<[u32; 3]> = order
            .iter()
            .enumerate()
            .map(|(k, &f)| {
                let [a, b, c] = puck.triangles()[f];
                [[a, b, c], [b, c, a], [c, a, b]][k % 3]
            })
            .collect();
        let shuffled = TriMesh::new(puck.positions().to_vec(), tris).unwrap();
        let out = remesh_flat_regions(&shuffled, &FlatRemeshOptions::default()).unwrap();
        assert_eq!(out.mesh.positions(), base.mesh.positions());
        let all = 0..out.mesh.face_count();
        assert_eq!(key(&out.mesh, all.clone()), key(&base.mesh, all));
        assert_eq!(
            key(&out.mesh, 0..kept),
            key(&base.mesh, 0..kept),
            "the faces kept come first"
        );
    }
}

#[test]
fn float32_rounded_caps_are_flat_and_remeshed() {
    let puck = shapes::puck(96, 0.3, CapTriangulation::Fan);
    let mut positions = puck.positions().to_vec();
    // Tilted and placed at 100, then written as float32: the caps' corners leave their
    // planes by float32's rounding.
    let turn = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    for p in &mut positions {
        *p = (turn * *p + DVec3::splat(100.0)).as_vec3().as_dvec3();
    }
    let rounded = TriMesh::new(positions, puck.triangles().to_vec()).unwrap();
    let regions = flat_regions(&rounded, 1e-6 * coordinate_scale(&rounded));
    // The two caps and the side's 96 rectangles.
    assert_eq!(regions.len(), 98);
    let caps: Vec<&FlatRegion> = regions.iter().filter(|r| r.faces.len() == 94).collect();
    assert_eq!(caps.len(), 2);
    assert!(caps.iter().all(|r| r.deviation > 0.0 && r.deviation < 2e-5));
    let out = remesh_flat_regions(&rounded, &FlatRemeshOptions::default()).unwrap();
    assert_eq!(out.report.remeshed.len(), 2);
    assert_eq!(out.mesh.euler_characteristic(), 2);
}

#[test]
fn nearly_flat_curved_faces_are_not_a_region() {
    // A torus's faces bend by 15° or 30° across each edge between its planar quads: its
    // flat regions are those quads. A grid bent into an arc of 0.5° per column chains
    // pairs within a loose tolerance, but the chain is not flat as a whole.
    let torus = flat_regions(&shapes::torus(24, 12, 1.0, 0.3), 1e-6 * 2.6);
    assert_eq!(torus.len(), 24 * 12);
    assert!(torus.iter().all(|r| r.faces.len() == 2));
    assert!(flat_regions(&shapes::icosphere(3), 1e-6).is_empty());
    let mut bent = shapes::grid(40, 2);
    for p in bent.positions_mut() {
        let a = p.x * 0.5f64.to_radians();
        *p = DVec3::new(50.0 * a.sin(), p.y, 50.0 * (1.0 - a.cos()));
    }
    let loose = 0.01;
    let joined = flat_regions(&bent, loose);
    assert!(
        joined.iter().all(|r| r.faces.len() < bent.face_count()),
        "the 40 columns bend by 20°: not one flat region"
    );
}

#[test]
fn new_vertices_get_the_region_normal_as_file_normal() {
    let mut puck = shapes::puck(48, 0.3, CapTriangulation::Fan);
    let normals: Vec<DVec3> = puck.positions().iter().map(|p| p.normalize()).collect();
    puck.set_file_normals(Some(normals.clone())).unwrap();
    let out = remesh_flat_regions(&puck, &FlatRemeshOptions::default()).unwrap();
    let n = out.mesh.file_normals().unwrap();
    assert_eq!(&n[..96], &normals[..]);
    for (p, n) in out.mesh.positions()[96..].iter().zip(&n[96..]) {
        let expected = if p.z > 0.1 { DVec3::Z } else { -DVec3::Z };
        assert!(n.distance(expected) < 1e-15, "{p} {n}");
    }
}

#[test]
fn remeshing_is_deterministic() {
    let puck = shapes::puck(128, 0.3, CapTriangulation::Strip);
    let a = remesh_flat_regions(&puck, &FlatRemeshOptions::default()).unwrap();
    let b = remesh_flat_regions(&puck, &FlatRemeshOptions::default()).unwrap();
    assert!(a.report.changed());
    assert_eq!(a.mesh.positions(), b.mesh.positions());
    assert_eq!(a.mesh.triangles(), b.mesh.triangles());
    assert_eq!(a.report, b.report);
}

#[test]
fn random_convex_fans_keep_boundary_and_area() {
    // Random convex polygons (sorted random angles, radii 0.8..1.2 kept convex by taking the
    // hull's order), random planes, fan-triangulated: the remesh keeps the boundary and the
    // area, and never makes more thin faces.
    let mut rng = Lcg(2024);
    for trial in 0..60 {
        let n = 8 + (rng.next() * 120.0) as u32;
        let mut angles: Vec<f64> = (0..n).map(|_| rng.next() * TAU).collect();
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        let o = rng.point() * 5.0;
        let u = rng.vec().normalize();
        let v = u.any_orthonormal_vector().lerp(rng.vec(), 0.3);
        let v = (v - u * u.dot(v)).normalize();
        let positions: Vec<DVec3> = angles
            .iter()
            .map(|a| o + u * a.cos() + v * a.sin())
            .collect();
        let m = positions.len() as u32;
        let fan = TriMesh::new(positions, (1..m - 1).map(|i| [0, i, i + 1]).collect()).unwrap();
        let out = remesh_flat_regions(&fan, &FlatRemeshOptions::default()).unwrap();
        assert_eq!(
            directed_boundary(&out.mesh),
            directed_boundary(&fan),
            "trial {trial}"
        );
        let (a0, a1) = (area(&fan), area(&out.mesh));
        assert!((a1 - a0).abs() <= 1e-11 * a0, "trial {trial}: {a0} → {a1}");
        assert!(
            skinny_count(&out.mesh) <= skinny_count(&fan),
            "trial {trial}"
        );
        if out.report.changed() {
            assert!(
                skinny_count(&out.mesh) < skinny_count(&fan),
                "trial {trial}"
            );
        }
    }
}

#[test]
fn options_out_of_range_are_refused() {
    let fan = fan_disc(8);
    for (options, name) in [
        (
            FlatRemeshOptions {
                tolerance: f64::NAN,
                ..FlatRemeshOptions::default()
            },
            "tolerance",
        ),
        (
            FlatRemeshOptions {
                skinny_angle_degrees: -1.0,
                ..FlatRemeshOptions::default()
            },
            "skinny_angle_degrees",
        ),
        (
            FlatRemeshOptions {
                min_angle_degrees: 40.0,
                ..FlatRemeshOptions::default()
            },
            "min_angle_degrees",
        ),
        (
            FlatRemeshOptions {
                min_angle_degrees: 0.0,
                ..FlatRemeshOptions::default()
            },
            "min_angle_degrees",
        ),
        (
            FlatRemeshOptions {
                split_narrow_strips: Some(f64::NAN),
                ..FlatRemeshOptions::default()
            },
            "split_narrow_strips",
        ),
        (
            FlatRemeshOptions {
                split_narrow_strips: Some(181.0),
                ..FlatRemeshOptions::default()
            },
            "split_narrow_strips",
        ),
    ] {
        let e = remesh_flat_regions(&fan, &options).unwrap_err();
        assert!(
            matches!(&e, MeshError::InvalidOption(s) if s.contains(name)),
            "{e}"
        );
    }
}

#[test]
fn a_thin_plate_is_split_at_its_rims_and_stays_a_closed_manifold() {
    // A 2 × 2 × 0.02 plate: its thin sides are strips of two 1 × 0.02 rectangles (1.1°
    // faces), between creases of 90°. Their long edges are split into 50 pieces (the strip's
    // width), the short ones not; the large sides take the new points on their rims.
    let plate = shapes::plate(2, 2.0, 0.02);
    // Kept by default: the strips are skipped, as no triangulation of their corners helps.
    let kept = remesh_flat_regions(&plate, &FlatRemeshOptions::default()).unwrap();
    assert_eq!(kept.report.split_edges, 0);
    assert_eq!(kept.report.skipped.len(), 4, "{:?}", kept.report);
    let out = remesh_flat_regions(&plate, &SPLIT_EVERYWHERE).unwrap();
    let report = &out.report;
    assert_eq!(report.split_edges, 16, "{report:?}");
    assert_eq!(report.remeshed.len(), 6, "every side");
    assert!(report.skipped.is_empty(), "{report:?}");
    assert_eq!(skinny_count(&out.mesh), 0);
    assert!(angles_of(&out.mesh).into_iter().all(|a| a >= 24.9));
    // Each thin side's long edges carry 49 points each, and each large side's rim has them
    // all: counted once per region.
    let on_rims: u32 = report.remeshed.iter().map(|r| r.boundary_vertices).sum();
    assert_eq!(on_rims, 2 * 16 * 49);
    // Closed, of the same genus, volume and vertices (kept first, by id and position).
    let topo = out.mesh.topology();
    assert!((0..topo.edge_count() as u32).all(|e| topo.edge_face_count(e) == 2));
    assert_eq!(out.mesh.euler_characteristic(), 2);
    let (v0, v1) = (plate.signed_volume(), out.mesh.signed_volume());
    assert!((v1 - v0).abs() <= 1e-12 * v0, "{v0} → {v1}");
    assert_eq!(&out.mesh.positions()[..18], plate.positions());
    // No vertex on another's edge (a T-junction would be one): the split points are the
    // same vertices on both sides of their crease.
    let p = out.mesh.positions();
    for e in 0..topo.edge_count() as u32 {
        let [a, b] = topo.edge(e);
        let (pa, pb) = (p[a as usize], p[b as usize]);
        let d = pb - pa;
        for (v, &x) in p.iter().enumerate() {
            let t = (x - pa).dot(d) / d.length_squared();
            let off = (pa + d * t).distance(x);
            assert!(
                v as u32 == a || v as u32 == b || t <= 0.0 || t >= 1.0 || off > 1e-9,
                "vertex {v} on edge {a}–{b}"
            );
        }
    }
    // A thicker plate (0.5: sides of 1 × 0.5, 26.6°) has no skinny face and stays as it is.
    let thick = shapes::plate(2, 2.0, 0.5);
    let out = remesh_flat_regions(&thick, &SPLIT_EVERYWHERE).unwrap();
    assert!(!out.report.changed() && out.report.split_edges == 0);
}

#[test]
fn a_narrow_strip_on_a_smooth_surface_is_not_split() {
    // A strip of 2 × 0.02 between two flat quads (two faces each) tilted 10° against it:
    // asked to split at creases of 30° and more, nothing qualifies, and the strip is kept,
    // with its reason.
    let tilt = 10f64.to_radians();
    let (c, s) = (tilt.cos(), tilt.sin());
    let mesh = TriMesh::new(
        vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 0.02, 0.0),
            DVec3::new(0.0, 0.02, 0.0),
            DVec3::new(2.0, -c, s),
            DVec3::new(0.0, -c, s),
            DVec3::new(0.0, 0.02 + c, s),
            DVec3::new(2.0, 0.02 + c, s),
        ],
        vec![
            [0, 1, 2],
            [0, 2, 3],
            [1, 0, 5],
            [1, 5, 4],
            [3, 2, 7],
            [3, 7, 6],
        ],
    )
    .unwrap();
    assert_eq!(
        flat_regions(&mesh, 1e-9).len(),
        3,
        "the strip and both quads"
    );
    let out = remesh_flat_regions(&mesh, &FlatRemeshOptions::default()).unwrap();
    assert_eq!(out.report.split_edges, 0);
    assert!(!out.report.changed());
    assert_eq!(out.report.skipped[0].reason, SkipReason::NoImprovement);
    assert_eq!(out.mesh.triangles(), mesh.triangles());
}

#[test]
fn a_thin_walled_tube_is_split_along_its_walls_only_when_every_edge_may_be() {
    // A tube of radii 1 and 0.95, 2 long, 48 segments (`shapes::washer`): its walls are rows
    // of 0.13 × 2 quads (3.7° faces), each a flat region next to the others at 7.5°, and its
    // ends are rings of well-shaped faces. Split at creases of 30° and more nothing
    // qualifies (the rims' edges, the creases, are the quads' short ones); everywhere, the
    // quads' long edges are split into pieces no longer than the quads are wide, and the
    // walls come out without skinny faces.
    let tube = shapes::washer(48, 1.0, 0.95, 2.0);
    let creases = FlatRemeshOptions {
        split_narrow_strips: Some(30.0),
        ..FlatRemeshOptions::default()
    };
    let out = remesh_flat_regions(&tube, &creases).unwrap();
    assert_eq!(out.report.split_edges, 0);
    assert!(!out.report.changed());
    let out = remesh_flat_regions(&tube, &SPLIT_EVERYWHERE).unwrap();
    assert_eq!(
        out.report.split_edges,
        2 * 48,
        "every wall edge between two quads"
    );
    assert_eq!(skinny_count(&out.mesh), 0);
    let topo = out.mesh.topology();
    assert!((0..topo.edge_count() as u32).all(|e| topo.edge_face_count(e) == 2));
    assert_eq!(out.mesh.euler_characteristic(), 0, "a torus");
    let (v0, v1) = (tube.signed_volume(), out.mesh.signed_volume());
    assert!((v1 - v0).abs() <= 1e-12 * v0, "{v0} → {v1}");
}

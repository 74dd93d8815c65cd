//! Shared helpers of the integration tests.
#![allow(dead_code)]

use algesurf_hull::{Side, SimplicialHull, mid_edge_coefficient};
use glam::DVec3;

/// The regular icosahedron on the unit sphere (the mesh crate's, as positions and triangles).
pub fn icosahedron() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    icosphere(0)
}

/// Midpoint subdivision of the icosahedron projected to the sphere (the mesh crate's).
pub fn icosphere(level: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let m = algesurf_mesh::shapes::icosphere(level);
    (m.positions().to_vec(), m.triangles().to_vec())
}

/// Checks the properties t_l, t_lm of §3.1 exist for on every face tetrahedron: the Step 2
/// coefficients `(w − p_l)ᵀn_l` are > 0 (u) / < 0 (v) and the Step 4 mid-edge coefficients are
/// ≥ 0 (u) / ≤ 0 (v), up to rounding relative to the face size. Returns the smallest margin.
pub fn check_apex_properties(hull: &SimplicialHull) -> f64 {
    let p = hull.mesh().positions();
    let n = hull.normals();
    let mut least = f64::INFINITY;
    for (f, face) in hull.faces().iter().enumerate() {
        for side in [Side::Positive, Side::Negative] {
            let Some(t) = face.tetrahedron(side) else {
                continue;
            };
            let s = if side == Side::Positive { 1.0 } else { -1.0 };
            let w = t.apex;
            let scale = (0..3)
                .map(|c| {
                    p[face.vertices[c] as usize].distance(p[face.vertices[(c + 1) % 3] as usize])
                })
                .fold(0.0, f64::max);
            for &v in &face.vertices {
                let x = s * (w - p[v as usize]).dot(n[v as usize]);
                assert!(x > 0.0, "face {f} {side:?}: (w - p_{v})·n_{v} = {x}");
                least = least.min(x / scale);
            }
            for c in 0..3 {
                let (a, b) = (
                    face.vertices[c] as usize,
                    face.vertices[(c + 1) % 3] as usize,
                );
                let x = s * mid_edge_coefficient(w, p[a], p[b], n[a], n[b]);
                assert!(
                    x >= -1e-12 * scale,
                    "face {f} {side:?}: Step 4 coefficient of ({a},{b}) = {x}"
                );
            }
        }
    }
    least
}

/// The smallest relative measure over all hull tetrahedra.
pub fn min_relative_measure(hull: &SimplicialHull) -> f64 {
    let mut m = f64::INFINITY;
    for f in hull.faces() {
        for t in f.positive.iter().chain(f.negative.iter()) {
            m = m.min(t.tetrahedron.relative_measure());
        }
    }
    for e in hull.edges() {
        for t in e.positive.iter().chain(e.negative.iter()) {
            m = m.min(t.tetrahedron.relative_measure());
        }
    }
    m
}

/// All pairs of tetrahedra checked by brute force (tests only).
pub fn brute_force_overlaps(hull: &SimplicialHull, tol: f64) -> usize {
    let t = hull.tetrahedra();
    let mut k = 0;
    for i in 0..t.len() {
        for j in i + 1..t.len() {
            if algesurf_hull::tetrahedra_overlap(&t[i].vertices, &t[j].vertices, tol) {
                k += 1;
            }
        }
    }
    k
}

/// A height field `z = h(x, y)` on an `n × n` grid over `[-1, 1]²` with exact unit normals
/// `(−h_x, −h_y, 1)`; triangles counter-clockwise seen from +z.
pub fn height_field(
    n: usize,
    h: impl Fn(f64, f64) -> (f64, f64, f64),
) -> (Vec<DVec3>, Vec<[u32; 3]>, Vec<DVec3>) {
    let mut p = Vec::new();
    let mut nn = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let x = -1.0 + 2.0 * i as f64 / n as f64;
            let y = -1.0 + 2.0 * j as f64 / n as f64;
            let (z, hx, hy) = h(x, y);
            p.push(DVec3::new(x, y, z));
            nn.push(DVec3::new(-hx, -hy, 1.0).normalize());
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (p, t, nn)
}

/// `z = a sin(ωx) sin(ωy)` with its gradient.
pub fn wave(a: f64, w: f64) -> impl Fn(f64, f64) -> (f64, f64, f64) {
    move |x, y| {
        let (sx, cx, sy, cy) = ((w * x).sin(), (w * x).cos(), (w * y).sin(), (w * y).cos());
        (a * sx * sy, a * w * cx * sy, a * w * sx * cy)
    }
}

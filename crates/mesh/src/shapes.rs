//! Small meshes built in code, for tests, examples and benchmarks.

use crate::TriMesh;
use glam::DVec3;
use std::collections::HashMap;
use std::f64::consts::PI;

fn build(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> TriMesh {
    // The generators below only produce in-range, non-repeating triangles.
    TriMesh::new(positions, triangles)
        .unwrap_or_else(|e| unreachable!("generated mesh invalid: {e}"))
}

/// The regular octahedron with vertices at ±x, ±y, ±z (outward oriented).
pub fn octahedron() -> TriMesh {
    let p = vec![
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let t = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    build(p, t)
}

/// The unit icosahedron subdivided `level` times (edges split at midpoints, new vertices
/// projected to the unit sphere). Outward oriented; 12 vertices of valence 5, the rest 6.
pub fn icosphere(level: u32) -> TriMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pos: Vec<DVec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|a| DVec3::from_array(*a).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        let mut m = |a: u32, b: u32, pos: &mut Vec<DVec3>| -> u32 {
            let k = (a.min(b), a.max(b));
            *mid.entry(k).or_insert_with(|| {
                pos.push(((pos[a as usize] + pos[b as usize]) * 0.5).normalize());
                pos.len() as u32 - 1
            })
        };
        for [a, b, c] in tris {
            let ab = m(a, b, &mut pos);
            let bc = m(b, c, &mut pos);
            let ca = m(c, a, &mut pos);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    build(pos, tris)
}

/// A torus around the z axis with radii `major > minor`, `n` segments around the axis and
/// `m` around the tube (each at least 3). Outward oriented; every vertex has valence 6.
pub fn torus(n: u32, m: u32, major: f64, minor: f64) -> TriMesh {
    let (n, m) = (n.max(3), m.max(3));
    let mut pos = Vec::with_capacity((n * m) as usize);
    for i in 0..n {
        let u = 2.0 * PI * i as f64 / n as f64;
        for j in 0..m {
            let v = 2.0 * PI * j as f64 / m as f64;
            let r = major + minor * v.cos();
            pos.push(DVec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut tris = Vec::with_capacity((2 * n * m) as usize);
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    build(pos, tris)
}

/// A bicone: two cones of height `h` over the unit disk in the xy-plane, glued along their
/// rim. Tips `(0, 0, ±h)`, one ring of `n` vertices at radius ½ on each side (rotated by half
/// a step), and the rim ring of `n` vertices at `z = 0`; outward oriented, `2 + 3n` vertices
/// and `6n` faces (`n ≥ 3`). A small `h` makes a sharp rim: any normal there is nearly
/// orthogonal to the faces on one side or the other (84° for the horizontal normal at
/// `h = 0.1`), the configuration that makes §3.1's apexes tall.
///
/// ```
/// let m = algesurf_mesh::shapes::bicone(16, 0.1);
/// assert_eq!((m.vertex_count(), m.face_count()), (50, 96));
/// ```
pub fn bicone(n: u32, h: f64) -> TriMesh {
    let n = n.max(3);
    let mut pos = vec![DVec3::new(0.0, 0.0, h), DVec3::new(0.0, 0.0, -h)];
    for (r, z, shift) in [(0.5, 0.5 * h, 0.5), (1.0, 0.0, 0.0), (0.5, -0.5 * h, 0.5)] {
        for k in 0..n {
            let a = 2.0 * PI * (k as f64 + shift) / n as f64;
            pos.push(DVec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    let (up, rim, lo) = (2, 2 + n, 2 + 2 * n);
    let mut tris = Vec::with_capacity(6 * n as usize);
    for k in 0..n {
        let k1 = (k + 1) % n;
        tris.push([0, up + k, up + k1]);
        tris.push([up + k, rim + k, rim + k1]);
        tris.push([up + k, rim + k1, up + k1]);
        tris.push([1, lo + k1, lo + k]);
        tris.push([lo + k, rim + k1, rim + k]);
        tris.push([lo + k, lo + k1, rim + k1]);
    }
    build(pos, tris)
}

/// A regular triangulated grid of `nx × ny` squares in the xy-plane over `[0, nx] × [0, ny]`,
/// each square split along its diagonal (all interior vertices have valence 6), normals +z.
pub fn grid(nx: u32, ny: u32) -> TriMesh {
    let (nx, ny) = (nx.max(1), ny.max(1));
    let mut pos = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            pos.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(pos, tris)
}

/// How [`puck`] triangulates its flat caps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CapTriangulation {
    /// A fan from the rim's first vertex, as CAD exporters and ear clipping triangulate a
    /// convex face: `n - 2` triangles, most of them thin.
    Fan,
    /// A zig-zag strip across the cap (rim vertices `0, 1, n-1, 2, n-2, …`).
    Strip,
}

/// A closed cylinder of radius 1 from `z = 0` to `z = height` with `n ≥ 3` segments, its
/// side split into `2n` triangles and its two caps triangulated without interior vertices
/// as `caps` says: the CAD export of a puck or a shaft, whose fan caps are flat regions of
/// thin faces (`crate::flat`). Outward oriented; `2n` vertices, rim of the bottom cap
/// first.
///
/// ```
/// use algesurf_mesh::shapes::{puck, CapTriangulation};
/// let m = puck(48, 0.3, CapTriangulation::Fan);
/// assert_eq!((m.vertex_count(), m.face_count()), (96, 4 * 48 - 4));
/// assert!(m.signed_volume() > 0.0);
/// ```
pub fn puck(n: u32, height: f64, caps: CapTriangulation) -> TriMesh {
    let n = n.max(3);
    let mut pos = Vec::with_capacity(2 * n as usize);
    for z in [0.0, height] {
        for k in 0..n {
            let a = 2.0 * PI * k as f64 / n as f64;
            pos.push(DVec3::new(a.cos(), a.sin(), z));
        }
    }
    let mut tris = Vec::with_capacity(4 * n as usize);
    for k in 0..n {
        let k1 = (k + 1) % n;
        tris.push([k, k1, n + k1]);
        tris.push([k, n + k1, n + k]);
    }
    // The cap's triangles counter-clockwise seen from +z, as rim indices.
    let cap: Vec<[u32; 3]> = match caps {
        CapTriangulation::Fan => (1..n - 1).map(|k| [0, k, k + 1]).collect(),
        CapTriangulation::Strip => {
            let mut order = vec![0];
            let (mut lo, mut hi) = (1, n - 1);
            while lo <= hi {
                order.push(lo);
                lo += 1;
                if lo <= hi {
                    order.push(hi);
                    hi -= 1;
                }
            }
            order
                .windows(3)
                .enumerate()
                .map(|(i, w)| {
                    if i % 2 == 0 {
                        [w[0], w[1], w[2]]
                    } else {
                        [w[0], w[2], w[1]]
                    }
                })
                .collect()
        }
    };
    for [a, b, c] in cap {
        tris.push([a, c, b]); // bottom: facing -z
        tris.push([n + a, n + b, n + c]);
    }
    build(pos, tris)
}

/// A closed box `[0, size]² × [0, thickness]` whose two large sides are grids of `n × n`
/// squares and whose four thin sides are strips of `n` rectangles, each square and rectangle
/// split along a diagonal: a CAD export of a plate. With `thickness` far below `size / n` the
/// thin sides are strips of skinny faces between creases (`crate::flat`, "narrow strips").
/// Outward oriented; `2(n + 1)²` vertices, `4n² + 8n` faces.
///
/// ```
/// use algesurf_mesh::shapes::plate;
/// let m = plate(2, 2.0, 0.02);
/// assert_eq!((m.vertex_count(), m.face_count()), (18, 32));
/// assert!((m.signed_volume() - 2.0 * 2.0 * 0.02).abs() < 1e-12);
/// assert_eq!(m.euler_characteristic(), 2);
/// ```
pub fn plate(n: u32, size: f64, thickness: f64) -> TriMesh {
    let n = n.max(1);
    // Vertex (i, j) of the bottom grid is `j (n + 1) + i`, of the top `(n + 1)² + j (n + 1) + i`.
    let side = n + 1;
    let id = |i: u32, j: u32, top: bool| u32::from(top) * side * side + j * side + i;
    let mut pos = Vec::with_capacity(2 * (side * side) as usize);
    for z in [0.0, thickness] {
        for j in 0..=n {
            for i in 0..=n {
                let at = |k: u32| size * f64::from(k) / f64::from(n);
                pos.push(DVec3::new(at(i), at(j), z));
            }
        }
    }
    let mut tris = Vec::with_capacity((4 * n * n + 8 * n) as usize);
    // A quad `a b c d`, counter-clockwise seen from outside, split along `a c`.
    let mut quad = |a: u32, b: u32, c: u32, d: u32| {
        tris.push([a, b, c]);
        tris.push([a, c, d]);
    };
    for j in 0..n {
        for i in 0..n {
            // Bottom, seen from −z; top, seen from +z.
            quad(
                id(i, j, false),
                id(i, j + 1, false),
                id(i + 1, j + 1, false),
                id(i + 1, j, false),
            );
            quad(
                id(i, j, true),
                id(i + 1, j, true),
                id(i + 1, j + 1, true),
                id(i, j + 1, true),
            );
        }
    }
    for k in 0..n {
        // The four thin sides: y = 0, x = size, y = size, x = 0, each seen from outside.
        quad(
            id(k, 0, false),
            id(k + 1, 0, false),
            id(k + 1, 0, true),
            id(k, 0, true),
        );
        quad(
            id(n, k, false),
            id(n, k + 1, false),
            id(n, k + 1, true),
            id(n, k, true),
        );
        quad(
            id(k + 1, n, false),
            id(k, n, false),
            id(k, n, true),
            id(k + 1, n, true),
        );
        quad(
            id(0, k + 1, false),
            id(0, k, false),
            id(0, k, true),
            id(0, k + 1, true),
        );
    }
    build(pos, tris)
}

/// A closed washer: the ring between radii `inner < outer` about the z-axis, from `z = 0` to
/// `z = thickness`, with `n ≥ 3` segments; its flat sides are strips of `2n` triangles
/// (outer rim to inner rim, no vertex between) and its two cylindrical walls one row of `n`
/// quads each, split along a diagonal. Outward oriented; `4n` vertices, `8n` faces, a torus
/// (Euler characteristic 0).
///
/// ```
/// use algesurf_mesh::shapes::washer;
/// let m = washer(32, 1.0, 0.5, 0.05);
/// assert_eq!((m.vertex_count(), m.face_count()), (128, 256));
/// assert_eq!(m.euler_characteristic(), 0);
/// assert!(m.signed_volume() > 0.0);
/// ```
pub fn washer(n: u32, outer: f64, inner: f64, thickness: f64) -> TriMesh {
    let n = n.max(3);
    // Vertex k of ring `r` (0 outer, 1 inner) at height `h` (0 bottom, 1 top).
    let id = |h: u32, r: u32, k: u32| h * 2 * n + r * n + k % n;
    let mut pos = Vec::with_capacity(4 * n as usize);
    for z in [0.0, thickness] {
        for radius in [outer, inner] {
            for k in 0..n {
                let a = 2.0 * PI * k as f64 / n as f64;
                pos.push(DVec3::new(radius * a.cos(), radius * a.sin(), z));
            }
        }
    }
    let mut tris = Vec::with_capacity(8 * n as usize);
    for k in 0..n {
        let (o0, o1, i0, i1) = (id(1, 0, k), id(1, 0, k + 1), id(1, 1, k), id(1, 1, k + 1));
        tris.push([o0, o1, i1]);
        tris.push([o0, i1, i0]);
        let (o0, o1, i0, i1) = (id(0, 0, k), id(0, 0, k + 1), id(0, 1, k), id(0, 1, k + 1));
        tris.push([o0, i1, o1]);
        tris.push([o0, i0, i1]);
        let (a, b, c, d) = (id(0, 0, k), id(0, 0, k + 1), id(1, 0, k + 1), id(1, 0, k));
        tris.push([a, b, c]);
        tris.push([a, c, d]);
        let (a, b, c, d) = (id(0, 1, k), id(0, 1, k + 1), id(1, 1, k + 1), id(1, 1, k));
        tris.push([a, c, b]);
        tris.push([a, d, c]);
    }
    build(pos, tris)
}

//! Folds: places where a smooth surface with one normal per vertex cannot follow the mesh.
//!
//! §3 of Xu–Huang–Bajaj 2001 (and any construction that lays a graph-like patch over each face)
//! needs, at every vertex, a normal on the positive side of all its faces (`n_fᵀn_v > 0`): the
//! faces' normals must fit in an open hemisphere. Real meshes break this in two ways, and
//! [`crate::repair()`] mends both:
//!
//! - *Folded caps* ([`flip_folded_caps`]): nearly flat triangles (one angle close to 180°) whose
//!   normal points against the neighbour across their longest edge — a corner pushed through
//!   the opposite edge, as in scans (the Stanford bunny has them). Flipping the longest edge
//!   removes the cap and keeps every vertex where it is.
//! - *Folded vertices* ([`unfold_vertices`]): the rim of a thin flap whose two sides meet at
//!   less than zero degrees (the cow's ears), or a crease turned back on itself. No edge flip
//!   helps; the vertex is moved towards the centroid of its neighbours, the least distance
//!   that opens its faces' normals (and its neighbours') to the required cone. This changes the
//!   data, so it is reported vertex by vertex with the distance moved.

use crate::fasthash::FastMap;
use glam::DVec3;

/// The least angle that makes a triangle a cap: 150°. A cap's corner lies within
/// `tan(15°)·½` of its longest edge's length from that edge, so after the flip its two new
/// triangles lie close to the neighbour's plane.
const CAP_MIN_ANGLE_COS: f64 = -0.866_025_403_784_438_6; // cos 150°

/// The faces of an edge: the first two met, and how many in all (saturating).
#[derive(Clone, Copy)]
struct EdgeFaces {
    faces: [usize; 2],
    count: u8,
}

fn key(a: u32, b: u32) -> (u32, u32) {
    if a < b { (a, b) } else { (b, a) }
}

fn unit_normal(p: [DVec3; 3]) -> DVec3 {
    (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
}

/// Flips the longest edge of every folded cap among the triangles of `faces` (polygons are
/// left alone) and returns the flipped edges (vertex ids as in `faces`).
///
/// A cap `(a, b, c)` with its obtuse corner at `c` and neighbour `(b, a, d)` across `a b` is
/// replaced by `(a, d, c)` and `(d, b, c)` (same orientation, same face ids) when: the edge is
/// shared by exactly these two faces, `c d` is not an edge yet, the cap's normal points
/// against the neighbour's (`n_cap · n_nb < 0`), and both new triangles face the neighbour's
/// side (positive dot with `n_nb`), so the flip leaves no fold behind.
pub(crate) fn flip_folded_caps(
    faces: &mut [(u32, Vec<u32>)],
    pos: impl Fn(u32) -> DVec3,
    min_area: f64,
) -> Vec<[u32; 2]> {
    // Caps first (one angle test per triangle): most meshes have none, and then the edge map
    // below is not needed at all.
    let obtuse_corner = |f: &[u32]| -> Option<usize> {
        if f.len() != 3 {
            return None;
        }
        let p = [pos(f[0]), pos(f[1]), pos(f[2])];
        (0..3).find(|&i| {
            let (u, v) = (p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]);
            let d = u.length() * v.length();
            d > 0.0 && u.dot(v) < CAP_MIN_ANGLE_COS * d
        })
    };
    // In face order, as one pass over all faces would meet them; a flip can make the
    // neighbour a cap, which is then met later in that order too.
    let mut caps: std::collections::BTreeSet<usize> = (0..faces.len())
        .filter(|&k| obtuse_corner(&faces[k].1).is_some())
        .collect();
    if caps.is_empty() {
        return Vec::new();
    }
    // Per undirected edge: its first two faces and how many it has (no allocation per edge).
    let mut edges: FastMap<(u32, u32), EdgeFaces> = FastMap::default();
    edges.reserve(faces.len() * 3 / 2);
    for (k, (_, f)) in faces.iter().enumerate() {
        for i in 0..f.len() {
            let e = edges
                .entry(key(f[i], f[(i + 1) % f.len()]))
                .or_insert(EdgeFaces {
                    faces: [k, k],
                    count: 0,
                });
            if e.count < 2 {
                e.faces[e.count as usize] = k;
            }
            e.count = e.count.saturating_add(1);
        }
    }
    let mut flipped = Vec::new();
    while let Some(k) = caps.pop_first() {
        // An earlier flip may have rewritten this face: test it again as it is now.
        let Some(i) = obtuse_corner(&faces[k].1) else {
            continue;
        };
        let f = [faces[k].1[0], faces[k].1[1], faces[k].1[2]];
        let p = [pos(f[0]), pos(f[1]), pos(f[2])];
        let (c, a, b) = (f[i], f[(i + 1) % 3], f[(i + 2) % 3]);
        let users = edges[&key(a, b)];
        if users.count != 2 {
            continue;
        }
        let g = if users.faces[0] == k {
            users.faces[1]
        } else {
            users.faces[0]
        };
        let gf = &faces[g].1;
        if gf.len() != 3 {
            continue;
        }
        let Some(j) = (0..3).find(|&j| gf[j] == b && gf[(j + 1) % 3] == a) else {
            continue; // inconsistent orientation across a b: not a fold this step can judge
        };
        let d = gf[(j + 2) % 3];
        if d == c || edges.contains_key(&key(c, d)) {
            continue;
        }
        let n_cap = unit_normal(p);
        let n_nb = unit_normal([pos(b), pos(a), pos(d)]);
        if n_cap.dot(n_nb) >= 0.0 {
            continue;
        }
        let t1 = [a, d, c];
        let t2 = [d, b, c];
        let faces_side = |t: [u32; 3]| {
            let [p0, p1, p2] = [pos(t[0]), pos(t[1]), pos(t[2])];
            let n = (p1 - p0).cross(p2 - p0);
            0.5 * n.length() > min_area && n.dot(n_nb) > 0.0
        };
        if !faces_side(t1) || !faces_side(t2) {
            continue;
        }
        // Update the edge map: a b disappears, c d appears; b c moves from k to the second
        // new face and a d from g to the first.
        edges.remove(&key(a, b));
        edges.insert(
            key(c, d),
            EdgeFaces {
                faces: [k, g],
                count: 2,
            },
        );
        for (e, from, to) in [(key(b, c), k, g), (key(a, d), g, k)] {
            if let Some(u) = edges.get_mut(&e) {
                for x in u.faces.iter_mut().filter(|x| **x == from) {
                    *x = to;
                }
            }
        }
        faces[k].1 = t1.to_vec();
        faces[g].1 = t2.to_vec();
        flipped.push([a, b]);
        if g > k {
            caps.insert(g);
        }
    }
    flipped
}

/// The unit normal of triangle `t` (zero when degenerate).
fn face_normal(t: &[u32], p: &[DVec3]) -> DVec3 {
    unit_normal([p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]])
}

/// The triangles around each vertex, as one flat list with offsets (one allocation for the
/// whole mesh instead of one per vertex), and which vertices also have a polygon face (the
/// unfolding leaves those where they are).
struct VertexTriangles {
    offsets: Vec<usize>,
    faces: Vec<usize>,
    polygon_vertex: Vec<bool>,
}

impl VertexTriangles {
    fn new(faces: &[(u32, Vec<u32>)], nv: usize) -> VertexTriangles {
        let mut offsets = vec![0usize; nv + 1];
        let mut polygon_vertex = vec![false; nv];
        for (_, f) in faces {
            for &v in f {
                if f.len() == 3 {
                    offsets[v as usize + 1] += 1;
                } else {
                    polygon_vertex[v as usize] = true;
                }
            }
        }
        for v in 0..nv {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut list = vec![0usize; offsets[nv]];
        for (k, (_, f)) in faces.iter().enumerate() {
            if f.len() == 3 {
                for &v in f {
                    list[fill[v as usize]] = k;
                    fill[v as usize] += 1;
                }
            }
        }
        VertexTriangles {
            offsets,
            faces: list,
            polygon_vertex,
        }
    }

    fn of(&self, v: u32) -> &[usize] {
        &self.faces[self.offsets[v as usize]..self.offsets[v as usize + 1]]
    }
}

/// The smallest cosine of vertex `v`'s faces' normals with the axis the search of
/// [`crate::cone_axis`] ends at (a lower bound of the best one, which that axis attains: a
/// vertex it calls folded may not be, and is moved the least distance that satisfies it);
/// `+∞` for a vertex with no non-degenerate triangle.
fn cone_best(v: u32, around: &VertexTriangles, faces: &[(u32, Vec<u32>)], p: &[DVec3]) -> f64 {
    let normals: Vec<DVec3> = around
        .of(v)
        .iter()
        .map(|&k| face_normal(&faces[k].1, p))
        .collect();
    crate::normals::searched_cone_axis(&normals).map_or(f64::INFINITY, |(_, best)| best)
}

/// Whether every face normal of vertex `v` (from `normals`, one per face) makes at least
/// `min_cos` with their normalised sum. Sufficient for "not folded" (the sum is then an axis
/// that reaches `min_cos`), and a handful of dot products where [`cone_best`] runs an
/// optimisation: every vertex of the mesh is screened on each pass, and almost all pass this
/// test.
fn mean_axis_fits(v: u32, around: &VertexTriangles, normals: &[DVec3], min_cos: f64) -> bool {
    let of = around.of(v);
    let m = of
        .iter()
        .map(|&k| normals[k])
        .sum::<DVec3>()
        .normalize_or_zero();
    m != DVec3::ZERO
        && of.iter().all(|&k| {
            let n = normals[k];
            n == DVec3::ZERO || n.dot(m) >= min_cos
        })
}

/// Moves every *folded* vertex — one whose triangles' normals fit in no cone of half-angle
/// `acos(min_cos)` — towards the centroid of its neighbours, `p + λ (c − p)`, by the least
/// `λ ∈ {1/32, 2/32, …, 1}` for which it and all its neighbours reach `min_cos`, or, if none
/// does, by the `λ` that makes the worst of them best (when that improves on not moving). A `λ` that
/// leaves a face of the vertex with area at most `min_area` is never taken (a degenerate face
/// has no normal, so it would drop out of the cone test instead of passing it).
/// Three passes, as moving one vertex can fold a neighbour. Returns `(vertex, distance moved)`
/// for every vertex moved, in the order moved. Only vertices all of whose faces are triangles
/// are considered.
///
/// Why towards the centroid: it is one step of Laplacian smoothing, which flattens the
/// one-ring; at the rim of a flap whose sides fold past each other it pulls the rim vertex
/// back between the sides, so they open up from it.
pub(crate) fn unfold_vertices(
    faces: &[(u32, Vec<u32>)],
    positions: &mut [DVec3],
    min_cos: f64,
    min_area: f64,
) -> Vec<(u32, f64)> {
    let nv = positions.len();
    let around = VertexTriangles::new(faces, nv);
    // Unit normals per face (zero for polygons and degenerate triangles), kept up to date as
    // vertices move: the screening reads them instead of recomputing each face per corner.
    let mut normals: Vec<DVec3> = faces
        .iter()
        .map(|(_, f)| {
            if f.len() == 3 {
                face_normal(f, positions)
            } else {
                DVec3::ZERO
            }
        })
        .collect();
    let ring = |v: u32| -> Vec<u32> {
        let mut r: Vec<u32> = around
            .of(v)
            .iter()
            .flat_map(|&k| faces[k].1.iter().copied())
            .filter(|&w| w != v)
            .collect();
        r.sort_unstable();
        r.dedup();
        r
    };
    let mut moved = Vec::new();
    for _pass in 0..3 {
        let mut any = false;
        for v in 0..nv as u32 {
            if around.polygon_vertex[v as usize]
                || around.of(v).is_empty()
                || mean_axis_fits(v, &around, &normals, min_cos)
                || cone_best(v, &around, faces, positions) >= min_cos
            {
                continue;
            }
            let r = ring(v);
            let p0 = positions[v as usize];
            let c = r.iter().map(|&w| positions[w as usize]).sum::<DVec3>() / r.len() as f64;
            let mut affected = r.clone();
            affected.push(v);
            let worst_at = |positions: &mut [DVec3], lambda: f64| -> f64 {
                positions[v as usize] = p0 + (c - p0) * lambda;
                let degenerate = around.of(v).iter().any(|&k| {
                    let t = &faces[k].1;
                    let [a, b, d] = [0, 1, 2].map(|i| positions[t[i] as usize]);
                    0.5 * (b - a).cross(d - a).length() <= min_area
                });
                if degenerate {
                    positions[v as usize] = p0;
                    return f64::NEG_INFINITY;
                }
                let w = affected
                    .iter()
                    .map(|&x| cone_best(x, &around, faces, positions))
                    .fold(f64::INFINITY, f64::min);
                positions[v as usize] = p0;
                w
            };
            let before = worst_at(positions, 0.0);
            let mut best = (0.0, before);
            for k in 1..=32 {
                let lambda = k as f64 / 32.0;
                let w = worst_at(positions, lambda);
                if w >= min_cos {
                    best = (lambda, w);
                    break;
                }
                if w > best.1 {
                    best = (lambda, w);
                }
            }
            if best.0 > 0.0 {
                positions[v as usize] = p0 + (c - p0) * best.0;
                for &k in around.of(v) {
                    normals[k] = face_normal(&faces[k].1, positions);
                }
                moved.push((v, (c - p0).length() * best.0));
                any = true;
            }
        }
        if !any {
            break;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The neighbour `(b, a, d)` lies in z = 0 facing +z; the cap `(a, b, c)` has its corner
    /// `c` just across `a b`, so it faces −z when `c.y < 0`.
    fn setup(cy: f64) -> (Vec<DVec3>, Vec<(u32, Vec<u32>)>) {
        let p = vec![
            DVec3::new(0.0, 0.0, 0.0),  // a
            DVec3::new(1.0, 0.0, 0.0),  // b
            DVec3::new(0.5, cy, 0.0),   // c
            DVec3::new(0.5, -1.0, 0.0), // d
        ];
        (p, vec![(7, vec![0, 1, 2]), (9, vec![1, 0, 3])])
    }

    #[test]
    fn folded_cap_is_flipped_and_faces_the_neighbours_side() {
        let (p, mut faces) = setup(-0.01);
        let flipped = flip_folded_caps(&mut faces, |v| p[v as usize], 0.0);
        assert_eq!(flipped, vec![[0, 1]]);
        assert_eq!(faces[0], (7, vec![0, 3, 2]));
        assert_eq!(faces[1], (9, vec![3, 1, 2]));
        for (_, f) in &faces {
            let n = unit_normal([p[f[0] as usize], p[f[1] as usize], p[f[2] as usize]]);
            assert!(n.z > 0.99, "{n}");
        }
    }

    /// A fan of eight triangles around `v`, flat in z = 0, with `v` pushed outside its ring:
    /// the faces on the far side turn over (normal −z against +z), so `v`'s faces' normals fit
    /// in no open hemisphere.
    #[test]
    fn folded_vertex_is_moved_until_its_faces_fit_a_cone() {
        let ring = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
        ];
        let mut p = vec![DVec3::new(1.5, 0.2, 0.0)];
        p.extend(ring.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)));
        let faces: Vec<(u32, Vec<u32>)> = (0..8u32)
            .map(|i| (i, vec![0, 1 + i, 1 + (i + 1) % 8]))
            .collect();
        let vf = VertexTriangles::new(&faces, p.len());
        assert!(cone_best(0, &vf, &faces, &p) <= 0.0, "v is folded");
        let moved = unfold_vertices(&faces, &mut p, 0.1, 1e-12);
        assert!(moved.iter().any(|m| m.0 == 0), "{moved:?}");
        for v in 0..p.len() as u32 {
            assert!(cone_best(v, &vf, &faces, &p) >= 0.1, "vertex {v}");
        }
    }

    #[test]
    fn unfolded_cap_is_left_alone() {
        let (p, mut faces) = setup(0.01);
        let before = faces.clone();
        assert!(flip_folded_caps(&mut faces, |v| p[v as usize], 0.0).is_empty());
        assert_eq!(faces, before);
    }
}

//! Folded caps: nearly flat triangles (one angle close to 180°) whose normal points against
//! the neighbour across their longest edge — a corner pushed through the opposite edge, as in
//! scanned meshes (the Stanford bunny has them). Their orientation is rounding noise, and a
//! surface interpolating the mesh with one normal per vertex cannot be on the positive side of
//! such a face and its neighbour at once (§3 of Xu–Huang–Bajaj 2001 needs `n_fᵀn_v > 0`).
//! Flipping the longest edge removes the cap and keeps every vertex where it is.

use glam::DVec3;
use std::collections::HashMap;

/// The least angle that makes a triangle a cap: 150°. A cap's corner lies within
/// `tan(15°)·½` of its longest edge's length from that edge, so after the flip its two new
/// triangles lie close to the neighbour's plane.
pub(crate) const CAP_MIN_ANGLE_COS: f64 = -0.866_025_403_784_438_6; // cos 150°

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
) -> Vec<[u32; 2]> {
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (k, (_, f)) in faces.iter().enumerate() {
        for i in 0..f.len() {
            edges
                .entry(key(f[i], f[(i + 1) % f.len()]))
                .or_default()
                .push(k);
        }
    }
    let mut flipped = Vec::new();
    for k in 0..faces.len() {
        let f = faces[k].1.clone();
        if f.len() != 3 {
            continue;
        }
        let p = [pos(f[0]), pos(f[1]), pos(f[2])];
        // Obtuse corner c = f[i]; the longest edge is the one opposite it.
        let Some(i) = (0..3).find(|&i| {
            let (u, v) = (p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]);
            let d = u.length() * v.length();
            d > 0.0 && u.dot(v) < CAP_MIN_ANGLE_COS * d
        }) else {
            continue;
        };
        let (c, a, b) = (f[i], f[(i + 1) % 3], f[(i + 2) % 3]);
        let users = &edges[&key(a, b)];
        if users.len() != 2 {
            continue;
        }
        let g = if users[0] == k { users[1] } else { users[0] };
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
        let faces_side =
            |t: [u32; 3]| unit_normal([pos(t[0]), pos(t[1]), pos(t[2])]).dot(n_nb) > 0.0;
        if !faces_side(t1) || !faces_side(t2) {
            continue;
        }
        // Update the edge map: a b disappears, c d appears; b c moves from k to the second
        // new face and a d from g to the first.
        edges.remove(&key(a, b));
        edges.insert(key(c, d), vec![k, g]);
        for (e, from, to) in [(key(b, c), k, g), (key(a, d), g, k)] {
            if let Some(u) = edges.get_mut(&e) {
                for x in u.iter_mut().filter(|x| **x == from) {
                    *x = to;
                }
            }
        }
        faces[k].1 = t1.to_vec();
        faces[g].1 = t2.to_vec();
        flipped.push([a, b]);
    }
    flipped
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
        let flipped = flip_folded_caps(&mut faces, |v| p[v as usize]);
        assert_eq!(flipped, vec![[0, 1]]);
        assert_eq!(faces[0], (7, vec![0, 3, 2]));
        assert_eq!(faces[1], (9, vec![3, 1, 2]));
        for (_, f) in &faces {
            let n = unit_normal([p[f[0] as usize], p[f[1] as usize], p[f[2] as usize]]);
            assert!(n.z > 0.99, "{n}");
        }
    }

    #[test]
    fn unfolded_cap_is_left_alone() {
        let (p, mut faces) = setup(0.01);
        let before = faces.clone();
        assert!(flip_folded_caps(&mut faces, |v| p[v as usize]).is_empty());
        assert_eq!(faces, before);
    }
}

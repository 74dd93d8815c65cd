//! The whole zero set of a function inside one tetrahedron, all its sheets, for the figure
//! of the multiple-sheeted surface (Fig. 3 of Xu–Huang–Bajaj 2001): marching tetrahedra on
//! the Freudenthal subdivision of the tetrahedron's barycentric lattice.
//!
//! The lattice of level `n` has the points `(a₀, a₁, a₂, a₃)/n` with `Σ aᵢ = n`. In the
//! coordinates `y₁ = a₁ + a₂ + a₃`, `y₂ = a₂ + a₃`, `y₃ = a₃` the tetrahedron is
//! `n ≥ y₁ ≥ y₂ ≥ y₃ ≥ 0`, which is exactly a union of Kuhn simplices of the unit cubes
//! (Freudenthal's triangulation), so every small tetrahedron is a Kuhn simplex whose four
//! corners satisfy those inequalities. Within each, F is replaced by its linear interpolant
//! and the zero set is one triangle or a quad.

use glam::DVec3;
use std::collections::HashMap;

/// A triangle soup welded on lattice edges: positions and triangles.
pub type Contour = (Vec<DVec3>, Vec<[u32; 3]>);

/// The `n³` small tetrahedra of the Freudenthal subdivision of level `n`, as corners in the
/// `y` coordinates of the module docs.
pub fn freudenthal_tetrahedra(n: usize) -> Vec<[[usize; 3]; 4]> {
    let inside = |y: [usize; 3]| n >= y[0] && y[0] >= y[1] && y[1] >= y[2];
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut out = Vec::with_capacity(n * n * n);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                for p in perms {
                    let mut v = [[i, j, k]; 4];
                    for s in 0..3 {
                        v[s + 1] = v[s];
                        v[s + 1][p[s]] += 1;
                    }
                    if v.iter().all(|&y| inside(y)) {
                        out.push(v);
                    }
                }
            }
        }
    }
    out
}

/// The zero set of `f` in the tetrahedron `tet` at lattice level `n`.
pub fn zero_set_in_tetrahedron(tet: [DVec3; 4], f: impl Fn(DVec3) -> f64, n: usize) -> Contour {
    let to_point = |y: [usize; 3]| -> DVec3 {
        // a₀ = n − y₁, a₁ = y₁ − y₂, a₂ = y₂ − y₃, a₃ = y₃.
        let a = [n - y[0], y[0] - y[1], y[1] - y[2], y[2]];
        (0..4).fold(DVec3::ZERO, |acc, i| {
            acc + tet[i] * (a[i] as f64 / n as f64)
        })
    };
    let mut value: HashMap<[usize; 3], f64> = HashMap::new();
    let mut val = |y: [usize; 3]| *value.entry(y).or_insert_with(|| f(to_point(y)));
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut on_edge: HashMap<([usize; 3], [usize; 3]), u32> = HashMap::new();
    for v in freudenthal_tetrahedra(n) {
        let fv: [f64; 4] = std::array::from_fn(|c| val(v[c]));
        let mut cut = |a: usize, b: usize| -> u32 {
            let key = if v[a] < v[b] {
                (v[a], v[b])
            } else {
                (v[b], v[a])
            };
            *on_edge.entry(key).or_insert_with(|| {
                let t = fv[a] / (fv[a] - fv[b]);
                positions.push(to_point(v[a]).lerp(to_point(v[b]), t));
                (positions.len() - 1) as u32
            })
        };
        // Corners with f < 0 are "in"; zero counts as out, so every sign change is
        // strict and `t` above is in [0, 1).
        let ins: Vec<usize> = (0..4).filter(|&c| fv[c] < 0.0).collect();
        let outs: Vec<usize> = (0..4).filter(|&c| fv[c] >= 0.0).collect();
        match ins.len() {
            1 | 3 => {
                let (one, rest) = if ins.len() == 1 {
                    (ins[0], outs)
                } else {
                    (outs[0], ins)
                };
                let t = [cut(one, rest[0]), cut(one, rest[1]), cut(one, rest[2])];
                triangles.push(t);
            }
            2 => {
                let q = [
                    cut(ins[0], outs[0]),
                    cut(ins[0], outs[1]),
                    cut(ins[1], outs[1]),
                    cut(ins[1], outs[0]),
                ];
                triangles.push([q[0], q[1], q[2]]);
                triangles.push([q[0], q[2], q[3]]);
            }
            _ => {}
        }
    }
    (positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_through_a_tetrahedron_is_cut_exactly() {
        let tet = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let (p, t) = zero_set_in_tetrahedron(tet, |x| x.z - 0.3, 5);
        assert!(!t.is_empty());
        // A linear function is its own interpolant: every contour point is on the plane.
        assert!(p.iter().all(|x| (x.z - 0.3).abs() < 1e-12));
        // Area of the cut: the triangle z = 0.3 of the unit corner tetrahedron, (0.7²)/2.
        let area: f64 = t
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| p[i as usize]);
                (b - a).cross(c - a).length() / 2.0
            })
            .sum();
        assert!((area - 0.245).abs() < 1e-12, "{area}");
    }

    #[test]
    fn freudenthal_lattice_fills_the_tetrahedron() {
        // n³ Kuhn simplices, each of volume 1/(6n³) in the y coordinates (unimodular map to
        // the barycentric lattice), fill the simplex n ≥ y₁ ≥ y₂ ≥ y₃ ≥ 0 of volume n³/6.
        for n in 1..6 {
            let t = freudenthal_tetrahedra(n);
            assert_eq!(t.len(), n * n * n);
            let vol: f64 = t
                .iter()
                .map(|v| {
                    let p = v.map(|y| DVec3::new(y[0] as f64, y[1] as f64, y[2] as f64));
                    (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]).abs() / 6.0
                })
                .sum();
            assert!((vol - (n * n * n) as f64 / 6.0).abs() < 1e-12);
        }
    }
}

//! Discrete mean curvature at the vertices (the cotangent Laplacian).

use glam::DVec3;

/// Mean curvature `H` at each vertex from the cotangent Laplace–Beltrami operator:
/// `Δx_i = (1 / 2A_i) Σ_j (cot α_ij + cot β_ij)(x_j − x_i) = −2 H_i n_i` (Meyer, Desbrun,
/// Schröder, Barr 2003, eq. 8, with their mixed Voronoi area `A_i`: the Voronoi part of each
/// non-obtuse incident triangle, half or a quarter of an obtuse one), so
/// `H_i = −(Δx_i · n_i) / 2`: positive where the surface bends away from its normal (a sphere
/// with outward normals has `H = 1/r`). Boundary vertices get the value of the triangles they
/// have (biased); degenerate triangles (zero area) contribute nothing; a vertex with no area
/// gets 0.
///
/// The estimate is only as good as the triangles: on the A-patch tessellation of the smoothed
/// icosahedron (the exact unit sphere, but with triangles down to 4.7° angles at the patch
/// corners) it reads 0.90 to 1.16 instead of 1, in spots around the corners; on a regular
/// level-4 icosphere it is within 5 % (tested below).
pub fn mean_curvature(positions: &[DVec3], triangles: &[[u32; 3]], normals: &[DVec3]) -> Vec<f64> {
    let n = positions.len();
    let mut lap = vec![DVec3::ZERO; n];
    let mut area = vec![0.0f64; n];
    for t in triangles {
        let p = t.map(|i| positions[i as usize]);
        let doubled = (p[1] - p[0]).cross(p[2] - p[0]).length();
        if doubled.is_nan() || doubled <= 0.0 {
            continue;
        }
        // cot of the angle at each corner: (u·v)/|u×v|.
        let cot: [f64; 3] = std::array::from_fn(|k| {
            let (b, c) = ((k + 1) % 3, (k + 2) % 3);
            (p[b] - p[k]).dot(p[c] - p[k]) / doubled
        });
        let obtuse = (0..3).find(|&k| cot[k] < 0.0);
        for k in 0..3 {
            let (b, c) = ((k + 1) % 3, (k + 2) % 3);
            let (ib, ic) = (t[b] as usize, t[c] as usize);
            // The angle at k weighs the opposite edge (b, c).
            lap[ib] += cot[k] * (p[c] - p[b]);
            lap[ic] += cot[k] * (p[b] - p[c]);
            area[t[k] as usize] += match obtuse {
                // Voronoi area of corner k: (|kb|² cot c + |kc|² cot b) / 8.
                None => {
                    ((p[b] - p[k]).length_squared() * cot[c]
                        + (p[c] - p[k]).length_squared() * cot[b])
                        / 8.0
                }
                Some(o) if o == k => doubled / 4.0,
                Some(_) => doubled / 8.0,
            };
        }
    }
    (0..n)
        .map(|i| {
            if area[i] > 0.0 {
                -(lap[i] / (2.0 * area[i])).dot(normals[i]) / 2.0
            } else {
                0.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_curvature_of_a_fine_icosphere_is_one() {
        let s = algesurf_mesh::shapes::icosphere(4);
        let normals: Vec<DVec3> = s.positions().iter().map(|p| p.normalize()).collect();
        let h = mean_curvature(s.positions(), s.triangles(), &normals);
        // With mixed Voronoi areas the estimate on a level-4 icosphere (edges ≈ 0.07) is
        // within a few percent, also at the 12 valence-5 vertices.
        for v in h {
            assert!((v - 1.0).abs() < 0.05, "H = {v}");
        }
    }
}

//! Gradient magnitudes from unit normals: the step that lets unit-normal data reproduce every
//! quadric, not only the sphere (READING-NOTES; beyond the paper).
//!
//! Theorem 4.2 of Xu–Huang–Bajaj 2001 reproduces a quadric `Q` when the vertex data are `Q`'s
//! values and *gradients*. Meshes come with unit normals; on a sphere those are `∇Q/2`
//! everywhere, but on an ellipsoid `|∇Q|` varies from vertex to vertex and the surface leaves
//! it. [`quadric_consistent_scales`] recovers per-vertex magnitudes `s_v` (so `s_v n_v` are
//! the gradients) in two steps:
//!
//! 1. At every vertex `v`, fit a quadric `Q_v` to the *directions* of its two-ring: `Q_v(p) = 0`
//!    and `∇Q_v(p) × n = 0` at each point, the homogeneous least-squares problem whose
//!    solution is the right singular vector of the smallest singular value. On data from one
//!    quadric the fit is that quadric (up to scale). Each neighbour `w` gets the ratio
//!    `r_vw = (∇Q_v(p_v)·n_v) / (∇Q_v(p_w)·n_w)`, which does not depend on `Q_v`'s scale.
//! 2. Solve `log s_v − log s_w = log r_vw` over all edges in least squares (the two ratios an
//!    edge gets from its end points' fits are averaged): a graph-Laplacian system, solved by
//!    conjugate gradients from zero, which gives log-scales of mean zero on each connected
//!    piece. Consistent ratios (data on one quadric) are reproduced exactly up to rounding.
//!
//! # Example
//! ```
//! use algesurf_apatch::gradient_scale::quadric_consistent_scales;
//! use algesurf_mesh::{TriMesh, shapes::icosphere};
//! use glam::DVec3;
//!
//! // An ellipsoid x²/a² + y²/b² + z²/c² = 1 with its unit normals.
//! let axes = DVec3::new(1.5, 1.0, 0.7);
//! let sphere = icosphere(2);
//! let pos: Vec<DVec3> = sphere.positions().iter().map(|p| *p * axes).collect();
//! let grad: Vec<DVec3> = pos.iter().map(|p| *p / (axes * axes)).collect();
//! let unit: Vec<DVec3> = grad.iter().map(|g| g.normalize()).collect();
//! let mesh = TriMesh::new(pos, sphere.triangles().to_vec()).unwrap();
//! let s = quadric_consistent_scales(&mesh, &unit).unwrap();
//! // The recovered gradients are ∇Q up to one common factor.
//! let k = s[0] / grad[0].length();
//! for (v, g) in grad.iter().enumerate() {
//!     assert!((s[v] / g.length() / k - 1.0).abs() < 1e-9);
//! }
//! ```

use crate::ApatchError;
use algesurf_mesh::TriMesh;
use glam::DVec3;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// A fit whose second-smallest singular value is below this fraction of the largest has a
/// family of at least two quadrics fitting its data (the scaled system has O(1) entries, so
/// this is far above rounding): a planar neighbourhood, where every `L·M` (`L` the plane, `M`
/// any affine function) fits. There the ratios are not determined by the fit, and the plane's
/// own gradient is constant, so the ratio is taken as 1.
const AMBIGUOUS_FIT: f64 = 1e-6;

/// The largest gradient ratio accepted across one edge: `4`. A quadric whose gradient
/// magnitude changes by more than that between neighbouring vertices is not resolved by the
/// mesh; such ratios come from fits to data that are not near a quadric (creases, noise), and
/// are clamped so that one bad fit cannot swing the scales of a whole region.
const MAX_EDGE_RATIO: f64 = 4.0;

/// Per-vertex gradient magnitudes `s_v > 0` consistent with local quadric fits (see the
/// module docs); `s_v · n_v` are then the gradients to build F from. Normals must be unit
/// length (they are normalised here anyway). The log-scales have mean zero on each connected
/// piece of the mesh.
///
/// # Errors
/// [`ApatchError::Degenerate`] when `normals.len()` differs from the vertex count or a
/// normal is not finite and non-zero.
pub fn quadric_consistent_scales(
    mesh: &TriMesh,
    normals: &[DVec3],
) -> Result<Vec<f64>, ApatchError> {
    let nv = mesh.vertex_count();
    if normals.len() != nv {
        return Err(ApatchError::Degenerate(format!(
            "{nv} vertices but {} normals",
            normals.len()
        )));
    }
    let mut unit = Vec::with_capacity(nv);
    for (v, n) in normals.iter().enumerate() {
        let u = n.normalize_or_zero();
        if u == DVec3::ZERO || !u.is_finite() {
            return Err(ApatchError::Degenerate(format!(
                "vertex {v}: the normal is not a finite non-zero vector"
            )));
        }
        unit.push(u);
    }
    let topo = mesh.topology();
    let pos = mesh.positions();
    // Step 1: log-ratio estimates per directed edge (v, w) from v's fit.
    let estimates: Vec<Vec<(u32, f64)>> = (0..nv as u32)
        .into_par_iter()
        .map(|v| {
            let ring: Vec<u32> = neighbours(mesh, v);
            if ring.is_empty() {
                return Vec::new();
            }
            let mut hood = ring.clone();
            for &w in &ring {
                hood.extend(neighbours(mesh, w));
            }
            hood.push(v);
            hood.sort_unstable();
            hood.dedup();
            let samples: Vec<(DVec3, DVec3)> = hood
                .iter()
                .map(|&x| (pos[x as usize], unit[x as usize]))
                .collect();
            let fit = direction_fit(&samples);
            ring.iter()
                .map(|&w| {
                    let log_r = match &fit {
                        Some(q) => {
                            let gv = q.gradient(pos[v as usize]).dot(unit[v as usize]);
                            let gw = q.gradient(pos[w as usize]).dot(unit[w as usize]);
                            let r = gv / gw;
                            if r > 0.0 && r.is_finite() {
                                r.ln().clamp(-MAX_EDGE_RATIO.ln(), MAX_EDGE_RATIO.ln())
                            } else {
                                0.0
                            }
                        }
                        None => 0.0,
                    };
                    (w, log_r)
                })
                .collect()
        })
        .collect();
    // Step 2: per undirected edge, b_e = mean of the estimates of log s_v − log s_w.
    let ne = topo.edge_count();
    let mut edge_b = vec![0.0f64; ne];
    let mut edge_n = vec![0u8; ne];
    for (v, est) in estimates.iter().enumerate() {
        for &(w, log_r) in est {
            let e = topo.find_edge(v as u32, w).expect("ring edge") as usize;
            let [a, _] = topo.edge(e as u32);
            // Store as log s_a − log s_b for the edge's own orientation.
            edge_b[e] += if a == v as u32 { log_r } else { -log_r };
            edge_n[e] += 1;
        }
    }
    for e in 0..ne {
        if edge_n[e] > 0 {
            edge_b[e] /= edge_n[e] as f64;
        }
    }
    let x = solve_edge_laplacian(mesh, &edge_b);
    Ok(x.into_iter().map(f64::exp).collect())
}

fn neighbours(mesh: &TriMesh, v: u32) -> Vec<u32> {
    let t = mesh.topology();
    t.vertex_edges(v)
        .iter()
        .map(|&e| t.opposite_vertex(e, v))
        .collect()
}

/// A quadric fitted to point/normal-direction pairs: the homogeneous least-squares solution of
/// `q(y) = 0`, `∇q(y) × n = 0` in coordinates `y` centred on the samples and scaled by their
/// radius (so the system's entries are O(1) wherever and however large the mesh is). `None`
/// when the fit is ambiguous ([`AMBIGUOUS_FIT`]) or the data are degenerate.
fn direction_fit(samples: &[(DVec3, DVec3)]) -> Option<crate::Quadric> {
    let centre = samples.iter().map(|s| s.0).sum::<DVec3>() / samples.len() as f64;
    let h = samples
        .iter()
        .map(|s| s.0.distance(centre))
        .fold(0.0, f64::max);
    if !(h > 0.0 && h.is_finite()) || samples.len() < 4 {
        return None;
    }
    let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    let mut m = DMatrix::<f64>::zeros(samples.len() * 4, 10);
    for (s, (x, n)) in samples.iter().enumerate() {
        let y = ((*x - centre) / h).to_array();
        // Basis functions φ_k(y) and their gradients.
        let mut phi = [0.0; 10];
        let mut grad = [[0.0; 3]; 10];
        for (k, &(i, j)) in pairs.iter().enumerate() {
            phi[k] = y[i] * y[j];
            grad[k][i] += y[j];
            grad[k][j] += y[i];
        }
        for d in 0..3 {
            phi[6 + d] = y[d];
            grad[6 + d][d] = 1.0;
        }
        phi[9] = 1.0;
        let row = 4 * s;
        let n = n.to_array();
        for k in 0..10 {
            m[(row, k)] = phi[k];
            let g = grad[k];
            // (∇φ_k × n): rank 2 of these 3 rows, each O(1).
            m[(row + 1, k)] = g[1] * n[2] - g[2] * n[1];
            m[(row + 2, k)] = g[2] * n[0] - g[0] * n[2];
            m[(row + 3, k)] = g[0] * n[1] - g[1] * n[0];
        }
    }
    // The right singular vectors are the eigenvectors of MᵀM (10×10); its eigenvalues are the
    // squared singular values, so the ambiguity test compares their square roots.
    let mtm = m.transpose() * &m;
    let eig = mtm.symmetric_eigen();
    let mut order: Vec<usize> = (0..10).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let sigma = |i: usize| eig.eigenvalues[order[i]].max(0.0).sqrt();
    if sigma(1) <= AMBIGUOUS_FIT * sigma(9) {
        return None;
    }
    let q: Vec<f64> = eig.eigenvectors.column(order[0]).iter().copied().collect();
    // Back to x (the overall scale is irrelevant here).
    Some(crate::Quadric::from_local(&q, centre, h))
}

/// Least-squares `x` with `x_a − x_b ≈ b_e` for every edge `e = (a, b)`: the normal equations
/// `L x = Dᵀ b` (`L` the graph Laplacian, `D` the edge–vertex incidence), solved by conjugate
/// gradients from `x = 0`. `L` is singular (constants per connected piece), but `Dᵀb` lies in
/// its range and CG from zero stays there, so it converges to the solution of mean zero on
/// each piece. Stops when the residual is below `1e-14` of the right-hand side.
fn solve_edge_laplacian(mesh: &TriMesh, b: &[f64]) -> Vec<f64> {
    let topo = mesh.topology();
    let nv = mesh.vertex_count();
    let edges: Vec<[u32; 2]> = (0..topo.edge_count() as u32)
        .map(|e| topo.edge(e))
        .collect();
    let apply = |x: &[f64]| -> Vec<f64> {
        let mut y = vec![0.0; nv];
        for [a, c] in &edges {
            let d = x[*a as usize] - x[*c as usize];
            y[*a as usize] += d;
            y[*c as usize] -= d;
        }
        y
    };
    let mut rhs = vec![0.0; nv];
    for ([a, c], be) in edges.iter().zip(b) {
        rhs[*a as usize] += be;
        rhs[*c as usize] -= be;
    }
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
    let mut x = vec![0.0; nv];
    let mut r = rhs.clone();
    let mut p = r.clone();
    let mut rr = dot(&r, &r);
    let stop = 1e-28 * rr;
    // CG on an n×n positive semi-definite system converges in at most n steps in exact
    // arithmetic; the cap only guards against rounding stalls.
    for _ in 0..(4 * nv + 100) {
        if rr <= stop || rr == 0.0 {
            break;
        }
        let ap = apply(&p);
        let pap = dot(&p, &ap);
        if pap <= 0.0 {
            break;
        }
        let alpha = rr / pap;
        for i in 0..nv {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        let rr_new = dot(&r, &r);
        let beta = rr_new / rr;
        rr = rr_new;
        for i in 0..nv {
            p[i] = r[i] + beta * p[i];
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_mesh::shapes::{grid, icosphere};

    #[test]
    fn sphere_scales_are_all_one() {
        let m = icosphere(2);
        let n: Vec<DVec3> = m.positions().iter().map(|p| p.normalize()).collect();
        let s = quadric_consistent_scales(&m, &n).unwrap();
        assert!(s.iter().all(|x| (x - 1.0).abs() < 1e-12), "{s:?}");
    }

    #[test]
    fn plane_scales_are_all_one() {
        let m = grid(5, 5);
        let n = vec![DVec3::Z; m.vertex_count()];
        let s = quadric_consistent_scales(&m, &n).unwrap();
        assert!(s.iter().all(|x| (x - 1.0).abs() < 1e-12));
    }

    #[test]
    fn paraboloid_gradients_are_recovered_up_to_one_factor() {
        // z = x² + 0.3 y²: Q = x² + 0.3 y² − z, ∇Q = (2x, 0.6y, −1).
        let g = grid(6, 6);
        let pos: Vec<DVec3> = g
            .positions()
            .iter()
            .map(|p| DVec3::new(p.x, p.y, p.x * p.x + 0.3 * p.y * p.y))
            .collect();
        let grad: Vec<DVec3> = pos
            .iter()
            .map(|p| -DVec3::new(2.0 * p.x, 0.6 * p.y, -1.0))
            .collect();
        let unit: Vec<DVec3> = grad.iter().map(|v| v.normalize()).collect();
        let mesh = TriMesh::new(pos, g.triangles().to_vec()).unwrap();
        let s = quadric_consistent_scales(&mesh, &unit).unwrap();
        let k = s[0] / grad[0].length();
        for (v, gv) in grad.iter().enumerate() {
            let e = (s[v] / gv.length() / k - 1.0).abs();
            assert!(e < 1e-9, "vertex {v}: {e:e}");
        }
    }

    #[test]
    fn wrong_normal_count_is_an_error() {
        let m = icosphere(0);
        assert!(quadric_consistent_scales(&m, &[DVec3::Z]).is_err());
    }
}

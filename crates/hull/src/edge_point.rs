//! The split of one edge during local refinement (§3.1): the Butterfly edge point, pulled
//! towards the chord's midpoint where it would fold a face against a vertex normal.

use crate::HullError;
use algesurf_mesh::{
    DEFAULT_MIN_NORMAL_COSINE, LocalRefinement, TriMesh, butterfly_refine_edge, loop_limit_normal,
    split_edge,
};
use glam::DVec3;

/// Blend factors tried, from the Butterfly point (1) towards the chord's midpoint (0, the
/// fallback).
const BLENDS: [f64; 3] = [1.0, 0.5, 0.25];

/// Splits edge `a`–`b` of `mesh` at (or towards) its modified Butterfly point and returns the
/// refined mesh with the new vertex's normal, without making any face invalid.
///
/// A split replaces the edge's two faces by four; every other face is unchanged. The new
/// faces are *valid* when each corner's normal makes a cosine of at least
/// `min(DEFAULT_MIN_NORMAL_COSINE, c)` with the new face's unit normal, `c` the cosine it made
/// with the parent face (for the new vertex: the smaller of the parent's cosines at `a` and
/// `b`). So refinement never pushes a normal closer to its face than the normal conditioning
/// does, never folds a vertex, and never has to change a normal it was given.
///
/// Tried in order: the Butterfly point with the unit Loop limit normal of the refined mesh
/// (the paper's choice, §3.1), then with the normalised sum `n̂_a + n̂_b`; then the points
/// `s = ½, ¼` of the way from the chord's midpoint towards the Butterfly point with the same
/// two normals. The last resort, the midpoint with the sum, is valid without a test: its two
/// faces are coplanar with their parents, so the old corners keep their cosines, and the sum's
/// cosine with each parent normal `n_f` is `(n̂_a·n_f + n̂_b·n_f)/|n̂_a + n̂_b| ≥
/// min(n̂_a·n_f, n̂_b·n_f)` because `|n̂_a + n̂_b| ≤ 2`.
///
/// Before this, refinement kept the Butterfly point and re-conditioned the normals around it;
/// next to the sharp rims of the cow, the Stanford bunny and Suzanne that folded vertices
/// (their faces' normals fitting in no hemisphere) and stopped the build.
///
/// # Errors
/// [`HullError::Mesh`] if the edge does not exist or is not locally manifold.
pub(crate) fn fold_safe_split(
    mesh: &TriMesh,
    normals: &[DVec3],
    a: u32,
    b: u32,
) -> Result<(LocalRefinement, DVec3), HullError> {
    let (pa, pb) = (mesh.positions()[a as usize], mesh.positions()[b as usize]);
    let (na, nb) = (normals[a as usize], normals[b as usize]);
    let mid = 0.5 * (pa + pb);
    let sum = (na.normalize() + nb.normalize()).normalize_or_zero();
    let at_butterfly = butterfly_refine_edge(mesh, a, b)?;
    let m = at_butterfly.new_vertex;
    let butterfly = at_butterfly.mesh.positions()[m as usize];
    // The Loop limit normal of the new vertex does not depend on where it sits: its ring is
    // `a, w₁, b, w₂` (valence 4; `w` the opposite corners), and Loop's tangent masks
    // `cos(2πi/4)`, `sin(2πi/4)` give `(p_a − p_b) × (p_w₁ − p_w₂)`, the vertex's own position
    // cancelling; on the boundary (ring `a, w, b`) the masks give `(p_a + p_b − 2 p_w)` and
    // `p_a − p_b`, again without it. So it is computed once, and only its sign (towards the
    // new faces' side) is decided per candidate point.
    let loop_axis = loop_limit_normal(&at_butterfly.mesh, m)
        .filter(|l| l.is_finite() && *l != DVec3::ZERO)
        .map(DVec3::normalize);
    let faces = edge_faces(mesh, a, b);
    for s in BLENDS {
        let point = mid + s * (butterfly - mid);
        let new_faces = split_faces(mesh, &faces, point);
        let side: DVec3 = new_faces.iter().map(|f| f.area_normal).sum();
        let wanted = match loop_axis {
            Some(l) if l.dot(side) < 0.0 => -l,
            Some(l) => l,
            None => side.normalize_or_zero(),
        };
        for n in [wanted, sum] {
            if n.is_finite() && n != DVec3::ZERO && valid(normals, &new_faces, n, [a, b]) {
                let refined = if s == 1.0 {
                    at_butterfly
                } else {
                    split_edge(mesh, a, b, point)?
                };
                return Ok((refined, n));
            }
        }
    }
    // The midpoint with the normal sum, valid by the argument above without a test (a test
    // could fail by rounding: the sub-faces' normals equal their parents' only to an ulp).
    // If a parent face was invalid already, the hull build names it.
    Ok((split_edge(mesh, a, b, mid)?, sum))
}

/// One face of the split edge: its corners `[u, v, w]` with `u → v` the edge, and its unit
/// normal.
struct EdgeFace {
    corners: [u32; 3],
    normal: DVec3,
}

/// The faces of edge `a`–`b` (one or two; the edge exists, `butterfly_refine_edge` checked).
fn edge_faces(mesh: &TriMesh, a: u32, b: u32) -> Vec<EdgeFace> {
    let t = mesh.topology();
    let Some(e) = t.find_edge(a, b) else {
        return Vec::new();
    };
    t.edge_faces(e)
        .filter_map(|f| {
            let tri = mesh.triangles()[f as usize];
            let k = (0..3).find(|&k| {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                (u == a && v == b) || (u == b && v == a)
            })?;
            Some(EdgeFace {
                corners: [tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]],
                normal: mesh.face_normal(f as usize).normalize_or_zero(),
            })
        })
        .collect()
}

/// A face made by the split: its corners (`None` for the new vertex), its area-weighted
/// normal, and its parent's unit normal.
struct NewFace {
    corners: [Option<u32>; 3],
    area_normal: DVec3,
    parent_normal: DVec3,
}

/// The faces `[u, m, w]` and `[m, v, w]` that replace each face `[u, v, w]` when the new
/// vertex `m` sits at `point` (the same faces `split_edge` makes).
fn split_faces(mesh: &TriMesh, faces: &[EdgeFace], point: DVec3) -> Vec<NewFace> {
    let p = |v: Option<u32>| v.map_or(point, |v| mesh.positions()[v as usize]);
    let mut out = Vec::with_capacity(2 * faces.len());
    for f in faces {
        let [u, v, w] = f.corners;
        for corners in [[Some(u), None, Some(w)], [None, Some(v), Some(w)]] {
            let q = corners.map(p);
            out.push(NewFace {
                corners,
                area_normal: (q[1] - q[0]).cross(q[2] - q[0]),
                parent_normal: f.normal,
            });
        }
    }
    out
}

/// Whether every new face keeps its corners' normals on its positive side (see
/// [`fold_safe_split`]).
fn valid(normals: &[DVec3], faces: &[NewFace], new_normal: DVec3, [a, b]: [u32; 2]) -> bool {
    let new_normal = new_normal.normalize();
    for f in faces {
        let nf = f.area_normal.normalize_or_zero();
        if nf == DVec3::ZERO {
            return false;
        }
        let parent_cos = |v: u32| f.parent_normal.dot(normals[v as usize].normalize());
        for c in f.corners {
            let (n, floor) = match c {
                None => (new_normal, parent_cos(a).min(parent_cos(b))),
                Some(v) => (normals[v as usize].normalize(), parent_cos(v)),
            };
            if nf.dot(n) < DEFAULT_MIN_NORMAL_COSINE.min(floor) {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two flat triangles on the edge `0 → 1` with their four wing triangles pulled 40 below:
    /// Butterfly's wing weights −1/16 lift the edge point to `z = 10`, which tilts the new
    /// faces to within 3° of vertical against the `+z` normals. The split must back off
    /// towards the midpoint: `s = ½` still tilts them past `DEFAULT_MIN_NORMAL_COSINE`, `s =
    /// ¼` (`z = 2.5`) does not.
    #[test]
    fn butterfly_point_that_would_fold_is_pulled_towards_the_midpoint() {
        let v = DVec3::new;
        let p = vec![
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.5, 1.0, 0.0),
            v(0.5, -1.0, 0.0),
            v(-0.5, 0.8, -40.0),
            v(1.5, 0.8, -40.0),
            v(-0.5, -0.8, -40.0),
            v(1.5, -0.8, -40.0),
        ];
        let t = vec![
            [0, 1, 2],
            [1, 0, 3],
            [0, 2, 4],
            [2, 1, 5],
            [3, 0, 6],
            [1, 3, 7],
        ];
        let mesh = TriMesh::new(p, t).unwrap();
        let normals = vec![DVec3::Z; 8];
        let butterfly = {
            let r = butterfly_refine_edge(&mesh, 0, 1).unwrap();
            r.mesh.positions()[r.new_vertex as usize]
        };
        assert!((butterfly.z - 10.0).abs() < 1e-12, "{butterfly}");
        let (refined, n) = fold_safe_split(&mesh, &normals, 0, 1).unwrap();
        let m = refined.mesh.positions()[refined.new_vertex as usize];
        assert!((m - v(0.5, 0.0, 2.5)).length() < 1e-12, "{m}");
        let faces = edge_faces(&mesh, 0, 1);
        assert!(valid(&normals, &split_faces(&mesh, &faces, m), n, [0, 1]));
        // The Butterfly point itself fails the same test, whatever the new vertex's normal.
        let at_butterfly = split_faces(&mesh, &faces, butterfly);
        assert!(!valid(&normals, &at_butterfly, DVec3::Z, [0, 1]));
        // The faces predicted are the ones `split_edge` makes, with the same normals.
        for f in refined.mesh.topology().vertex_faces(refined.new_vertex) {
            let got = refined.mesh.face_normal(f as usize).normalize_or_zero();
            let predicted = split_faces(&mesh, &faces, m);
            assert!(
                predicted
                    .iter()
                    .any(|p| (p.area_normal.normalize() - got).length() < 1e-12)
            );
        }
    }
}

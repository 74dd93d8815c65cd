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
    let butterfly = {
        let r = butterfly_refine_edge(mesh, a, b)?;
        r.mesh.positions()[r.new_vertex as usize]
    };
    for s in BLENDS {
        let refined = split_edge(mesh, a, b, mid + s * (butterfly - mid))?;
        let wanted = loop_normal(&refined.mesh, refined.new_vertex);
        for n in [wanted, sum] {
            if n.is_finite() && n != DVec3::ZERO && valid(mesh, normals, &refined, n, [a, b]) {
                return Ok((refined, n));
            }
        }
    }
    // The midpoint with the normal sum, valid by the argument above without a test (a test
    // could fail by rounding: the sub-faces' normals equal their parents' only to an ulp).
    // If a parent face was invalid already, the hull build names it.
    Ok((split_edge(mesh, a, b, mid)?, sum))
}

/// The unit normal of face `f` (zero when degenerate).
fn unit_face_normal(mesh: &TriMesh, f: u32) -> DVec3 {
    let t = mesh.triangles()[f as usize];
    let p = |c: usize| mesh.positions()[t[c] as usize];
    (p(1) - p(0)).cross(p(2) - p(0)).normalize_or_zero()
}

/// Whether every face around the new vertex keeps its corners' normals on its positive side
/// (see [`fold_safe_split`]).
fn valid(
    old: &TriMesh,
    normals: &[DVec3],
    refined: &LocalRefinement,
    new_normal: DVec3,
    [a, b]: [u32; 2],
) -> bool {
    let m = refined.new_vertex;
    let unit = |v: u32| -> DVec3 {
        if v == m {
            new_normal.normalize()
        } else {
            normals[v as usize].normalize()
        }
    };
    for f in refined.mesh.topology().vertex_faces(m) {
        let parent = unit_face_normal(old, refined.face_parent[f as usize]);
        let nf = unit_face_normal(&refined.mesh, f);
        if nf == DVec3::ZERO {
            return false;
        }
        let parent_cos = |v: u32| parent.dot(normals[v as usize].normalize());
        for &v in &refined.mesh.triangles()[f as usize] {
            let floor = if v == m {
                parent_cos(a).min(parent_cos(b))
            } else {
                parent_cos(v)
            };
            if nf.dot(unit(v)) < DEFAULT_MIN_NORMAL_COSINE.min(floor) {
                return false;
            }
        }
    }
    true
}

/// The unit Loop limit normal of `v` (the paper's choice of normals, §3), turned to its
/// faces' side; the area-weighted normal where the Loop normal is undefined.
fn loop_normal(mesh: &TriMesh, v: u32) -> DVec3 {
    let mut area = DVec3::ZERO;
    for f in mesh.topology().vertex_faces(v) {
        area += mesh.face_normal(f as usize);
    }
    let l = loop_limit_normal(mesh, v).unwrap_or(DVec3::ZERO);
    let l = if l.length() > 0.0 && l.is_finite() {
        l.normalize()
    } else {
        area.normalize_or_zero()
    };
    if l.dot(area) < 0.0 { -l } else { l }
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
        assert!(valid(&mesh, &normals, &refined, n, [0, 1]));
        // The Butterfly point itself fails the same test.
        let at_butterfly = split_edge(&mesh, 0, 1, butterfly).unwrap();
        assert!(!valid(&mesh, &normals, &at_butterfly, DVec3::Z, [0, 1]));
    }
}

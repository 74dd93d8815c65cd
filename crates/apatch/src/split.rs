//! The face of a nonconvex mesh face: on each side three cubics on the centroid split
//! `[p_b, p_c, c, apex]` (§4.1 of Xu–Huang–Bajaj 2001, "the composite of three cubics").
//!
//! The paper fills the undetermined coefficients "by the Clough–Tocher scheme". We determine
//! all 120 coefficients of the six sub-tetrahedra (three per side) at once, as the solution of
//!
//! `min ‖x − t‖²` subject to `A x = b`,
//!
//! where the hard constraints `A x = b` are exactly the properties F must have — value 0 and
//! gradient `N_v` at the mesh vertices (2.1), the mid-edge transversal gradient `g` at each
//! outer edge (the data of Steps 3–4, shared with the neighbouring face), C1 across the three
//! internal faces of each side and across the face triangle between the sides (Lemma 2.2), and
//! the free parameter at each apex — and the target `t` are the BB coefficients of the local
//! quadric `Q + (f − Q(apex)) τ_apex²` (the family of Theorem 4.2). When the data lie on a
//! quadric the target satisfies every constraint, so F reproduces it exactly; in general the
//! coefficients the constraints leave free are as close to the local quadric as possible. The
//! layer `λ_apex = 2` is constrained only by C1 across the internal faces, which the target
//! satisfies, so it is the target's: `(f + 2 q)/3` as in (4.14), keeping Lemma 2.3's
//! `b t²` lifting for the single-sheet bound.

use crate::constrained::{System, solve};
use crate::cubic::{self, JoinPattern, JoinRow};
use crate::geometry::{add_apex_square, exact_barycentric, foot, snap_rounding_zeros};
use crate::{ApatchError, Quadric, VertexData};
use algesurf_bb::{BbPoly, Tetrahedron};
use glam::DVec3;
use std::cell::RefCell;

/// One side (apex) of a split face: three cubics on `[p_b, p_c, c, apex]`, `a` = 0, 1, 2 the
/// face vertex opposite the sub-tetrahedron (so sub-tetrahedron `a` carries the edge
/// `(p_{a+1}, p_{a+2})`).
#[derive(Clone, Debug)]
pub struct SplitSide {
    /// The sub-tetrahedra.
    pub tets: [Tetrahedron; 3],
    /// The cubic on each sub-tetrahedron.
    pub polys: [BbPoly<f64, 4>; 3],
}

/// Both sides of a split (nonconvex) face.
#[derive(Clone, Debug)]
pub struct SplitFace {
    /// Index 0: the side of the first apex given (the positive side `u`), 1: the other.
    pub sides: Vec<SplitSide>,
    /// Largest violation of the hard constraints after the solve, relative to the size of
    /// the right-hand side: ~1e-14 when they are consistent.
    pub constraint_residual: f64,
}

/// The joins of a split face's sub-tetrahedra, which share their faces in a fixed way
/// (sub-tetrahedron `a` of a side is `[p_{a+1}, p_{a+2}, c, apex]`):
/// * around one side, sub-tetrahedron `a` and `a + 1` share `[p_{a+2}, c, apex]`: the next
///   one's vertices 0, 2, 3 are this one's 1, 2, 3, and its vertex 1 (`p_a`) is new;
/// * across the face, the two sides' sub-tetrahedra `a` share `[p_{a+1}, p_{a+2}, c]`, and
///   only the apex (vertex 3) differs.
const AROUND_A_SIDE: JoinPattern = JoinPattern::new([Some(1), None, Some(2), Some(3)]);
const ACROSS_THE_FACE: JoinPattern = JoinPattern::new([Some(0), Some(1), Some(2), None]);

impl System {
    /// C0 and C1 between tetrahedra `ia` and `ib` (indices into `tets`), which share a face
    /// as `pattern` says: every coefficient of B with `λ_opp ≤ 1` equals A's continuation
    /// (Lemma 2.2), the blossom of A at B's vertices. The shared vertices are exact unit
    /// vectors in A's coordinates (`exact_barycentric`), so the blossom needs no general
    /// weights: a C0 condition (`λ_opp = 0`) says that B's coefficient equals A's coefficient
    /// of the same shared vertices' powers (an equal pair, [`System::push_equal`]), and a C1
    /// row (`λ_opp = 1`) is one de Casteljau step,
    /// `b_λ = Σ_k v_k a_{μ + e_k}` with `μ` the shared part of `λ` in A's indexing and `v`
    /// B's opposite vertex in A's coordinates (snapped, `snap_rounding_zeros`).
    fn join(&mut self, tets: &[Tetrahedron], ia: usize, ib: usize, pattern: &JoinPattern) {
        let (a, b) = (&tets[ia], &tets[ib]);
        debug_assert!(
            (0..4).all(|s| (0..4).find(|&k| a.vertex(k) == b.vertex(s)) == pattern.shared[s]),
            "the tetrahedra share the pattern's face"
        );
        let v = snap_rounding_zeros(exact_barycentric(a, b.vertex(pattern.opp)));
        // The C1 rows' terms of A: the same for every row but for A's coefficient, so the
        // non-zero ones are picked out once per join.
        let mut up_terms = [(0usize, 0.0f64); 4];
        let mut len = 0;
        for k in 0..4 {
            if v[k] != 0.0 {
                up_terms[len] = (k, -v[k]);
                len += 1;
            }
        }
        let up_terms = &up_terms[..len];
        for &(rank, join_row) in &pattern.rows {
            let row = ib * 20 + rank;
            match join_row {
                JoinRow::C0(mu) => self.push_equal(row, ia * 20 + mu),
                JoinRow::C1(up) => {
                    let (mut cols, mut weights) = ([row; 5], [1.0; 5]);
                    for (t, &(k, w)) in up_terms.iter().enumerate() {
                        cols[t + 1] = ia * 20 + up[k];
                        weights[t + 1] = w;
                    }
                    // One monomorphised push per row length (the row's own coefficient and
                    // the 1–4 non-zero weights of `v`): see `System::push_array`. `v` sums
                    // to 1, so `len ≥ 1`; the slice push is only a fallback.
                    match len {
                        1 => self.push_array(&first::<_, 2>(&cols), &first(&weights), 0.0),
                        2 => self.push_array(&first::<_, 3>(&cols), &first(&weights), 0.0),
                        3 => self.push_array(&first::<_, 4>(&cols), &first(&weights), 0.0),
                        4 => self.push_array(&cols, &weights, 0.0),
                        _ => self.push_slice(&cols[..=len], &weights[..=len], 0.0),
                    }
                }
            }
        }
    }
}

/// The first `K` entries of a join row's terms (`K ≤ 5`).
fn first<T: Copy, const K: usize>(x: &[T; 5]) -> [T; K] {
    std::array::from_fn(|i| x[i])
}

impl SplitSide {
    /// Raises this side's apex value by `delta`: every piece gains exactly `δ·τ_apex²`
    /// (`geometry::add_apex_square`), which meets every hard constraint with 1 at the apex, so
    /// no second solve is needed.
    pub(crate) fn raise_apex(&mut self, delta: f64) {
        for poly in &mut self.polys {
            add_apex_square(poly, delta);
        }
    }
}

impl SplitFace {
    /// Builds the split cubics of a face with vertices `v` (face order), apexes (one or two;
    /// the first is normally `u`, the second `v`), the mid-edge gradients of the edges opposite
    /// each vertex, the local quadric `q` and the free parameters `f[side]` (value of F at each
    /// apex).
    pub fn new(
        v: [VertexData; 3],
        apexes: &[DVec3],
        mid_gradients: [DVec3; 3],
        q: &Quadric,
        f: &[f64],
    ) -> Result<Self, ApatchError> {
        if apexes.is_empty() || apexes.len() > 2 || f.len() != apexes.len() {
            return Err(ApatchError::Inconsistent(
                "a split face needs one or two apexes with one free parameter each".into(),
            ));
        }
        let (x, residual, tets) = ROWS.with(|rows| {
            let mut sys = rows.borrow_mut();
            sys.clear();
            let (target, tets) = constraints(&mut sys, v, apexes, mid_gradients, q, f)?;
            let (x, residual, _) = solve(&sys, &target);
            Ok::<_, ApatchError>((x, residual, tets))
        })?;
        let mut sides = Vec::with_capacity(apexes.len());
        for side in 0..apexes.len() {
            let polys = std::array::from_fn(|a| {
                let ti = side * 3 + a;
                BbPoly::new(3, x[ti * 20..ti * 20 + 20].to_vec()).expect("20 coefficients")
            });
            let ts = std::array::from_fn(|a| tets[side * 3 + a]);
            sides.push(SplitSide { tets: ts, polys });
        }
        Ok(SplitFace {
            sides,
            constraint_residual: residual,
        })
    }
}

thread_local! {
    /// The constraint rows of the split faces built on this thread, one system emptied and
    /// refilled for each: two apexes make 120 rows of at most 444 terms and 90 equal pairs
    /// (~9 KB), and allocating them anew for every face put mimalloc's slow path in the
    /// bunny's profile.
    static ROWS: RefCell<System> = RefCell::new(System::with_capacity(128, 448));
}

/// The hard constraints of [`SplitFace::new`], pushed to `sys` (empty), and the target
/// coefficients and the sub-tetrahedra (side after side, sub-tetrahedron `a` of a side
/// carrying the edge `(p_{a+1}, p_{a+2})`).
fn constraints(
    sys: &mut System,
    v: [VertexData; 3],
    apexes: &[DVec3],
    mid_gradients: [DVec3; 3],
    q: &Quadric,
    f: &[f64],
) -> Result<(Vec<f64>, Vec<Tetrahedron>), ApatchError> {
    let p = v.map(|x| x.position);
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let mut tets = Vec::with_capacity(3 * apexes.len());
    for &apex in apexes {
        for a in 0..3 {
            let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
            tets.push(Tetrahedron::new([p[b], p[cc], c, apex])?);
        }
    }
    let n = tets.len() * 20;
    // Two apexes: 48 vertex, 12 mid-edge and 6 apex rows, and 9 joins of 6 C1 rows and 10
    // equal pairs (C1 rows have up to 5 terms, mid-edge rows up to 10: 120 rows of 444
    // terms at most), which the caller's system has room for.
    for side in 0..apexes.len() {
        let t0 = side * 3;
        for a in 0..3 {
            let ti = t0 + a;
            let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
            // Vertex data (2.1) at p_b and p_c: local vertices 0 and 1.
            for (local, vert) in [(0usize, b), (1usize, cc)] {
                let coeffs = algesurf_bb::continuity::vertex_and_neighbours(
                    tets[ti].vertices(),
                    3,
                    local,
                    0.0,
                    v[vert].gradient,
                )?;
                for (l, val) in coeffs {
                    sys.push([(ti * 20 + cubic::rank3(l), 1.0)], val);
                }
            }
            // Mid-edge transversal gradient at m = (p_b + p_c)/2 in two directions. The
            // barycentric directions are used as solved, rounding included: `x − foot(x)`
            // has an exact zero component in exact arithmetic (on the apex for the centroid's
            // direction, on the centroid for the apex's), but zeroing the computed one moves
            // the row off the direction `d` its right side `dᵀg` is for, and on small faces
            // far from the origin the sub-tetrahedra are ill-conditioned enough for that to
            // show: the value mismatch across the edge facets grew fivefold (cow, Suzanne),
            // and taking `d` back from the zeroed direction made the constraints inconsistent.
            let g = mid_gradients[a];
            for x in [c, apexes[side]] {
                let d = x - foot(x, p[b], p[cc]);
                let dir = tets[ti].barycentric_direction(d);
                // D_d F(m) = 3 b[d, m, m] at m = (p_b + p_c)/2, the first edge's midpoint
                // (see `cubic`).
                let weights = cubic::first_edge_midpoint_weights(dir).map(|w| 3.0 * w);
                let (mut cols, mut ws) = ([0usize; 20], [0.0f64; 20]);
                let mut len = 0;
                for (r, &w) in weights.iter().enumerate() {
                    if w != 0.0 {
                        cols[len] = ti * 20 + r;
                        ws[len] = w;
                        len += 1;
                    }
                }
                sys.push_slice(&cols[..len], &ws[..len], d.dot(g));
            }
            // Free parameter at the apex.
            sys.push([(ti * 20 + 19, 1.0)], f[side]);
        }
        // C1 across the internal faces [p_v, c, apex] of this side.
        for a in 0..3 {
            sys.join(&tets, t0 + a, t0 + (a + 1) % 3, &AROUND_A_SIDE);
        }
    }
    // C1 across the sub-triangles of the face between the two sides.
    if apexes.len() == 2 {
        for a in 0..3 {
            sys.join(&tets, a, 3 + a, &ACROSS_THE_FACE);
        }
    }
    // Target: the local quadric family Q + (f − Q(apex)) τ_apex², per sub-tetrahedron
    // (the quadric's blossom about the face centroid, see `Quadric::cubic_coefficients`).
    let mut target = vec![0.0; n];
    for (ti, tet) in tets.iter().enumerate() {
        let side = ti / 3;
        // The family of Theorem 4.2: Q + (f − Q(apex)) τ_apex²; τ_apex² is 1/3 on the
        // layer λ_apex = 2 and 1 at the apex (`apex_square`).
        let lift = f[side] - q.value(apexes[side]);
        let mut coeffs = q.cubic_coefficients(tet, c);
        for (l, x) in cubic::INDICES3.iter().zip(coeffs.iter_mut()) {
            match l[3] {
                2 => *x += lift / 3.0,
                3 => *x += lift,
                _ => {}
            }
        }
        target[ti * 20..ti * 20 + 20].copy_from_slice(&coeffs);
    }
    Ok((target, tets))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constrained::nearest_solution;
    use algesurf_mesh::test_rng::Lcg;

    /// Forcing unknowns in cascade changes neither the feasible set nor the objective, so the
    /// nearest point is the dense solve's, to rounding: for apexes on a slanted line and on
    /// the normal through the centroid (the hull places them on one line through it, which
    /// keeps the constraints consistent; the snapped zeros and the 2 × 2 pairs make the cascade
    /// reach far, which is checked too).
    #[test]
    fn cascade_elimination_gives_the_dense_solution() {
        let mut rng = Lcg(7);
        let mut worst = 0.0f64;
        for case in 0..40 {
            let p = [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.1, 0.0),
                DVec3::new(0.3, 0.9, 0.0),
            ]
            .map(|x| x + 0.2 * rng.vec() + DVec3::splat(3.0));
            let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let axis = (normal + 0.3 * rng.vec()).normalize();
            let (u, w) = if case % 2 == 0 {
                (c + 0.4 * axis, c - 0.3 * axis)
            } else {
                (c + 0.2 * normal, c - 0.7 * normal)
            };
            let grads = [0, 1, 2].map(|_| normal + 0.4 * rng.vec());
            let v = [0, 1, 2].map(|a| VertexData {
                position: p[a],
                gradient: grads[a],
            });
            let mids = [0, 1, 2].map(|a| (grads[(a + 1) % 3] + grads[(a + 2) % 3]) * 0.5);
            let q = Quadric {
                a: glam::DMat3::from_diagonal(DVec3::new(0.3, -0.2, 0.5)),
                b: normal,
                c: -normal.dot(c),
            };
            let f = [q.value(u) + 0.05, q.value(w) - 0.05];
            let mut sys = System::with_capacity(224, 640);
            let (target, _) = constraints(&mut sys, v, &[u, w], mids, &q, &f).unwrap();
            let (fast, r_fast, rows_fast) = nearest_solution(&sys, &target, true);
            // The plan of this pattern replays the cascade: every pivot passes, the same
            // number of rows is left, and the point is the same to rounding.
            let (plan, r_plan, rows_plan) =
                crate::constrained::planned(&sys, &target).expect("the plan's pivots pass");
            assert_eq!(rows_plan, rows_fast, "case {case}");
            assert!(r_plan < 1e-12, "case {case}: {r_plan:e}");
            let (dense, r_dense, rows_dense) = nearest_solution(&sys, &target, false);
            // The cascade reaches far (the bunny's split faces: 6 rows left of 54).
            assert!(
                rows_fast <= 8 && rows_dense >= 40,
                "case {case}: {rows_fast} rows left to the dense solve, {rows_dense} without the cascade"
            );
            assert!(
                r_fast < 1e-12 && r_dense < 1e-12,
                "case {case}: {r_fast:e} {r_dense:e}"
            );
            let size = dense.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let diff = fast
                .iter()
                .zip(&dense)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            let diff_plan = plan
                .iter()
                .zip(&dense)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            worst = worst.max(diff / size).max(diff_plan / size);
        }
        assert!(worst < 1e-11, "largest relative difference {worst:e}");
    }

    #[test]
    fn rounding_zeros_are_snapped_and_the_total_kept() {
        let x = snap_rounding_zeros([-1.0, -1.0 + 1e-16, 3.0, 3e-16]);
        assert_eq!(x[3], 0.0);
        assert_eq!(
            x,
            [-1.0, -1.0 + 1e-16, 3.0 + 3e-16, 0.0],
            "moved onto the largest"
        );
        let d = snap_rounding_zeros([0.5, -0.25, -0.25, 1e-9]);
        assert_eq!(
            d,
            [0.5, -0.25, -0.25, 1e-9],
            "1e-9 is geometry, not rounding"
        );
    }
}

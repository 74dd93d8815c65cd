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

use crate::cubic;
use crate::geometry::{apex_square, exact_barycentric, foot};
use crate::rowspace::RowBasis;
use crate::{ApatchError, Quadric, VertexData};
use algesurf_bb::{BbPoly, PowerPoly, Tetrahedron, multi_index};
use glam::DVec3;

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

/// Linear form of a coefficient of `poly_b` (on `b`) induced by `poly_a` (on `a`): weights
/// `w_μ` with `coeff_B(λ) = Σ_μ w_μ x_A[μ]` = blossom of A at B's vertices (Lemma 2.2).
fn continuation_weights(a: &Tetrahedron, b: &Tetrahedron, lambda: [usize; 4]) -> [f64; 20] {
    let verts: [[f64; 4]; 4] = std::array::from_fn(|s| exact_barycentric(a, b.vertex(s)));
    let [x, y, z] = cubic::blossom_args(&verts, lambda);
    cubic::blossom_weights(x, y, z)
}

struct System {
    rows: Vec<(Vec<(usize, f64)>, f64)>,
}

impl System {
    fn push(&mut self, terms: Vec<(usize, f64)>, rhs: f64) {
        self.rows.push((terms, rhs));
    }

    /// C0 and C1 between tetrahedra `ia` and `ib` (indices into `tets`), which share a face:
    /// every coefficient of B with `λ_opp ≤ 1` equals A's continuation (Lemma 2.2).
    fn join(&mut self, tets: &[Tetrahedron], ia: usize, ib: usize) {
        let (a, b) = (&tets[ia], &tets[ib]);
        let opp = (0..4)
            .find(|&s| !(0..4).any(|k| a.vertex(k) == b.vertex(s)))
            .expect("the tetrahedra share a face");
        for lambda in multi_index::iter::<4>(3).filter(|l| l[opp] <= 1) {
            let w = continuation_weights(a, b, lambda);
            let mut terms = vec![(ib * 20 + multi_index::rank(&lambda), 1.0)];
            terms.extend(
                w.iter()
                    .enumerate()
                    .filter(|(_, x)| **x != 0.0)
                    .map(|(r, x)| (ia * 20 + r, -x)),
            );
            self.push(terms, 0.0);
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
        let p = v.map(|x| x.position);
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let mut tets = Vec::new();
        for &apex in apexes {
            for a in 0..3 {
                let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
                tets.push(Tetrahedron::new([p[b], p[cc], c, apex])?);
            }
        }
        let n = tets.len() * 20;
        let mut sys = System { rows: Vec::new() };
        for side in 0..apexes.len() {
            let t0 = side * 3;
            for a in 0..3 {
                let ti = t0 + a;
                let (b, cc) = ((a + 1) % 3, (a + 2) % 3);
                // Vertex data (2.1) at p_b and p_c: local vertices 0 and 1.
                for (local, vert) in [(0usize, b), (1usize, cc)] {
                    let coeffs = algesurf_bb::continuity::vertex_coefficients(
                        tets[ti].vertices(),
                        3,
                        local,
                        0.0,
                        v[vert].gradient,
                        None,
                    )?;
                    for (l, val) in coeffs {
                        sys.push(vec![(ti * 20 + multi_index::rank(&l), 1.0)], val);
                    }
                }
                // Mid-edge transversal gradient at m = (p_b + p_c)/2 in two directions.
                let m = [0.5, 0.5, 0.0, 0.0];
                let g = mid_gradients[a];
                for d in [
                    c - foot(c, p[b], p[cc]),
                    apexes[side] - foot(apexes[side], p[b], p[cc]),
                ] {
                    let dir = tets[ti].barycentric_direction(d);
                    // D_d F(m) = 3 b[d, m, m] (see `cubic`).
                    let weights = cubic::blossom_weights(dir, m, m).map(|w| 3.0 * w);
                    let terms = weights.iter().enumerate().filter(|(_, w)| **w != 0.0);
                    sys.push(terms.map(|(r, w)| (ti * 20 + r, *w)).collect(), d.dot(g));
                }
                // Free parameter at the apex.
                sys.push(vec![(ti * 20 + 19, 1.0)], f[side]);
            }
            // C1 across the internal faces [p_v, c, apex] of this side.
            for a in 0..3 {
                sys.join(&tets, t0 + a, t0 + (a + 1) % 3);
            }
        }
        // C1 across the sub-triangles of the face between the two sides.
        if apexes.len() == 2 {
            for a in 0..3 {
                sys.join(&tets, a, 3 + a);
            }
        }
        // Target: the local quadric family Q + (f − Q(apex)) τ_apex², per sub-tetrahedron.
        let mut target = vec![0.0; n];
        for (ti, tet) in tets.iter().enumerate() {
            let side = ti / 3;
            let mut qp = PowerPoly::<4>::zero(2);
            let a = q.a.to_cols_array_2d();
            let names = [
                [2, 0, 0],
                [0, 2, 0],
                [0, 0, 2],
                [1, 1, 0],
                [1, 0, 1],
                [0, 1, 1],
            ];
            let vals = [
                a[0][0],
                a[1][1],
                a[2][2],
                2.0 * a[0][1],
                2.0 * a[0][2],
                2.0 * a[1][2],
            ];
            for (e, val) in names.iter().zip(vals) {
                qp.set(e, val)?;
            }
            qp.set(&[1, 0, 0], q.b.x)?;
            qp.set(&[0, 1, 0], q.b.y)?;
            qp.set(&[0, 0, 1], q.b.z)?;
            qp.set(&[0, 0, 0], q.c)?;
            // The family of Theorem 4.2: Q + (f − Q(apex)) τ_apex².
            let lift = f[side] - q.value(apexes[side]);
            let poly = BbPoly::from_cartesian(tet, &qp, 3)?.add_poly(&apex_square().scale(lift));
            for (r, c) in poly.coeffs().iter().enumerate() {
                target[ti * 20 + r] = *c;
            }
        }
        // Rows with a single unknown (vertex data (2.1), the free parameters) fix that
        // coefficient exactly; eliminate them so they carry no solver rounding, then find the
        // point of the remaining constraint set nearest the target: x = t + A⁺ (b − A t).
        let mut fixed: Vec<Option<f64>> = vec![None; n];
        for (terms, r) in &sys.rows {
            if let [(j, w)] = terms.as_slice() {
                fixed[*j] = Some(r / w);
            }
        }
        let free: Vec<usize> = (0..n).filter(|&j| fixed[j].is_none()).collect();
        let mut col = vec![usize::MAX; n];
        for (k, &j) in free.iter().enumerate() {
            col[j] = k;
        }
        let coupled: Vec<&(Vec<(usize, f64)>, f64)> =
            sys.rows.iter().filter(|(t, _)| t.len() > 1).collect();
        let (m, nf) = (coupled.len(), free.len());
        // Dense row-major m × nf (about 150 × 66 for two apexes).
        let mut a_mat = vec![0.0; m * nf];
        let mut rhs = vec![0.0; m];
        for (i, (terms, r)) in coupled.iter().enumerate() {
            let mut v = *r;
            for &(j, w) in terms {
                match fixed[j] {
                    Some(x) => v -= w * x,
                    None => a_mat[i * nf + col[j]] += w,
                }
            }
            rhs[i] = v;
        }
        let residual_of = |x: &[f64]| -> Vec<f64> {
            (0..m)
                .map(|i| {
                    let row = &a_mat[i * nf..(i + 1) * nf];
                    rhs[i] - row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>()
                })
                .collect()
        };
        let mut xf: Vec<f64> = free.iter().map(|&j| target[j]).collect();
        // Rank cut at 1e-10 of the largest row norm: the constraint matrix repeats conditions
        // (C0 rows shared by several joins), so exactly dependent rows appear (their residual
        // after projection is ~1e-16); rows are O(1).
        let basis = RowBasis::new(&a_mat, m, nf, 1e-10);
        // x = t + A⁺ (b − A t), then two steps of iterative refinement: each reduces the
        // constraint residual by the solver's relative accuracy again, ending at rounding level.
        for _ in 0..3 {
            let step = basis.solve(&residual_of(&xf));
            for (x, s) in xf.iter_mut().zip(step) {
                *x += s;
            }
        }
        let amax = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let residual =
            amax(&residual_of(&xf)) / amax(&rhs).max(amax(&target)).max(f64::MIN_POSITIVE);
        let mut x = vec![0.0; n];
        for j in 0..n {
            x[j] = match fixed[j] {
                Some(v) => v,
                None => xf[col[j]],
            };
        }
        let mut sides = Vec::new();
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

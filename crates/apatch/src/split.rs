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
use crate::geometry::{exact_barycentric, foot};
use crate::rowspace::RowBasis;
use crate::{ApatchError, Quadric, VertexData};
use algesurf_bb::{BbPoly, Tetrahedron, multi_index};
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
/// `verts`: B's vertices in A's barycentric coordinates (`exact_barycentric`).
fn continuation_weights(verts: &[[f64; 4]; 4], lambda: [usize; 4]) -> [f64; 20] {
    let [x, y, z] = cubic::blossom_args(verts, lambda);
    cubic::blossom_weights(x, y, z)
}

/// Sparse constraint rows `Σ w_j x_j = rhs`, stored flat (one allocation for all terms: a
/// split face has about 200 rows).
struct System {
    /// `(j, w_j)` of every row, row after row.
    terms: Vec<(usize, f64)>,
    /// Row `i`'s terms are `terms[starts[i]..starts[i + 1]]`.
    starts: Vec<usize>,
    rhs: Vec<f64>,
}

impl System {
    fn with_capacity(rows: usize, terms: usize) -> Self {
        let mut starts = Vec::with_capacity(rows + 1);
        starts.push(0);
        System {
            terms: Vec::with_capacity(terms),
            starts,
            rhs: Vec::with_capacity(rows),
        }
    }

    fn push(&mut self, terms: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.terms.extend(terms);
        self.starts.push(self.terms.len());
        self.rhs.push(rhs);
    }

    /// The rows as `(terms, rhs)`.
    fn rows(&self) -> impl Iterator<Item = (&[(usize, f64)], f64)> + '_ {
        self.starts
            .windows(2)
            .zip(&self.rhs)
            .map(|(w, r)| (&self.terms[w[0]..w[1]], *r))
    }

    /// C0 and C1 between tetrahedra `ia` and `ib` (indices into `tets`), which share a face:
    /// every coefficient of B with `λ_opp ≤ 1` equals A's continuation (Lemma 2.2).
    fn join(&mut self, tets: &[Tetrahedron], ia: usize, ib: usize) {
        let (a, b) = (&tets[ia], &tets[ib]);
        let opp = (0..4)
            .find(|&s| !(0..4).any(|k| a.vertex(k) == b.vertex(s)))
            .expect("the tetrahedra share a face");
        let verts: [[f64; 4]; 4] = std::array::from_fn(|s| exact_barycentric(a, b.vertex(s)));
        for lambda in multi_index::iter::<4>(3).filter(|l| l[opp] <= 1) {
            let w = continuation_weights(&verts, lambda);
            let terms = std::iter::once((ib * 20 + multi_index::rank(&lambda), 1.0)).chain(
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
        // Two apexes: 48 vertex, 12 mid-edge, 6 apex rows and 9 joins of 16 rows (C0 rows
        // have 2 terms, C1 rows up to 21).
        let mut sys = System::with_capacity(224, 2048);
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
                        sys.push([(ti * 20 + multi_index::rank(&l), 1.0)], val);
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
                    sys.push(terms.map(|(r, w)| (ti * 20 + r, *w)), d.dot(g));
                }
                // Free parameter at the apex.
                sys.push([(ti * 20 + 19, 1.0)], f[side]);
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
        // Target: the local quadric family Q + (f − Q(apex)) τ_apex², per sub-tetrahedron
        // (the quadric's blossom about the face centroid, see `Quadric::cubic_coefficients`).
        let mut target = vec![0.0; n];
        for (ti, tet) in tets.iter().enumerate() {
            let side = ti / 3;
            // The family of Theorem 4.2: Q + (f − Q(apex)) τ_apex²; τ_apex² is 1/3 on the
            // layer λ_apex = 2 and 1 at the apex (`apex_square`).
            let lift = f[side] - q.value(apexes[side]);
            let mut coeffs = q.cubic_coefficients(tet, c);
            for (l, x) in multi_index::iter::<4>(3).zip(coeffs.iter_mut()) {
                match l[3] {
                    2 => *x += lift / 3.0,
                    3 => *x += lift,
                    _ => {}
                }
            }
            target[ti * 20..ti * 20 + 20].copy_from_slice(&coeffs);
        }
        let (x, residual) = nearest_solution(&sys, &target);
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

/// Representative of `j`'s class in the union–find forest `parent` (with path halving).
fn find(parent: &mut [usize], mut j: usize) -> usize {
    while parent[j] != j {
        parent[j] = parent[parent[j]];
        j = parent[j];
    }
    j
}

/// The point nearest `target` (Euclidean norm over all coefficients) satisfying every row,
/// and the largest violation of the rows relative to the size of the right-hand side and the
/// target.
///
/// Two kinds of rows are eliminated exactly before the least-squares solve, so they carry no
/// solver rounding and the dense system is small (about 60 × 35 instead of 150 × 66 for two
/// apexes):
/// * rows with a single unknown (vertex data (2.1), the free parameters) fix it;
/// * rows `x_i − x_j = 0` (the C0 rows of the joins: a coefficient on a shared facet is the
///   blossom of its neighbour at the facet's vertices, which `exact_barycentric` makes exact
///   unit vectors, so the weights are exactly one 1) merge `i` and `j` into one unknown.
///
/// A class of merged unknowns that contains a fixed one takes its fixed value (the
/// least-indexed one; fixed values in one class agree to rounding, which the residual shows).
/// A free class `c` of `w_c` coefficients with targets `t_j` is one unknown `y_c`, and
/// `Σ_{j∈c} (y_c − t_j)² = w_c (y_c − t̄_c)² + const` with `t̄_c` their mean, so the problem is
/// `min Σ_c w_c (y_c − t̄_c)²` subject to the remaining rows `A y = r`: with
/// `y = t̄ + W^{−1/2} z` it is the minimum-norm `z` of `A W^{−1/2} z = r − A t̄`, which
/// [`RowBasis`] gives. In exact arithmetic this is the same point as the minimum-norm
/// correction of all unknowns (the same objective on the same feasible set).
fn nearest_solution(sys: &System, target: &[f64]) -> (Vec<f64>, f64) {
    let n = target.len();
    let mut fixed: Vec<Option<f64>> = vec![None; n];
    let mut parent: Vec<usize> = (0..n).collect();
    let is_equality = |terms: &[(usize, f64)], rhs: f64| matches!(terms, [(_, a), (_, b)] if *a == 1.0 && *b == -1.0 && rhs == 0.0);
    for (terms, r) in sys.rows() {
        if let [(j, w)] = terms {
            fixed[*j] = Some(r / w);
        } else if is_equality(terms, r) {
            let (a, b) = (find(&mut parent, terms[0].0), find(&mut parent, terms[1].0));
            // The smaller index represents the class (deterministic whatever the row order).
            let (lo, hi) = (a.min(b), a.max(b));
            parent[hi] = lo;
        }
    }
    // Per class (indexed by its representative): fixed value, size, target sum, column.
    let mut class_fixed: Vec<Option<f64>> = vec![None; n];
    let mut size = vec![0usize; n];
    let mut tsum = vec![0.0; n];
    for j in 0..n {
        let c = find(&mut parent, j);
        size[c] += 1;
        tsum[c] += target[j];
        if class_fixed[c].is_none() {
            class_fixed[c] = fixed[j];
        }
    }
    let mut col = vec![usize::MAX; n];
    let mut classes = Vec::new();
    for c in 0..n {
        if parent[c] == c && class_fixed[c].is_none() {
            col[c] = classes.len();
            classes.push(c);
        }
    }
    let nf = classes.len();
    // Column scale 1/√w_c and the class means t̄_c.
    let inv_sqrt_w: Vec<f64> = classes
        .iter()
        .map(|&c| 1.0 / (size[c] as f64).sqrt())
        .collect();
    let mean: Vec<f64> = classes.iter().map(|&c| tsum[c] / size[c] as f64).collect();
    // Value of unknown j: fixed, or its class's.
    let class_of: Vec<usize> = (0..n).map(|j| find(&mut parent, j)).collect();
    let coupled: Vec<(&[(usize, f64)], f64)> = sys
        .rows()
        .filter(|(t, r)| t.len() > 1 && !is_equality(t, *r))
        .collect();
    let m = coupled.len();
    // Dense row-major m × nf in the unknowns y (unscaled), and the reduced right-hand side.
    let mut a_mat = vec![0.0; m * nf];
    let mut rhs = vec![0.0; m];
    for (i, &(terms, r)) in coupled.iter().enumerate() {
        let mut v = r;
        for &(j, w) in terms {
            let c = class_of[j];
            match class_fixed[c] {
                Some(x) => v -= w * fixed[j].unwrap_or(x),
                None => a_mat[i * nf + col[c]] += w,
            }
        }
        rhs[i] = v;
    }
    let residual_of = |y: &[f64]| -> Vec<f64> {
        (0..m)
            .map(|i| {
                let row = &a_mat[i * nf..(i + 1) * nf];
                rhs[i] - row.iter().zip(y).map(|(a, b)| a * b).sum::<f64>()
            })
            .collect()
    };
    let mut scaled = a_mat.clone();
    for row in scaled.chunks_exact_mut(nf.max(1)) {
        for (a, s) in row.iter_mut().zip(&inv_sqrt_w) {
            *a *= s;
        }
    }
    // Rank cut at 1e-10 of the largest row norm: the constraint rows repeat conditions (C1
    // rows implied by others around the apex), so exactly dependent rows appear (their
    // residual after projection is ~1e-16); rows are O(1) and the column scales in [1/√6, 1].
    let basis = RowBasis::new(&scaled, m, nf, 1e-10);
    // y = t̄ + W^{−1/2} A_s⁺ (r − A t̄), then two steps of iterative refinement: each reduces
    // the constraint residual by the solver's relative accuracy again, ending at rounding level.
    let mut y = mean;
    for _ in 0..3 {
        let step = basis.solve(&residual_of(&y));
        for ((x, s), w) in y.iter_mut().zip(step).zip(&inv_sqrt_w) {
            *x += s * w;
        }
    }
    let x: Vec<f64> = (0..n)
        .map(|j| match (fixed[j], class_fixed[class_of[j]]) {
            (Some(v), _) | (None, Some(v)) => v,
            (None, None) => y[col[class_of[j]]],
        })
        .collect();
    // Residual of every row, eliminated ones included, at the final coefficients.
    let amax = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = amax(
        &mut sys
            .rows()
            .map(|(terms, r)| r - terms.iter().map(|&(j, w)| w * x[j]).sum::<f64>()),
    );
    let size_of = amax(&mut sys.rhs.iter().copied()).max(amax(&mut target.iter().copied()));
    (x, worst / size_of.max(f64::MIN_POSITIVE))
}

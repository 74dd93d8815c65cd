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
use crate::geometry::{exact_barycentric, foot, snap_rounding_zeros};
use crate::rowspace::RowBasis;
use crate::{ApatchError, Quadric, VertexData};
use algesurf_bb::{BbPoly, Tetrahedron};
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
    /// every coefficient of B with `λ_opp ≤ 1` equals A's continuation (Lemma 2.2), the
    /// blossom of A at B's vertices. The shared vertices are exact unit vectors in A's
    /// coordinates (`exact_barycentric`), so the blossom needs no general weights: a C0 row
    /// (`λ_opp = 0`) says that B's coefficient equals A's coefficient of the same shared
    /// vertices' powers, and a C1 row (`λ_opp = 1`) is one de Casteljau step,
    /// `b_λ = Σ_k v_k a_{μ + e_k}` with `μ` the shared part of `λ` in A's indexing and `v`
    /// B's opposite vertex in A's coordinates (snapped, `snap_rounding_zeros`).
    fn join(&mut self, tets: &[Tetrahedron], ia: usize, ib: usize) {
        let (a, b) = (&tets[ia], &tets[ib]);
        // A's vertex index of each of B's vertices, `None` for the one not shared.
        let shared: [Option<usize>; 4] =
            std::array::from_fn(|s| (0..4).find(|&k| a.vertex(k) == b.vertex(s)));
        let opp = shared
            .iter()
            .position(Option::is_none)
            .expect("the tetrahedra share a face");
        let v = snap_rounding_zeros(exact_barycentric(a, b.vertex(opp)));
        for lambda in cubic::INDICES3.into_iter().filter(|l| l[opp] <= 1) {
            let mut mu = [0usize; 4];
            for (s, k) in shared.iter().enumerate() {
                if let Some(k) = k {
                    mu[*k] += lambda[s];
                }
            }
            let row = (ib * 20 + cubic::rank3(lambda), 1.0);
            if lambda[opp] == 0 {
                self.push([row, (ia * 20 + cubic::rank3(mu), -1.0)], 0.0);
            } else {
                let terms = (0..4).filter(|&k| v[k] != 0.0).map(|k| {
                    let mut up = mu;
                    up[k] += 1;
                    (ia * 20 + cubic::rank3(up), -v[k])
                });
                self.push(std::iter::once(row).chain(terms), 0.0);
            }
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
        let (sys, target, tets) = constraints(v, apexes, mid_gradients, q, f)?;
        let (x, residual, _) = nearest_solution(&sys, &target, true);
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

/// The hard constraints of [`SplitFace::new`], the target coefficients and the
/// sub-tetrahedra (side after side, sub-tetrahedron `a` of a side carrying the edge
/// `(p_{a+1}, p_{a+2})`).
fn constraints(
    v: [VertexData; 3],
    apexes: &[DVec3],
    mid_gradients: [DVec3; 3],
    q: &Quadric,
    f: &[f64],
) -> Result<(System, Vec<f64>, Vec<Tetrahedron>), ApatchError> {
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
    // have 2 terms, C1 rows up to 5, mid-edge rows up to 10: 624 terms at most).
    let mut sys = System::with_capacity(224, 640);
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
            let m = [0.5, 0.5, 0.0, 0.0];
            let g = mid_gradients[a];
            for x in [c, apexes[side]] {
                let d = x - foot(x, p[b], p[cc]);
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
        for (l, x) in cubic::INDICES3.iter().zip(coeffs.iter_mut()) {
            match l[3] {
                2 => *x += lift / 3.0,
                3 => *x += lift,
                _ => {}
            }
        }
        target[ti * 20..ti * 20 + 20].copy_from_slice(&coeffs);
    }
    Ok((sys, target, tets))
}

/// Smallest pivot with which rows force unknowns (see [`force_determined_unknowns`]): a
/// single row's coefficient relative to its largest weight, and a pair's determinant
/// relative to `|a₁₁a₂₂| + |a₁₂a₂₁|`. 1e-3 bounds the growth of the rows' rounding in the
/// forced values by 10³; rows with a smaller pivot go to the dense solve, whose rank cut
/// decides them.
const FORCE_PIVOT: f64 = 1e-3;

/// The rows of [`force_determined_unknowns`] with the known values moved to the right side, in
/// flat arrays (two allocations per array, not one per row and class: a split face runs
/// this 54 k times on the bunny).
struct Cascade<'a> {
    /// Row `i`'s free classes with their summed coefficients are
    /// `free[start[i]..start[i] + len[i]]`.
    free: Vec<(usize, f64)>,
    start: Vec<usize>,
    len: Vec<usize>,
    /// Per row: the reduced right side.
    rhs: Vec<f64>,
    /// Per row: its largest weight (for the pivot tests).
    wmax: Vec<f64>,
    /// Per row: used to force values, or left without free classes.
    done: Vec<bool>,
    /// The rows class `c` is free in: `rows_of[class_start[c]..class_start[c + 1]]`.
    rows_of: Vec<usize>,
    class_start: Vec<usize>,
    /// Rows left with one free class, to look at.
    queue: Vec<usize>,
    class_fixed: &'a mut [Option<f64>],
}

impl Cascade<'_> {
    fn row(&self, i: usize) -> &[(usize, f64)] {
        &self.free[self.start[i]..self.start[i] + self.len[i]]
    }

    /// Fixes class `c` at `y`: every row it is free in moves it to the right side.
    fn fix(&mut self, c: usize, y: f64) {
        self.class_fixed[c] = Some(y);
        for r in self.class_start[c]..self.class_start[c + 1] {
            let i = self.rows_of[r];
            if self.done[i] {
                continue;
            }
            let (s, n) = (self.start[i], self.len[i]);
            if let Some(k) = self.free[s..s + n].iter().position(|t| t.0 == c) {
                let w = self.free[s + k].1;
                self.free.swap(s + k, s + n - 1);
                self.len[i] = n - 1;
                self.rhs[i] -= w * y;
                match n - 1 {
                    0 => self.done[i] = true,
                    1 => self.queue.push(i),
                    _ => {}
                }
            }
        }
    }

    /// Forces what single rows force, in cascade.
    fn singles(&mut self) {
        while let Some(i) = self.queue.pop() {
            if self.done[i] || self.len[i] != 1 {
                continue;
            }
            let (c, w) = self.row(i)[0];
            if w.abs() >= FORCE_PIVOT * self.wmax[i] {
                self.done[i] = true;
                self.fix(c, self.rhs[i] / w);
            }
        }
    }

    /// Forces the two classes of every pair of rows left with the same two free classes and
    /// a nonsingular 2 × 2 system (one pair per two classes; a pair whose classes an earlier
    /// one fixed waits). Whether anything was forced.
    fn pairs(&mut self) -> bool {
        let mut keyed: Vec<([usize; 2], usize)> = (0..self.len.len())
            .filter(|&i| {
                let f = self.row(i);
                !self.done[i]
                    && f.len() == 2
                    && f[0].1.abs().max(f[1].1.abs()) >= FORCE_PIVOT * self.wmax[i]
            })
            .map(|i| {
                let f = self.row(i);
                let (a, b) = (f[0].0, f[1].0);
                ([a.min(b), a.max(b)], i)
            })
            .collect();
        // By classes, then row order: deterministic.
        keyed.sort_unstable();
        let mut forced = false;
        for group in keyed.chunk_by(|x, y| x.0 == y.0) {
            let [ca, cb] = group[0].0;
            let coef =
                |f: &[(usize, f64)], c: usize| f.iter().find(|t| t.0 == c).map_or(0.0, |t| t.1);
            'pairs: for (k, &(_, i)) in group.iter().enumerate() {
                for &(_, j) in &group[k + 1..] {
                    if self.class_fixed[ca].is_some() || self.class_fixed[cb].is_some() {
                        break 'pairs;
                    }
                    let (a11, a12) = (coef(self.row(i), ca), coef(self.row(i), cb));
                    let (a21, a22) = (coef(self.row(j), ca), coef(self.row(j), cb));
                    let det = a11 * a22 - a12 * a21;
                    if det.abs() >= FORCE_PIVOT * ((a11 * a22).abs() + (a12 * a21).abs()) {
                        let (ri, rj) = (self.rhs[i], self.rhs[j]);
                        self.done[i] = true;
                        self.done[j] = true;
                        self.fix(ca, (ri * a22 - a12 * rj) / det);
                        self.fix(cb, (a11 * rj - a21 * ri) / det);
                        forced = true;
                        break 'pairs;
                    }
                }
            }
        }
        forced
    }
}

/// Rows that, with the values known so far, leave one free class `c` force its value, and two
/// rows that leave the same two free classes force both (their 2 × 2 system, when it is
/// nonsingular): every feasible point has these values, so fixing them leaves the feasible
/// set, and with it the nearest point, unchanged. Repeated until nothing is forced (a work
/// list: fixing a class visits only the rows it is in); the rows used are removed (rows left
/// without a free unknown too: they are implied, and the final residual still checks them).
/// The vertex data fix the coefficients next to the face's vertices; each sub-tetrahedron's
/// two mid-edge rows then force the two coefficients next to the middle of its edge (a 2 × 2
/// system: the computed direction from the centroid keeps a rounding-size weight on the apex
/// side), after which most C1 rows force one coefficient each, so the dense solve is left
/// with the coefficients about the centroid–apex axes.
///
/// Pivots: a single class's coefficient must be at least [`FORCE_PIVOT`] of the row's largest
/// weight, and a pair's determinant at least that fraction of `|a₁₁a₂₂| + |a₁₂a₂₁|` (so it
/// does not cancel by more), with each row's free coefficients not below that fraction of its
/// largest weight; rows that fail go to the dense solve.
fn force_determined_unknowns(
    rows: &mut Vec<(&[(usize, f64)], f64)>,
    class_of: &[usize],
    fixed: &[Option<f64>],
    class_fixed: &mut [Option<f64>],
) {
    let nr = rows.len();
    let n = class_of.len();
    let mut cascade = Cascade {
        free: Vec::with_capacity(rows.iter().map(|r| r.0.len()).sum()),
        start: Vec::with_capacity(nr),
        len: Vec::with_capacity(nr),
        rhs: Vec::with_capacity(nr),
        wmax: Vec::with_capacity(nr),
        done: vec![false; nr],
        rows_of: Vec::new(),
        class_start: vec![0; n + 1],
        queue: Vec::new(),
        class_fixed,
    };
    for (i, &(terms, r)) in rows.iter().enumerate() {
        let s = cascade.free.len();
        let (mut v, mut wmax) = (r, 0.0f64);
        for &(j, w) in terms {
            wmax = wmax.max(w.abs());
            let c = class_of[j];
            match cascade.class_fixed[c] {
                Some(x) => v -= w * fixed[j].unwrap_or(x),
                None => match cascade.free[s..].iter_mut().find(|t| t.0 == c) {
                    Some(t) => t.1 += w,
                    None => cascade.free.push((c, w)),
                },
            }
        }
        let len = cascade.free.len() - s;
        for k in s..s + len {
            cascade.class_start[cascade.free[k].0 + 1] += 1;
        }
        match len {
            0 => cascade.done[i] = true,
            1 => cascade.queue.push(i),
            _ => {}
        }
        cascade.start.push(s);
        cascade.len.push(len);
        cascade.rhs.push(v);
        cascade.wmax.push(wmax);
    }
    // Rows per class, by counting (compressed rows).
    for c in 0..n {
        cascade.class_start[c + 1] += cascade.class_start[c];
    }
    let mut next = cascade.class_start.clone();
    cascade.rows_of = vec![0; cascade.class_start[n]];
    for i in 0..nr {
        for k in cascade.start[i]..cascade.start[i] + cascade.len[i] {
            let c = cascade.free[k].0;
            cascade.rows_of[next[c]] = i;
            next[c] += 1;
        }
    }
    // Rows in order (the queue is a stack).
    cascade.queue.reverse();
    loop {
        cascade.singles();
        if !cascade.pairs() {
            break;
        }
    }
    let done = cascade.done;
    let mut k = 0;
    rows.retain(|_| {
        k += 1;
        !done[k - 1]
    });
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
/// Three kinds of rows are eliminated exactly before the least-squares solve, so they carry no
/// solver rounding and the dense system is small (6 × 8 instead of 150 × 66 for two apexes, on
/// every one of the Stanford bunny's 54,039 split faces; 54 × 29 before the third kind):
/// * rows with a single unknown (vertex data (2.1), the free parameters) fix it;
/// * rows `x_i − x_j = 0` (the C0 rows of the joins: a coefficient on a shared facet is the
///   blossom of its neighbour at the facet's vertices, which `exact_barycentric` makes exact
///   unit vectors, so the weights are exactly one 1) merge `i` and `j` into one unknown;
/// * rows that, once the first two kinds are in, leave a single free unknown force it, and
///   pairs of rows left with the same two free unknowns force both, in cascade
///   ([`force_determined_unknowns`]).
///
/// A class of merged unknowns that contains a fixed one takes its fixed value (the
/// least-indexed one; fixed values in one class agree to rounding, which the residual shows).
/// A free class `c` of `w_c` coefficients with targets `t_j` is one unknown `y_c`, and
/// `Σ_{j∈c} (y_c − t_j)² = w_c (y_c − t̄_c)² + const` with `t̄_c` their mean, so the problem is
/// `min Σ_c w_c (y_c − t̄_c)²` subject to the remaining rows `A y = r`: with
/// `y = t̄ + W^{−1/2} z` it is the minimum-norm `z` of `A W^{−1/2} z = r − A t̄`, which
/// [`RowBasis`] gives. In exact arithmetic this is the same point as the minimum-norm
/// correction of all unknowns (the same objective on the same feasible set).
///
/// `cascade: false` skips the third kind of elimination (the tests compare the two).
/// Returns the coefficients, the relative residual and the number of rows left to the dense
/// solve.
fn nearest_solution(sys: &System, target: &[f64], cascade: bool) -> (Vec<f64>, f64, usize) {
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
    // Value of unknown j: fixed, or its class's.
    let class_of: Vec<usize> = (0..n).map(|j| find(&mut parent, j)).collect();
    let mut coupled: Vec<(&[(usize, f64)], f64)> = sys
        .rows()
        .filter(|(t, r)| t.len() > 1 && !is_equality(t, *r))
        .collect();
    if cascade {
        force_determined_unknowns(&mut coupled, &class_of, &fixed, &mut class_fixed);
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
    (x, worst / size_of.max(f64::MIN_POSITIVE), m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

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
            let (sys, target, _) = constraints(v, &[u, w], mids, &q, &f).unwrap();
            let (fast, r_fast, rows_fast) = nearest_solution(&sys, &target, true);
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
            worst = worst.max(diff / size);
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

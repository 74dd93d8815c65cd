//! The constrained least-squares problem of the split faces ([`crate::split`]): the point
//! nearest a target satisfying sparse constraint rows, `min ‖x − t‖²` subject to `A x = b`.
//!
//! Most rows are eliminated exactly before a small dense solve ([`nearest_solution`]): single
//! unknowns are fixed, equal unknowns merged, and rows that then force one or two unknowns
//! force them in cascade. Which eliminations happen, and in what order, depends on the rows'
//! pattern (which unknowns each row has) and on pivot tests; every split face of a mesh
//! normally has the same pattern. [`solve`] therefore works the cascade out once per pattern,
//! symbolically ([`Plan`]), and for each face only redoes its arithmetic, checking each pivot;
//! where a pivot fails, the face takes the general path.

use crate::rowspace::RowBasis;
use std::cell::RefCell;
use std::rc::Rc;

/// Sparse constraint rows `Σ w_j x_j = rhs`, stored flat (one allocation for all terms: a
/// split face has about 200 rows).
pub(crate) struct System {
    /// `(j, w_j)` of every row, row after row.
    pub(crate) terms: Vec<(usize, f64)>,
    /// Row `i`'s terms are `terms[starts[i]..starts[i + 1]]`.
    pub(crate) starts: Vec<usize>,
    pub(crate) rhs: Vec<f64>,
}

impl System {
    pub(crate) fn with_capacity(rows: usize, terms: usize) -> Self {
        let mut starts = Vec::with_capacity(rows + 1);
        starts.push(0);
        System {
            terms: Vec::with_capacity(terms),
            starts,
            rhs: Vec::with_capacity(rows),
        }
    }

    pub(crate) fn push(&mut self, terms: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.terms.extend(terms);
        self.starts.push(self.terms.len());
        self.rhs.push(rhs);
    }

    /// The rows as `(terms, rhs)`.
    pub(crate) fn rows(&self) -> impl Iterator<Item = (&[(usize, f64)], f64)> + '_ {
        self.starts
            .windows(2)
            .zip(&self.rhs)
            .map(|(w, r)| (&self.terms[w[0]..w[1]], *r))
    }

    /// Row `i` as `(terms, rhs)`.
    fn row(&self, i: usize) -> (&[(usize, f64)], f64) {
        (&self.terms[self.starts[i]..self.starts[i + 1]], self.rhs[i])
    }

    /// What each row is to the eliminations (see [`RowKind`]).
    fn kinds(&self) -> impl Iterator<Item = RowKind> + '_ {
        self.rows().map(|(terms, r)| RowKind::of(terms, r))
    }
}

/// How [`nearest_solution`] treats a row before the cascade.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RowKind {
    /// One unknown: fixes it.
    Single,
    /// `x_i − x_j = 0` with weights exactly 1 and −1: merges the two unknowns.
    Equality,
    /// Anything else: for the cascade and the dense solve.
    Coupled,
}

impl RowKind {
    fn of(terms: &[(usize, f64)], rhs: f64) -> RowKind {
        match terms {
            [_] => RowKind::Single,
            [(_, a), (_, b)] if *a == 1.0 && *b == -1.0 && rhs == 0.0 => RowKind::Equality,
            _ => RowKind::Coupled,
        }
    }
}

/// One elimination of the cascade: a row that forces one class, or two rows that force two.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    Single {
        row: usize,
        class: usize,
    },
    Pair {
        rows: [usize; 2],
        classes: [usize; 2],
    },
}

/// One pivot test of the cascade and its outcome (see [`force_determined_unknowns`]): a row
/// left with one free class, a row left with two (whether it may enter a pair), and a pair's
/// determinant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PivotTest {
    Single {
        row: usize,
        class: usize,
        pass: bool,
    },
    PairRow {
        row: usize,
        classes: [usize; 2],
        pass: bool,
    },
    Pair {
        rows: [usize; 2],
        classes: [usize; 2],
        pass: bool,
    },
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
    /// What was forced, in order, and every pivot test with its outcome, in order (row
    /// indices local to the cascade): what a [`Plan`] replays and checks.
    steps: Vec<Step>,
    tests: Vec<PivotTest>,
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
            let pass = w.abs() >= FORCE_PIVOT * self.wmax[i];
            self.tests.push(PivotTest::Single {
                row: i,
                class: c,
                pass,
            });
            if pass {
                self.done[i] = true;
                self.steps.push(Step::Single { row: i, class: c });
                self.fix(c, self.rhs[i] / w);
            }
        }
    }

    /// Forces the two classes of every pair of rows left with the same two free classes and
    /// a nonsingular 2 × 2 system (one pair per two classes; a pair whose classes an earlier
    /// one fixed waits). Whether anything was forced.
    fn pairs(&mut self) -> bool {
        let mut keyed: Vec<([usize; 2], usize)> = Vec::new();
        for i in 0..self.len.len() {
            let f = self.row(i);
            if self.done[i] || f.len() != 2 {
                continue;
            }
            let ((a, wa), (b, wb)) = (f[0], f[1]);
            let pass = wa.abs().max(wb.abs()) >= FORCE_PIVOT * self.wmax[i];
            self.tests.push(PivotTest::PairRow {
                row: i,
                classes: [a, b],
                pass,
            });
            if pass {
                keyed.push(([a.min(b), a.max(b)], i));
            }
        }
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
                    let pass = pair_pivot(a11, a12, a21, a22);
                    self.tests.push(PivotTest::Pair {
                        rows: [i, j],
                        classes: [ca, cb],
                        pass,
                    });
                    if pass {
                        let (ri, rj) = (self.rhs[i], self.rhs[j]);
                        self.done[i] = true;
                        self.done[j] = true;
                        self.steps.push(Step::Pair {
                            rows: [i, j],
                            classes: [ca, cb],
                        });
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
///
/// Every pivot test is recorded with its outcome ([`Cascaded`]; row indices into `rows`): each
/// test reads only the summed weights of a row's classes and its largest weight, never a
/// forced value, so a [`Plan`] can check them all on another system of the same pattern.
fn force_determined_unknowns(
    rows: &[(&[(usize, f64)], f64)],
    class_of: &[usize],
    fixed: &[Option<f64>],
    class_fixed: &mut [Option<f64>],
) -> Cascaded {
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
        steps: Vec::new(),
        tests: Vec::new(),
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
    Cascaded {
        done: cascade.done,
        steps: cascade.steps,
        tests: cascade.tests,
    }
}

/// What [`force_determined_unknowns`] did: per row, whether it was used (or left without a
/// free class); the steps and the pivot tests, in order.
struct Cascaded {
    done: Vec<bool>,
    steps: Vec<Step>,
    tests: Vec<PivotTest>,
}

/// The pair test of the cascade: the 2 × 2 determinant must not cancel below [`FORCE_PIVOT`]
/// of `|a₁₁a₂₂| + |a₁₂a₂₁|`.
fn pair_pivot(a11: f64, a12: f64, a21: f64, a22: f64) -> bool {
    let det = a11 * a22 - a12 * a21;
    det.abs() >= FORCE_PIVOT * ((a11 * a22).abs() + (a12 * a21).abs())
}

/// Representative of `j`'s class in the union–find forest `parent` (with path halving).
fn find(parent: &mut [usize], mut j: usize) -> usize {
    while parent[j] != j {
        parent[j] = parent[parent[j]];
        j = parent[j];
    }
    j
}

/// The first two kinds of elimination of [`nearest_solution`]: unknowns fixed by single rows,
/// and classes of unknowns merged by equality rows (union–find; the least index represents a
/// class, whatever the row order).
struct Classes {
    /// Per unknown: the value its single row gives it (the last such row's).
    fixed: Vec<Option<f64>>,
    /// Per unknown: its class's representative.
    class_of: Vec<usize>,
    /// Per representative: the unknown whose fixed value the class takes (the least-indexed
    /// fixed one; fixed values in one class agree to rounding, which the residual shows).
    fixed_from: Vec<Option<usize>>,
    /// Per representative: the number of unknowns in the class.
    size: Vec<usize>,
    /// The rows with one unknown, and the coupled rows, in order.
    singles: Vec<usize>,
    coupled: Vec<usize>,
}

impl Classes {
    fn new(sys: &System, n: usize) -> Classes {
        let mut fixed: Vec<Option<f64>> = vec![None; n];
        let mut parent: Vec<usize> = (0..n).collect();
        let (mut singles, mut coupled) = (Vec::new(), Vec::new());
        for (i, ((terms, r), kind)) in sys.rows().zip(sys.kinds()).enumerate() {
            match kind {
                RowKind::Single => {
                    let (j, w) = terms[0];
                    fixed[j] = Some(r / w);
                    singles.push(i);
                }
                RowKind::Equality => {
                    let (a, b) = (find(&mut parent, terms[0].0), find(&mut parent, terms[1].0));
                    let (lo, hi) = (a.min(b), a.max(b));
                    parent[hi] = lo;
                }
                RowKind::Coupled => coupled.push(i),
            }
        }
        let class_of: Vec<usize> = (0..n).map(|j| find(&mut parent, j)).collect();
        let mut fixed_from = vec![None; n];
        let mut size = vec![0usize; n];
        for (j, &c) in class_of.iter().enumerate() {
            size[c] += 1;
            if fixed_from[c].is_none() && fixed[j].is_some() {
                fixed_from[c] = Some(j);
            }
        }
        Classes {
            fixed,
            class_of,
            fixed_from,
            size,
            singles,
            coupled,
        }
    }

    /// Per representative: the fixed value of the class, if any.
    fn class_fixed(&self) -> Vec<Option<f64>> {
        self.fixed_from
            .iter()
            .map(|f| f.and_then(|j| self.fixed[j]))
            .collect()
    }
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
/// solve. [`solve`] gives the same point (to rounding) faster.
pub(crate) fn nearest_solution(
    sys: &System,
    target: &[f64],
    cascade: bool,
) -> (Vec<f64>, f64, usize) {
    let n = target.len();
    let classes = Classes::new(sys, n);
    let mut class_fixed = classes.class_fixed();
    let dense: Vec<usize> = if cascade {
        let rows: Vec<(&[(usize, f64)], f64)> =
            classes.coupled.iter().map(|&i| sys.row(i)).collect();
        let done =
            force_determined_unknowns(&rows, &classes.class_of, &classes.fixed, &mut class_fixed)
                .done;
        classes
            .coupled
            .iter()
            .zip(done)
            .filter_map(|(&i, d)| (!d).then_some(i))
            .collect()
    } else {
        classes.coupled.clone()
    };
    dense_solve(
        sys,
        target,
        &classes.fixed,
        &classes.class_of,
        &class_fixed,
        &classes.size,
        &dense,
    )
}

/// The least-squares solve left after the eliminations: the free classes' values nearest
/// their targets' means subject to the rows `dense` (indices into `sys`), every unknown's value,
/// and the residual of all rows (see [`nearest_solution`]).
fn dense_solve(
    sys: &System,
    target: &[f64],
    fixed: &[Option<f64>],
    class_of: &[usize],
    class_fixed: &[Option<f64>],
    size: &[usize],
    dense: &[usize],
) -> (Vec<f64>, f64, usize) {
    let n = target.len();
    let mut tsum = vec![0.0; n];
    for (j, &c) in class_of.iter().enumerate() {
        tsum[c] += target[j];
    }
    let coupled: Vec<(&[(usize, f64)], f64)> = dense.iter().map(|&i| sys.row(i)).collect();
    let mut col = vec![usize::MAX; n];
    let mut classes = Vec::new();
    for c in 0..n {
        if class_of[c] == c && class_fixed[c].is_none() {
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

/// The eliminations [`nearest_solution`] made on one system, recorded so that another system
/// of the same pattern can skip deciding them ([`solve`]).
///
/// The cascade's decisions depend on the pattern of the rows (each row's unknowns in order and
/// its [`RowKind`]) and on the outcomes of its pivot tests, and on nothing else: each test reads
/// only a row's summed weights and largest weight ([`PivotTest`]). So a system of the same
/// pattern on which every recorded test has the recorded outcome ([`Plan::fits`]) gets exactly
/// the recorded steps from the cascade; the plan replays them ([`Plan::replay`]) without the
/// cascade's bookkeeping. Two plans that both fit one system record the same steps (the
/// cascade's, on that system), so the result is a function of the system alone, whichever face
/// recorded the plan and whatever the thread count.
struct Plan {
    /// The pattern: row starts, every term's unknown, every row's kind.
    starts: Vec<usize>,
    columns: Vec<usize>,
    kinds: Vec<RowKind>,
    /// As in [`Classes`] (a function of the pattern).
    singles: Vec<usize>,
    class_of: Vec<usize>,
    fixed_from: Vec<Option<usize>>,
    size: Vec<usize>,
    /// The cascade's pivot tests and steps, with rows as indices into the system.
    tests: Vec<PivotTest>,
    steps: Vec<Step>,
    /// The rows left for the dense solve.
    dense: Vec<usize>,
}

impl Plan {
    /// Records the eliminations of [`nearest_solution`] on `sys` (`n` unknowns).
    fn record(sys: &System, n: usize) -> Plan {
        let classes = Classes::new(sys, n);
        let rows: Vec<(&[(usize, f64)], f64)> =
            classes.coupled.iter().map(|&i| sys.row(i)).collect();
        let mut class_fixed = classes.class_fixed();
        let cascaded =
            force_determined_unknowns(&rows, &classes.class_of, &classes.fixed, &mut class_fixed);
        let row = |k: usize| classes.coupled[k];
        Plan {
            starts: sys.starts.clone(),
            columns: sys.terms.iter().map(|t| t.0).collect(),
            kinds: sys.kinds().collect(),
            tests: cascaded
                .tests
                .into_iter()
                .map(|t| match t {
                    PivotTest::Single {
                        row: k,
                        class,
                        pass,
                    } => PivotTest::Single {
                        row: row(k),
                        class,
                        pass,
                    },
                    PivotTest::PairRow {
                        row: k,
                        classes,
                        pass,
                    } => PivotTest::PairRow {
                        row: row(k),
                        classes,
                        pass,
                    },
                    PivotTest::Pair {
                        rows,
                        classes,
                        pass,
                    } => PivotTest::Pair {
                        rows: rows.map(row),
                        classes,
                        pass,
                    },
                })
                .collect(),
            steps: cascaded
                .steps
                .into_iter()
                .map(|s| match s {
                    Step::Single { row: k, class } => Step::Single { row: row(k), class },
                    Step::Pair { rows, classes } => Step::Pair {
                        rows: rows.map(row),
                        classes,
                    },
                })
                .collect(),
            dense: classes
                .coupled
                .iter()
                .zip(cascaded.done)
                .filter_map(|(&i, d)| (!d).then_some(i))
                .collect(),
            singles: classes.singles,
            class_of: classes.class_of,
            fixed_from: classes.fixed_from,
            size: classes.size,
        }
    }

    /// The summed weight of class `c` in row `i` of `sys`, in term order as the cascade sums
    /// it (so the same bits), and the row's largest weight.
    fn weight(&self, sys: &System, i: usize, c: usize) -> (f64, f64) {
        let (terms, _) = sys.row(i);
        let (mut w, mut wmax) = (0.0, 0.0f64);
        for &(j, x) in terms {
            wmax = wmax.max(x.abs());
            if self.class_of[j] == c {
                w += x;
            }
        }
        (w, wmax)
    }

    /// Whether `sys` (`n` unknowns) has this plan's pattern and every recorded pivot test has
    /// its recorded outcome on it: then the cascade makes exactly this plan's steps on `sys`.
    fn fits(&self, sys: &System, n: usize) -> bool {
        let pattern = self.class_of.len() == n
            && self.starts == sys.starts
            && self.columns.iter().zip(&sys.terms).all(|(a, t)| *a == t.0)
            && self.kinds.iter().copied().eq(sys.kinds());
        pattern
            && self.tests.iter().all(|t| match *t {
                PivotTest::Single { row, class, pass } => {
                    let (w, wmax) = self.weight(sys, row, class);
                    (w.abs() >= FORCE_PIVOT * wmax) == pass
                }
                PivotTest::PairRow {
                    row,
                    classes: [a, b],
                    pass,
                } => {
                    let ((wa, wmax), (wb, _)) =
                        (self.weight(sys, row, a), self.weight(sys, row, b));
                    (wa.abs().max(wb.abs()) >= FORCE_PIVOT * wmax) == pass
                }
                PivotTest::Pair {
                    rows: [i, j],
                    classes: [a, b],
                    pass,
                } => {
                    let (a11, a12) = (self.weight(sys, i, a).0, self.weight(sys, i, b).0);
                    let (a21, a22) = (self.weight(sys, j, a).0, self.weight(sys, j, b).0);
                    pair_pivot(a11, a12, a21, a22) == pass
                }
            })
    }

    /// [`nearest_solution`] of a system the plan [fits](Plan::fits): the recorded steps with
    /// `sys`'s numbers (each forced value from its row, the known values moved to the right
    /// side in term order), then the dense solve. `None` only if a step meets a value not
    /// known yet, which a fitting system cannot do.
    fn replay(&self, sys: &System, target: &[f64]) -> Option<(Vec<f64>, f64, usize)> {
        let n = target.len();
        let mut fixed: Vec<Option<f64>> = vec![None; n];
        for &i in &self.singles {
            let (terms, r) = sys.row(i);
            fixed[terms[0].0] = Some(r / terms[0].1);
        }
        let mut class_fixed: Vec<Option<f64>> = self
            .fixed_from
            .iter()
            .map(|f| f.and_then(|j| fixed[j]))
            .collect();
        // Row `i` with its known values moved to the right side: the summed weights of the
        // classes `a` and `b` and the reduced right side.
        let reduce = |class_fixed: &[Option<f64>], i: usize, a: usize, b: usize| {
            let (terms, r) = sys.row(i);
            let (mut wa, mut wb, mut v) = (0.0, 0.0, r);
            for &(j, w) in terms {
                let c = self.class_of[j];
                if c == a {
                    wa += w;
                } else if c == b {
                    wb += w;
                } else {
                    v -= w * fixed[j].or(class_fixed[c])?;
                }
            }
            Some((wa, wb, v))
        };
        for step in &self.steps {
            match *step {
                Step::Single { row, class } => {
                    let (w, _, v) = reduce(&class_fixed, row, class, usize::MAX)?;
                    class_fixed[class] = Some(v / w);
                }
                Step::Pair {
                    rows: [i, j],
                    classes: [ca, cb],
                } => {
                    let (a11, a12, ri) = reduce(&class_fixed, i, ca, cb)?;
                    let (a21, a22, rj) = reduce(&class_fixed, j, ca, cb)?;
                    let det = a11 * a22 - a12 * a21;
                    class_fixed[ca] = Some((ri * a22 - a12 * rj) / det);
                    class_fixed[cb] = Some((a11 * rj - a21 * ri) / det);
                }
            }
        }
        Some(dense_solve(
            sys,
            target,
            &fixed,
            &self.class_of,
            &class_fixed,
            &self.size,
            &self.dense,
        ))
    }
}

/// How many plans each thread keeps ([`solve`]): a mesh's split faces normally share one;
/// a few more cover faces whose pivot tests or snapped zeros differ. Evicting a plan only
/// costs recording it again: the results do not depend on what is cached (see [`Plan`]).
const PLANS_PER_THREAD: usize = 8;

thread_local! {
    static PLANS: RefCell<Vec<Rc<Plan>>> = const { RefCell::new(Vec::new()) };
}

/// The point of [`nearest_solution`] (with the cascade) by a [`Plan`]: a kept one that fits
/// `sys`, or one recorded on `sys` now. Either way the cascade's own steps on `sys`, so the
/// result depends on `sys` alone; the replay computes the forced values in its own order, so
/// it agrees with [`nearest_solution`] to rounding, not to the bit.
pub(crate) fn solve(sys: &System, target: &[f64]) -> (Vec<f64>, f64, usize) {
    let n = target.len();
    let plan = PLANS.with(|cell| {
        let mut plans = cell.borrow_mut();
        if let Some(p) = plans.iter().find(|p| p.fits(sys, n)) {
            return Rc::clone(p);
        }
        let p = Rc::new(Plan::record(sys, n));
        if plans.len() == PLANS_PER_THREAD {
            plans.remove(0);
        }
        plans.push(Rc::clone(&p));
        p
    });
    plan.replay(sys, target)
        .unwrap_or_else(|| nearest_solution(sys, target, true))
}

/// The replay of the plan recorded on `sys` itself (for tests).
#[cfg(test)]
pub(crate) fn planned(sys: &System, target: &[f64]) -> Option<(Vec<f64>, f64, usize)> {
    Plan::record(sys, target.len()).replay(sys, target)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `x0 = 1` (single row); `x1 − x2 = 0` (equality); a pair in the classes of x1 and x3
    /// (`w x1 + x3 = 1`, `x2 + w x3 = 0.5`, singular for w = ±1); a row forcing x4 once x0 and
    /// x3 are known.
    fn system(w: f64) -> System {
        let mut sys = System::with_capacity(5, 9);
        sys.push([(0, 2.0)], 2.0);
        sys.push([(1, 1.0), (2, -1.0)], 0.0);
        sys.push([(1, w), (3, 1.0)], 1.0);
        sys.push([(2, 1.0), (3, w)], 0.5);
        sys.push([(0, 1.0), (3, w), (4, 1.0)], 3.0);
        sys
    }

    /// A plan recorded on one system fits another of the same pattern exactly when the
    /// cascade's pivot tests come out the same, and then its steps are the cascade's there.
    #[test]
    fn a_plan_fits_where_the_cascade_decides_the_same() {
        let (a, b) = (system(0.5), system(-3.0));
        let (pa, pb) = (Plan::record(&a, 5), Plan::record(&b, 5));
        assert_eq!(pa.steps, pb.steps);
        assert_eq!(pa.tests, pb.tests);
        assert_eq!(pa.dense, pb.dense);
        assert!(pa.fits(&b, 5) && pb.fits(&a, 5));
        assert_eq!(
            pa.steps,
            vec![
                Step::Pair {
                    rows: [2, 3],
                    classes: [1, 3]
                },
                Step::Single { row: 4, class: 4 }
            ]
        );
        // w = 1: the pair is singular, its test fails, and the cascade leaves both rows (and
        // the last, which needs x3) to the dense solve.
        let singular = system(1.0);
        assert!(!pa.fits(&singular, 5));
        let ps = Plan::record(&singular, 5);
        assert!(ps.steps.is_empty(), "{:?}", ps.steps);
        assert_eq!(ps.dense, vec![2, 3, 4]);
        // Another pattern does not fit, nor another unknown count.
        let mut other = system(0.5);
        other.terms[2].0 = 3;
        assert!(!pa.fits(&other, 5));
        assert!(!pa.fits(&a, 6));
    }

    /// The replay is the general solve's point, to rounding, and [`solve`] returns it whether
    /// or not a plan was kept.
    #[test]
    fn the_replay_is_the_general_solution() {
        let target = [0.3, -0.1, 0.2, 0.0, 1.0];
        for w in [0.5, -3.0, 1.0, 2.5] {
            let sys = system(w);
            let (x, r, m) = planned(&sys, &target).expect("a fitting plan replays");
            let (y, ry, my) = nearest_solution(&sys, &target, true);
            assert_eq!(m, my, "w = {w}");
            // w = 1 makes the pair's rows contradict each other (x1 + x3 = 1 and 0.5): both
            // paths then leave the same least-squares residual.
            let consistent = w != 1.0;
            assert!(
                (r - ry).abs() < 1e-15 && (r < 1e-15) == consistent,
                "w = {w}: {r} {ry}"
            );
            for (u, v) in x.iter().zip(&y) {
                assert!((u - v).abs() < 1e-15, "w = {w}: {x:?} {y:?}");
            }
            // Twice: recorded the first time, kept the second; the same bits both times.
            assert_eq!(solve(&sys, &target).0, x, "w = {w}");
            assert_eq!(solve(&sys, &target).0, x, "w = {w}");
        }
    }
}

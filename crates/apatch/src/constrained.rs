//! The constrained least-squares problem of the split faces ([`crate::split`]): the point
//! nearest a target satisfying sparse constraint rows, `min ‖x − t‖²` subject to `A x = b`.
//!
//! Most rows are eliminated exactly before a small dense solve ([`nearest_solution`]): single
//! unknowns are fixed, equal unknowns merged, and rows that then force one or two unknowns
//! force them in cascade. Which eliminations happen, and in what order, depends on the rows'
//! pattern (which unknowns each row has) and on the outcomes of pivot tests; every split face
//! of a mesh normally has the same pattern and the same outcomes. [`solve`] therefore records
//! the cascade's tests and steps once (`plan::Plan`) and, for every face on which each
//! recorded test comes out the same, replays the steps with the face's numbers instead of
//! deciding them again.

use crate::rowspace::RowBasis;
use algesurf_bb::extremes::{max_abs, max_not_nan};

mod plan;
#[cfg(test)]
pub(crate) use plan::planned;
pub(crate) use plan::solve;

/// Sparse constraint rows `Σ w_j x_j = rhs`, stored flat (one allocation for all terms: a
/// split face has 120 rows and 90 equal pairs).
///
/// The terms' unknowns and weights are two arrays, not one of pairs: a `plan::Plan` checks
/// that a system has its pattern, which is then `starts` and `cols` compared as two blocks of
/// integers (`memcmp`) instead of term by term: `Plan::fits` went from ~10 k to ~6 k
/// instructions a split face (bunny, `cachegrind`: a second `fits` per face cost 540 M
/// instructions before, 326 M after).
///
/// Conditions `x_i = x_j` known as such when they are made (the split faces' C0 joins, 90 of
/// their 210 conditions) are kept as pairs ([`System::push_equal`]), not rows: all the solver
/// does with them is merge two unknowns into one class, as with any row `x_i − x_j = 0`
/// ([`RowKind::Equality`]), and as pairs they cost neither two terms each in every pass over
/// the rows nor a place in the pattern's rows.
pub(crate) struct System {
    /// Every term's unknown `j`, row after row.
    pub(crate) cols: Vec<usize>,
    /// Every term's weight `w_j`, in the order of `cols`.
    pub(crate) weights: Vec<f64>,
    /// Row `i`'s terms are `cols[starts[i]..starts[i + 1]]` with those `weights`.
    pub(crate) starts: Vec<usize>,
    pub(crate) rhs: Vec<f64>,
    /// Pairs `[i, j]` of unknowns constrained equal, `x_i − x_j = 0`, in the order given.
    pub(crate) equal: Vec<[usize; 2]>,
}

/// One row of a [`System`]: its terms' unknowns, their weights (as long) and its right side.
pub(crate) type Row<'a> = (&'a [usize], &'a [f64], f64);

impl System {
    pub(crate) fn with_capacity(rows: usize, terms: usize) -> Self {
        let mut starts = Vec::with_capacity(rows + 1);
        starts.push(0);
        System {
            cols: Vec::with_capacity(terms),
            weights: Vec::with_capacity(terms),
            starts,
            rhs: Vec::with_capacity(rows),
            equal: Vec::new(),
        }
    }

    /// Empties the system, keeping its allocations (see `split`'s reuse of one per thread).
    pub(crate) fn clear(&mut self) {
        self.cols.clear();
        self.weights.clear();
        self.starts.truncate(1);
        self.rhs.clear();
        self.equal.clear();
    }

    /// Adds the condition `x_i = x_j`: the row `x_i − x_j = 0`, kept as a pair (see
    /// [`System`]).
    #[inline]
    pub(crate) fn push_equal(&mut self, i: usize, j: usize) {
        self.equal.push([i, j]);
    }

    /// Appends the row `Σ w_j x_j = rhs` with `terms` its `(j, w_j)`.
    #[inline]
    pub(crate) fn push(&mut self, terms: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        for (j, w) in terms {
            self.cols.push(j);
            self.weights.push(w);
        }
        self.starts.push(self.cols.len());
        self.rhs.push(rhs);
    }

    /// [`System::push`] of a row whose unknowns and weights are at hand in slices (of equal
    /// length): one capacity check per array. Extending by a filtered iterator (no exact
    /// length) checked the capacity term by term, ~170 instructions a row for the split faces'
    /// 16 rows per join (`cachegrind`, bunny). A slice iterator's `extend` still calls
    /// `memcpy` once per array (~30 instructions for the 2–10 terms of a row; seen in the
    /// disassembly): rows of a length known in advance take [`System::push_array`].
    ///
    /// # Panics
    /// If `cols` and `weights` differ in length (a bug in the caller).
    #[inline]
    pub(crate) fn push_slice(&mut self, cols: &[usize], weights: &[f64], rhs: f64) {
        assert_eq!(cols.len(), weights.len(), "one weight per unknown");
        self.cols.extend(cols.iter().copied());
        self.weights.extend(weights.iter().copied());
        self.starts.push(self.cols.len());
        self.rhs.push(rhs);
    }

    /// [`System::push_slice`] of a row of exactly `K` terms. With the length a constant, the
    /// copies are a few moves in line: `push_slice`'s `extend` becomes a `memcpy` call per
    /// array (two per row), and for the 2–5 terms of a split face's C1 rows those calls were
    /// ~1.3 % of the bunny's `perf` samples (`memmove` under `join`, 5.8 M calls).
    #[inline]
    pub(crate) fn push_array<const K: usize>(
        &mut self,
        cols: &[usize; K],
        weights: &[f64; K],
        rhs: f64,
    ) {
        self.cols.extend_from_slice(cols);
        self.weights.extend_from_slice(weights);
        self.starts.push(self.cols.len());
        self.rhs.push(rhs);
    }

    /// The rows as `(unknowns, weights, rhs)`.
    pub(crate) fn rows(&self) -> impl Iterator<Item = Row<'_>> + '_ {
        self.starts
            .windows(2)
            .zip(&self.rhs)
            .map(|(w, r)| (&self.cols[w[0]..w[1]], &self.weights[w[0]..w[1]], *r))
    }

    /// Row `i` as `(unknowns, weights, rhs)`.
    #[inline]
    fn row(&self, i: usize) -> Row<'_> {
        let (s, e) = (self.starts[i], self.starts[i + 1]);
        (&self.cols[s..e], &self.weights[s..e], self.rhs[i])
    }

    /// What each row is to the eliminations (see [`RowKind`]).
    fn kinds(&self) -> impl Iterator<Item = RowKind> + '_ {
        self.rows().map(|(_, ws, r)| RowKind::of(ws, r))
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
    /// The kind of a row with these weights (one per term) and right side.
    fn of(weights: &[f64], rhs: f64) -> RowKind {
        match weights {
            [_] => RowKind::Single,
            [a, b] if *a == 1.0 && *b == -1.0 && rhs == 0.0 => RowKind::Equality,
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
    /// Row `i`'s index in the system, for what is recorded.
    ids: &'a [usize],
    /// What was forced, in order, and every pivot test with its outcome, in order (rows as
    /// indices into the system): what a `plan::Plan` replays and checks.
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
                row: self.ids[i],
                class: c,
                pass,
            });
            if pass {
                self.done[i] = true;
                self.steps.push(Step::Single {
                    row: self.ids[i],
                    class: c,
                });
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
                row: self.ids[i],
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
                        rows: [self.ids[i], self.ids[j]],
                        classes: [ca, cb],
                        pass,
                    });
                    if pass {
                        let (ri, rj) = (self.rhs[i], self.rhs[j]);
                        self.done[i] = true;
                        self.done[j] = true;
                        self.steps.push(Step::Pair {
                            rows: [self.ids[i], self.ids[j]],
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
/// `ids` are the rows of `sys` to work on (the coupled ones). Every pivot test is recorded with
/// its outcome ([`Cascaded`]): each test reads only the summed weights of a row's classes and
/// its largest weight, never a forced value, so a `plan::Plan` can check them all on another
/// system of the same pattern.
fn force_determined_unknowns(
    sys: &System,
    ids: &[usize],
    class_of: &[usize],
    fixed: &[Option<f64>],
    class_fixed: &mut [Option<f64>],
) -> Cascaded {
    let rows: Vec<Row<'_>> = ids.iter().map(|&i| sys.row(i)).collect();
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
        ids,
        steps: Vec::new(),
        tests: Vec::new(),
    };
    for (i, &(cols, ws, r)) in rows.iter().enumerate() {
        let s = cascade.free.len();
        let (mut v, mut wmax) = (r, 0.0f64);
        for (&j, &w) in cols.iter().zip(ws) {
            wmax = max_not_nan(wmax, w.abs());
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
        dense: ids
            .iter()
            .zip(&cascade.done)
            .filter_map(|(&i, &d)| (!d).then_some(i))
            .collect(),
        steps: cascade.steps,
        tests: cascade.tests,
    }
}

/// What [`force_determined_unknowns`] did, with rows as indices into the system: the rows it
/// neither used nor left without a free class (for the dense solve), and the steps and the
/// pivot tests, in order.
struct Cascaded {
    dense: Vec<usize>,
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
/// and classes of unknowns merged by the equal pairs and the equality rows (union–find; the
/// least index represents a class, whatever the order of the merges: each root is the least
/// of its class, and a merge keeps the lesser root).
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
        let mut merge = |i: usize, j: usize| {
            let (a, b) = (find(&mut parent, i), find(&mut parent, j));
            let (lo, hi) = (a.min(b), a.max(b));
            parent[hi] = lo;
        };
        for &[i, j] in &sys.equal {
            merge(i, j);
        }
        for (i, ((cols, ws, r), kind)) in sys.rows().zip(sys.kinds()).enumerate() {
            match kind {
                RowKind::Single => {
                    fixed[cols[0]] = Some(r / ws[0]);
                    singles.push(i);
                }
                RowKind::Equality => merge(cols[0], cols[1]),
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
/// * equal pairs `x_i = x_j` ([`System::push_equal`]: the C0 conditions of the joins, where a
///   coefficient on a shared facet is the blossom of its neighbour at the facet's vertices,
///   which `exact_barycentric` makes exact unit vectors, so one coefficient each) and rows
///   `x_i − x_j = 0` merge `i` and `j` into one unknown;
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
        force_determined_unknowns(
            sys,
            &classes.coupled,
            &classes.class_of,
            &classes.fixed,
            &mut class_fixed,
        )
        .dense
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
    let coupled: Vec<Row<'_>> = dense.iter().map(|&i| sys.row(i)).collect();
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
    for (i, &(cols, ws, r)) in coupled.iter().enumerate() {
        let mut v = r;
        for (&j, &w) in cols.iter().zip(ws) {
            let c = class_of[j];
            match class_fixed[c] {
                Some(x) => v -= w * fixed[j].unwrap_or(x),
                None => a_mat[i * nf + col[c]] += w,
            }
        }
        rhs[i] = v;
    }
    let y = nearest_classes(&a_mat, &rhs, &inv_sqrt_w, mean);
    let x: Vec<f64> = (0..n)
        .map(|j| match (fixed[j], class_fixed[class_of[j]]) {
            (Some(v), _) | (None, Some(v)) => v,
            (None, None) => y[col[class_of[j]]],
        })
        .collect();
    let residual = sys.relative_residual(&x, target);
    (x, residual, m)
}

/// The free classes' values `y` nearest their targets' means `t̄` (weights `w_c`, given as
/// `1/√w_c`) subject to `A y = r` (`A` dense row-major, `r.len()` rows): the minimum-norm
/// `z` of `A W^{−1/2} z = r − A t̄` by [`RowBasis`], `y = t̄ + W^{−1/2} z` (see
/// [`nearest_solution`]), refined twice.
fn nearest_classes(a_mat: &[f64], rhs: &[f64], inv_sqrt_w: &[f64], mean: Vec<f64>) -> Vec<f64> {
    let mut y = mean;
    DenseScratch::default().nearest_classes(a_mat, rhs, inv_sqrt_w, &mut y);
    y
}

/// The buffers of [`nearest_classes`], kept from one solve to the next by the split faces'
/// replay ([`plan::solve`]): 16 vectors a face otherwise, 864 k of the bunny's 3.2 M
/// allocations (`docs/PERFORMANCE.md`, twenty-seventh pass).
#[derive(Debug, Default)]
pub(crate) struct DenseScratch {
    scaled: Vec<f64>,
    basis: RowBasis,
    residual: Vec<f64>,
    z: Vec<f64>,
    step: Vec<f64>,
}

impl DenseScratch {
    /// [`nearest_classes`] with `y` holding the means on entry and the values on return, in
    /// this scratch's buffers: the same operations in the same order, so the same bits.
    pub(crate) fn nearest_classes(
        &mut self,
        a_mat: &[f64],
        rhs: &[f64],
        inv_sqrt_w: &[f64],
        y: &mut [f64],
    ) {
        let (m, nf) = (rhs.len(), inv_sqrt_w.len());
        let residual_of = |y: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend((0..m).map(|i| {
                let row = &a_mat[i * nf..(i + 1) * nf];
                rhs[i] - row.iter().zip(y).map(|(a, b)| a * b).sum::<f64>()
            }));
        };
        self.scaled.clear();
        self.scaled.extend_from_slice(a_mat);
        for row in self.scaled.chunks_exact_mut(nf.max(1)) {
            for (a, s) in row.iter_mut().zip(inv_sqrt_w) {
                *a *= s;
            }
        }
        // Rank cut at 1e-10 of the largest row norm: the constraint rows repeat conditions
        // (C1 rows implied by others around the apex), so exactly dependent rows appear
        // (their residual after projection is ~1e-16); rows are O(1) and the column scales in
        // [1/√6, 1].
        self.basis.factor(&self.scaled, m, nf, 1e-10);
        // y = t̄ + W^{−1/2} A_s⁺ (r − A t̄), then two steps of iterative refinement: each
        // reduces the constraint residual by the solver's relative accuracy again, ending at
        // rounding level.
        for _ in 0..3 {
            residual_of(y, &mut self.residual);
            self.basis
                .solve_into(&self.residual, &mut self.z, &mut self.step);
            for ((x, s), w) in y.iter_mut().zip(&self.step).zip(inv_sqrt_w) {
                *x += s * w;
            }
        }
    }
}

impl System {
    /// The largest violation of the rows and equal pairs at `x`, eliminated ones included,
    /// relative to the size of the right-hand side and the target. A plain loop over the
    /// rows: through an iterator of rows behind `&mut dyn Iterator` this was 13 % of a split
    /// face's samples on the bunny (the same sums, so the same value). The running maxima are
    /// [`max_not_nan`] from 0, `f64::max`'s value in one comparison: `f64::max` handles a NaN
    /// in either operand, which made a split face's residual (13.7 k instructions of a bunny
    /// split face's 83 k, `callgrind`) 2.1 k instructions longer (spot, `cachegrind`).
    fn relative_residual(&self, x: &[f64], target: &[f64]) -> f64 {
        let mut worst = 0.0f64;
        let mut start = 0;
        for (&end, &r) in self.starts[1..].iter().zip(&self.rhs) {
            let mut dot = 0.0;
            for (&j, &w) in self.cols[start..end].iter().zip(&self.weights[start..end]) {
                dot += w * x[j];
            }
            start = end;
            worst = max_not_nan(worst, (r - dot).abs());
        }
        // The equal pairs as the rows `x_i − x_j = 0` they stand for: that row's violation
        // `|0 − ((0 + 1·x_i) + (−1)·x_j)|` is `|fl(x_i − x_j)|` (the products by ±1 are exact,
        // adding 0 changes at most a zero's sign, and `a + (−b)` rounds as `a − b`), and
        // the running maximum keeps the greatest magnitude whatever the order it sees them in.
        for &[i, j] in &self.equal {
            worst = max_not_nan(worst, (x[i] - x[j]).abs());
        }
        let size_of = max_abs(&self.rhs).max(max_abs(target));
        worst / size_of.max(f64::MIN_POSITIVE)
    }
}

#[cfg(test)]
mod tests {
    use super::{DenseScratch, System, nearest_solution};
    use algesurf_mesh::test_rng::Lcg;

    /// A system with `x1 = x2` given as an equal pair or as the row `x1 − x2 = 0`; `x1` fixed
    /// at `fixed1` and, if given, `x2` at `fixed2`.
    fn with_equality(as_pair: bool, fixed1: f64, fixed2: Option<f64>) -> System {
        let mut sys = System::with_capacity(6, 12);
        sys.push([(0, 1.0)], 1.0);
        sys.push([(1, 1.0)], fixed1);
        if as_pair {
            sys.push_equal(1, 2);
        } else {
            sys.push([(1, 1.0), (2, -1.0)], 0.0);
        }
        if let Some(v) = fixed2 {
            sys.push([(2, 1.0)], v);
        }
        sys.push([(2, 1.0), (3, 2.0)], 4.0);
        sys.push([(0, 1.0), (3, 1.0), (4, 1.0)], 2.0);
        sys
    }

    /// An equal pair merges its unknowns as the row `x_i − x_j = 0` does: the same point and
    /// the same residual, bit for bit, also where the class holds two fixed values that
    /// disagree (which only the residual shows).
    #[test]
    fn an_equal_pair_is_the_equality_row() {
        let target = [0.0, 0.5, 0.25, 1.0, -1.0];
        for (fixed1, fixed2) in [
            (3.0, None),
            (-0.5, None),
            (3.0, Some(3.0)),
            (3.0, Some(3.5)),
        ] {
            for cascade in [true, false] {
                let (xa, ra, ma) =
                    nearest_solution(&with_equality(true, fixed1, fixed2), &target, cascade);
                let (xb, rb, mb) =
                    nearest_solution(&with_equality(false, fixed1, fixed2), &target, cascade);
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&xa), bits(&xb), "{fixed1} {fixed2:?} {cascade}");
                assert_eq!(ra.to_bits(), rb.to_bits(), "{fixed1} {fixed2:?} {cascade}");
                assert_eq!(ma, mb);
            }
        }
        // x1 = 3 and x2 = 3.5 in one class: each keeps its own fixed value, and the pair's
        // violation 0.5 over the largest right side 4 is the residual.
        let (x, r, _) = nearest_solution(&with_equality(true, 3.0, Some(3.5)), &target, true);
        assert_eq!((x[1], x[2]), (3.0, 3.5));
        assert_eq!(r, 0.5 / 4.0);
    }

    /// A scratch reused for dense steps of other sizes and ranks gives the bits of a fresh one:
    /// nothing of an earlier solve leaks into a later one (large then small, full rank then
    /// with repeated rows, and back).
    #[test]
    fn a_reused_dense_scratch_gives_the_bits_of_a_fresh_one() {
        let mut rng = Lcg(11);
        let mut reused = DenseScratch::default();
        for (m, nf, repeat) in [
            (6, 8, false),
            (2, 3, false),
            (7, 9, true),
            (1, 1, false),
            (6, 8, true),
        ] {
            let mut a: Vec<f64> = (0..m * nf).map(|_| rng.centred()).collect();
            if repeat {
                // Row 1 repeats row 0: a dependent row the rank cut drops.
                let (r0, r1) = a.split_at_mut(nf);
                r1[..nf].copy_from_slice(r0);
            }
            let x_true: Vec<f64> = (0..nf).map(|_| rng.centred()).collect();
            let rhs: Vec<f64> = (0..m)
                .map(|i| (0..nf).map(|j| a[i * nf + j] * x_true[j]).sum())
                .collect();
            let inv_sqrt_w: Vec<f64> = (0..nf).map(|k| 1.0 / ((k % 3 + 1) as f64).sqrt()).collect();
            let mean: Vec<f64> = (0..nf).map(|_| rng.centred()).collect();
            let mut fresh_y = mean.clone();
            DenseScratch::default().nearest_classes(&a, &rhs, &inv_sqrt_w, &mut fresh_y);
            let mut reused_y = mean;
            reused.nearest_classes(&a, &rhs, &inv_sqrt_w, &mut reused_y);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&fresh_y),
                bits(&reused_y),
                "{m} × {nf}, repeated rows: {repeat}"
            );
            // And it solves: every row holds at the result.
            for i in 0..m {
                let ax: f64 = (0..nf).map(|j| a[i * nf + j] * fresh_y[j]).sum();
                assert!(
                    (ax - rhs[i]).abs() < 1e-12,
                    "{m} × {nf}, row {i}: {ax} vs {}",
                    rhs[i]
                );
            }
        }
    }
}

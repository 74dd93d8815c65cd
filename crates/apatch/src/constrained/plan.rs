//! Elimination plans: the cascade of [`super::nearest_solution`] recorded once and replayed
//! on every split face whose pivot tests come out the same ([`solve`]).

use super::{
    Classes, DenseScratch, FORCE_PIVOT, PivotTest, RowKind, Step, System,
    force_determined_unknowns, nearest_solution, pair_pivot,
};
use algesurf_bb::extremes::max_abs;
use std::cell::RefCell;
use std::rc::Rc;

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
    /// The pattern: row starts, every term's unknown, and every row's kind, of which only the
    /// two-term rows' are kept (`(row, kind)`, in row order): the others follow from the row
    /// starts (see [`Plan::fits`]).
    starts: Vec<usize>,
    columns: Vec<usize>,
    two_term_kinds: Vec<(usize, RowKind)>,
    /// The system's equal pairs ([`System::push_equal`]), part of the pattern too.
    equal: Vec<[usize; 2]>,
    /// The number of unknowns.
    n: usize,
    /// The rows with one unknown, as in [`Classes`] (a function of the pattern).
    singles: Vec<usize>,
    /// The cascade's pivot tests, with rows as indices into the system (kept for the tests:
    /// [`Plan::fits`] reads `checks`).
    #[cfg(test)]
    tests: Vec<PivotTest>,
    /// The pivot tests with their reads worked out ([`Check`]), and the terms those read.
    checks: Vec<Check>,
    reads: Vec<usize>,
    /// The cascade's steps, with rows as indices into the system.
    steps: Vec<Step>,
    /// The rows left for the dense solve.
    dense: Vec<usize>,
    /// The replay worked out from all of the above; `None` if a step would meet a value not
    /// known yet, which the cascade's own steps never do (then [`solve`] falls back to
    /// [`nearest_solution`]).
    replay: Option<Replay>,
}

/// A [`PivotTest`] with what it reads worked out once per plan: each summed weight of a class
/// in a row is the sum of the terms `reads[s..e]` (`(s, e)`, into [`Plan`]'s `reads`: the
/// row's terms of that class, in term order), and a row's largest weight is over its terms
/// `weights[s..e]` of the system. Looking the classes up term by term for every test (`weight`)
/// was 9 k instructions a split face (`callgrind`, bunny: 2.8 M reads of ~180 instructions).
#[derive(Clone, Copy, Debug)]
enum Check {
    Single {
        w: (usize, usize),
        row: (usize, usize),
        pass: bool,
    },
    PairRow {
        a: (usize, usize),
        b: (usize, usize),
        row: (usize, usize),
        pass: bool,
    },
    Pair {
        w: [(usize, usize); 4],
        pass: bool,
    },
}

/// Where [`Plan::replay`] reads an unknown of a dense row or of the result, decided once per
/// plan: a known value's slot (`Known`: an unknown its single row fixed, `j < n`, or a class
/// known after the steps, `n + c`) or a free class's column in the dense solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Src {
    Known(usize),
    Column(usize),
}

/// Where a step's row reads an unknown: one of the step's two classes (`A`, `B`) or a value
/// known by then (its slot, as in [`Src::Known`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StepSrc {
    A,
    B,
    Known(usize),
}

/// A [`Plan`]'s eliminations with every lookup done: per term of the rows a step or the dense
/// solve reads, where its unknown's value comes from ([`Src`]); the classes that take a fixed
/// unknown's value; the free classes with their unknowns, in index order, and column scales;
/// and per unknown where its final value comes from. The replay then reads only the system's
/// weights and right sides, with no class lookups or `Option`s per term.
#[derive(Debug)]
struct Replay {
    /// `(class, unknown)`: the class's value is that fixed unknown's.
    class_from_fixed: Vec<(usize, usize)>,
    /// Per step row (a `Single` step has one, a `Pair` two), in step order: its terms' sources
    /// are `step_src[step_start[k]..step_start[k + 1]]`, in term order.
    step_src: Vec<StepSrc>,
    step_start: Vec<usize>,
    /// Free class `k`'s unknowns are `members[member_start[k]..member_start[k + 1]]`.
    members: Vec<usize>,
    member_start: Vec<usize>,
    /// Per free class: `1/√w_c` and `w_c`.
    inv_sqrt_w: Vec<f64>,
    weight: Vec<f64>,
    /// Per dense row, its terms' sources (`dense_start` as `step_start`).
    dense_src: Vec<Src>,
    dense_start: Vec<usize>,
    /// Per unknown: where its value comes from.
    x_src: Vec<Src>,
}

impl Plan {
    /// Records the eliminations of [`nearest_solution`] on `sys` (`n` unknowns).
    fn record(sys: &System, n: usize) -> Plan {
        let classes = Classes::new(sys, n);
        let mut class_fixed = classes.class_fixed();
        let cascaded = force_determined_unknowns(
            sys,
            &classes.coupled,
            &classes.class_of,
            &classes.fixed,
            &mut class_fixed,
        );
        let mut reads = Vec::new();
        let mut read = |i: usize, c: usize| {
            let start = reads.len();
            for t in sys.starts[i]..sys.starts[i + 1] {
                if classes.class_of[sys.cols[t]] == c {
                    reads.push(t);
                }
            }
            (start, reads.len())
        };
        let row = |i: usize| (sys.starts[i], sys.starts[i + 1]);
        let checks = cascaded
            .tests
            .iter()
            .map(|t| match *t {
                PivotTest::Single {
                    row: i,
                    class,
                    pass,
                } => Check::Single {
                    w: read(i, class),
                    row: row(i),
                    pass,
                },
                PivotTest::PairRow {
                    row: i,
                    classes: [a, b],
                    pass,
                } => Check::PairRow {
                    a: read(i, a),
                    b: read(i, b),
                    row: row(i),
                    pass,
                },
                PivotTest::Pair {
                    rows: [i, j],
                    classes: [a, b],
                    pass,
                } => Check::Pair {
                    w: [read(i, a), read(i, b), read(j, a), read(j, b)],
                    pass,
                },
            })
            .collect();
        let replay = Replay::compile(sys, &classes, &cascaded.steps, &cascaded.dense);
        Plan {
            starts: sys.starts.clone(),
            columns: sys.cols.clone(),
            equal: sys.equal.clone(),
            two_term_kinds: sys
                .starts
                .windows(2)
                .zip(sys.kinds())
                .enumerate()
                .filter(|(_, (w, _))| w[1] - w[0] == 2)
                .map(|(i, (_, kind))| (i, kind))
                .collect(),
            #[cfg(test)]
            tests: cascaded.tests,
            checks,
            reads,
            steps: cascaded.steps,
            dense: cascaded.dense,
            n,
            singles: classes.singles,
            replay,
        }
    }

    /// The summed weight of the terms `reads[s..e]` of `sys`, in term order as the cascade
    /// sums a class's weights in a row (so the same bits).
    fn weight(&self, sys: &System, (s, e): (usize, usize)) -> f64 {
        self.reads[s..e]
            .iter()
            .fold(0.0, |w, &t| w + sys.weights[t])
    }

    /// Whether `sys` (`n` unknowns) has this plan's pattern and every recorded pivot test has
    /// its recorded outcome on it: then the cascade makes exactly this plan's steps on `sys`.
    fn fits(&self, sys: &System, n: usize) -> bool {
        // With equal row starts, a row's kind can differ only where it has two terms: one
        // term is always `Single` and three or more always `Coupled` (`RowKind::of`), so only
        // the two-term rows (a split face's C0 joins, about half of its rows) are classified
        // again. The starts and the unknowns are integer slices, compared as blocks.
        let pattern = self.n == n
            && self.starts == sys.starts
            && self.columns == sys.cols
            && self.equal == sys.equal
            && self.two_term_kinds.iter().all(|&(i, kind)| {
                let s = sys.starts[i];
                kind == RowKind::of(&sys.weights[s..s + 2], sys.rhs[i])
            });
        pattern
            && self.checks.iter().all(|c| match *c {
                Check::Single { w, row, pass } => {
                    (self.weight(sys, w).abs() >= FORCE_PIVOT * largest_weight(sys, row)) == pass
                }
                Check::PairRow { a, b, row, pass } => {
                    let (wa, wb) = (self.weight(sys, a), self.weight(sys, b));
                    (wa.abs().max(wb.abs()) >= FORCE_PIVOT * largest_weight(sys, row)) == pass
                }
                Check::Pair { w, pass } => {
                    let [a11, a12, a21, a22] = w.map(|r| self.weight(sys, r));
                    pair_pivot(a11, a12, a21, a22) == pass
                }
            })
    }

    /// [`nearest_solution`] of a system the plan [fits](Plan::fits): the recorded steps with
    /// `sys`'s numbers (each forced value from its row, the known values moved to the right
    /// side in term order), then the dense solve with the operations of `dense_solve` in its
    /// order. `None` if the plan has no [`Replay`] (see [`Replay::compile`]).
    fn replay(&self, sys: &System, target: &[f64]) -> Option<(Vec<f64>, f64, usize)> {
        let rp = self.replay.as_ref()?;
        Some(SCRATCH.with(|cell| self.replay_in(rp, sys, target, &mut cell.borrow_mut())))
    }

    /// [`Plan::replay`] with `rp`, in `scratch`'s buffers.
    fn replay_in(
        &self,
        rp: &Replay,
        sys: &System,
        target: &[f64],
        scratch: &mut ReplayScratch,
    ) -> (Vec<f64>, f64, usize) {
        let n = target.len();
        let ReplayScratch {
            vals,
            mean,
            a_mat,
            rhs,
            dense,
        } = scratch;
        // Value slots: unknowns fixed by their single rows `0..n`, known classes `n..2n`.
        vals.clear();
        vals.resize(2 * n, 0.0);
        for &i in &self.singles {
            let (cols, ws, r) = sys.row(i);
            vals[cols[0]] = r / ws[0];
        }
        for &(c, j) in &rp.class_from_fixed {
            vals[n + c] = vals[j];
        }
        // Step row `k` with its known values moved to the right side: the summed weights of
        // the step's classes and the reduced right side.
        let reduce = |vals: &[f64], k: usize, row: usize| {
            let (_, ws, r) = sys.row(row);
            let srcs = &rp.step_src[rp.step_start[k]..rp.step_start[k + 1]];
            let (mut wa, mut wb, mut v) = (0.0, 0.0, r);
            for (&w, &src) in ws.iter().zip(srcs) {
                match src {
                    StepSrc::A => wa += w,
                    StepSrc::B => wb += w,
                    StepSrc::Known(slot) => v -= w * vals[slot],
                }
            }
            (wa, wb, v)
        };
        let mut k = 0;
        for step in &self.steps {
            match *step {
                Step::Single { row, class } => {
                    let (w, _, v) = reduce(vals, k, row);
                    vals[n + class] = v / w;
                    k += 1;
                }
                Step::Pair {
                    rows: [i, j],
                    classes: [ca, cb],
                } => {
                    let (a11, a12, ri) = reduce(vals, k, i);
                    let (a21, a22, rj) = reduce(vals, k + 1, j);
                    let det = a11 * a22 - a12 * a21;
                    vals[n + ca] = (ri * a22 - a12 * rj) / det;
                    vals[n + cb] = (a11 * rj - a21 * ri) / det;
                    k += 2;
                }
            }
        }
        // The dense solve: the free classes' target means, the rows left in their columns.
        let nf = rp.weight.len();
        mean.clear();
        mean.extend((0..nf).map(|k| {
            let ms = &rp.members[rp.member_start[k]..rp.member_start[k + 1]];
            ms.iter().fold(0.0, |s, &j| s + target[j]) / rp.weight[k]
        }));
        let m = self.dense.len();
        a_mat.clear();
        a_mat.resize(m * nf, 0.0);
        rhs.clear();
        rhs.resize(m, 0.0);
        for (i, &row) in self.dense.iter().enumerate() {
            let (_, ws, r) = sys.row(row);
            let srcs = &rp.dense_src[rp.dense_start[i]..rp.dense_start[i + 1]];
            let mut v = r;
            for (&w, &src) in ws.iter().zip(srcs) {
                match src {
                    Src::Column(col) => a_mat[i * nf + col] += w,
                    Src::Known(slot) => v -= w * vals[slot],
                }
            }
            rhs[i] = v;
        }
        dense.nearest_classes(a_mat, rhs, &rp.inv_sqrt_w, mean);
        let y = &*mean;
        let x: Vec<f64> = rp
            .x_src
            .iter()
            .map(|&src| match src {
                Src::Column(col) => y[col],
                Src::Known(slot) => vals[slot],
            })
            .collect();
        let residual = sys.relative_residual(&x, target);
        (x, residual, m)
    }
}

/// The buffers of [`Plan::replay`], one set per thread, kept from face to face (see
/// [`DenseScratch`]).
#[derive(Debug, Default)]
struct ReplayScratch {
    vals: Vec<f64>,
    /// The free classes' target means, then their values.
    mean: Vec<f64>,
    a_mat: Vec<f64>,
    rhs: Vec<f64>,
    dense: DenseScratch,
}

thread_local! {
    static SCRATCH: RefCell<ReplayScratch> = RefCell::new(ReplayScratch::default());
}

impl Replay {
    /// The replay of the plan with `classes`, `steps` and `dense` rows recorded on `sys`:
    /// which values are known at each step, followed through the steps as [`Plan::replay`]
    /// will take them. `None` if a step's row has a term whose value is not known then.
    fn compile(sys: &System, classes: &Classes, steps: &[Step], dense: &[usize]) -> Option<Replay> {
        let n = classes.class_of.len();
        let mut fixed = vec![false; n];
        for &i in &classes.singles {
            fixed[sys.row(i).0[0]] = true;
        }
        let mut known: Vec<bool> = classes.fixed_from.iter().map(Option::is_some).collect();
        let class_from_fixed = (0..n)
            .filter_map(|c| classes.fixed_from[c].map(|j| (c, j)))
            .collect();
        // The value slot of unknown `j` once its class is known (`None` while it is not).
        let known_slot = |known: &[bool], j: usize| {
            let c = classes.class_of[j];
            if fixed[j] {
                Some(j)
            } else {
                known[c].then_some(n + c)
            }
        };
        let (mut step_src, mut step_start) = (Vec::new(), vec![0]);
        for step in steps {
            let (rows, [a, b]) = match *step {
                Step::Single { row, class } => ([row, usize::MAX], [class, usize::MAX]),
                Step::Pair {
                    rows,
                    classes: pair,
                } => (rows, pair),
            };
            for &row in rows.iter().filter(|&&r| r != usize::MAX) {
                for &j in sys.row(row).0 {
                    let c = classes.class_of[j];
                    step_src.push(if c == a {
                        StepSrc::A
                    } else if c == b {
                        StepSrc::B
                    } else {
                        StepSrc::Known(known_slot(&known, j)?)
                    });
                }
                step_start.push(step_src.len());
            }
            for c in [a, b].into_iter().filter(|&c| c != usize::MAX) {
                known[c] = true;
            }
        }
        // The free classes (representatives not known after the steps), in index order.
        let mut column = vec![usize::MAX; n];
        let mut free = Vec::new();
        for c in 0..n {
            if classes.class_of[c] == c && !known[c] {
                column[c] = free.len();
                free.push(c);
            }
        }
        let mut member_start = vec![0; free.len() + 1];
        for &c in &classes.class_of {
            if column[c] != usize::MAX {
                member_start[column[c] + 1] += 1;
            }
        }
        for k in 0..free.len() {
            member_start[k + 1] += member_start[k];
        }
        let mut next = member_start.clone();
        let mut members = vec![0; member_start[free.len()]];
        for (j, &c) in classes.class_of.iter().enumerate() {
            if column[c] != usize::MAX {
                members[next[column[c]]] = j;
                next[column[c]] += 1;
            }
        }
        let src = |j: usize| match known_slot(&known, j) {
            Some(slot) => Src::Known(slot),
            None => Src::Column(column[classes.class_of[j]]),
        };
        let (mut dense_src, mut dense_start) = (Vec::new(), vec![0]);
        for &i in dense {
            dense_src.extend(sys.row(i).0.iter().map(|&j| src(j)));
            dense_start.push(dense_src.len());
        }
        Some(Replay {
            class_from_fixed,
            step_src,
            step_start,
            members,
            member_start,
            inv_sqrt_w: free
                .iter()
                .map(|&c| 1.0 / (classes.size[c] as f64).sqrt())
                .collect(),
            weight: free.iter().map(|&c| classes.size[c] as f64).collect(),
            dense_src,
            dense_start,
            x_src: (0..n).map(src).collect(),
        })
    }
}

/// The largest weight of the terms `s..e` of `sys` (a row's), as the cascade takes it.
fn largest_weight(sys: &System, (s, e): (usize, usize)) -> f64 {
    max_abs(&sys.weights[s..e])
}

/// How many plans each thread keeps ([`solve`]), most recently used first. Spot's 2 956 split
/// faces have at least 42 patterns (pivot tests and snapped zeros differ): with 8 plans kept
/// oldest-first it recorded 191 plans, most recently used first 164, with 32 kept 42 (spot at
/// 1 × 1 on one thread: 1 089 M → 1 070 M instructions). Evicting a plan only costs recording
/// it again: the results do not depend on what is cached (see [`Plan`]).
const PLANS_PER_THREAD: usize = 32;

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
        // Most recently used first: the next face most likely fits the plan the last one did.
        if let Some(k) = plans.iter().position(|p| p.fits(sys, n)) {
            plans[..=k].rotate_right(1);
            return Rc::clone(&plans[0]);
        }
        let p = Rc::new(Plan::record(sys, n));
        plans.truncate(PLANS_PER_THREAD - 1);
        plans.insert(0, Rc::clone(&p));
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
        other.cols[2] = 3;
        assert!(!pa.fits(&other, 5));
        // The same pattern with a two-term row of another kind: row 1's weights no longer
        // merge x1 and x2 (an equality needs exactly 1 and −1), so the cascade sees other
        // classes.
        let mut coupled = system(0.5);
        coupled.weights[2] = -0.5;
        assert!(!pa.fits(&coupled, 5));
        coupled.weights[2] = -1.0;
        coupled.rhs[1] = 0.25;
        assert!(!pa.fits(&coupled, 5));
        coupled.rhs[1] = 0.0;
        assert!(pa.fits(&coupled, 5));
        // Equal pairs are part of the pattern.
        let mut paired = system(0.5);
        paired.push_equal(0, 4);
        assert!(!pa.fits(&paired, 5));
        assert!(Plan::record(&paired, 5).fits(&paired, 5));
        assert!(!pa.fits(&a, 6));
    }

    /// A plan's [`Replay`] reads each value where the unplanned solve finds it: `x1` fixed by
    /// its single row, `x2` through its class (merged with `x1` by an equality), `x3` forced by
    /// a step that reads `x2`, and a dense row that reads `x3` with two free classes left.
    #[test]
    fn the_replay_reads_fixed_merged_and_forced_values() {
        let mut sys = System::with_capacity(4, 8);
        sys.push([(1, 1.0)], 2.0);
        sys.push([(1, 1.0), (2, -1.0)], 0.0);
        sys.push([(2, 1.0), (3, 1.0)], 5.0);
        sys.push([(0, 1.0), (3, 1.0), (4, 1.0)], 1.0);
        let target = [0.5, 0.0, 0.0, 0.0, -0.7];
        let plan = Plan::record(&sys, 5);
        let rp = plan.replay.as_ref().expect("a replay");
        assert_eq!(rp.class_from_fixed, vec![(1, 1)]);
        assert_eq!(plan.steps, vec![Step::Single { row: 2, class: 3 }]);
        assert_eq!(rp.step_src, vec![StepSrc::Known(5 + 1), StepSrc::A]);
        assert_eq!(plan.dense, vec![3]);
        assert_eq!(
            rp.dense_src,
            vec![Src::Column(0), Src::Known(5 + 3), Src::Column(1)]
        );
        assert_eq!(
            rp.x_src,
            vec![
                Src::Column(0),
                Src::Known(1),
                Src::Known(5 + 1),
                Src::Known(5 + 3),
                Src::Column(1)
            ]
        );
        let (x, r, m) = plan.replay(&sys, &target).expect("replayed");
        let (y, ry, my) = nearest_solution(&sys, &target, true);
        assert_eq!((m, my), (1, 1));
        assert!(r < 1e-15 && ry < 1e-15, "{r} {ry}");
        assert_eq!(&x[1..4], &[2.0, 2.0, 3.0]);
        // x0 + x4 = −2 nearest (0.5, −0.7): both move by −0.9.
        for (u, v) in x.iter().zip(&y) {
            assert!((u - v).abs() < 1e-15, "{x:?} {y:?}");
        }
        assert!(
            (x[0] + 0.4).abs() < 1e-15 && (x[4] + 1.6).abs() < 1e-15,
            "{x:?}"
        );
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

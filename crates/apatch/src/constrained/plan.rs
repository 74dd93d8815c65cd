//! Elimination plans: the cascade of [`super::nearest_solution`] recorded once and replayed
//! on every split face whose pivot tests come out the same ([`solve`]).

use super::{
    Classes, FORCE_PIVOT, PivotTest, RowKind, Step, System, dense_solve, force_determined_unknowns,
    nearest_solution, pair_pivot,
};
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
        let mut class_fixed = classes.class_fixed();
        let cascaded = force_determined_unknowns(
            sys,
            &classes.coupled,
            &classes.class_of,
            &classes.fixed,
            &mut class_fixed,
        );
        Plan {
            starts: sys.starts.clone(),
            columns: sys.terms.iter().map(|t| t.0).collect(),
            kinds: sys.kinds().collect(),
            tests: cascaded.tests,
            steps: cascaded.steps,
            dense: cascaded.dense,
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
        // With equal row starts, a row's kind can differ only where it has two terms: one
        // term is always `Single` and three or more always `Coupled` (`RowKind::of`), so only
        // the two-term rows (a split face's C0 joins, about half of its rows) are classified
        // again.
        let pattern = self.class_of.len() == n
            && self.starts == sys.starts
            && self.columns.iter().zip(&sys.terms).all(|(a, t)| *a == t.0)
            && self
                .starts
                .windows(2)
                .zip(&self.kinds)
                .zip(&sys.rhs)
                .all(|((w, &kind), &r)| {
                    w[1] - w[0] != 2 || kind == RowKind::of(&sys.terms[w[0]..w[1]], r)
                });
        debug_assert!(!pattern || self.kinds.iter().copied().eq(sys.kinds()));
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

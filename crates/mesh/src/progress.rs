//! Progress of long computations: the library reports steps and units done to a
//! [`Progress`] sink, which a user interface polls or forwards.
//!
//! The constructions that take seconds on large meshes (the simplicial hull and its
//! refinement rounds, the A-patch function, the tessellation) have `_with_progress` forms that
//! take a `&dyn Progress`. They call [`Progress::start`] once per step, from the thread that
//! called them, and [`Progress::advance`] from any thread while the step runs, in batches of
//! up to [`REPORT_EVERY`] units, so a sink's cost stays far below the work's. Reporting never
//! changes a result: the same input gives the same bits with any sink.
//!
//! A sink can also stop the work ([`Progress::cancelled`], polled at every step and every
//! batch of units): the computation then returns its crate's `Cancelled` error (built from
//! [`Cancelled`]) instead of a result, and nothing it made is kept. This is the
//! interrupter of OpenVDB's and CGAL's long algorithms, for a user interface's cancel button.
//!
//! ```
//! use algesurf_mesh::progress::{Cancelled, Progress, ProgressCounter};
//! use algesurf_mesh::parallel::collect_first_error_with_progress;
//!
//! let counter = ProgressCounter::new();
//! counter.start("squares", 1000);
//! let squares =
//!     collect_first_error_with_progress(1000, |i| Ok::<_, Cancelled>(i * i), || 0, &counter)?;
//! assert_eq!(squares[999], 998_001);
//! // A user interface thread would poll this while the loop runs.
//! let now = counter.snapshot();
//! assert_eq!((now.step.as_str(), now.done, now.total), ("squares", 1000, 1000));
//!
//! // A cancel button: the loop stops at the next batch and reports `Cancelled`.
//! counter.start("cubes", 1000);
//! let cubes = collect_first_error_with_progress(
//!     1000,
//!     |i| {
//!         if i == 10 {
//!             counter.cancel();
//!         }
//!         Ok::<_, Cancelled>(i * i * i)
//!     },
//!     || 0,
//!     &counter,
//! );
//! assert_eq!(cubes, Err(Cancelled));
//! # Ok::<(), Cancelled>(())
//! ```

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The most units a loop of the library counts before it reports them
/// ([`Progress::advance`]): a bar lags at most this far behind, and a sink is called once
/// per 64 faces or patches (a microsecond of work or more each), not once per unit.
pub const REPORT_EVERY: usize = 64;

/// Where long computations report what they are doing.
///
/// Implementations must be cheap and must not block for long: `advance` is called from the
/// worker threads of a parallel loop. [`ProgressCounter`] is one to poll from another
/// thread; [`NoProgress`] ignores everything.
pub trait Progress: Sync {
    /// A new step begins: `name` says what it does (e.g. `"hull: faces"`), `total` is the
    /// number of units it will report, or 0 when that is not known in advance (a refinement
    /// round, an overlap check).
    fn start(&self, name: &str, total: u64);

    /// `units` more units of the current step are done. Called from any thread.
    fn advance(&self, units: u64);

    /// Whether the work should stop. Polled from any thread at every step and every batch of
    /// [`REPORT_EVERY`] units (and at every refinement round of a hull); once it answers
    /// `true`, the computation returns its `Cancelled` error as soon as it next looks. The
    /// default never stops.
    fn cancelled(&self) -> bool {
        false
    }
}

/// The work was stopped by its [`Progress::cancelled`]; each crate's error type has a
/// `Cancelled` variant made from this.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// `Err(Cancelled)` when `progress` asks to stop: for the points between steps.
///
/// # Errors
/// [`Cancelled`] when [`Progress::cancelled`] is true.
pub fn check_cancelled(progress: &dyn Progress) -> Result<(), Cancelled> {
    if progress.cancelled() {
        Err(Cancelled)
    } else {
        Ok(())
    }
}

/// A [`Progress`] that ignores every report: what the forms without `_with_progress` use.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    #[inline]
    fn start(&self, _name: &str, _total: u64) {}
    #[inline]
    fn advance(&self, _units: u64) {}
}

/// A [`Progress`] that keeps the current step and its count for another thread to read
/// ([`ProgressCounter::snapshot`]): the command line's progress bar polls one ten times a
/// second. `advance` is one relaxed atomic addition. Another thread can stop the work with
/// [`ProgressCounter::cancel`].
#[derive(Debug, Default)]
pub struct ProgressCounter {
    /// The current step's name and total.
    step: Mutex<(String, u64)>,
    done: AtomicU64,
    cancel: AtomicBool,
}

/// What a [`ProgressCounter`] held when it was read.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ProgressSnapshot {
    /// The current step's name; empty before the first step.
    pub step: String,
    /// Units done in the current step (at most `total` when `total` is not 0).
    pub done: u64,
    /// The current step's units, 0 when not known.
    pub total: u64,
}

impl ProgressCounter {
    /// A counter before any step.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the work reporting to this counter to stop ([`Progress::cancelled`]).
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// The current step, its units done and its total.
    pub fn snapshot(&self) -> ProgressSnapshot {
        // The count is read under the lock that `start` holds while it resets it, so it
        // belongs to the step read with it.
        let (step, total, done) = {
            let s = self.step.lock().unwrap_or_else(|p| p.into_inner());
            (s.0.clone(), s.1, self.done.load(Ordering::Relaxed))
        };
        // A unit reported just before the step changed can show against the new step for
        // one reading; never more than its total.
        let done = if total > 0 { done.min(total) } else { done };
        ProgressSnapshot { step, done, total }
    }
}

impl Progress for ProgressCounter {
    fn start(&self, name: &str, total: u64) {
        let mut s = self.step.lock().unwrap_or_else(|p| p.into_inner());
        s.0.clear();
        s.0.push_str(name);
        s.1 = total;
        self.done.store(0, Ordering::Relaxed);
    }

    #[inline]
    fn advance(&self, units: u64) {
        self.done.fetch_add(units, Ordering::Relaxed);
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// A [`Progress`] that keeps every step it was told of, with the units reported in it: for
/// tests of what a computation reports, and for logs.
///
/// ```
/// use algesurf_mesh::progress::{LoggedStep, Progress, ProgressLog};
/// let log = ProgressLog::default();
/// log.start("faces", 2);
/// log.advance(2);
/// log.start("rounds", 0);
/// assert_eq!(
///     log.steps(),
///     [LoggedStep { name: "faces".into(), total: 2, done: 2 },
///      LoggedStep { name: "rounds".into(), total: 0, done: 0 }]
/// );
/// ```
#[derive(Debug, Default)]
pub struct ProgressLog {
    steps: Mutex<Vec<LoggedStep>>,
    /// Asks to stop once a step whose name starts with this begins.
    cancel_at: Option<String>,
    cancel: AtomicBool,
}

/// One step a [`ProgressLog`] was told of.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoggedStep {
    /// Its name, as given to [`Progress::start`].
    pub name: String,
    /// Its total, as given to [`Progress::start`].
    pub total: u64,
    /// The units reported while it was the current step.
    pub done: u64,
}

impl ProgressLog {
    /// A log that asks to stop ([`Progress::cancelled`]) once a step whose name starts with
    /// `prefix` begins: for tests of how a computation stops.
    ///
    /// ```
    /// use algesurf_mesh::progress::{Progress, ProgressLog};
    /// let log = ProgressLog::cancelling_at("hull: faces");
    /// log.start("hull: edges", 10);
    /// assert!(!log.cancelled());
    /// log.start("hull: faces", 8);
    /// assert!(log.cancelled());
    /// ```
    pub fn cancelling_at(prefix: &str) -> Self {
        ProgressLog {
            cancel_at: Some(prefix.to_string()),
            ..Self::default()
        }
    }

    /// The steps so far, in order.
    pub fn steps(&self) -> Vec<LoggedStep> {
        self.steps.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }
}

impl Progress for ProgressLog {
    fn start(&self, name: &str, total: u64) {
        if self
            .cancel_at
            .as_deref()
            .is_some_and(|prefix| name.starts_with(prefix))
        {
            self.cancel.store(true, Ordering::Relaxed);
        }
        self.steps
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(LoggedStep {
                name: name.to_string(),
                total,
                done: 0,
            });
    }

    fn advance(&self, units: u64) {
        if let Some(last) = self
            .steps
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .last_mut()
        {
            last.done += units;
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// Counts the units of a loop over `0..n` for `progress` in batches, and stops it when
/// `progress` asks: call [`UnitTally::unit_done`] with each index as its unit finishes (in
/// any order, from any thread), skip the units left once [`UnitTally::stopped`] is true, and
/// call [`UnitTally::finish`] after the loop. Every index `i` with
/// `i % REPORT_EVERY == REPORT_EVERY − 1` reports a whole batch and polls
/// [`Progress::cancelled`], and `finish` reports the last, partial batch, so the reports add
/// up to exactly `n` once every index is done, with one sink call per [`REPORT_EVERY`] units.
///
/// ```
/// use algesurf_mesh::progress::{Cancelled, Progress, ProgressCounter, UnitTally};
/// let counter = ProgressCounter::new();
/// let tally = UnitTally::start(&counter, "units", 1000);
/// let mut work = 0;
/// for i in 0..1000 {
///     if tally.stopped() {
///         continue; // the rest is skipped
///     }
///     work += 1;
///     tally.unit_done(i);
///     if i == 99 {
///         counter.cancel(); // from a user interface, say
///     }
/// }
/// assert_eq!(tally.finish(), Err(Cancelled));
/// assert_eq!(work, 128); // up to the next batch's poll
/// ```
pub struct UnitTally<'a> {
    progress: &'a dyn Progress,
    n: usize,
    stop: AtomicBool,
}

impl<'a> UnitTally<'a> {
    /// Starts the step `name` of `n` units on `progress`.
    pub fn start(progress: &'a dyn Progress, name: &str, n: usize) -> Self {
        progress.start(name, n as u64);
        Self::counting(progress, n)
    }

    /// A tally of `n` units for the step `progress` is in (started by the caller).
    pub fn counting(progress: &'a dyn Progress, n: usize) -> Self {
        UnitTally {
            progress,
            n,
            stop: AtomicBool::new(progress.cancelled()),
        }
    }

    /// Unit `i` of the loop is done.
    #[inline]
    pub fn unit_done(&self, i: usize) {
        if i % REPORT_EVERY == REPORT_EVERY - 1 {
            self.progress.advance(REPORT_EVERY as u64);
            if self.progress.cancelled() {
                self.stop.store(true, Ordering::Relaxed);
            }
        }
    }

    /// Whether the loop should skip its remaining units: `progress` asked to stop at a batch's
    /// end (or before the loop).
    #[inline]
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The loop is over: reports the units of the last, partial batch.
    ///
    /// # Errors
    /// [`Cancelled`] when the loop was stopped or `progress` asks to stop now: its results
    /// are incomplete and must not be used.
    pub fn finish(self) -> Result<(), Cancelled> {
        if self.stop.into_inner() {
            return Err(Cancelled);
        }
        let rest = self.n % REPORT_EVERY;
        if rest > 0 {
            self.progress.advance(rest as u64);
        }
        check_cancelled(self.progress)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    /// A tally's reports add up to the loop's length, whatever the length and the order in
    /// which the units finish, in about one call per batch.
    #[test]
    fn a_tally_reports_every_unit_exactly_once() {
        struct Calls(AtomicU64, AtomicU64);
        impl Progress for Calls {
            fn start(&self, _: &str, _: u64) {}
            fn advance(&self, units: u64) {
                self.0.fetch_add(units, Ordering::Relaxed);
                self.1.fetch_add(1, Ordering::Relaxed);
            }
        }
        for n in [0, 1, 63, 64, 65, 1000, 4096, 10_007] {
            let calls = Calls(AtomicU64::new(0), AtomicU64::new(0));
            let tally = UnitTally::start(&calls, "loop", n);
            (0..n)
                .into_par_iter()
                .rev()
                .for_each(|i| tally.unit_done(i));
            tally.finish().unwrap();
            assert_eq!(calls.0.load(Ordering::Relaxed), n as u64, "n = {n}");
            let expected_calls = n.div_ceil(REPORT_EVERY) as u64;
            assert_eq!(calls.1.load(Ordering::Relaxed), expected_calls, "n = {n}");
        }
    }

    /// A counter reads back the step it was given and starts each step from zero; a late
    /// unit never shows more than the step's total.
    #[test]
    fn a_counter_shows_the_current_step() {
        let c = ProgressCounter::new();
        assert_eq!(c.snapshot(), ProgressSnapshot::default());
        c.start("faces", 10);
        c.advance(4);
        c.advance(3);
        assert_eq!(
            c.snapshot(),
            ProgressSnapshot {
                step: "faces".into(),
                done: 7,
                total: 10
            }
        );
        c.start("rounds", 0);
        assert_eq!(c.snapshot().done, 0);
        c.advance(25);
        assert_eq!((c.snapshot().done, c.snapshot().total), (25, 0));
        c.start("edges", 5);
        c.advance(9);
        assert_eq!(c.snapshot().done, 5);
    }
}

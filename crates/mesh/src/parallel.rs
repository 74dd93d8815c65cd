//! Parallel loops over mesh elements whose result must not depend on the thread count.

use crate::progress::{Cancelled, NoProgress, Progress, UnitTally};
use rayon::prelude::*;
use std::sync::Mutex;

/// Below this many items a loop or sort that has a parallel form runs in series instead.
///
/// Handing work to rayon's pool from outside it wakes a worker and blocks until it is done;
/// for the many small meshes the Butterfly limit normals and the hull's edge splits build (a
/// cut-out of a few hundred corners, each with its topology and often a tree), that hand-off
/// cost more than the work: the context switches (`_raw_spin_unlock_irqrestore`,
/// `finish_task_switch`) were 36 % of the samples of Suzanne's normal stage. 4096 items is
/// about a hundred microseconds of sorting, well above the hand-off's few microseconds, and far
/// below the sizes whose parallel form measurably helps (the bunny's 208 k corners). The
/// results are the same either way (the sorts' keys are distinct).
pub const SERIAL_BELOW: usize = 1 << 12;

/// At most this many consecutive items of [`collect_first_error`] run as one piece of work.
///
/// Rayon splits an indexed loop into a few pieces per thread and splits a piece again only
/// when another thread steals it; a piece a thread has started runs to its end. With two
/// threads the bunny's 70 k A-patch faces ran in pieces of thousands, and the last one kept
/// one thread busy for 0.15 s after the other had run out of work (`perf`, 2026-12-02). At
/// 256 items a piece of the costliest loop (split faces, ~15 µs each) takes about 4 ms,
/// which bounds that tail, and the ~300 pieces cost rayon microseconds each.
pub const GRAIN: usize = 256;

/// `f(i)` for every `i < n`, in parallel, collected in index order; or, if some `f(i)` fails,
/// the error of the least failing index, so that which error is reported does not depend on
/// the thread count or the scheduling.
///
/// The values are written straight into the result. The usual way to get the same
/// determinism, collecting a `Vec<Result<T, E>>` and unpacking it serially, moves every value
/// twice more on one thread: for the hull's faces and edges and the A-patch construction's
/// face functions (hundreds of bytes to kilobytes each, 70–100 k of them on the Stanford
/// bunny) that was tens of megabytes of serial copying per pass. Slots whose `f` failed hold
/// `filler()` until the error is returned; they are never seen.
///
/// ```
/// use algesurf_mesh::parallel::collect_first_error;
/// let halves = collect_first_error(6, |i| if i % 2 == 0 { Ok(i / 2) } else { Err(i) }, || 0);
/// assert_eq!(halves, Err(1));
/// let doubled = collect_first_error(4, |i| Ok::<_, ()>(2 * i), || 0);
/// assert_eq!(doubled, Ok(vec![0, 2, 4, 6]));
/// ```
pub fn collect_first_error<T: Send, E: Send>(
    n: usize,
    f: impl Fn(usize) -> Result<T, E> + Sync,
    filler: impl Fn() -> T + Sync,
) -> Result<Vec<T>, E> {
    let mut out = Vec::new();
    collect_first_error_into(&mut out, n, f, filler)?;
    Ok(out)
}

/// [`collect_first_error`] into `out` (its contents replaced), reusing its allocation when it
/// has room for `n` values: for a result that will grow later, allocated once with room for
/// that. On an error `out` holds unspecified values.
///
/// ```
/// use algesurf_mesh::parallel::collect_first_error_into;
/// let mut v = Vec::with_capacity(10);
/// collect_first_error_into(&mut v, 4, |i| Ok::<_, ()>(i + 1), || 0).unwrap();
/// assert_eq!((v.as_slice(), v.capacity() >= 10), (&[1, 2, 3, 4][..], true));
/// ```
pub fn collect_first_error_into<T: Send, E: Send>(
    out: &mut Vec<T>,
    n: usize,
    f: impl Fn(usize) -> Result<T, E> + Sync,
    filler: impl Fn() -> T + Sync,
) -> Result<(), E> {
    // `NoProgress` never asks to stop, so only an item's error comes back.
    match collect(out, n, f, filler, &NoProgress) {
        Err(Stop::Failed(e)) => Err(e),
        Ok(()) | Err(Stop::Cancelled) => Ok(()),
    }
}

/// [`collect_first_error`], reporting each finished item as a unit of the current step of
/// `progress` (in batches, [`UnitTally`]; the caller starts the step with its total `n`), and
/// skipping the items left once `progress` asks to stop.
///
/// # Errors
/// [`Cancelled`] (as `E`) when `progress` asked to stop; otherwise the error of the least
/// failing index, as [`collect_first_error`].
pub fn collect_first_error_with_progress<T: Send, E: Send + From<Cancelled>>(
    n: usize,
    f: impl Fn(usize) -> Result<T, E> + Sync,
    filler: impl Fn() -> T + Sync,
    progress: &dyn Progress,
) -> Result<Vec<T>, E> {
    let mut out = Vec::new();
    collect_first_error_into_with_progress(&mut out, n, f, filler, progress)?;
    Ok(out)
}

/// [`collect_first_error_into`] with the progress reports and the stop of
/// [`collect_first_error_with_progress`].
///
/// # Errors
/// As [`collect_first_error_with_progress`].
pub fn collect_first_error_into_with_progress<T: Send, E: Send + From<Cancelled>>(
    out: &mut Vec<T>,
    n: usize,
    f: impl Fn(usize) -> Result<T, E> + Sync,
    filler: impl Fn() -> T + Sync,
    progress: &dyn Progress,
) -> Result<(), E> {
    collect(out, n, f, filler, progress).map_err(|stop| match stop {
        Stop::Failed(e) => e,
        Stop::Cancelled => Cancelled.into(),
    })
}

/// Why [`collect`] returned no complete result.
enum Stop<E> {
    /// An item failed (the least failing index's error).
    Failed(E),
    /// `progress` asked to stop; the items after that were skipped.
    Cancelled,
}

/// The loop of the `collect_first_error` forms.
fn collect<T: Send, E: Send>(
    out: &mut Vec<T>,
    n: usize,
    f: impl Fn(usize) -> Result<T, E> + Sync,
    filler: impl Fn() -> T + Sync,
    progress: &dyn Progress,
) -> Result<(), Stop<E>> {
    // The step was started by the caller; the tally only counts (its `start` is not used
    // so that a caller can name the step once for several loops).
    let tally = UnitTally::counting(progress, n);
    let first: Mutex<Option<(usize, E)>> = Mutex::new(None);
    (0..n)
        .into_par_iter()
        .with_max_len(GRAIN)
        .map(|i| {
            if tally.stopped() {
                return filler();
            }
            let r = f(i);
            tally.unit_done(i);
            r.unwrap_or_else(|e| {
                // A poisoned lock only means another closure panicked; the slot is still valid.
                let mut slot = first.lock().unwrap_or_else(|p| p.into_inner());
                if slot.as_ref().is_none_or(|(j, _)| i < *j) {
                    *slot = Some((i, e));
                }
                filler()
            })
        })
        .collect_into_vec(out);
    tally.finish().map_err(|Cancelled| Stop::Cancelled)?;
    match first.into_inner().unwrap_or_else(|p| p.into_inner()) {
        Some((_, e)) => Err(Stop::Failed(e)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The least failing index's error is returned, whatever the thread count; without
    /// errors the values come in index order.
    #[test]
    fn the_least_failing_index_is_reported_for_every_thread_count() {
        let f =
            |i: usize| -> Result<usize, usize> { if i % 997 == 500 { Err(i) } else { Ok(i * 2) } };
        in_pools(|_| {
            assert_eq!(collect_first_error(10_000, f, || 0), Err(500));
            let ok = collect_first_error(400, f, || 0).unwrap();
            assert_eq!(ok, (0..400).map(|i| i * 2).collect::<Vec<_>>());
        });
    }

    /// Runs `f(threads)` in pools of 1, 2 and 4 threads.
    fn in_pools(f: impl Fn(usize) + Sync) {
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| f(threads));
        }
    }

    /// A loop whose sink asks to stop returns `Cancelled`, even where an item failed, and
    /// skips most of its items: every thread polls at its next batch of
    /// [`crate::progress::REPORT_EVERY`] units, and each piece of [`GRAIN`] items it has
    /// started skips its rest.
    #[test]
    fn a_cancelled_loop_stops_and_says_so() {
        use crate::progress::{Cancelled, ProgressCounter};
        use std::sync::atomic::{AtomicUsize, Ordering};
        #[derive(Debug, PartialEq)]
        enum E {
            Item(usize),
            Stopped,
        }
        impl From<Cancelled> for E {
            fn from(_: Cancelled) -> Self {
                E::Stopped
            }
        }
        in_pools(|threads| {
            let counter = ProgressCounter::new();
            let calls = AtomicUsize::new(0);
            let r = collect_first_error_with_progress(
                100_000,
                |i| {
                    calls.fetch_add(1, Ordering::Relaxed);
                    if i == 5 {
                        counter.cancel();
                    }
                    if i == 7 { Err(E::Item(i)) } else { Ok(i) }
                },
                || 0,
                &counter,
            );
            assert_eq!(r, Err(E::Stopped), "{threads} threads");
            let calls = calls.into_inner();
            assert!(
                calls < 20_000,
                "{threads} threads: {calls} calls of 100 000"
            );
            // A sink that never cancels changes nothing.
            let plain = collect_first_error_with_progress(1000, Ok::<_, E>, || 0, &NoProgress);
            assert_eq!(plain, Ok((0..1000).collect::<Vec<_>>()));
        });
    }
}

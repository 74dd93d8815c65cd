//! Ctrl-C (SIGINT) and SIGTERM stop a command cleanly: the stage that is running sees the
//! signal through its [`Progress`] sink ([`Interruptible`], which every [`crate::stage`]
//! hands out) and returns its `Cancelled` error at its next batch; a write in progress removes
//! its temporary file (`algesurf_io::write_with_progress`), so the output is either the
//! complete new file or the old one, never a partial file or a stray `.tmp` beside it. The
//! command then says what stopped it and exits with 128 + the signal's number (130 for
//! Ctrl-C, 143 for SIGTERM), as a shell's own commands do.
//!
//! A second signal ends the process at once (the same exit status), for a stage that does
//! not stop quickly enough: the reading and repair of the input, the normals and the
//! deviation check do not poll the flag (each takes well under a second on the corpus), and
//! neither does the renderer. Such a stage is followed by [`check`], so the command stops
//! right after it.
//!
//! On other platforms than Unix nothing is installed, and a signal ends the process as it
//! would without this module.

use algesurf_mesh::progress::Progress;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// The flags the signal handlers set: whether a signal came, and which (its number).
struct Flags {
    requested: Arc<AtomicBool>,
    signal: Arc<AtomicUsize>,
}

static FLAGS: OnceLock<Flags> = OnceLock::new();

fn flags() -> &'static Flags {
    FLAGS.get_or_init(|| Flags {
        requested: Arc::new(AtomicBool::new(false)),
        signal: Arc::new(AtomicUsize::new(0)),
    })
}

/// Installs the handlers for SIGINT and SIGTERM (on Unix; nothing elsewhere). Called first
/// thing in `main`. A handler that cannot be installed leaves that signal's default action,
/// which ends the process as before: not worth failing the command for.
pub(crate) fn install() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let f = flags();
        for signal in [SIGINT, SIGTERM] {
            // The order matters (signal-hook's `flag` documentation): the conditional exit is
            // registered first, so that the first signal finds the flag unset and only sets
            // it, and a second one finds it set and ends the process.
            let status = 128 + signal;
            let _ = signal_hook::flag::register_conditional_shutdown(
                signal,
                status,
                Arc::clone(&f.requested),
            );
            let _ =
                signal_hook::flag::register_usize(signal, Arc::clone(&f.signal), signal as usize);
            let _ = signal_hook::flag::register(signal, Arc::clone(&f.requested));
        }
    }
}

/// Whether a signal asked the command to stop.
pub(crate) fn requested() -> bool {
    flags().requested.load(Ordering::Relaxed)
}

/// The command was stopped by a signal before it finished. Returned by [`check`]; `main`
/// prints it and exits with [`Interrupted::exit_status`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "interrupted by {} before the command finished; no output was written (an existing output file is as it was)",
    signal_name(*signal)
)]
pub(crate) struct Interrupted {
    /// The signal's number (0 when unknown).
    pub(crate) signal: usize,
}

impl Interrupted {
    /// 128 + the signal's number, the status a shell reports for a command a signal ended
    /// (130 for Ctrl-C); 130 when the signal is not known.
    pub(crate) fn exit_status(self) -> u8 {
        u8::try_from(128 + if self.signal == 0 { 2 } else { self.signal }).unwrap_or(130)
    }
}

fn signal_name(signal: usize) -> &'static str {
    match signal {
        2 => "Ctrl-C (SIGINT)",
        15 => "SIGTERM",
        _ => "a signal",
    }
}

/// `Err(Interrupted)` once a signal came: called after every stage, before the stage's own
/// error (a `Cancelled` one, when the signal stopped it) is turned into a message.
///
/// # Errors
/// [`Interrupted`] when [`requested`].
pub(crate) fn check() -> Result<(), Interrupted> {
    if requested() {
        Err(Interrupted {
            signal: flags().signal.load(Ordering::Relaxed),
        })
    } else {
        Ok(())
    }
}

/// A [`Progress`] sink that passes every report on to `inner` and is
/// [cancelled](Progress::cancelled) when `inner` is or a signal came: what the stages hand to
/// the library's `_with_progress` functions.
pub(crate) struct Interruptible<'a>(pub(crate) &'a dyn Progress);

impl Progress for Interruptible<'_> {
    fn start(&self, name: &str, total: u64) {
        self.0.start(name, total);
    }

    fn advance(&self, units: u64) {
        self.0.advance(units);
    }

    fn cancelled(&self) -> bool {
        requested() || self.0.cancelled()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_mesh::progress::ProgressCounter;

    /// The sink forwards reports, and stops when its inner sink does (the signal's own path
    /// is tested end to end in `tests/interrupt.rs`, with real signals: a unit test raising
    /// the process-wide flag would stop every other test of this binary).
    #[test]
    fn the_sink_forwards_reports_and_stops_with_its_inner_sink() {
        let inner = ProgressCounter::new();
        let sink = Interruptible(&inner);
        sink.start("writing", 10);
        sink.advance(4);
        assert_eq!(inner.snapshot().done, 4);
        assert_eq!(inner.snapshot().step, "writing");
        assert!(!sink.cancelled());
        inner.cancel();
        assert!(sink.cancelled());
    }

    #[test]
    fn the_exit_status_is_128_plus_the_signal() {
        assert_eq!(Interrupted { signal: 2 }.exit_status(), 130);
        assert_eq!(Interrupted { signal: 15 }.exit_status(), 143);
        assert_eq!(Interrupted { signal: 0 }.exit_status(), 130);
        assert!(
            Interrupted { signal: 2 }
                .to_string()
                .starts_with("interrupted by Ctrl-C")
        );
    }
}

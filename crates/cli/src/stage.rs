//! The `smooth` command's stages: each one timed, with its minor page faults, and a spinner
//! on stderr when it runs longer than a second.

use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Wall-clock seconds of each stage.
#[derive(Debug, Default, Clone)]
pub(crate) struct Timings {
    pub(crate) read: f64,
    pub(crate) repair: f64,
    pub(crate) normals: f64,
    pub(crate) hull: f64,
    pub(crate) function: f64,
    pub(crate) construction: f64,
    pub(crate) tessellation: f64,
    /// The check, which runs while the output is written (`check_and_write`).
    pub(crate) check: f64,
    /// Writing the output, while the check runs.
    pub(crate) write: f64,
    /// The check and the write together, from the start of both to the end of the later.
    pub(crate) check_and_write: f64,
    /// Page faults per stage.
    pub(crate) faults: StageFaults,
}

/// Minor page faults of each stage ([`crate::memory`]), `None` where they cannot be read.
#[derive(Debug, Default, Clone)]
pub(crate) struct StageFaults {
    pub(crate) read: Option<u64>,
    pub(crate) repair: Option<u64>,
    pub(crate) normals: Option<u64>,
    pub(crate) construction: Option<u64>,
    pub(crate) tessellation: Option<u64>,
    /// The check and the write, which run at the same time (the counts are the process's).
    pub(crate) check_and_write: Option<u64>,
}

/// [`stage`], also counting the minor page faults the process took during it.
pub(crate) fn measured<T>(
    name: &str,
    progress: bool,
    f: impl FnOnce() -> T,
) -> (T, f64, Option<u64>) {
    let before = crate::memory::minor_faults();
    let (r, dt) = stage(name, progress, f);
    let faults = before
        .zip(crate::memory::minor_faults())
        .map(|(a, b)| b.saturating_sub(a));
    (r, dt, faults)
}

/// Runs `f`, timing it; with `progress`, shows a spinner named `name` on stderr once it has
/// run for a second.
pub(crate) fn stage<T>(name: &str, progress: bool, f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    if !progress {
        let r = f();
        return (r, start.elapsed().as_secs_f64());
    }
    let (tx, rx) = mpsc::channel::<()>();
    let r = std::thread::scope(|s| {
        s.spawn(move || {
            if rx.recv_timeout(Duration::from_secs(1)) != Err(mpsc::RecvTimeoutError::Timeout) {
                return;
            }
            let bar = indicatif::ProgressBar::new_spinner().with_message(name.to_string());
            bar.set_style(
                indicatif::ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
            );
            bar.enable_steady_tick(Duration::from_millis(100));
            let _ = rx.recv(); // returns when the stage drops the sender
            bar.finish_and_clear();
        });
        let r = f();
        drop(tx);
        r
    });
    (r, start.elapsed().as_secs_f64())
}

//! The commands' stages: each one timed, with its minor page faults and CPU time, a progress
//! display on stderr (the stage, its current step and that step's count) when it runs longer
//! than a second, and a sink that Ctrl-C cancels ([`crate::interrupt`]).

use crate::interrupt::Interruptible;
use algesurf_mesh::progress::{NoProgress, Progress, ProgressCounter, ProgressSnapshot};
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
    /// Page faults and CPU time per stage.
    pub(crate) usage: StageUsage,
}

/// What one stage cost the process besides wall time: its minor page faults and CPU seconds,
/// all threads together ([`crate::memory::ProcessCounters`]); each `None` where they cannot
/// be read.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Usage {
    pub(crate) faults: Option<u64>,
    pub(crate) cpu: Option<f64>,
}

impl Usage {
    /// The sum of two stages' usage (`None` where either is unknown).
    pub(crate) fn plus(self, other: Usage) -> Usage {
        Usage {
            faults: self.faults.zip(other.faults).map(|(a, b)| a + b),
            cpu: self.cpu.zip(other.cpu).map(|(a, b)| a + b),
        }
    }
}

/// The [`Usage`] of each stage.
#[derive(Debug, Default, Clone)]
pub(crate) struct StageUsage {
    pub(crate) read: Usage,
    pub(crate) repair: Usage,
    pub(crate) normals: Usage,
    pub(crate) construction: Usage,
    pub(crate) tessellation: Usage,
    /// The check and the write, which run at the same time (the counts are the process's).
    pub(crate) check_and_write: Usage,
}

impl StageUsage {
    /// The stages by their report names, in order.
    pub(crate) fn named(&self) -> [(&'static str, Usage); 6] {
        [
            ("read", self.read),
            ("repair", self.repair),
            ("normals", self.normals),
            ("construction", self.construction),
            ("tessellation", self.tessellation),
            ("check_and_write", self.check_and_write),
        ]
    }
}

/// [`stage`], also counting the minor page faults and the CPU time the process took during
/// it.
pub(crate) fn measured<T>(
    name: &str,
    progress: bool,
    f: impl FnOnce(&dyn Progress) -> T,
) -> (T, f64, Usage) {
    let before = crate::memory::process_counters();
    let (r, dt) = stage(name, progress, f);
    let counters = before.zip(crate::memory::process_counters());
    let usage = Usage {
        faults: counters.map(|(a, b)| b.minor_faults.saturating_sub(a.minor_faults)),
        cpu: counters.map(|(a, b)| crate::cpu::seconds_between(a.cpu_ticks, b.cpu_ticks)),
    };
    (r, dt, usage)
}

/// How often the progress display reads the stage's counter and redraws.
const REDRAW: Duration = Duration::from_millis(100);

/// Runs `f`, timing it; with `progress`, shows on stderr, once the stage has run for a
/// second, a spinner named `name`, or the step `f` reports to the [`Progress`] it is given
/// with a bar where the step has a count ([`bar_text`]). The sink `f` is given is cancelled
/// by Ctrl-C ([`Interruptible`]), shown or not; the caller follows the stage with
/// [`crate::interrupt::check`].
pub(crate) fn stage<T>(name: &str, progress: bool, f: impl FnOnce(&dyn Progress) -> T) -> (T, f64) {
    let start = Instant::now();
    if !progress {
        let r = f(&Interruptible(&NoProgress));
        return (r, start.elapsed().as_secs_f64());
    }
    let counter = ProgressCounter::new();
    let (tx, rx) = mpsc::channel::<()>();
    let r = std::thread::scope(|s| {
        let counter = &counter;
        s.spawn(move || {
            if rx.recv_timeout(Duration::from_secs(1)) != Err(mpsc::RecvTimeoutError::Timeout) {
                return;
            }
            // A bar per step, made whole before it is first drawn (changing a drawn bar's
            // message, length and count one by one drew frames that mixed two steps). Its
            // clock counts from the stage's start, not from the second it waited.
            let bar_for = |message: String, length: u64, done: u64| {
                let template = if length > 0 {
                    "{spinner} {msg} [{bar:30}] {pos}/{len} {elapsed}"
                } else {
                    "{spinner} {msg} {elapsed}"
                };
                indicatif::ProgressBar::with_draw_target(
                    Some(length),
                    indicatif::ProgressDrawTarget::stderr(),
                )
                .with_style(
                    indicatif::ProgressStyle::with_template(template)
                        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
                )
                .with_message(message)
                .with_position(done)
                .with_elapsed(start.elapsed())
            };
            let mut shown: Option<((String, u64), indicatif::ProgressBar)> = None;
            loop {
                let now = counter.snapshot();
                let text = bar_text(name, &now);
                match &shown {
                    Some((was, bar)) if *was == text => bar.set_position(now.done),
                    _ => {
                        if let Some((_, old)) = shown.take() {
                            old.finish_and_clear();
                        }
                        let bar = bar_for(text.0.clone(), text.1, now.done);
                        shown = Some((text, bar));
                    }
                }
                if let Some((_, bar)) = &shown {
                    bar.tick();
                }
                // Returns when the stage drops the sender.
                if rx.recv_timeout(REDRAW) != Err(mpsc::RecvTimeoutError::Timeout) {
                    break;
                }
            }
            if let Some((_, bar)) = shown {
                bar.finish_and_clear();
            }
        });
        let r = f(&Interruptible(counter));
        drop(tx);
        r
    });
    (r, start.elapsed().as_secs_f64())
}

/// The progress display's message and bar length for the stage `name` at `now`: the stage's
/// name alone until it reports a step, then the name and the step; the step's count as the
/// length (0: no bar, a spinner only).
pub(crate) fn bar_text(name: &str, now: &ProgressSnapshot) -> (String, u64) {
    if now.step.is_empty() {
        (name.to_string(), 0)
    } else {
        (format!("{name} ({})", now.step), now.total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The display names the stage, and the step once there is one, with a bar exactly
    /// where the step has a count.
    #[test]
    fn the_bar_names_the_stage_and_its_step() {
        let counter = ProgressCounter::new();
        assert_eq!(
            bar_text("tessellating", &counter.snapshot()),
            ("tessellating".to_string(), 0)
        );
        counter.start("tessellation: face patches", 120);
        counter.advance(64);
        let now = counter.snapshot();
        assert_eq!(
            bar_text("tessellating", &now),
            ("tessellating (tessellation: face patches)".to_string(), 120)
        );
        assert_eq!(now.done, 64);
        counter.start("hull: refinement round 2 (31 overlapping pairs)", 0);
        assert_eq!(bar_text("building", &counter.snapshot()).1, 0);
    }

    /// A stage gives its closure a sink that records its steps when progress is shown, and
    /// returns the closure's value either way.
    #[test]
    fn a_stage_passes_its_progress_on() {
        for shown in [false, true] {
            let (r, dt) = stage("counting", shown, |p| {
                p.start("step", 3);
                p.advance(3);
                7
            });
            assert_eq!(r, 7);
            assert!(dt >= 0.0);
        }
    }
}

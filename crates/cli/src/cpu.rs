//! The process's CPU time, for `smooth`'s summary and report: how many cores a stage kept
//! busy, beside its wall time (`cpu_s` beside `timings_s`). Read from Linux's `/proc`; `None`
//! on other systems or when it cannot be read ([`crate::memory::process_counters`]).
//!
//! Why it is reported: the benchmarks compare wall times on a 2-core machine, and a peer can
//! run on one core (libigl's `igl.loop` does: its CPU time equals its wall time) while the
//! construction runs on both; the CPU seconds say which.

/// Clock ticks per second of `/proc/self/stat`'s times ([`crate::memory::ProcessCounters`]):
/// the kernel reports them in `USER_HZ`, which is 100 on every architecture but Alpha
/// (`sysconf(_SC_CLK_TCK)` returns the same constant; reading it would be an FFI call for a
/// number the ABI fixes). So the times have a resolution of 10 ms: ±1 % of a one-second
/// stage.
const USER_HZ: f64 = 100.0;

/// The shortest wall time for which [`cores_busy`] gives a figure: 0.1 s. Each reading is
/// off by up to one 10 ms tick, so the CPU seconds of a stage are good to ±20 ms, which over
/// 0.1 s of wall time is ±0.2 core (the bunny's 0.11 s tessellation at 3 × 2 keeps its
/// figure); over the built-in mesh's 1 ms construction one tick made "13.3 cores".
pub(crate) const MIN_WALL_FOR_CORES_S: f64 = 0.1;

/// How many cores a stage kept busy on average: `cpu` seconds over `wall` seconds, or `None`
/// when the stage was too short for the 10 ms ticks to say ([`MIN_WALL_FOR_CORES_S`]).
pub(crate) fn cores_busy(cpu: f64, wall: f64) -> Option<f64> {
    (wall >= MIN_WALL_FOR_CORES_S).then(|| cpu / wall)
}

/// The seconds between two readings of [`crate::memory::ProcessCounters::cpu_ticks`] (`0` if
/// the second is not later).
pub(crate) fn seconds_between(before: u64, after: u64) -> f64 {
    after.saturating_sub(before) as f64 / USER_HZ
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    /// Cores are given only for stages long enough for the ticks: one tick over a 1 ms stage
    /// is no figure, one second over half a second is two cores.
    #[test]
    fn cores_need_a_stage_longer_than_the_ticks() {
        assert_eq!(cores_busy(0.01, 0.00075), None);
        assert_eq!(cores_busy(0.0, 0.09), None);
        assert_eq!(cores_busy(1.0, 0.5), Some(2.0));
    }

    /// A thread kept busy for 300 ms shows as at least ~250 ms of the process's CPU time (on
    /// Linux; elsewhere `None`). Other tests of this binary may run at the same time and add
    /// their own, so only the lower bound is checked: 10 ms ticks and a busy-wait that the
    /// scheduler can interrupt leave it a little below the wall time at worst.
    #[test]
    fn a_busy_thread_shows_as_cpu_time() {
        let ticks = || crate::memory::process_counters().map(|c| c.cpu_ticks);
        let before = ticks();
        if !cfg!(target_os = "linux") {
            assert_eq!(before, None);
            return;
        }
        let before = before.expect("/proc/self/stat is readable on Linux");
        let busy = std::thread::spawn(|| {
            let start = Instant::now();
            let mut x = 0u64;
            while start.elapsed() < Duration::from_millis(300) {
                x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
            }
            x
        });
        busy.join().expect("the busy thread");
        let spent = seconds_between(before, ticks().unwrap());
        assert!(spent >= 0.25, "{spent} s of CPU for 0.3 s of busy work");
    }
}

//! The process's memory figures for `smooth`'s summary and report: minor page faults (the
//! kernel mapping a fresh zeroed page on first touch, read with the CPU time in
//! [`ProcessCounters`]) and the peak resident size; and the
//! memory the system has available, which `--resolution` is checked against
//! ([`crate::grid::check_memory`]). Read from Linux's `/proc`; `None` on other systems or when
//! it cannot be read.
//!
//! Why they are reported: on the 2-core machine the benchmarks run on, first-touching a page
//! costs about 3.5 µs, and the bunny's command takes ~170 k of them (docs/PERFORMANCE.md,
//! "Construction, sixth pass"), so a stage's faults explain much of its time.

/// The process's counters that `/proc/self/stat` holds, for all its threads so far (those
/// that have ended included), read together so that a stage's before and after each cost one
/// read of the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ProcessCounters {
    /// Minor page faults (field 10).
    pub(crate) minor_faults: u64,
    /// CPU time, user + system (fields 14 and 15), in clock ticks ([`crate::cpu`]).
    pub(crate) cpu_ticks: u64,
}

/// The [`ProcessCounters`] now.
pub(crate) fn process_counters() -> Option<ProcessCounters> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it
    // (field 3 is the first there, so field k is the (k − 2)th).
    let (_, rest) = stat.rsplit_once(')')?;
    let mut fields = rest.split_whitespace();
    let minor_faults = fields.nth(7)?.parse().ok()?;
    let mut field = || fields.next()?.parse::<u64>().ok();
    // Fields 11–13 (child faults, major faults) before the times.
    for _ in 0..3 {
        field()?;
    }
    let (user, system) = (field()?, field()?);
    Some(ProcessCounters {
        minor_faults,
        cpu_ticks: user + system,
    })
}

/// The peak resident set size in bytes (`VmHWM` of `/proc/self/status`).
pub(crate) fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// The memory the system can give a new allocation without swapping, in bytes
/// (`MemAvailable` of `/proc/meminfo`, Linux 3.14 and later).
pub(crate) fn available_bytes() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Touching 64 MiB of fresh memory shows as page faults and raises the peak (on Linux;
    /// elsewhere both are `None`).
    #[test]
    fn first_touch_shows_as_faults_and_peak() {
        let faults = || process_counters().map(|c| c.minor_faults);
        let (before, peak) = (faults(), peak_resident_bytes());
        if !cfg!(target_os = "linux") {
            assert_eq!((before, peak), (None, None));
            return;
        }
        let before = before.expect("/proc/self/stat is readable on Linux");
        let bytes = 64 << 20;
        let v = vec![1u8; bytes];
        assert_eq!(v.iter().map(|&x| x as usize).sum::<usize>(), bytes);
        let after = faults().unwrap();
        // Transparent huge pages can back it with 2 MiB pages: 32 faults at least.
        assert!(after - before >= 32, "{before} → {after}");
        assert!(peak_resident_bytes().unwrap() >= bytes as u64);
    }

    /// On Linux the available memory is read, and is more than nothing and less than
    /// 2⁶⁰ bytes; elsewhere it is `None`.
    #[test]
    fn available_memory_is_read_on_linux() {
        let available = available_bytes();
        assert_eq!(
            available.is_some(),
            cfg!(target_os = "linux"),
            "{available:?}"
        );
        if let Some(b) = available {
            assert!(b > 0 && b < 1 << 60, "{b}");
        }
    }
}

//! CPU time of the calling thread, for time bounds that must hold on a
//! loaded machine: the test threads share two cores with other builds, so
//! wall time says more about the neighbours than about the code.

use std::time::Duration;

/// CPU time this thread has used (user + system), from
/// `/proc/thread-self/stat` (clock ticks of 10 ms); `None` off Linux.
pub fn thread_cpu() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
    // Fields after the command name, which is in parentheses and may hold spaces.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

/// Runs `f` and returns its result with the CPU time it took on this
/// thread (wall time where CPU time cannot be read).
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let (cpu, wall) = (thread_cpu(), std::time::Instant::now());
    let out = f();
    let took = match (cpu, thread_cpu()) {
        (Some(a), Some(b)) => b.saturating_sub(a),
        _ => wall.elapsed(),
    };
    (out, took)
}

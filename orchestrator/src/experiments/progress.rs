//! How an experiment shows that it is still working. On a terminal each
//! batch of runs draws a bar ([`phase`]); off one (a pipe, a log file, CI)
//! the bar draws nothing, so the command starts a [`Ticker`] that prints
//! `progress: DONE/TOTAL runs, T s` on stderr at least every [`EVERY`],
//! whether or not a run finished meanwhile, and once more when the command
//! ends. Every batch counts its runs into one tally for the process, which
//! only the ticker reads: one place, whatever experiment makes the runs.

use std::io::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The longest an experiment off a terminal goes without a progress line.
pub const EVERY: Duration = Duration::from_secs(10);

/// Runs finished and runs planned, over every batch of the process.
static DONE: AtomicU64 = AtomicU64::new(0);
static TOTAL: AtomicU64 = AtomicU64::new(0);

/// One batch of `len` runs: counted into the process's tally, and drawn
/// as a bar with the elapsed and remaining time on stderr when `bar`.
pub fn phase(len: u64, bar: bool) -> Phase {
    TOTAL.fetch_add(len, Ordering::Relaxed);
    Phase { bar: if bar { terminal_bar(len) } else { ProgressBar::hidden() } }
}

/// A batch of runs under way ([`phase`]).
pub struct Phase {
    bar: ProgressBar,
}

impl Phase {
    /// `n` more runs finished.
    pub fn inc(&self, n: u64) {
        DONE.fetch_add(n, Ordering::Relaxed);
        self.bar.inc(n);
    }

    /// The batch is over (or failed): the bar goes.
    pub fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
    }
}

fn terminal_bar(len: u64) -> ProgressBar {
    let b = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    b.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} runs, eta {eta}")
            .expect("static template")
            .progress_chars("=> "),
    );
    // Redraw (elapsed, eta) even while no run finishes: single runs of a
    // large scenario can take seconds.
    b.enable_steady_tick(Duration::from_millis(200));
    b
}

/// The progress line at `elapsed` since the command started.
/// A command without runs (`--grids`) says only that it is working.
pub fn line(done: u64, total: u64, elapsed: Duration) -> String {
    let t = elapsed.as_secs_f64();
    if total == 0 {
        format!("progress: working, {t:.1} s")
    } else {
        format!("progress: {done}/{total} runs, {t:.1} s")
    }
}

/// When the next line is due: every `every` from the start, a missed
/// one skipped rather than printed late in a burst.
#[derive(Clone, Copy, Debug)]
pub struct Due {
    every: Duration,
    next: Duration,
}

impl Due {
    pub fn new(every: Duration) -> Self {
        Due { every, next: every }
    }

    /// Whether a line is due at `now`; if so, the next is the first
    /// multiple of `every` after `now`.
    pub fn poll(&mut self, now: Duration) -> bool {
        if now < self.next {
            return false;
        }
        let periods = (now.as_nanos() / self.every.as_nanos().max(1)) as u32;
        self.next = self.every * (periods + 1);
        true
    }

    /// How long from `now` until the next line is due.
    pub fn wait(&self, now: Duration) -> Duration {
        self.next.saturating_sub(now)
    }
}

/// Prints [`line`]s on stderr while it lives, from a thread of its own,
/// and a last one when dropped (at the end of the command) if any run was
/// planned or a line printed.
pub struct Ticker {
    stop: Option<mpsc::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl Ticker {
    /// Lines timed from `started`, the command's start.
    pub fn start(started: Instant) -> Ticker {
        let (stop, rx) = mpsc::channel::<()>();
        let thread = std::thread::spawn(move || {
            let now = || started.elapsed();
            // Not eprintln!: a closed stderr must not panic the thread.
            let show = |t| {
                let text = line(DONE.load(Ordering::Relaxed), TOTAL.load(Ordering::Relaxed), t);
                let _ = writeln!(std::io::stderr(), "{text}");
            };
            let mut due = Due::new(EVERY);
            let mut shown = false;
            loop {
                match rx.recv_timeout(due.wait(now())) {
                    Err(RecvTimeoutError::Timeout) => {
                        let t = now();
                        if due.poll(t) {
                            show(t);
                            shown = true;
                        }
                    }
                    // Dropped: the command is over. A last line, unless it
                    // ran nothing and said nothing (a bad input's error
                    // stays the only line).
                    _ if shown || TOTAL.load(Ordering::Relaxed) > 0 => break show(now()),
                    _ => break,
                }
            }
        });
        Ticker { stop: Some(stop), thread: Some(thread) }
    }
}

impl Drop for Ticker {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(x: f64) -> Duration {
        Duration::from_secs_f64(x)
    }

    /// Lines at 10, 20, 30 s on a clock that ticks every 0.5 s; a clock
    /// that jumps (a thread woken late) gets one line, not a burst.
    #[test]
    fn a_line_is_due_every_ten_seconds_and_never_in_a_burst() {
        let mut due = Due::new(EVERY);
        let printed: Vec<f64> = (0..=70).map(|i| i as f64 * 0.5).filter(|&t| due.poll(s(t))).collect();
        assert_eq!(printed, [10.0, 20.0, 30.0]);
        assert_eq!(due.wait(s(35.0)), s(5.0));
        assert!(due.poll(s(67.5)), "late: due at once");
        assert!(!due.poll(s(67.6)), "the missed ones at 50 and 60 s are not printed");
        assert_eq!(due.wait(s(67.5)), s(2.5), "back on the 10 s beat");
        assert!(due.poll(s(70.0)));
    }

    #[test]
    fn the_wait_never_exceeds_the_period() {
        let mut due = Due::new(EVERY);
        for i in 0..1000 {
            let t = s(i as f64 * 0.37);
            due.poll(t);
            assert!(due.wait(t) <= EVERY, "{i}");
        }
    }

    #[test]
    fn the_line_says_runs_done_of_planned_and_the_time() {
        assert_eq!(line(1234, 26000, s(12.34)), "progress: 1234/26000 runs, 12.3 s");
        assert_eq!(line(0, 0, s(10.0)), "progress: working, 10.0 s");
    }
}

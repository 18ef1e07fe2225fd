//! Faults applied to robot processes while the world pauses at them
//! (`fault K` on its stdout): the kernel models every fault at its
//! simulated time; the process is made to match before the world goes on.
//!
//! - crash: SIGKILL, and wait until the child is dead (reaped);
//! - freeze: SIGSTOP, and wait until the process is stopped;
//! - thaw: SIGCONT;
//! - slow: nothing (the kernel delays the robot's wake-ups itself).

use std::process::Child;
use std::time::{Duration, Instant};

use gridswarm::ipc;
use gridswarm::sim::FaultKind;

use crate::launch;

/// How long a signalled process gets to reach the state asked for.
const SETTLE: Duration = Duration::from_secs(2);

/// Applies `kind` to `child`; false if the process was already gone.
pub fn apply(kind: FaultKind, child: &mut Child) -> bool {
    let pid = child.id();
    match kind {
        FaultKind::Crash => {
            let sent = launch::signal(pid, libc::SIGKILL);
            let _ = child.wait();
            sent
        }
        FaultKind::Freeze => {
            let sent = launch::signal(pid, libc::SIGSTOP);
            let t = Instant::now();
            while sent && !ipc::pid_stopped(pid) && ipc::pid_alive(pid) && t.elapsed() < SETTLE {
                std::thread::sleep(Duration::from_micros(200));
            }
            sent
        }
        FaultKind::Thaw => launch::signal(pid, libc::SIGCONT),
        FaultKind::Slow(_) => true,
    }
}

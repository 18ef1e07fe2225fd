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
use gridswarm::sim::{Fault, FaultKind};

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

/// Robots whose last applied freeze was not followed by an applied thaw.
pub fn still_frozen(faults: &[Fault], applied: &[bool]) -> Vec<usize> {
    let mut frozen: Vec<usize> = Vec::new();
    for (f, _) in faults.iter().zip(applied).filter(|(_, &a)| a) {
        match f.kind {
            FaultKind::Freeze => frozen.push(f.robot),
            FaultKind::Thaw => frozen.retain(|&r| r != f.robot),
            _ => {}
        }
    }
    frozen
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::sim::schedule::parse_freeze;

    #[test]
    fn frozen_until_thawed() {
        let mut f = parse_freeze("2@3:6").unwrap();
        f.extend(parse_freeze("4@1").unwrap());
        assert_eq!(still_frozen(&f, &[true, true, true]), vec![4]);
        assert_eq!(still_frozen(&f, &[true, false, false]), vec![2]);
    }
}

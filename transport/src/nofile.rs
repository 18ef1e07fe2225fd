//! Open-file limits of a distributed run (feature `ipc`): what the
//! processes of a run of `N` robots need (the world-server's descriptors
//! grow with `N`; an agent's and the orchestrator's do not), and the check
//! every program makes before it creates anything, raising the soft limit
//! when the hard one allows. Running out midway would not fail cleanly:
//! iceoryx2 drops connections it cannot open, and robots look dead or slow.

use std::io;

/// Descriptors the world-server holds per robot, counted by link target in
/// `/proc/PID/fd` of a world at 20, 64 and 200 robots: for the robot's own
/// inbox service its static config file, its dynamic config and the
/// world's port tag, the world's data segment and its connection; the
/// robot's data segment and connection in its group's outbox; the shared
/// memory and socket of the connection to its listener. (Before outboxes
/// and wake-ups were shared, 15: each cost three more.)
pub const WORLD_FDS_PER_ROBOT: u64 = 9;
/// Descriptors the world-server holds per outbox group
/// ([`crate::ipc::outbox`]): the service's static config, dynamic config
/// and the world's port tag.
pub const WORLD_FDS_PER_GROUP: u64 = 3;
/// Descriptors any process of a run holds besides: the world's own 20
/// (its node, the two shared event services), an agent's 29 (whatever N),
/// the orchestrator's 9, and room for the files they open for a moment
/// (`/proc`, node lists, the report).
pub const FDS_BASE: u64 = 40;

/// The open-file limit (`RLIMIT_NOFILE`) every process of a run of
/// `robots` robots needs: the world-server's, the largest.
pub fn needed(robots: usize) -> u64 {
    let groups = crate::ipc::outbox::groups(robots) as u64;
    FDS_BASE + WORLD_FDS_PER_ROBOT * robots as u64 + WORLD_FDS_PER_GROUP * groups
}

/// This process's open-file limits, soft and hard.
pub fn limits() -> io::Result<(u64, u64)> {
    let mut lim = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: getrlimit with a valid pointer to a local struct.
    if unsafe { libc::getrlimit(libc::RLIMIT_NOFILE, &mut lim) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok((lim.rlim_cur as u64, lim.rlim_max as u64))
}

/// Makes sure this process (and every child it spawns afterwards, which
/// inherits it) may open `needed` files: raises the soft limit to the hard
/// limit if the soft one is lower, as the user could with `ulimit -n`.
/// Returns the soft limit now in force, or a message naming the number
/// needed, the limits found and the fix.
pub fn ensure(needed: u64, what: &str) -> Result<u64, String> {
    let (soft, hard) = limits().map_err(|e| format!("cannot read the open-file limit: {e}"))?;
    if soft >= needed {
        return Ok(soft);
    }
    // The hard limit first, as is common; an unlimited one the kernel caps
    // (`fs.nr_open`), so then just what is needed.
    for cur in [hard, needed].into_iter().filter(|&c| hard >= needed && c >= needed) {
        let want = libc::rlimit { rlim_cur: cur as libc::rlim_t, rlim_max: hard as libc::rlim_t };
        // SAFETY: setrlimit with a valid pointer to a local struct.
        if unsafe { libc::setrlimit(libc::RLIMIT_NOFILE, &want) } == 0 {
            return Ok(cur);
        }
    }
    Err(format!(
        "{what} needs {needed} open files ({FDS_BASE} + {WORLD_FDS_PER_ROBOT} a robot + {WORLD_FDS_PER_GROUP} per {} robots in the world-server), \
         but the open-file limit is {soft} (hard limit {hard}); raise it with `ulimit -n {needed}` \
         (above the hard limit only root can, e.g. in /etc/security/limits.conf), or run fewer robots",
        crate::ipc::outbox::OUTBOX_GROUP
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_file_needs_are_checked_against_the_limits() {
        assert_eq!(needed(0), FDS_BASE);
        assert_eq!(needed(100) - needed(99), WORLD_FDS_PER_ROBOT, "the same group");
        assert_eq!(needed(97) - needed(96), WORLD_FDS_PER_ROBOT + WORLD_FDS_PER_GROUP, "a new group");
        assert_eq!(needed(1000), 40 + 9 * 1000 + 3 * 32);
        let (soft, hard) = limits().unwrap();
        assert!(soft <= hard);
        assert_eq!(ensure(1, "x"), Ok(soft), "enough: nothing changes");
        let err = ensure(u64::MAX, "a run of many robots").unwrap_err();
        assert!(err.starts_with(&format!("a run of many robots needs {}", u64::MAX)), "{err}");
        assert!(
            err.contains(&format!("ulimit -n {}", u64::MAX)) && err.contains(&format!("hard limit {hard}")),
            "{err}"
        );
    }
}

//! Ending on a signal without leaving the run's files behind.
//!
//! The orchestrator spawns the world with `PR_SET_PDEATHSIG(SIGTERM)`, so
//! a `kill -9` of `gridswarm` (which nothing can catch) reaches the world
//! as SIGTERM; a world started by hand gets SIGINT, SIGHUP or SIGQUIT from
//! its terminal. Either way no one else would remove the run's iceoryx2
//! files until the next run's sweep, so the world does it on its way out:
//! every file of its prefix (the agents' too: they died with the
//! orchestrator, or will find the world gone), and the orchestrator's
//! temporary directory of the run if the orchestrator is gone.
//!
//! The signals are blocked in every thread and taken by one thread with
//! `sigwait`, so the cleanup runs as ordinary code, not in a handler,
//! whatever the main thread is blocked in. The orchestrator's death can
//! also end the main thread first (its stdout closes, or its robots vanish
//! with it): so the world cleans up on its way out too whenever the
//! orchestrator is gone ([`Orphan`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use gridswarm::ipc;

const SIGNALS: [libc::c_int; 4] = [libc::SIGTERM, libc::SIGINT, libc::SIGHUP, libc::SIGQUIT];

/// What the world removes when a signal ends it.
#[derive(Clone)]
pub struct Cleanup {
    pub prefix: String,
    /// The orchestrator's temporary directory of the run (the run file's
    /// directory, when it has the name the orchestrator gives it).
    pub run_dir: Option<PathBuf>,
}

/// The orchestrator's directory of the run whose run file is `run_file`:
/// `gridswarm-<prefix>`, and nothing else (a world started by hand must
/// never remove a user's directory).
pub fn run_dir_of(run_file: &Path, prefix: &str) -> Option<PathBuf> {
    let dir = run_file.parent()?;
    (dir.file_name()?.to_str()? == format!("gridswarm-{prefix}")).then(|| dir.to_path_buf())
}

/// Removes the run's files when dropped if the orchestrator is gone.
pub struct Orphan {
    cleanup: Cleanup,
    parent: libc::pid_t,
}

impl Drop for Orphan {
    fn drop(&mut self) {
        if orphaned(self.parent) {
            remove(&self.cleanup, true);
            std::thread::sleep(SETTLE);
            remove(&self.cleanup, true);
        }
    }
}

/// How long agents killed with the orchestrator may take to be gone.
const SETTLE: Duration = Duration::from_millis(100);

fn orphaned(parent: libc::pid_t) -> bool {
    // SAFETY: getppid has no preconditions.
    unsafe { libc::getppid() != parent }
}

/// Blocks the signals in this thread (and so in every thread started
/// after it) and starts the thread that ends the process on them. Call it
/// first, before any other thread exists; keep the [`Orphan`] until the
/// world's ports are gone.
pub fn end_cleanly_on_signals(cleanup: Cleanup) -> Result<Orphan, String> {
    // SAFETY: sigset operations on a local set; pthread_sigmask on this thread.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for s in SIGNALS {
            libc::sigaddset(&mut set, s);
        }
        let rc = libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        if rc != 0 {
            return Err(format!("cannot block signals: {}", std::io::Error::from_raw_os_error(rc)));
        }
        set
    };
    // SAFETY: getppid has no preconditions.
    let parent = unsafe { libc::getppid() };
    let orphan = Orphan { cleanup: cleanup.clone(), parent };
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            let mut sig: libc::c_int = 0;
            // SAFETY: sigwait on a set of signals blocked in every thread.
            while unsafe { libc::sigwait(&set, &mut sig) } != 0 {}
            // The parent's death signals each thread of the world in turn,
            // before this one is reparented: ask who the parent is later.
            // Agents killed with it may still be finishing a write, too.
            std::thread::sleep(SETTLE);
            let orphaned = orphaned(parent);
            remove(&cleanup, orphaned);
            std::thread::sleep(SETTLE);
            remove(&cleanup, orphaned);
            let why = if orphaned { " (the orchestrator is gone)" } else { "" };
            eprintln!("error: stopped by signal {sig}{why}; removed the run's shared-memory files");
            // SAFETY: _exit ends the process without running destructors
            // of ports whose files are already gone.
            unsafe { libc::_exit(1) }
        })
        .map_err(|e| format!("cannot start the signal thread: {e}"))?;
    Ok(orphan)
}

fn remove(c: &Cleanup, orphaned: bool) {
    let _ = ipc::cleanup_run(&c.prefix);
    if let (true, Some(dir)) = (orphaned, &c.run_dir) {
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_orchestrators_directory_of_the_run_is_removed() {
        let p = "gs12x0a_";
        assert_eq!(
            run_dir_of(Path::new("/tmp/gridswarm-gs12x0a_/run.json"), p),
            Some(PathBuf::from("/tmp/gridswarm-gs12x0a_"))
        );
        assert_eq!(run_dir_of(Path::new("/tmp/gridswarm-gs12x0b_/run.json"), p), None);
        assert_eq!(run_dir_of(Path::new("/home/me/run.json"), p), None);
        assert_eq!(run_dir_of(Path::new("run.json"), p), None);
    }
}

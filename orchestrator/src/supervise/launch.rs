//! Process plumbing for `gridswarm run`: finding the sibling binaries,
//! spawning children that cannot outlive the orchestrator, turning SIGINT,
//! SIGTERM, SIGHUP (a closed terminal) and SIGQUIT into an event, and
//! reading the world-server's stdout lines.
//!
//! Signals are handled from the first line of `main` ([`handle_signals`])
//! to the last write: during a run they are events of its loop, which ends
//! the children first ([`forward_signals`]); at any other moment (setup,
//! checks, an in-process run, writing the outputs) the signal thread
//! removes the command's unfinished folders ([`remove_on_interrupt`]) and
//! exits 1 with one line naming the signal.
//!
//! Every child gets `PR_SET_PDEATHSIG` (it dies with the thread that
//! spawned it: always the main thread here) and its own process group,
//! so a Ctrl-C at the terminal reaches only the orchestrator, which then
//! ends the children itself and removes the run's files. Agents get
//! SIGKILL; the world-server SIGTERM, on which it removes the run's files
//! itself: after a `kill -9` of the orchestrator nobody else would.

use std::io::{BufRead, BufReader};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command};
use std::sync::mpsc::Sender;
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// What the orchestrator's main loop waits for.
#[derive(Debug)]
pub enum Event {
    /// A line the world-server printed.
    Line(String),
    /// The world-server's stdout closed: it exited or died.
    WorldClosed,
    /// One of [`SIGNALS`] reached the orchestrator.
    Signal(i32),
}

/// The directory of the running `gridswarm` binary (symlinks resolved),
/// where `world-server` and `robot-agent` are built (`target/release/`) or
/// installed (`scripts/install.sh`) too. `GRIDSWARM_BIN_DIR` overrides it.
pub fn binary(name: &str) -> Result<PathBuf, String> {
    let dir = match std::env::var_os("GRIDSWARM_BIN_DIR") {
        Some(d) => PathBuf::from(d),
        None => {
            let exe = std::env::current_exe().map_err(|e| format!("cannot locate the gridswarm binary: {e}"))?;
            exe.parent().map(PathBuf::from).ok_or("the gridswarm binary has no directory")?
        }
    };
    let path = dir.join(name);
    if path.is_file() {
        Ok(path)
    } else {
        Err(format!(
            "`{name}` not found next to gridswarm (looked for {}); build the three programs with `cargo build --release`, or install them together with scripts/install.sh",
            path.display()
        ))
    }
}

/// The signals that end a run cleanly (children reaped, files removed).
pub const SIGNALS: [i32; 4] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP, libc::SIGQUIT];

/// A signal's name, for messages.
pub fn signal_name(sig: i32) -> String {
    match sig {
        libc::SIGINT => "SIGINT".into(),
        libc::SIGTERM => "SIGTERM".into(),
        libc::SIGHUP => "SIGHUP".into(),
        libc::SIGQUIT => "SIGQUIT".into(),
        s => format!("signal {s}"),
    }
}

/// Makes `cmd` spawn a child that gets `death_signal` when the
/// orchestrator dies and that sits in a process group of its own.
pub fn guard(cmd: &mut Command, death_signal: i32) -> &mut Command {
    let parent = std::process::id() as libc::pid_t;
    cmd.process_group(0);
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            if libc::prctl(libc::PR_SET_PDEATHSIG, death_signal as libc::c_ulong, 0, 0, 0) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // The parent may have died before the prctl took effect.
            if libc::getppid() != parent {
                libc::_exit(1);
            }
            Ok(())
        })
    }
}

/// Sends `signal` to `pid`; false if it could not (already gone).
pub fn signal(pid: u32, signal: i32) -> bool {
    // SAFETY: kill(2) with a pid we spawned.
    unsafe { libc::kill(pid as libc::pid_t, signal) == 0 }
}

/// Forwards each stdout line of the world-server as an [`Event`].
pub fn read_lines(stdout: ChildStdout, tx: Sender<Event>) {
    std::thread::spawn(move || {
        let reader = BufReader::new(stdout);
        for line in reader.lines() {
            match line {
                Ok(l) => {
                    if tx.send(Event::Line(l)).is_err() {
                        return;
                    }
                }
                Err(_) => break,
            }
        }
        let _ = tx.send(Event::WorldClosed);
    });
}

static SIGNAL_PIPE: OnceLock<i32> = OnceLock::new();
/// Where the signal thread sends: the current run's channel (one process
/// may do many runs, e.g. `experiment failures`).
static SIGNAL_TX: Mutex<Option<Sender<Event>>> = Mutex::new(None);
/// Folders a signal outside a run removes before the command exits: the
/// unfinished output folder, the run's temporary folder. Held while a
/// folder is renamed into place, so a signal never cuts that in two.
static UNFINISHED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// A signal outside a run removes `dir` (until [`finished`]).
pub fn remove_on_interrupt(dir: &Path) {
    UNFINISHED.lock().unwrap_or_else(|e| e.into_inner()).push(dir.to_path_buf());
}

/// `dir` is done with (renamed into place, or removed): a signal leaves it.
pub fn finished(dir: &Path) {
    UNFINISHED.lock().unwrap_or_else(|e| e.into_inner()).retain(|d| d != dir);
}

/// Runs `f` (renaming folders into place) with signals held off: the
/// command ends after it, never in the middle. `f` must not call
/// [`remove_on_interrupt`] or [`finished`].
pub fn uninterrupted<T>(f: impl FnOnce() -> T) -> T {
    let _held = UNFINISHED.lock().unwrap_or_else(|e| e.into_inner());
    f()
}

/// The end of a command a signal reached outside a run: its unfinished
/// folders removed, one line, exit status 1 (README's table).
fn exit_interrupted(sig: i32) -> ! {
    // Held until the exit: no folder is renamed into place meanwhile.
    let dirs = UNFINISHED.lock().unwrap_or_else(|e| e.into_inner());
    for d in dirs.iter() {
        let _ = std::fs::remove_dir_all(d);
    }
    eprintln!("error: interrupted by {}", signal_name(sig));
    // SAFETY: _exit ends the process at once; the main thread may be
    // anywhere, and no destructor of its must run after the removals.
    unsafe { libc::_exit(1) }
}

/// Delivers signal `sig` to the current run, or ends the command.
fn deliver(sig: i32) {
    if let Some(tx) = SIGNAL_TX.lock().unwrap_or_else(|e| e.into_inner()).as_ref() {
        if tx.send(Event::Signal(sig)).is_ok() {
            return;
        }
    }
    exit_interrupted(sig)
}

extern "C" fn on_signal(sig: libc::c_int) {
    if let Some(&fd) = SIGNAL_PIPE.get() {
        let b = sig as u8;
        // SAFETY: write(2) is async-signal-safe; a full pipe just drops it.
        unsafe {
            libc::write(fd, &b as *const u8 as *const libc::c_void, 1);
        }
    }
}

/// Turns [`SIGNALS`] into [`Event::Signal`] on `tx` until
/// [`default_signals`]. A later call (the next run in the same process)
/// redirects the events to its own `tx`.
pub fn forward_signals(tx: Sender<Event>) -> Result<(), String> {
    *SIGNAL_TX.lock().unwrap_or_else(|e| e.into_inner()) = Some(tx);
    handle_signals()
}

/// Catches [`SIGNALS`] (a self-pipe read by a thread): outside a run they
/// end the command cleanly ([`exit_interrupted`]). `main` calls it first.
pub fn handle_signals() -> Result<(), String> {
    if SIGNAL_PIPE.get().is_none() {
        let mut fds = [0i32; 2];
        // SAFETY: pipe2 with a valid array; close-on-exec so children never hold it.
        if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC | libc::O_NONBLOCK) } != 0 {
            return Err(format!("cannot create a pipe: {}", std::io::Error::last_os_error()));
        }
        let (read_fd, write_fd) = (fds[0], fds[1]);
        // The reading end blocks; only the handler's end must not.
        // SAFETY: fcntl on a descriptor we own.
        unsafe {
            let flags = libc::fcntl(read_fd, libc::F_GETFL);
            libc::fcntl(read_fd, libc::F_SETFL, flags & !libc::O_NONBLOCK);
        }
        if SIGNAL_PIPE.set(write_fd).is_err() {
            // Another thread installed it first: a second reader would race
            // the first for the bytes.
            // SAFETY: closing descriptors we own.
            unsafe {
                libc::close(read_fd);
                libc::close(write_fd);
            }
        } else {
            std::thread::spawn(move || loop {
                let mut b = 0u8;
                // SAFETY: read(2) into a local byte.
                let n = unsafe { libc::read(read_fd, &mut b as *mut u8 as *mut libc::c_void, 1) };
                if n == 1 {
                    deliver(b as i32);
                } else if n < 0 && std::io::Error::last_os_error().kind() == std::io::ErrorKind::Interrupted {
                    continue;
                } else {
                    return;
                }
            });
        }
    }
    for sig in SIGNALS {
        // SAFETY: installing a handler that only calls write(2).
        unsafe {
            let mut sa: libc::sigaction = std::mem::zeroed();
            sa.sa_sigaction = on_signal as *const () as usize;
            sa.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut sa.sa_mask);
            if libc::sigaction(sig, &sa, std::ptr::null_mut()) != 0 {
                return Err(format!("cannot handle signal {sig}: {}", std::io::Error::last_os_error()));
            }
        }
    }
    Ok(())
}

/// Ends the forwarding to the run (once the run's children are gone there
/// is nothing left to end first): a signal now ends the command itself,
/// its unfinished folders removed.
pub fn default_signals() {
    *SIGNAL_TX.lock().unwrap_or_else(|e| e.into_inner()) = None;
}

/// Kills (SIGKILL) and reaps every child still running; returns how many it had to kill.
pub fn kill_and_reap(children: &mut [Child]) -> usize {
    let mut killed = 0;
    for c in children.iter_mut() {
        if matches!(c.try_wait(), Ok(None)) {
            let _ = c.kill();
            killed += 1;
        }
    }
    for c in children.iter_mut() {
        let _ = c.wait();
    }
    killed
}

/// Waits up to `timeout` for every child to exit by itself, then kills and
/// reaps the rest. Returns how many had to be killed.
pub fn reap_within(children: &mut [Child], timeout: Duration) -> usize {
    let deadline = Instant::now() + timeout;
    loop {
        let running = children.iter_mut().map(|c| c.try_wait()).filter(|s| matches!(s, Ok(None))).count();
        if running == 0 {
            return 0;
        }
        if Instant::now() >= deadline {
            return kill_and_reap(children);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// How a child ended, in words: `exit status 1`, `signal 9`.
pub fn describe(status: std::process::ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(c), _) => format!("exit status {c}"),
        (None, Some(s)) => format!("signal {s}"),
        _ => "unknown status".into(),
    }
}

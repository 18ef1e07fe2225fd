//! The run's processes: the world-server, then one robot-agent per robot.
//! Every child is spawned with [`launch::guard`] (killed with the
//! orchestrator, in its own process group) before this process creates
//! any iceoryx2 resource (it never does), and everything it started is
//! killed, reaped and its iceoryx2 files removed on every exit path
//! ([`Processes::abort`], also on drop).
//!
//! Agents are spawned from [`SPAWNERS`] threads at once: a spawn returns
//! only once its child has exec'd, and with hundreds of agents starting up
//! on two cores a new child waits its turn to run, so one thread spent
//! most of the time waiting (1,000 agents: 14.6 s). The threads stay
//! parked until the agents are gone, for a child's parent-death signal
//! fires when the thread that forked it ends, not only the process.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Sender};
use std::thread::JoinHandle;

use gridswarm::ipc;

use super::files::RunFiles;
use crate::error::{Error, Result};
use crate::launch::{self, Event};

/// Everything the run started, so every exit path can end it.
pub struct Processes {
    pub world: Option<Child>,
    world_in: Option<ChildStdin>,
    pub agents: Vec<Child>,
    prefix: String,
    /// Where the world-server's stderr goes.
    world_log: Option<PathBuf>,
    /// Where the agents' stderr goes.
    agent_log: Option<PathBuf>,
    spawners: Spawners,
}

/// Threads that spawn agents at once.
pub const SPAWNERS: usize = 4;

/// The threads that spawned the agents, parked until [`Spawners::release`].
#[derive(Default)]
struct Spawners {
    /// Dropping it wakes the parked threads.
    keep: Option<Sender<()>>,
    threads: Vec<JoinHandle<()>>,
}

impl Spawners {
    /// Spawns `cmd(i)` for every `i < n` from [`SPAWNERS`] threads; the
    /// children in order of `i`, or the first error with every child that
    /// did start (the caller must end them).
    fn spawn_all(
        &mut self,
        n: usize,
        cmd: impl Fn(usize) -> Result<Command> + Send + Sync + 'static,
    ) -> (Vec<Child>, Option<Error>) {
        let (keep, parked) = mpsc::channel::<()>();
        let parked = std::sync::Arc::new(std::sync::Mutex::new(parked));
        let cmd = std::sync::Arc::new(cmd);
        let (tx, rx) = mpsc::channel();
        for t in 0..SPAWNERS.min(n.max(1)) {
            let (tx, cmd, parked) = (tx.clone(), cmd.clone(), parked.clone());
            self.threads.push(std::thread::spawn(move || {
                for i in (t..n).step_by(SPAWNERS) {
                    let child = cmd(i).and_then(|mut c| {
                        c.spawn().map_err(|e| Error::Run(format!("cannot start robot-agent {i}: {e}")))
                    });
                    if tx.send((i, child)).is_err() {
                        break;
                    }
                }
                drop(tx);
                // Parked until released: its children's death signal is tied to it.
                let _ = parked.lock().map(|p| p.recv());
            }));
        }
        drop(tx);
        self.keep = Some(keep);
        let mut results: Vec<(usize, Result<Child>)> = rx.iter().collect();
        results.sort_by_key(|(i, _)| *i);
        let mut children = Vec::with_capacity(n);
        let mut first_error = None;
        for (_, r) in results {
            match r {
                Ok(c) => children.push(c),
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        (children, first_error)
    }

    /// Lets the threads end; only once their children are gone.
    fn release(&mut self) {
        self.keep = None;
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

impl Processes {
    pub fn new(prefix: &str) -> Self {
        Processes {
            world: None,
            world_in: None,
            agents: Vec::new(),
            prefix: prefix.to_string(),
            world_log: None,
            agent_log: None,
            spawners: Spawners::default(),
        }
    }

    pub fn world_pid(&self) -> u32 {
        self.world.as_ref().map_or(0, Child::id)
    }

    /// Starts the world-server; its stdout lines go to `tx`, its stderr
    /// to the run's world log ([`Processes::world_said`]).
    pub fn start_world(&mut self, bin: &Path, files: &RunFiles, tx: Sender<Event>, extra: &[String]) -> Result<()> {
        let log_path = files.world_log();
        let log = fs::File::create(&log_path).map_err(Error::write(&log_path))?;
        self.world_log = Some(log_path);
        let mut cmd = Command::new(bin);
        cmd.arg("--prefix")
            .arg(&self.prefix)
            .arg("--run")
            .arg(files.run_file())
            .arg("--report")
            .arg(files.report())
            .arg("--progress")
            .args(extra)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(log);
        // It removes the run's files on SIGTERM: after a kill -9 of this
        // process, nobody else would until the next run.
        launch::guard(&mut cmd, libc::SIGTERM);
        let mut child = cmd.spawn().map_err(|e| Error::Run(format!("cannot start {}: {e}", bin.display())))?;
        self.world_in = child.stdin.take();
        if let Some(out) = child.stdout.take() {
            launch::read_lines(out, tx);
        }
        self.world = Some(child);
        Ok(())
    }

    /// Starts robot-agent `0..robots`, their stderr into the run's log.
    pub fn start_agents(&mut self, bin: &Path, files: &RunFiles, robots: usize, extra: &[String]) -> Result<()> {
        let log_path = files.agent_log();
        let log = fs::File::create(&log_path).map_err(Error::write(&log_path))?;
        self.agent_log = Some(log_path.clone());
        let world_pid = self.world_pid().to_string();
        let (bin, prefix) = (bin.to_path_buf(), self.prefix.clone());
        let setups: Vec<PathBuf> = (0..robots).map(|i| files.setup(i)).collect();
        let extra = extra.to_vec();
        let (children, error) = self.spawners.spawn_all(robots, move |i| {
            let mut cmd = Command::new(&bin);
            cmd.arg("--prefix")
                .arg(&prefix)
                .arg("--setup")
                .arg(&setups[i])
                .arg("--world-pid")
                .arg(&world_pid)
                .args(&extra)
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(log.try_clone().map_err(Error::write(&log_path))?);
            launch::guard(&mut cmd, libc::SIGKILL);
            Ok(cmd)
        });
        self.agents = children;
        error.map_or(Ok(()), Err)
    }

    /// The lines the world-server wrote to its stderr so far.
    pub fn world_said(&self) -> Vec<String> {
        let text = self.world_log.as_ref().and_then(|p| fs::read_to_string(p).ok()).unwrap_or_default();
        text.lines().filter(|l| !l.trim().is_empty()).map(str::to_string).collect()
    }

    /// The first agent found to have exited with an error status (neither
    /// 0, `End`, nor [`ipc::EXIT_WORLD_GONE`]; a signal is a fault or a
    /// death the world finds by itself): its number and how it ended.
    /// `at_start`: before the world's first slot, when any exit (0, a
    /// signal) is a failure: a robot that never says hello would stall the
    /// run until the world's hello time-out (30 s). Later a robot killed by a
    /// signal is a crash the others detect, and status 0 or
    /// [`ipc::EXIT_WORLD_GONE`] its normal end.
    pub fn failed_agent(&mut self, at_start: bool) -> Option<(usize, ExitStatus)> {
        let failed = |st: &ExitStatus| at_start || st.code().is_some_and(|c| c != 0 && c != ipc::EXIT_WORLD_GONE);
        self.agents.iter_mut().enumerate().find_map(|(k, c)| match c.try_wait() {
            Ok(Some(st)) if failed(&st) => Some((k, st)),
            _ => None,
        })
    }

    /// Whether the world-server has exited (its status is kept for [`Child::wait`]).
    pub fn world_exited(&mut self) -> bool {
        self.world.as_mut().is_some_and(|w| matches!(w.try_wait(), Ok(Some(_))))
    }

    /// What agent `k` said: its own line in the agents' log (ours start
    /// `robot-agent K`), else the log's first line (another program's).
    pub fn agent_said(&self, k: usize) -> Option<String> {
        let text = self.agent_log.as_ref().and_then(|p| fs::read_to_string(p).ok()).unwrap_or_default();
        let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
        let own = format!("robot-agent {k}:");
        text.lines().find(|l| l.starts_with(&own)).or_else(|| lines.next()).map(str::to_string)
    }

    /// Tells the paused world to go on; false if it is gone.
    pub fn go(&mut self) -> bool {
        self.world_in.as_mut().is_some_and(|w| writeln!(w, "go").and_then(|()| w.flush()).is_ok())
    }

    /// Kills and reaps every child, removes the run's iceoryx2 files.
    pub fn abort(&mut self) {
        self.world_in = None;
        if let Some(w) = self.world.as_mut() {
            let _ = w.kill();
            let _ = w.wait();
        }
        launch::kill_and_reap(&mut self.agents);
        self.spawners.release();
        self.cleanup();
    }

    pub fn cleanup(&mut self) {
        let _ = ipc::cleanup_run(&self.prefix);
    }
}

impl Drop for Processes {
    fn drop(&mut self) {
        // Whatever path left the run (an error, a panic), nothing outlives it.
        self.abort();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn sleeper(i: usize) -> Result<Command> {
        let mut cmd = Command::new("sleep");
        cmd.arg(format!("30.{i:03}"));
        launch::guard(&mut cmd, libc::SIGKILL);
        Ok(cmd)
    }

    /// Children come back in order, and outlive the spawn: were the
    /// spawning threads gone, their parent-death signal would kill them.
    #[test]
    fn agents_spawned_from_threads_are_in_order_and_stay_alive_until_released() {
        let mut sp = Spawners::default();
        let (mut kids, err) = sp.spawn_all(9, sleeper);
        assert!(err.is_none());
        assert_eq!(kids.len(), 9);
        for (i, k) in kids.iter().enumerate() {
            let cmdline = fs::read_to_string(format!("/proc/{}/cmdline", k.id())).unwrap_or_default();
            assert!(cmdline.contains(&format!("30.{i:03}")), "child {i}: {cmdline:?}");
        }
        std::thread::sleep(Duration::from_millis(300));
        assert!(kids.iter_mut().all(|k| matches!(k.try_wait(), Ok(None))), "a child died with its spawning thread");
        assert_eq!(launch::kill_and_reap(&mut kids), 9);
        sp.release();
        assert!(sp.threads.is_empty());
    }

    /// A child that cannot start is an error naming it; the others started.
    #[test]
    fn a_failed_spawn_is_named_and_the_rest_are_returned() {
        let mut sp = Spawners::default();
        let (mut kids, err) =
            sp.spawn_all(5, |i| if i == 3 { Ok(Command::new("/nonexistent/robot-agent")) } else { sleeper(i) });
        let err = err.expect("robot-agent 3 cannot start").to_string();
        assert!(err.contains("cannot start robot-agent 3"), "{err}");
        assert_eq!(kids.len(), 4);
        launch::kill_and_reap(&mut kids);
        sp.release();
    }
}
